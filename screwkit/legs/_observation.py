"""The paper's three observation rules, applied to a numeric constraint system.

Rules (section 2.2 of the paper):

1. a constraint force is perpendicular to every prismatic joint;
2. a constraint force meets or is parallel to every revolute axis (and so
   passes through the centre of every spherical joint);
3. a constraint couple is perpendicular to every revolute axis.

:func:`decompose` finds a basis of the constraint system made of pure couples
and pure forces on lines (wherever one exists) and leaves the rest as
finite-pitch screws; :func:`explain_force` and :func:`explain_couple` check the
rules joint by joint *geometrically* (angles and distances, not reciprocal
products) and say which rule makes each joint do no work.
"""

from __future__ import annotations

from dataclasses import dataclass
from itertools import combinations

import numpy as np

from ..screws import (GEOMETRY_RTOL, Line, Normalisation, RANK_RTOL, Wrench, couple_wrench,
                      force_wrench, screw_pitch)

# ``leg`` arguments are :class:`screwkit.legs.Leg` objects, used by duck typing
# (``joints``, ``twists``, ``points``, ``A``, ``a``, ``length``, ``centres()``):
# the chain module is not imported, so that ``Leg.analyze`` can import this module
# without an import cycle.

__all__ = ["RuleNote", "ConstraintWrench", "decompose", "explain_force", "explain_couple",
           "named_points", "candidate_points", "reciprocity_residual", "point_label"]


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
        if j1.spec.position == j2.spec.position:
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
            s = float(np.linalg.norm(np.cross(d, j.direction)))
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


def _rank(Mn, rtol=RANK_RTOL):
    if len(Mn) == 0:
        return 0
    s = np.linalg.svd(np.asarray(Mn), compute_uv=False)
    return int(np.sum(s > rtol * 1e2 * max(1.0, s[0])))


def _null(M, rtol=1e-9):
    M = np.atleast_2d(M)
    _, s, Vt = np.linalg.svd(M, full_matrices=True)
    tol = rtol * max(1.0, s[0] if s.size else 1.0)
    r = int(np.sum(s > tol))
    return Vt[r:]


def _skew(p):
    return np.array([[0, -p[2], p[1]], [p[2], 0, -p[0]], [-p[1], p[0], 0]])


def _unit_wrench(w):
    f, m = w[:3], w[3:]
    nf = np.linalg.norm(f)
    return w / nf if nf > 0 else w / np.linalg.norm(m)


def reciprocity_residual(w, twists, norm: Normalisation) -> float:
    """Largest ``|W . V| / (|W| |V|)`` in normalised coordinates over the rows of ``twists``.

    Unit-free (invariant under a change of frame and of length units); 0 for
    an empty set of twists.
    """
    T = np.asarray(twists, float).reshape(-1, 6)
    if len(T) == 0:
        return 0.0
    Wn = norm.wrenches(w)
    Tn = norm.twists(T)
    num = np.abs(Tn @ Wn)
    den = np.linalg.norm(Tn, axis=1) * np.linalg.norm(Wn)
    return float(np.max(num / den))


def _forces_through(Wbasis, p):
    """Coefficients of forces through point p in span(Wbasis): m - p x f = 0."""
    F, M = Wbasis[:, :3].T, Wbasis[:, 3:].T
    return _null(M - _skew(p) @ F)


def _forces_parallel(Wbasis, d):
    """Coefficients of zero-pitch wrenches with f parallel to d: d x f = 0, d . m = 0."""
    F, M = Wbasis[:, :3].T, Wbasis[:, 3:].T
    return _null(np.vstack([_skew(d) @ F, d @ M]))


def _zero_pitch_roots(w1, w2):
    """s such that w1 + s w2 has f.m = 0 (quadratic); returns real roots."""
    f1, m1, f2, m2 = w1[:3], w1[3:], w2[:3], w2[3:]
    a = float(f2 @ m2)
    b = float(f1 @ m2 + f2 @ m1)
    c = float(f1 @ m1)
    if abs(a) < 1e-15 * max(1.0, abs(b), abs(c)):
        return [-c / b] if abs(b) > 1e-15 else []
    disc = b * b - 4 * a * c
    if disc < 0:
        return []
    r = np.sqrt(disc)
    return [(-b + r) / (2 * a), (-b - r) / (2 * a)]


def decompose(wrenches, leg: "Leg", norm: Normalisation, seed: int = 0) -> tuple:
    """Decompose a wrench system into pure couples, pure forces and finite-pitch screws.

    Parameters
    ----------
    wrenches : ndarray, shape (k, 6)
        A basis of the system (physical units).
    leg : Leg
        Used for candidate lines and for the explanations.
    norm : Normalisation
        The normalisation used for rank decisions.
    seed : int
        Seed of the randomised search used only when no observable line is found.

    Returns
    -------
    tuple of ConstraintWrench
        Couples first, then forces, then screws; together they span the system.
    """
    W = np.asarray(wrenches, float).reshape(-1, 6)
    k = len(W)
    if k == 0:
        return ()
    L = norm.length
    tol_dist = GEOMETRY_RTOL * 10 * max(leg.length, L)
    Wn = norm.wrenches(W)
    chosen: list[np.ndarray] = []          # normalised rows
    out: list[ConstraintWrench] = []

    def try_add(w, kind):
        wn = norm.wrenches(w)
        wn = wn / np.linalg.norm(wn)
        if _rank(np.array(chosen + [wn])) == len(chosen) + 1:
            chosen.append(wn)
            out.append(_make(w, kind, leg, norm, tol_dist))
            return True
        return False

    # 1. couples: f(c) = 0
    for c in _null(W[:, :3].T) if k else []:
        w = c @ W
        if np.linalg.norm(w[3:]) > 0:
            try_add(w, "couple")
    # 2. forces on observable lines: through named / meeting points, parallel to axes
    pts = candidate_points(leg, tol_dist)
    dirs = [j.direction for j in leg.joints]
    for (i, j) in combinations(range(len(leg.joints)), 2):
        c = np.cross(leg.joints[i].direction, leg.joints[j].direction)
        if np.linalg.norm(c) > 1e-6:
            dirs.append(c / np.linalg.norm(c))
    for p in pts.values():
        if len(chosen) == k:
            break
        for c in _forces_through(W, p):
            w = c @ W
            if np.linalg.norm(w[:3]) > 1e-9 * np.linalg.norm(norm.wrenches(w)):
                try_add(w, "force")
    for d in dirs:
        if len(chosen) == k:
            break
        for c in _forces_parallel(W, d):
            w = c @ W
            if np.linalg.norm(w[:3]) > 1e-6 * np.linalg.norm(norm.wrenches(w)):
                try_add(w, "force")
    # 3. randomised search on the zero-pitch quadric f.m = 0 of the system: along random
    #    lines w1 + s w2 of the (normalised, orthonormal) basis, so no combination vanishes
    if k >= 2 and len(chosen) < k:
        rng = np.random.default_rng(seed)
        Wn_basis = np.linalg.qr(Wn.T)[0].T            # orthonormal rows spanning the system
        for _ in range(200):
            if len(chosen) == k:
                break
            c = np.linalg.qr(rng.standard_normal((k, 2)))[0].T   # two orthonormal coefficient rows
            u1, u2 = c @ Wn_basis
            for s_ in _zero_pitch_roots(norm.wrenches_back(u1), norm.wrenches_back(u2)):
                un = (u1 + s_ * u2) / np.sqrt(1 + s_ * s_)      # unit norm in normalised space
                w = norm.wrenches_back(un)
                fn = np.linalg.norm(un[:3])
                if fn > 1e-6 and abs(un[:3] @ un[3:]) <= 1e-9 * fn:
                    try_add(w, "force")
    elif k == 1 and len(chosen) == 0:
        un = Wn[0] / np.linalg.norm(Wn[0])
        fn = np.linalg.norm(un[:3])
        if fn > 1e-6 and abs(un[:3] @ un[3:]) <= 1e-9 * fn:
            try_add(W[0], "force")
    # 4. what is left: finite-pitch screws orthogonal (normalised) to the chosen ones
    if len(chosen) < k:
        Q = np.array(chosen).reshape(-1, 6)
        rest = Wn - (Wn @ Q.T) @ Q if len(Q) else Wn.copy()
        U, s, Vt = np.linalg.svd(rest)
        for v in Vt[: k - len(chosen)]:
            try_add(norm.wrenches_back(v), "screw")
    return tuple(out)


def _orientation_sign(d, leg) -> float:
    """+1 or -1 so that ``sign * d`` points along the leg line (A -> a) or, when ``d`` is
    perpendicular to it, along the first joint axis (chain order) it is not perpendicular to.

    The sign of a constraint wrench is a convention; this one depends only on the leg's own
    geometry, so reported values do not change with the base frame or the units.
    """
    refs = [leg.a - leg.A] + [j.direction for j in leg.joints]
    for r in refs:
        r = np.asarray(r, float)
        c = float(np.dot(d, r)) / max(np.linalg.norm(r), 1e-300)
        if abs(c) > 1e-6:
            return 1.0 if c > 0 else -1.0
    return 1.0


def _make(w, kind, leg: "Leg", norm: Normalisation, tol_dist) -> ConstraintWrench:
    w = _unit_wrench(np.asarray(w, float))
    part = w[3:] if kind == "couple" else w[:3]
    w = w * _orientation_sign(part / np.linalg.norm(part), leg)
    f, m = w[:3], w[3:]
    if kind == "couple":
        d = m / np.linalg.norm(m)
        wr = couple_wrench(d)
        return ConstraintWrench("couple", wr, d, None, None, float("inf"), explain_couple(d, leg),
                                reciprocity_residual(wr.vector, leg.twists, norm))
    d = f / np.linalg.norm(f)
    p0 = np.cross(f, m) / (f @ f)
    if kind == "force":
        # name a point of the line where one is known
        name, p = _point_name(p0, d, candidate_points(leg, tol_dist), tol_dist)
        if p is None:
            c = leg.points.mean(axis=0)
            p = p0 + np.dot(c - p0, d) * d
        wr = force_wrench(d, p)
        return ConstraintWrench("force", wr, d, p, name, 0.0, explain_force(d, p, leg),
                                reciprocity_residual(wr.vector, leg.twists, norm))
    wr = Wrench(w)
    pitch = float(screw_pitch(w, "wrench"))
    return ConstraintWrench("screw", wr, d, p0, None, pitch,
                            (RuleNote("-", None, "finite-pitch wrench: no observation rule "
                                      "applies; reciprocity checked numerically", True),),
                            reciprocity_residual(w, leg.twists, norm))
