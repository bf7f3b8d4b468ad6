"""Analysis of one leg: connectivity, constraint wrenches explained, actuation wrench.

Examples
--------
>>> import screwkit
>>> res = screwkit.leg("SPR").analyze()
>>> res.connectivity, [c.kind for c in res.constraints]
(5, ['force'])
>>> res.constraints[0].point_name
'S1'
"""

from __future__ import annotations

from dataclasses import dataclass
from functools import cached_property
from itertools import combinations

import numpy as np

from ..screws import (GEOMETRY_RTOL, Line, ReciprocalSystem, couple_wrench, force_wrench,
                      independent_subset, reciprocal_system, same_span)
from ._decompose import _null, _through_matrix, constraint_kinds, decompose, reciprocity_residual
from ._observation import ConstraintWrench, RuleNote, candidate_points, explain_couple, explain_force
from ..screws import cross

# ``leg`` arguments are :class:`screwkit.legs.Leg` objects, used by duck typing
# (``joints``, ``twists``, ``points``, ``actuated_index``, ``A``, ``a``, ``length``, ``centres()``):
# the chain module is not imported, so that ``Leg.analyze`` can import this module
# without an import cycle.

__all__ = ["LegAnalysis", "ActuationWrench", "analyze_leg", "actuation_wrench", "has_actuation_wrench"]


@dataclass(frozen=True)
class ActuationWrench:
    """The actuation wrench of a leg's actuated joint.

    Reciprocal to every passive joint, not to the actuated one, scaled so that
    its reciprocal product with the actuated joint's unit twist is 1: a unit
    actuator force (or torque) transmits this wrench to the platform.

    Attributes
    ----------
    member : ConstraintWrench
        Kind, line or direction, and the rule notes for the passive joints.
    wrench : ndarray (6,)
        The scaled wrench ``[f; m]``.
    scale : float
        Factor between ``member.wrench`` (unit force or couple) and ``wrench``.
    joint : str
        Name of the actuated joint.
    """

    member: ConstraintWrench
    wrench: np.ndarray
    scale: float
    joint: str


@dataclass(frozen=True, eq=False)
class LegAnalysis:
    """Everything screwkit says about one leg at one geometry."""

    leg: "Leg"
    system: ReciprocalSystem

    @property
    def connectivity(self) -> int:
        """Rank of the joint twists (the leg's connectivity)."""
        return self.system.rank

    @cached_property
    def dependent_joints(self) -> tuple:
        """Names of joints whose twists are spanned by earlier joints (empty when independent)."""
        _, dep = independent_subset(self.leg.twists, self.leg.points)
        return tuple(self.leg.joints[i].name for i in dep)

    @cached_property
    def constraints(self) -> tuple:
        """The constraint system as pure couples, pure forces and finite-pitch screws."""
        return decompose(self.system.wrenches, self.leg, self.system.normalisation)

    @property
    def n_forces(self) -> int:
        return sum(c.kind == "force" for c in self.constraints)

    @property
    def n_couples(self) -> int:
        return sum(c.kind == "couple" for c in self.constraints)

    @property
    def n_screws(self) -> int:
        return sum(c.kind == "screw" for c in self.constraints)

    @cached_property
    def actuation(self) -> ActuationWrench | None:
        """The actuation wrench, or None when the actuated joint is dependent."""
        return actuation_wrench(self.leg, self.system)

    def agrees(self) -> bool:
        """True when the explained members span exactly the solver's system and every
        rule note holds (the observation rules and the numeric solver agree)."""
        rows = np.array([c.wrench.vector for c in self.constraints]).reshape(-1, 6)
        return (same_span(rows, self.system.wrenches, self.system.normalisation)
                and all(c.explained for c in self.constraints))

    def summary(self) -> str:
        return _summary_of(c.kind for c in self.constraints)

    def kinds_summary(self) -> str:
        """:meth:`summary` from the kinds of the members alone (the same search, without
        building and explaining the members, unless they are already built)."""
        if "constraints" in self.__dict__:
            return self.summary()
        return _summary_of(constraint_kinds(self.system.wrenches, self.leg,
                                            self.system.normalisation))


def _summary_of(kinds) -> str:
    """``"1 force + 2 couples"``... from the kinds (``"force"``, ``"couple"``, ``"screw"``)."""
    kinds = tuple(kinds)
    nf, nc, ns = kinds.count("force"), kinds.count("couple"), kinds.count("screw")
    parts = []
    if nf:
        parts.append(f"{nf} force{'s' * (nf > 1)}")
    if nc:
        parts.append(f"{nc} couple{'s' * (nc > 1)}")
    if ns:
        parts.append(f"{ns} finite-pitch wrench{'es' * (ns > 1)}")
    return " + ".join(parts) if parts else "no constraint wrench"


def analyze_leg(leg: "Leg") -> LegAnalysis:
    """Analyse a placed leg (see :class:`LegAnalysis`)."""
    return LegAnalysis(leg, reciprocal_system(leg.twists, leg.points))


def actuation_wrench(leg: "Leg", system: ReciprocalSystem | None = None) -> ActuationWrench | None:
    """Actuation wrench of the leg's actuated joint (see :class:`ActuationWrench`).

    Among the wrenches reciprocal to the passive joints and not to the actuated
    one, a pure force on an observable line is preferred: first a line through
    two named points (for a linear actuator between two joint centres, the line
    of the leg), then forces through a named point, then any pure force, then a
    pure couple; failing all, the least-norm wrench orthogonal to the
    constraint system.
    """
    system = system or reciprocal_system(leg.twists, leg.points)
    norm = system.normalisation
    ia = leg.actuated_index
    xi, Tp, N, scale_ref = _passive_system(leg, system)
    if N is None:
        return None                        # the actuated joint is dependent on the passive ones
    L = max(leg.length, norm.length)
    tol = GEOMETRY_RTOL * 10 * L
    pts = candidate_points(leg, tol)

    def member_ok(w):
        return abs(w @ xi) > 1e-6 * np.linalg.norm(norm.wrenches(w)) * scale_ref and \
            reciprocity_residual(w, Tp, norm) < 1e-8

    choice = None
    names = list(pts)
    for n1, n2 in combinations(names, 2):
        p, q = pts[n1], pts[n2]
        if np.linalg.norm(q - p) <= tol:
            continue
        w = force_wrench(q - p, p).vector
        if member_ok(w):
            choice = ("force", w)
            break
    if choice is None:
        # a force through a named point, along the actuated joint if possible
        # the null spaces on the normalised basis (dimensionless, the same decision in
        # every frame and unit; see screwkit.legs._decompose.NULL_RTOL)
        Nn = norm.wrenches(N)
        for p in pts.values():
            for c in _null(_through_matrix(Nn, (p - norm.centre) / norm.length)):
                w = c @ N
                if np.linalg.norm(w[:3]) > 0 and member_ok(w):
                    choice = ("force", w)
                    break
            if choice:
                break
    if choice is None:
        # a pure couple
        for c in _null(N[:, :3].T):
            w = c @ N
            if member_ok(w):
                choice = ("couple", w)
                break
    if choice is None:
        # least-norm wrench orthogonal (normalised) to the constraint system
        Nn = norm.wrenches(N)
        C = norm.wrenches(system.wrenches)
        Q = np.linalg.qr(C.T)[0].T if len(C) else np.zeros((0, 6))
        best = max(Nn, key=lambda v: abs(norm.wrenches_back(v) @ xi))
        best = best - (best @ Q.T) @ Q if len(Q) else best
        choice = ("screw", norm.wrenches_back(best))
    kind, w = choice
    f, m = w[:3], w[3:]
    if kind == "force":
        d = f / np.linalg.norm(f)
        p0 = cross(f, m) / (f @ f)
        nm, p = next(((n, q) for n, q in pts.items() if Line.through(p0, d).distance_to_point(q) <= tol),
                     (None, p0))
        unit_w = force_wrench(d, p).vector
        notes = explain_force(d, p, _passive_leg_view(leg, ia))
        member = ConstraintWrench("force", force_wrench(d, p), d, p, nm, 0.0, notes,
                                  reciprocity_residual(unit_w, Tp, norm))
    elif kind == "couple":
        d = m / np.linalg.norm(m)
        unit_w = couple_wrench(d).vector
        member = ConstraintWrench("couple", couple_wrench(d), d, None, None, float("inf"),
                                  explain_couple(d, _passive_leg_view(leg, ia)),
                                  reciprocity_residual(unit_w, Tp, norm))
    else:
        from ..screws import Wrench, screw_pitch
        unit_w = w / np.linalg.norm(f if np.linalg.norm(f) > 0 else m)
        member = ConstraintWrench("screw", Wrench(unit_w), unit_w[:3] / max(np.linalg.norm(unit_w[:3]), 1e-300),
                                  cross(f, m) / max(f @ f, 1e-300), None,
                                  float(screw_pitch(unit_w, "wrench")),
                                  (RuleNote("-", None, "no pure force or couple actuates this joint", True),),
                                  reciprocity_residual(unit_w, Tp, norm))
    k = 1.0 / float(unit_w @ xi)
    if kind == "force" and k < 0:
        # orient the line so that the actuator force is positive along it
        d = -member.direction
        member = ConstraintWrench("force", force_wrench(d, member.point), d, member.point,
                                  member.point_name, 0.0, member.rules, member.reciprocity)
        unit_w, k = -unit_w, -k
    return ActuationWrench(member, k * unit_w, k, leg.joints[ia].name)


def _passive_system(leg: "Leg", system: ReciprocalSystem):
    """``(xi, Tp, N, scale_ref)``: the actuated twist, the passive twists, the wrenches
    reciprocal to the passive joints (None when none of them works on the actuated
    joint: it depends on the passive ones) and the scale of the test."""
    norm = system.normalisation
    ia = leg.actuated_index
    T = leg.twists                         # rows are the joints' unit twists
    xi = T[ia]
    Tp = np.delete(T, ia, axis=0)
    N = reciprocal_system(Tp, leg.points, length=norm.length).wrenches
    prod = N @ xi
    scale_ref = np.linalg.norm(norm.twists(xi)) * norm.length
    if np.max(np.abs(prod), initial=0.0) <= 1e-9 * scale_ref:
        return xi, Tp, None, scale_ref
    return xi, Tp, N, scale_ref


def has_actuation_wrench(leg: "Leg", system: ReciprocalSystem | None = None) -> bool:
    """Whether :func:`actuation_wrench` finds a wrench (the actuated joint is independent
    of the passive ones), without choosing and explaining it."""
    system = system or reciprocal_system(leg.twists, leg.points)
    return _passive_system(leg, system)[2] is not None


class _PassiveView:
    """A leg-like view without the actuated joint, for rule explanations."""

    def __init__(self, leg: "Leg", skip: int):
        self.joints = tuple(j for i, j in enumerate(leg.joints) if i != skip)
        self.length = leg.length
        self.A, self.a = leg.A, leg.a
        self._leg = leg

    def centres(self):
        return self._leg.centres()


def _passive_leg_view(leg: "Leg", skip: int):
    return _PassiveView(leg, skip)
