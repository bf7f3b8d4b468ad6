"""Dynamics layer: inverse dynamics and stiffness of a PM (the paper's section 5.2).

* motions: the independent pose parameters with their rates and accelerations
  (:class:`Motion`; exact derivatives of expressions by automatic differentiation,
  smoothing splines of samples);
* :func:`dynamics` -> :class:`DynamicsResult`: along a motion, the loop-closure velocity and
  acceleration equations with the engine's Jacobians, Newton-Euler of every leg link and of
  the platform, and the unified statics (eq. 9) under the dynamic workload: dynamic active
  forces, constraint values, leg reactions, joint efforts, energies;
* :func:`stiffness` -> :class:`StiffnessResult`: ``K = J^T K_r J`` about ``o``, the deflection
  under a workload, the principal stiffnesses;
* :func:`stiffness_fields`: per-pose scalars of the stiffness of many poses (for maps);
* :func:`check_dynamics`: the same inverse dynamics from Pinocchio's closed-loop model.

The module itself is callable: ``screwkit.dynamics(pm, motion, ...)`` is
:func:`dynamics`.  Masses and stiffnesses are the model's ``dynamics:`` block
(:mod:`screwkit.pm._physical`) or given with ``params=``.
"""

import sys as _sys
import types as _types

from ._jets import Jet, derivatives
from ._motion import (Motion, motion_from_args, motion_from_csv, motion_from_expressions,
                      motion_from_path, motion_from_samples)
from ._result import STATUSES, DynamicsResult
from ._dynamics import CHUNK, dynamics, resolve_parameters
from ._stiffness import StiffnessResult, row_stiffness, stiffness, stiffness_of
from ._stiffness_fields import STIFFNESS_FIELDS, stiffness_fields
from ._pinocchio import DynamicsCheck, check_dynamics

__all__ = [
    "Jet", "derivatives", "Motion", "motion_from_expressions", "motion_from_samples",
    "motion_from_csv", "motion_from_path", "motion_from_args",
    "DynamicsResult", "STATUSES", "dynamics", "resolve_parameters", "CHUNK",
    "StiffnessResult", "stiffness", "stiffness_of", "row_stiffness", "STIFFNESS_FIELDS",
    "stiffness_fields", "DynamicsCheck", "check_dynamics",
]


class _CallableModule(_types.ModuleType):
    """``screwkit.dynamics(pm, motion, ...)`` calls :func:`dynamics`."""

    def __call__(self, *args, **kwargs):
        return dynamics(*args, **kwargs)


_sys.modules[__name__].__class__ = _CallableModule
