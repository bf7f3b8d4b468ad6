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
                     threshold: float = COND_THRESHOLD, passive: Sequence[int] = (),
                     frame: tuple | None = None) -> JacobianResult:
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
    frame : (rotation (3, 3), origin (3,)), optional
        The base frame whose axes are the reference directions (see Notes), in world
        coordinates; default the world's.  Legs moved by ``x -> R x + p`` (:meth:`Leg.moved`)
        and given ``frame=(R, p)`` give the same rows as before, in the moved world.

    Returns
    -------
    JacobianResult
        Never raises at a singular pose (see :meth:`JacobianResult.check`).

    Notes
    -----
    The members of a constraint system of two or more (two forces in a plane, two
    couples...) are picked by reference directions: the axes of ``frame`` (a model's are its
    base and platform axes, which move with it).  Rotating the legs without the frame can
    pick other members, which changes the normalised condition number a little and can flip
    the sign of a single member's value; translations and a change of units change neither.
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
           for i in passive) or len(set(passive)) == len(legs) or len(set(passive)) != len(passive):
        raise InputError(f"passive must list distinct 0-based leg indices below {len(legs)} "
                         f"(at least one leg actuated), got {passive!r:.60}")
    Rf, pf = _frame_of(frame)
    J, info, n_act, scale, points, cond = _rows_of(legs, o, analyses, passive, Rf, pf)
    return JacobianResult(J, info, n_act, scale, points, o[None], cond, float(threshold), True,
                          lambda _: legs, analyses)


def _frame_of(frame):
    """``(R, p)`` of a ``frame`` argument (the world's for None), checked."""
    InputError = _errors()
    if frame is None:
        return np.eye(3), np.zeros(3)
    try:
        R, p = frame
        R = np.asarray(R, float)
    except (TypeError, ValueError):
        raise InputError("frame must be (rotation (3, 3), origin (3,))") from None
    p = as_vector3(p, "frame origin")
    if R.shape != (3, 3) or not np.all(np.isfinite(R)) or \
            not np.allclose(R.T @ R, np.eye(3), atol=1e-9) or np.linalg.det(R) < 0:
        raise InputError("frame's rotation must be a proper rotation matrix (3, 3)")
    return R, p


def _rows_of(legs, o, analyses, passive=(), R=None, p=None):
    """The rows of placed legs at one pose by the kernels: ``(J (1, m, 6), info,
    n_actuated, scale, points (1, m, 3), Conditioning)``."""
    from ._flat import flatten_legs
    from ._kernels import kernels
    from ._launch import run_poses
    from ._pipeline import Conditioning
    from ._templates import make_labels
    from ._templates import RowTemplate
    R = np.eye(3) if R is None else R
    p = np.zeros(3) if p is None else p
    templates = tuple(RowTemplate(lg, an, R, p, R, o, passive=i in passive)
                      for i, (lg, an) in enumerate(zip(legs, analyses)))
    info = make_labels(templates)
    flat = flatten_legs(legs, templates, o, info, passive, (R, p))
    P6 = np.concatenate([R.T @ (o - p), np.zeros(3)])[None]     # (the base frame's)
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
                  threshold: float = COND_THRESHOLD, passive: Sequence[int] = (),
                  frame: tuple | None = None) -> StaticsResult:
    """Shortcut: :func:`statics` of :func:`unified_jacobian` ``(legs, o)`` with the load at
    ``o`` (``passive``: the passive legs' indices; ``frame``: the reference directions'
    base frame, as there)."""
    jac = unified_jacobian(legs, o, analyses, threshold=threshold, passive=passive,
                           frame=frame)
    return statics(jac, F, T, o, raise_on_singular=raise_on_singular)
