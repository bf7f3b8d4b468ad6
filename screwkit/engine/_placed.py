"""The unified Jacobian and statics of placed legs at one pose (paper eqs. 8-9).

Plain :class:`~screwkit.legs.Leg` objects placed in the base frame (no PM model): their rows
through the engine's row builder, then :func:`~._statics.statics`.
"""

from __future__ import annotations

from collections.abc import Sequence
from typing import TYPE_CHECKING

import numpy as np
from numpy.typing import ArrayLike

from ._jacobian import COND_THRESHOLD, JacobianResult
from ._statics import StaticsResult, _errors, statics
from ..screws import as_vector3

if TYPE_CHECKING:
    from ..legs import Leg, LegAnalysis

__all__ = ["unified_jacobian", "solve_statics"]


def unified_jacobian(legs: Sequence[Leg], o: ArrayLike,
                     analyses: Sequence[LegAnalysis] | None = None, *,
                     threshold: float = COND_THRESHOLD, passive: Sequence[int] = ()
                     ) -> JacobianResult:
    """The unified Jacobian ``J = [J_a; J_c]`` of placed legs at one pose.

    Parameters
    ----------
    legs : sequence of Leg
        The legs at the pose (world = base frame, moments about its origin ``O``).
    o : array_like (3,)
        Platform centre: the reference point of the paper's rows and of the workload.
    analyses : sequence of LegAnalysis, optional
        Each leg's analysis (computed if omitted): it decides what each row is.
    threshold : float
        Normalised condition number above which the pose counts as singular.
    passive : sequence of int
        0-based indices of passive legs: no actuation row, their constraint rows only.

    Returns
    -------
    JacobianResult
        Never raises at a singular pose (see :meth:`JacobianResult.check`).

    Notes
    -----
    The members of a constraint system of two or more (two forces in a plane, two
    couples...) are picked by reference directions, here the world's axes (a model's are
    its base and platform axes, which move with it): rotating the legs alone can pick
    other members, which changes the normalised condition number a little and can flip the
    sign of a single member's value.  Translations and a change of units change neither.
    """
    from ..legs import Leg
    InputError = _errors()
    o = as_vector3(o, "platform centre o")
    if not (np.isfinite(threshold) and threshold > 1):
        raise InputError(f"threshold must be a finite number > 1, got {threshold}")
    legs = tuple(legs)
    if not legs:
        raise InputError("unified_jacobian needs at least one leg")
    for i, leg in enumerate(legs):
        if not isinstance(leg, Leg):
            raise InputError(f"legs[{i}] is a {type(leg).__name__}, not a screwkit Leg")
    if analyses is None:
        analyses = tuple(leg.analyze() for leg in legs)
    else:
        analyses = tuple(analyses)
        if len(analyses) != len(legs):
            raise InputError(f"{len(analyses)} analyses given for {len(legs)} legs")
        for i, (leg, an) in enumerate(zip(legs, analyses)):
            if getattr(an, "leg", None) is not leg:
                raise InputError(f"analyses[{i}] is not the analysis of legs[{i}] ({leg.name})")
    passive = tuple(passive)
    if any(isinstance(i, bool) or not isinstance(i, (int, np.integer)) or not 0 <= i < len(legs)
           for i in passive) or len(set(passive)) == len(legs):
        raise InputError(f"passive must list distinct 0-based leg indices below {len(legs)} "
                         f"(at least one leg actuated), got {passive!r:.60}")
    J, info, n_act, scale, points, cond = _rows_of(legs, o, analyses, passive)
    return JacobianResult(J, info, n_act, scale, points, o[None], cond, float(threshold), True,
                          lambda _: legs, analyses)


def _rows_of(legs, o, analyses, passive=()):
    """The rows of placed legs at one pose by the kernels: ``(J (1, m, 6), info,
    n_actuated, scale, points (1, m, 3), Conditioning)``."""
    from ._flat import flatten_legs
    from ._kernels import kernels
    from ._launch import run_poses
    from ._pipeline import Conditioning
    from ._templates import make_labels
    from ._templates import RowTemplate
    templates = tuple(RowTemplate(lg, an, np.eye(3), np.zeros(3), np.eye(3), o,
                                  passive=i in passive)
                      for i, (lg, an) in enumerate(zip(legs, analyses)))
    info = make_labels(templates)
    flat = flatten_legs(legs, templates, o, info, passive)
    P6 = np.concatenate([o, np.zeros(3)])[None]
    X = np.zeros((1, flat.nx))
    out = run_poses(flat, flat.Z, P6, X=X, statics=False)
    points = np.full(out["J"].shape[:2] + (3,), np.nan)
    kernels().row_points_range(flat.M, flat.Z[0], flat.Z[1], P6, X, out["J"], points, 0, 1)
    cond = Conditioning(out["centre"], out["length"], out["singular_values"], out["rank"],
                        out["condition_number"], out["constraint_rank"],
                        out["constraint_condition_number"])
    return out["J"], info, flat.n_act, out["scale"], points, cond


def solve_statics(legs: Sequence[Leg], o: ArrayLike, F: ArrayLike, T: ArrayLike, *,
                  analyses: Sequence[LegAnalysis] | None = None, raise_on_singular: bool = True,
                  threshold: float = COND_THRESHOLD, passive: Sequence[int] = ()
                  ) -> StaticsResult:
    """Shortcut: :func:`statics` of :func:`unified_jacobian` ``(legs, o)`` with the load at
    ``o`` (``passive``: the passive legs' indices)."""
    jac = unified_jacobian(legs, o, analyses, threshold=threshold, passive=passive)
    return statics(jac, F, T, o, raise_on_singular=raise_on_singular)
