"""Engine layer: one batched engine for the inverse displacement, the unified Jacobian and the
statics of a PM at N poses (one pose is N = 1).

The solvers take the constant models of :mod:`screwkit.pm` (and placed legs of
:mod:`screwkit.legs`); every array has the poses on its leading axis (dropped for
a one-pose result, as :class:`scipy.spatial.transform.Rotation` holds one or many):

* inverse displacement: :func:`solve` (:class:`PoseSolution`), batched Gauss-Newton on
  the loop closures with per-pose convergence, warm starts along paths;
* the unified Jacobian ``J = [J_a; J_c]`` (:class:`JacobianResult`, row templates decided
  once per leg by the observation rules), its length-normalised conditioning, and the
  statics ``F_r = -(J^-1)^T W`` (:class:`StaticsResult`);
* :func:`analyze` (:class:`PMAnalysis`) chains the three, in chunks, on threads;
* for placed legs at one pose: :func:`unified_jacobian`, :func:`statics`,
  :func:`solve_statics`.
"""

from ..pm import LENGTH_PARAMS, PARAMS
from ._chains import leg_forward
from ._closure import ACCEPTED, CONVERGED
from ._run import CHUNK
from ._jacobian import COND_THRESHOLD, JacobianResult, JacobianRow
from ._quality import CONDITIONING, ILL_CONDITIONED_COND, NEAR_SINGULAR_COND, classify
from ._pipeline import RowInfo
from ._solution import STATUSES, PoseSolution, solve
from ._placed import solve_statics, unified_jacobian
from ._statics import StaticsResult, statics, workload_wrench
from ._analysis import PAPER_FORCE, PAPER_TORQUE, PMAnalysis, analyze
from ._links import LinkFrames, link_frames
from ._assembly import (analyze_pm, check_default_pose, default_full_pose, load_assembled_pm,
                        solve_path, solve_pose)
from ._forward import ForwardResult, forward_kinematics
from ._motion import check_declared_motion, finite_motion
from ..pm import set_finite_motion_solver as _set_solver

_set_solver(finite_motion)        # screwkit.pm.mobility reports the finite motion type
from ._modes import AssemblyModes, assembly_modes
from ._report import constraint_resultants
from ._indices import TransmissionIndices
from ._transmission import power_coefficient, transmission_indices
from ._scene import scene_of, wrench_rows

__all__ = [
    "PARAMS", "LENGTH_PARAMS", "CONVERGED", "ACCEPTED", "STATUSES", "COND_THRESHOLD", "CHUNK",
    "ILL_CONDITIONED_COND", "NEAR_SINGULAR_COND", "CONDITIONING", "classify",
    "PoseSolution", "solve", "solve_pose", "solve_path", "leg_forward",
    "RowInfo", "JacobianRow", "JacobianResult", "unified_jacobian",
    "StaticsResult", "statics", "solve_statics", "workload_wrench",
    "PAPER_FORCE", "PAPER_TORQUE", "PMAnalysis", "analyze", "analyze_pm",
    "load_assembled_pm", "check_default_pose", "default_full_pose",
    "finite_motion", "check_declared_motion",
    "ForwardResult", "forward_kinematics", "AssemblyModes", "assembly_modes",
    "LinkFrames", "link_frames", "constraint_resultants", "scene_of", "wrench_rows",
    "TransmissionIndices", "transmission_indices", "power_coefficient",
]
