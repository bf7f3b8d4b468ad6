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
from ._pipeline import legs_rows
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
    rows = legs_rows(legs, o, analyses, passive)
    return JacobianResult.from_rows(rows, o[None], threshold=threshold, single=True,
                                    leg_provider=lambda _: legs, analyses=analyses)


def solve_statics(legs: Sequence[Leg], o: ArrayLike, F: ArrayLike, T: ArrayLike, *,
                  analyses: Sequence[LegAnalysis] | None = None, raise_on_singular: bool = True,
                  threshold: float = COND_THRESHOLD, passive: Sequence[int] = ()
                  ) -> StaticsResult:
    """Shortcut: :func:`statics` of :func:`unified_jacobian` ``(legs, o)`` with the load at
    ``o`` (``passive``: the passive legs' indices)."""
    jac = unified_jacobian(legs, o, analyses, threshold=threshold, passive=passive)
    return statics(jac, F, T, o, raise_on_singular=raise_on_singular)
