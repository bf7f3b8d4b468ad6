"""Engine layer: inverse displacement, unified Jacobian, statics and the analysis of a PM.

The solvers take the constant models of :mod:`screwkit.pm` (and placed legs of
:mod:`screwkit.legs`) as input:

* inverse displacement (:func:`solve_pose`, :func:`solve_path`,
  :class:`PoseSolution`) and leg kinematics (:func:`leg_forward`);
* the unified Jacobian (:func:`unified_jacobian`) and statics (:func:`statics`,
  :func:`solve_statics`);
* the per-pose analysis of a PM (:func:`analyze_pm`, :class:`PMAnalysis`);
* the batched (vectorised over samples) kinematics and statics of a path
  (:func:`newton_batch`, :func:`jacobian_statics_batch`, ...);
* loading a PM for use with the check that its default pose assembles
  (:func:`load_assembled_pm`, :func:`check_default_pose`).
"""

from ._kinematics import (ACCEPTED, CONVERGED, LENGTH_PARAMS, PARAMS, PoseSolution, leg_forward,
                          placed_leg, solve_path, solve_pose, structure_vector)
from ._jacobian import COND_THRESHOLD, JacobianResult, JacobianRow, unified_jacobian
from ._statics import StaticsResult, solve_statics, statics, workload_wrench
from ._assembly import check_default_pose, default_full_pose, load_assembled_pm
from ._analyze import PAPER_FORCE, PAPER_TORQUE, PMAnalysis, analyze_pm
from ._batch import (BatchProblem, BatchStatics, KinematicsBatch, LegArrays, LegTemplate,
                     assemble_batch, forward_batch, jacobian_statics_batch, leg_arrays,
                     newton_batch, twists_batch)

__all__ = [
    # kinematics
    "PARAMS", "LENGTH_PARAMS", "PoseSolution", "leg_forward", "placed_leg", "solve_pose",
    "solve_path", "structure_vector", "CONVERGED", "ACCEPTED",
    # Jacobian and statics
    "COND_THRESHOLD", "JacobianRow", "JacobianResult", "unified_jacobian",
    "StaticsResult", "statics", "solve_statics", "workload_wrench",
    # loading and analysis
    "load_assembled_pm", "check_default_pose", "default_full_pose",
    "PAPER_FORCE", "PAPER_TORQUE", "PMAnalysis", "analyze_pm",
    # batched path computations
    "LegArrays", "leg_arrays", "forward_batch", "twists_batch", "KinematicsBatch", "BatchProblem",
    "newton_batch", "assemble_batch", "LegTemplate", "jacobian_statics_batch", "BatchStatics",
]
