"""A basis of a leg's constraint system made of pure forces on lines and pure couples.

:func:`decompose` finds, wherever one exists, a basis of the constraint system
made of pure couples and pure forces on lines, and leaves the rest as
finite-pitch screws; each member is explained by the observation rules
(:mod:`screwkit.legs._observation`).
"""

from __future__ import annotations

import math
from itertools import combinations

import numpy as np

from ..screws import (GEOMETRY_RTOL, RANK_RTOL, Normalisation, Wrench, couple_wrench, force_wrench,
                      screw_pitch)
from ._observation import (ConstraintWrench, RuleNote, _point_name, candidate_points, explain_couple,
                           explain_force)
from ..screws import cross
from ..screws._svd import decided_count, small_rank, small_singular_values, svd_full, svd_values

#: Relative tolerance of the null spaces the search takes its members from: the through-a-
#: point and parallel-to-a-direction conditions are written on the length-normalised basis
#: (``[f; (m - c x f) / L]``, orthonormal rows) and a singular value below ``NULL_RTOL *
#: max(1, s_max)`` counts as zero, so a decision is the same in every base frame and unit.
NULL_RTOL = RANK_RTOL / 10

#: Smallest force part, relative to the normalised wrench, of a member taken as a force
#: from the null space of a through-a-point condition (the couples are taken before).
THROUGH_FORCE_RTOL = NULL_RTOL

#: The same for a parallel-to-a-direction condition (whose null space also holds the
#: couples normal to the direction).
PARALLEL_FORCE_RTOL = 100 * RANK_RTOL

# ``leg`` arguments are :class:`screwkit.legs.Leg` objects, used by duck typing
# (``joints``, ``twists``, ``points``, ``A``, ``a``, ``length``, ``centres()``):
# the chain module is not imported, so that ``Leg.analyze`` can import this module
# without an import cycle.

__all__ = ["decompose", "constraint_kinds", "reciprocity_residual"]


def _rank(Mn, rtol=RANK_RTOL):
    if len(Mn) == 0:
        return 0
    Mn = np.asarray(Mn, float)
    r = small_rank(Mn.tolist(), rtol * 1e2)
    if r is None:
        s = svd_values(Mn)
        r = int(np.sum(s > rtol * 1e2 * max(1.0, s[0])))
    return r


def _null(M, rtol=NULL_RTOL):
    """The null vectors of ``M`` (a dimensionless matrix: see :data:`NULL_RTOL`)."""
    M = np.atleast_2d(M)
    _, s, Vt = svd_full(M)
    tol = rtol * max(1.0, s[0] if s.size else 1.0)
    r = int(np.sum(s > tol))
    return Vt[r:]


def _nulls(Ms, rtol=NULL_RTOL) -> list:
    """:func:`_null` of each matrix of a list of same-shape matrices, in one SVD call
    (numpy's stacked SVD runs the same LAPACK routine per matrix: the same bases)."""
    if not Ms:
        return []
    _, S, VT = svd_full(np.array(Ms, float))
    out = []
    for s, Vt in zip(S.tolist(), VT):
        tol = rtol * max(1.0, s[0] if s else 1.0)
        out.append(Vt[sum(x > tol for x in s):])
    return out


def _surely_empty(cols) -> bool:
    """Whether the null space that :func:`_null` finds for the matrix of columns ``cols``
    (one or two lists of floats) is surely empty: every singular value clearly above its
    threshold.  Most candidate lines fail this way; the others get the SVD."""
    s = small_singular_values(cols)
    return s is not None and decided_count(s, NULL_RTOL * max(1.0, s[0])) == len(cols)


def _through_rows(Fl, Ml, p) -> list:
    # the columns m - p x f of _through_matrix, on floats
    p0, p1, p2 = np.asarray(p, float).tolist()
    return [[m0 - (p1 * f2 - p2 * f1), m1 - (p2 * f0 - p0 * f2), m2 - (p0 * f1 - p1 * f0)]
            for (f0, f1, f2), (m0, m1, m2) in zip(Fl, Ml)]


def _parallel_rows(Fl, Ml, d) -> list:
    # the columns [d x f; d . m] of _parallel_matrix, on floats
    d0, d1, d2 = np.asarray(d, float).tolist()
    return [[d1 * f2 - d2 * f1, d2 * f0 - d0 * f2, d0 * f1 - d1 * f0, d0 * m0 + d1 * m1 + d2 * m2]
            for (f0, f1, f2), (m0, m1, m2) in zip(Fl, Ml)]


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


def _through_matrix(Wn, pn):
    """The condition ``m - p x f = 0`` (the force passes through ``p``) on the combinations
    of the normalised basis ``Wn``, with ``pn = (p - c) / L`` the normalised point: ``m - p
    x f = L (m_n - p_n x f)`` for ``m_n = (m - c x f) / L``, so the null space is the same
    and the matrix is dimensionless (its decisions do not depend on the frame or the unit)."""
    F, M = Wn[:, :3].T, Wn[:, 3:].T
    return M - _skew(pn) @ F


def _parallel_matrix(Wn, d):
    """The conditions ``d x f = 0, d . m = 0`` (zero-pitch wrenches with ``f`` along ``d``)
    on the combinations of the normalised basis ``Wn``: where ``f`` is along ``d``, ``d . m
    = L d . m_n`` (``d . (c x f) = 0``), so the null space is the same, dimensionless."""
    F, M = Wn[:, :3].T, Wn[:, 3:].T
    return np.vstack([_skew(d) @ F, d @ M])


def _pitch_quadratic(w1, w2):
    """``(a, b, c)``: the pitch condition of ``w1 + s w2`` is ``f.m = a s^2 + b s + c``."""
    f1, m1, f2, m2 = w1[:3], w1[3:], w2[:3], w2[3:]
    return float(f2 @ m2), float(f1 @ m2 + f2 @ m1), float(f1 @ m1)


def _zero_pitch_roots(w1, w2):
    """s such that w1 + s w2 has f.m = 0 (quadratic); returns real roots."""
    a, b, c = _pitch_quadratic(w1, w2)
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
    return _decompose(wrenches, leg, norm, seed, _make)


def constraint_kinds(wrenches, leg: "Leg", norm: Normalisation, seed: int = 0) -> tuple:
    """``tuple(c.kind for c in decompose(wrenches, leg, norm, seed))`` without building and
    explaining the members (the search is the same: building them does not steer it)."""
    return _decompose(wrenches, leg, norm, seed, lambda w, kind, *args: kind)


def _decompose(wrenches, leg, norm: Normalisation, seed: int, make) -> tuple:
    """:func:`decompose`, each member made by ``make(w, kind, leg, norm, tol_dist)``."""
    W = np.asarray(wrenches, float).reshape(-1, 6)
    k = len(W)
    if k == 0:
        return ()
    L = norm.length
    tol_dist = GEOMETRY_RTOL * 10 * max(leg.length, L)
    Wn = norm.wrenches(W)
    chosen: list[np.ndarray] = []          # normalised rows
    out: list = []
    # the null spaces below are taken on the normalised basis (its combinations are those of
    # W: the normalisation is linear), never on moments in the model's units about O
    Fl, Ml = Wn[:, :3].tolist(), Wn[:, 3:].tolist()
    centre = np.asarray(norm.centre, float)

    def try_add(w, kind):
        wn = norm.wrenches(w)
        wn = wn / np.linalg.norm(wn)
        if _rank(np.array(chosen + [wn])) == len(chosen) + 1:
            chosen.append(wn)
            out.append(make(w, kind, leg, norm, tol_dist))
            return True
        return False

    # 1. couples: f(c) = 0
    for c in _null(W[:, :3].T) if not _surely_empty(Fl) else []:
        w = c @ W
        if np.linalg.norm(w[3:]) > 0:
            try_add(w, "couple")
    # 2. forces on observable lines: through named / meeting points, parallel to axes
    pts = candidate_points(leg, tol_dist)

    def add_forces(nulls, rtol):
        # the wrenches of each candidate's null space that carry a force (|f| above rtol of
        # the normalised wrench), until k are chosen
        for c_x in nulls:
            if len(chosen) == k:
                return
            for c in c_x:
                w = c @ W
                if np.linalg.norm(w[:3]) > rtol * np.linalg.norm(norm.wrenches(w)):
                    try_add(w, "force")

    # the null spaces of every candidate point (then direction) in one SVD call each;
    # they do not depend on what is chosen, only the loops stop early
    if len(chosen) < k:
        pns = [(p - centre) / L for p in pts.values()]
        cand = [pn for pn in pns if not _surely_empty(_through_rows(Fl, Ml, pn))]
        add_forces(_nulls([_through_matrix(Wn, pn) for pn in cand]), THROUGH_FORCE_RTOL)
    if len(chosen) < k:
        cand = [d for d in _candidate_directions(leg)
                if not _surely_empty(_parallel_rows(Fl, Ml, d))]
        add_forces(_nulls([_parallel_matrix(Wn, d) for d in cand]), PARALLEL_FORCE_RTOL)
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
            w1, w2 = norm.wrenches_back(u1), norm.wrenches_back(u2)
            for s_ in _zero_pitch_roots(w1, w2):
                un = (u1 + s_ * u2) / np.sqrt(1 + s_ * s_)      # unit norm in normalised space
                w = norm.wrenches_back(un)
                fn = np.linalg.norm(un[:3])
                if fn > 1e-6 and abs(un[:3] @ un[3:]) <= 1e-9 * fn:
                    try_add(w, "force")
            if k == 2:
                # the lines span the whole 2-system, and the discriminant b^2 - 4ac of the
                # pitch quadratic is -4 det of the form f.m on it in an orthonormal basis:
                # the same for every line.  Clearly negative: no draw has a root, stop.
                a, b, c0 = _pitch_quadratic(w1, w2)
                if b * b - 4 * a * c0 < -1e-9 * (b * b + 4 * abs(a * c0)):
                    break
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


def _candidate_directions(leg) -> list:
    """Joint axes, then the unit common normals of pairs of non-parallel axes."""
    dirs = [j.direction for j in leg.joints]
    for (i, j) in combinations(range(len(leg.joints)), 2):
        c = cross(leg.joints[i].direction, leg.joints[j].direction)
        n = math.sqrt(c.dot(c))                  # == np.linalg.norm(c)
        if n > 1e-6:
            dirs.append(c / n)
    return dirs


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
    p0 = cross(f, m) / (f @ f)
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
