"""Interoperability layer: Pinocchio models of legs and PMs, and the cross-check with Pinocchio.

* :func:`build_leg_model`, :func:`build_closed_loop_model`: a screwkit leg or a
  whole PM rebuilt with Pinocchio's native joints (:class:`LegChain`,
  :class:`LegModel`, :class:`ClosedLoopModel`);
* :func:`to_pinocchio`, :func:`write_urdf`: a PM's Pinocchio model with its constraint
  models; its URDF tree with the loop closures in a JSON sidecar (``screwkit export``);
* :func:`write_mjcf`, :func:`mjcf_text`: the PM as MJCF for MuJoCo (SI units, loops as weld
  equality constraints, the ``dynamics:`` block's inertias, keyframe 0 at a solved pose);
* :func:`check_leg`, :func:`check_closed_loop`, :func:`check_pm`,
  :class:`PMChecker`, :func:`check_analysis`, :func:`check_all`: closure, joint
  twists, mobility and statics compared with Pinocchio (``screwkit check``).

Pinocchio is imported lazily, inside the functions.
"""

from ._pinocchio_chain import JointBlock, LegChain, as_pose, sphere_angles
from ._pinocchio_model import ClosedLoopModel, LegModel, build_closed_loop_model, build_leg_model
from ._check_rows import CHECK_RTOL, CheckReport, CheckRow
from ._check_leg import check_leg
from ._check_mobility import Mobility, constraint_jacobian, mobility
from ._pinocchio_check import PMChecker, check_closed_loop, check_pm
from ._urdf import closures, to_pinocchio, urdf_text, write_urdf
from ._mjcf import mjcf_text, si_factors, write_mjcf
from ._check_catalog import (SUMMARY_CHECKS, PMCheckReport, check_all, check_analysis,
                             regular_analyses, summarize)

__all__ = [
    # Pinocchio models
    "JointBlock", "LegChain", "LegModel", "ClosedLoopModel", "build_leg_model",
    "build_closed_loop_model", "sphere_angles", "as_pose",
    # URDF export (tree + loop closures sidecar) and the model with its constraint models
    "urdf_text", "closures", "write_urdf", "to_pinocchio",
    # MJCF export (SI, loops as weld equalities, inertias of the dynamics: block)
    "mjcf_text", "write_mjcf", "si_factors",
    # checks
    "CHECK_RTOL", "SUMMARY_CHECKS", "CheckRow", "CheckReport", "Mobility", "PMChecker",
    "PMCheckReport", "check_leg", "check_closed_loop", "check_pm", "check_analysis", "check_all",
    "regular_analyses", "summarize", "constraint_jacobian", "mobility",
]
