"""The paper's three observation rules, applied to a numeric constraint system.

Rules (section 2.2 of the paper):

1. a constraint force is perpendicular to every prismatic joint;
2. a constraint force meets or is parallel to every revolute axis (and so
   passes through the centre of every spherical joint);
3. a constraint couple is perpendicular to every revolute axis.

:func:`~screwkit.legs.decompose` (:mod:`screwkit.legs._decompose`) finds a basis
of the constraint system made of pure couples and pure forces on lines (wherever
one exists) and leaves the rest as finite-pitch screws; :func:`explain_force` and :func:`explain_couple` check the
rules joint by joint *geometrically* (angles and distances, not reciprocal
products) and say which rule makes each joint do no work.
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from itertools import combinations

import numpy as np

from ..screws._frozen import freeze_fields
from ..screws import GEOMETRY_RTOL, Line, Wrench, force_wrench
from ..screws import cross

# ``leg`` arguments are :class:`screwkit.legs.Leg` objects, used by duck typing
# (``joints``, ``twists``, ``points``, ``A``, ``a``, ``length``, ``centres()``):
# the chain module is not imported, so that ``Leg.analyze`` can import this module
# without an import cycle.

__all__ = ["RuleNote", "ConstraintWrench", "explain_force", "explain_couple", "named_points",
           "candidate_points", "point_label"]


@dataclass(frozen=True)
class RuleNote:
    """Why one joint (or one S/U group) does no work against a wrench.

    Attributes
    ----------
    joint : str
        ``"R1"``, ``"S1"`` (a whole spherical joint) ...
    rule : int or None
        1, 2 or 3 (the paper's rules); None where no rule applies (helical
        joints, finite-pitch screws: checked by the reciprocal product only).
    text : str
    holds : bool
        Whether the geometric condition holds within tolerance.
    """

    joint: str
    rule: int | None
    text: str
    holds: bool

    def __str__(self):
        tag = f" (rule {self.rule})" if self.rule else ""
        return f"{self.text}{tag}" + ("" if self.holds else "  [FAILS]")


@dataclass(frozen=True)
class ConstraintWrench:
    """One member of a decomposed constraint (or actuation) system.

    Attributes
    ----------
    kind : str
        ``"force"``, ``"couple"`` or ``"screw"`` (finite pitch).
    wrench : Wrench
        Unit force (``|f| = 1``), unit couple (``|m| = 1``) or a screw with ``|f| = 1``.
    direction : ndarray (3,)
        Force or couple direction (unit).
    point : ndarray (3,) or None
        A point of the force line (a named point where one lies on it).
    point_name : str or None
    pitch : float
        0 for a force, ``inf`` for a couple.
    rules : tuple of RuleNote
    reciprocity : float
        Largest normalised ``|W . V| / (|W| |V|)`` over the joints it must not
        work against.
    """

    kind: str
    wrench: Wrench
    direction: np.ndarray
    point: np.ndarray | None
    point_name: str | None
    pitch: float
    rules: tuple
    reciprocity: float

    def __post_init__(self):
        freeze_fields(self, ("direction", "point"))

    @property
    def line(self) -> Line | None:
        return Line.through(self.point, self.direction) if self.kind == "force" else None

    @property
    def explained(self) -> bool:
        """True when every rule note holds."""
        return all(n.holds for n in self.rules)

    def describe(self) -> str:
        """One line: kind, line or direction."""
        d = _fmt(self.direction)
        if self.kind == "force":
            where = point_label(self.point_name) or _fmt(self.point)
            return f"force along {d} through {where}"
        if self.kind == "couple":
            return f"couple about {d}"
        return f"screw of pitch {self.pitch:.6g} along {d}"


def point_label(name: str | None) -> str | None:
    """Readable form of a named point: ``"R1^R5"`` -> ``"Q (where R1 meets R5)"``,
    ``"S1"`` -> ``"the centre of S1"``; other names unchanged."""
    if not name:
        return name
    if "^" in name:
        a, b = name.split("^", 1)
        return f"Q (where {a} meets {b})"
    if name[0] in "SU" and name[1:].isdigit():
        return f"the centre of {name}"
    return name


def _fmt(v) -> str:
    return "(" + ", ".join(f"{x:.6g}" for x in np.where(np.abs(v) < 5e-13, 0.0, v)) + ")"


def named_points(leg: "Leg") -> dict:
    """Points worth naming: S/U centres, then the end points ``A`` and ``a``."""
    out = dict(leg.centres())
    out.setdefault("A", leg.A)
    out.setdefault("a", leg.a)
    return out


def candidate_points(leg: "Leg", tol: float) -> dict:
    """Named points plus the meeting points of pairs of R axes (``R1^R5``)."""
    pts = named_points(leg)
    rs = [j for j in leg.joints if j.kind == "R"]
    for j1, j2 in combinations(rs, 2):
        if j1.spec.position == j2.spec.position or _surely_apart(j1, j2, tol):
            continue
        l1, l2 = j1.line, j2.line
        if l1.is_parallel(l2):
            continue
        x1, x2 = l1.closest_points(l2)
        if np.linalg.norm(x1 - x2) <= tol:
            pts.setdefault(f"{j1.name}^{j2.name}", 0.5 * (x1 + x2))
    for j in leg.joints:
        pts.setdefault(j.name, j.point)
    return pts


def _surely_apart(j1, j2, tol: float) -> bool:
    """Whether the axes of two joints are clearly neither parallel nor within ``tol`` of
    each other (their distance ``|(p2 - p1) . n| / |n|``, ``n = d1 x d2``, on floats):
    most pairs are, and skip the exact closest points.  Doubtful pairs (nearly parallel,
    or near the tolerance) get the exact test."""
    a0, a1, a2 = j1.direction.tolist()
    b0, b1, b2 = j2.direction.tolist()
    n0, n1, n2 = a1 * b2 - a2 * b1, a2 * b0 - a0 * b2, a0 * b1 - a1 * b0
    nn = math.sqrt(n0 * n0 + n1 * n1 + n2 * n2)
    if not nn > 1e-3:
        return False
    p0, p1, p2 = j1.point.tolist()
    q0, q1, q2 = j2.point.tolist()
    return abs((q0 - p0) * n0 + (q1 - p1) * n1 + (q2 - p2) * n2) / nn > 1.001 * tol


def _point_name(point, direction, pts: dict, tol: float):
    line = Line.through(point, direction)
    for name, p in pts.items():
        if line.distance_to_point(p) <= tol:
            return name, np.asarray(p, float)
    return None, None


def explain_force(direction, point, leg: "Leg", tol_angle: float = GEOMETRY_RTOL * 10,
                  tol_dist: float | None = None) -> tuple:
    """Check rules 1 and 2 for a force on the line (``point``, ``direction``), joint by joint.

    Returns
    -------
    tuple of RuleNote
    """
    line = Line.through(point, direction)
    d = line.direction
    L = max(leg.length, 1e-300)
    tol_dist = tol_angle * L if tol_dist is None else tol_dist
    pts = named_points(leg)
    notes = []
    done_groups = set()
    for j in leg.joints:
        sp = j.spec
        group = f"{sp.origin}{sp.position}"
        if sp.origin in "SU" and group not in done_groups:
            if line.distance_to_point(j.point) <= tol_dist:
                done_groups.add(group)
                what = "spherical" if sp.origin == "S" else "universal"
                notes.append(RuleNote(group, 2, f"passes through the centre of {group} "
                                                f"(the {what} joint's axes all meet it there)", True))
                continue
            if sp.origin == "S":
                done_groups.add(group)
                notes.append(RuleNote(group, 2, f"misses the centre of {group} by "
                                                f"{line.distance_to_point(j.point):.3g}", False))
                continue
        if group in done_groups:
            continue
        if j.kind == "P":
            c = float(np.dot(d, j.direction))
            notes.append(RuleNote(j.name, 1, f"perpendicular to {j.name}" if abs(c) <= tol_angle
                                  else f"not perpendicular to {j.name} (cos = {c:.3g})",
                                  abs(c) <= tol_angle))
        elif j.kind == "R":
            jl = j.line
            s = float(np.linalg.norm(cross(d, j.direction)))
            if s <= tol_angle:
                notes.append(RuleNote(j.name, 2, f"parallel to {j.name}", True))
                continue
            dist = line.distance_to_line(jl)
            if dist <= tol_dist:
                q = line.closest_points(jl)[0]
                nm = next((n for n, p in pts.items() if np.linalg.norm(q - p) <= tol_dist), None)
                at = nm if nm else _fmt(q)
                notes.append(RuleNote(j.name, 2, f"meets {j.name} at {at}", True))
            else:
                notes.append(RuleNote(j.name, 2, f"neither meets nor is parallel to {j.name} "
                                                 f"(distance {dist:.3g})", False))
        else:  # helical: no observation rule; the reciprocal product decides
            w = force_wrench(d, line.point).vector
            r = float(np.dot(w, j.twist.vector)) / L
            notes.append(RuleNote(j.name, None, f"reciprocal to helical {j.name} "
                                  f"(f.v + m.w = {r * L:.3g})", abs(r) <= tol_angle))
    return tuple(notes)


def explain_couple(direction, leg: "Leg", tol_angle: float = GEOMETRY_RTOL * 10) -> tuple:
    """Check rule 3 for a couple about ``direction``, joint by joint."""
    t = np.asarray(direction, float) / np.linalg.norm(direction)
    notes = []
    for j in leg.joints:
        if j.kind == "P":
            notes.append(RuleNote(j.name, None, f"does no work on {j.name} "
                                  "(a couple is reciprocal to every prismatic joint)", True))
            continue
        c = float(np.dot(t, j.direction))
        ok = abs(c) <= tol_angle
        notes.append(RuleNote(j.name, 3, f"perpendicular to {j.name}" if ok
                              else f"not perpendicular to {j.name} (cos = {c:.3g})", ok))
    return tuple(notes)
