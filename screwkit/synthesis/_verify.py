"""Verification of a synthesized leg by the reciprocal-screw solver.

:func:`verify` sees only the concrete :class:`~screwkit.legs.Leg` and the
predicted wrenches: the reciprocal-screw system has the predicted dimension and
contains each predicted wrench, the joints are independent (or the dependence
was predicted), and the actuated joint has an actuation wrench.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from ..errors import InputError
from ..legs import Leg
from ..legs._analysis import has_actuation_wrench
from ..screws import compare_spans, independent_subset, reciprocal_system, twist_rank

__all__ = ["Verification", "verify"]


# --------------------------------------------------------------------------- verifier
@dataclass(frozen=True)
class Verification:
    """Result of :func:`verify`.

    Attributes
    ----------
    dimension : int
        Dimension of the leg's constraint system (reciprocal-screw solver).
    expected_dimension : int
        Number of predicted wrenches.
    contained : tuple of bool
        Whether each predicted wrench lies in the solver's system.
    same_span : bool
        Whether the predicted wrenches span the solver's system exactly.
    dependent_joints : tuple of str
        Joints spanned by earlier joints.
    dependence_allowed : bool
        Whether a dependence was predicted (more joints than ``6 - k``).
    actuation : bool
        Whether the actuated joint has an actuation wrench.
    residual : float
        Largest normalised ``|W . V| / (|W| |V|)`` of a predicted wrench and a joint twist.
    condition_number : float
        Of the joint twists (normalised), over the retained singular values.
    """

    dimension: int
    expected_dimension: int
    contained: tuple
    same_span: bool
    dependent_joints: tuple
    dependence_allowed: bool
    actuation: bool
    residual: float
    condition_number: float

    @property
    def problems(self) -> tuple:
        """What disagrees with the prediction (empty when verified)."""
        out = []
        if self.dimension != self.expected_dimension:
            out.append(f"constraint system has dimension {self.dimension}, predicted "
                       f"{self.expected_dimension}")
        missing = [i for i, c in enumerate(self.contained) if not c]
        if missing:
            out.append(f"predicted wrench(es) {missing} not in the constraint system")
        if not missing and self.dimension == self.expected_dimension and not self.same_span:
            out.append("predicted wrenches do not span the constraint system")
        if self.dependent_joints and not self.dependence_allowed:
            out.append(f"dependent joints {', '.join(self.dependent_joints)}")
        if self.dependence_allowed and not self.dependent_joints:
            out.append("a dependence was predicted but the joints are independent")
        if not self.actuation:
            out.append("the actuated joint has no actuation wrench (it depends on the passive joints)")
        return tuple(out)

    @property
    def ok(self) -> bool:
        return not self.problems


def verify(leg: Leg, predicted, allow_dependent: bool = False,
           actuation: str = "wrench") -> Verification:
    """Check a concrete leg against predicted constraint wrenches with the solver only.

    Parameters
    ----------
    leg : Leg
    predicted : array_like, shape (k, 6)
        Predicted constraint wrenches ``[f; m]`` (moments about O).
    allow_dependent : bool
        Whether dependent joints are expected (reported, not a failure).
    actuation : {"wrench", "rank"}
        ``"wrench"``: the actuated joint must have an actuation wrench
        (:func:`screwkit.legs.actuation_wrench` is not None); ``"rank"``: the
        equivalent, cheaper test that the passive joints' twists have a lower rank
        than all the twists (used for repeated draws).

    Returns
    -------
    Verification
    """
    W = np.asarray(predicted, float).reshape(-1, 6)
    if not np.all(np.isfinite(W)):
        raise InputError("predicted wrenches contain NaN or infinite entries")
    T, pts = leg.twists, leg.points
    system = reciprocal_system(T, pts)
    norm = system.normalisation
    contained, same = compare_spans(system.wrenches, W, norm)
    same = same if len(W) or system.dimension == 0 else False
    # independent twists (full rank) have no dependent prefix: skip the greedy search
    dep = [] if system.rank == len(T) else independent_subset(T, pts)[1]
    Tn = norm.twists(T)
    Wn = norm.wrenches(W)
    if len(W) and len(Tn):
        num = np.abs(Wn @ Tn.T)
        den = np.outer(np.linalg.norm(Wn, axis=1), np.linalg.norm(Tn, axis=1))
        residual = float(np.max(num / den))
    else:
        residual = 0.0
    if actuation == "wrench":
        act = has_actuation_wrench(leg, system)
    elif actuation == "rank":
        ia = leg.actuated_index
        passive = np.delete(T, ia, axis=0)
        act = twist_rank(passive, pts, length=norm.length) < system.rank
    else:
        raise InputError(f"actuation must be 'wrench' or 'rank', got {actuation!r}")
    return Verification(system.dimension, len(W), contained, same,
                        tuple(leg.joints[i].name for i in dep), bool(allow_dependent), act,
                        residual, system.condition_number)
