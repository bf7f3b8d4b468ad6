"""Motion/force transmission and constraint indices of N poses (private; ``docs/design.md``).

The indices of Wang, Wu and Liu (2010) and Liu, Wu and Wang (2012), computed from the
engine's own screws: the rows of ``J = [J_a; J_c]`` (the transmission wrenches of the active
legs, the constraint wrenches) and each active leg's actuated-joint unit twist.

**Power coefficient.**  For a wrench ``W = [f; m_O]`` (pitch ``lambda``) acting on a body
through the point ``p`` of its axis, and a twist ``V = [v_O; w]`` of that body,

    zeta = |W . V| / (|f| |u|),   u = v(p) + lambda w,   v(p) = v_O + w x p

(``W . V = f . u``).  With ``V`` of pitch ``h`` and ``d`` the distance from ``p`` to the
twist axis, ``|u| / |w| = sqrt((lambda + h)^2 + d^2)``: Wang et al.'s
``|W . V| / |W . V|_max`` with the *potential maximal* moment arm ``d_max = d``, the arm the
wrench would have through ``p`` perpendicular to the twist axis.  For a translation ``V``
(``w = 0``) it is ``|cos|`` of the angle between ``f`` and ``v``; for a couple row
``[0; c]`` it is ``|c . w| / (|c| |w|)``.  Each is in [0, 1], unit-free and independent
of the base frame, and 0 exactly when the wrench does no work on the twist.

**Where a wrench acts.**  A leg's wrench is reciprocal to the leg's joints after the body
it drives, so its axis meets the axis of the joint through which it enters that body: the
point ``p`` is the point of the wrench axis nearest the axis of that joint (its own point
where the two are parallel).  For the input index the body is the actuated link, entered
through the next non-prismatic joint of the leg (the elbow of a planar R-R-R, the S centre
of an R-S-R); for the output and constraint indices it is the platform, entered through
the leg's last non-prismatic joint.  A leg without such a joint uses its platform point
``a_i``.  These are the characteristic lengths: every arm ``d`` is the distance from such a
model point to a twist axis at the pose (``*_arm``, model lengths; NaN for translations
and couples).

**The indices.**  Per active leg ``i`` (an actuation row of ``J``; a passive leg has none):

* ``ITI_i`` (input): the transmission wrench ``W_i`` on the actuated joint's unit twist;
* ``OTI_i`` (output): ``W_i`` on the platform twist ``V_i`` reciprocal to every other row of
  ``J`` (the other actuators locked, the constraints acting);
* ``LTI = min_i min(ITI_i, OTI_i)`` (local transmission index);
* per constraint row ``c``: ``CTI_c``, the row on the twist reciprocal to every other row
  (all actuators locked, that constraint removed); ``CTI = min_c CTI_c``.

The twist reciprocal to the other rows is their null space, found by an SVD of the
length-normalised rows (:mod:`~screwkit.engine._conditioning`).  Where that null space has
more than one dimension (the other rows have lost rank: ``J`` is singular) the index is 0;
where it is empty (a redundant constraint row, as the shared planar constraints of a
planar 3-RRR) the row's index is NaN and left out of the minimum; both decided at
:data:`~screwkit.engine._conditioning.RANK_RTOL`.  At a pose the engine flags singular
(``J`` rank-deficient), every twist reciprocal to all rows but one does no work on that
row, so every ``OTI`` and ``CTI`` is exactly 0 there; an actuation row the engine could not
form (a dependent actuator: an input singularity) has ``ITI`` 0.  Unreachable poses: NaN.
"""

from __future__ import annotations

import numpy as np

from ._conditioning import RANK_RTOL
from ..screws import cross

__all__ = ["transmission_indices", "leg_screws", "power_coefficient", "TRANSLATION_RTOL",
           "LEVERAGE_RTOL"]

#: Below this ``|w| L / |V|`` a twist counts as a translation (no axis, no arm).
TRANSLATION_RTOL = 1e-12


def power_coefficient(W, V, p, couple):
    """``(zeta, arm)``: the power coefficient of wrenches on twists (module docstring).

    ``W``, ``V (..., 6)`` about one origin, ``p (..., 3)`` a point of each wrench axis in
    the same frame, ``couple (...)`` True for pure couples.  ``arm`` is the distance from
    ``p`` to the twist axis (NaN for translations and couples).  A zero wrench or twist
    gives 0.
    """
    f, m = W[..., :3], W[..., 3:]
    v, w = V[..., :3], V[..., 3:]
    ff = np.sum(f * f, axis=-1)
    lam = np.sum(f * m, axis=-1) / np.where(ff > 0, ff, 1.0)
    vp = v + cross(w, p)
    u = vp + lam[..., None] * w
    num = np.abs(np.sum(f * u, axis=-1))
    den = np.sqrt(ff * np.sum(u * u, axis=-1))
    cm = np.sqrt(np.sum(m * m, axis=-1))
    ww = np.sqrt(np.sum(w * w, axis=-1))
    num = np.where(couple, np.abs(np.sum(m * w, axis=-1)), num)
    den = np.where(couple, cm * ww, den)
    zeta = np.where(den > 0, num / np.where(den > 0, den, 1.0), 0.0)
    rot = ww > TRANSLATION_RTOL * np.sqrt(np.sum(V * V, axis=-1))
    what = np.where(rot, ww, 1.0)
    wh = w / what[..., None]
    perp = vp - np.sum(vp * wh, axis=-1)[..., None] * wh
    arm = np.where(rot & ~couple, np.sqrt(np.sum(perp * perp, axis=-1)) / what, np.nan)
    return np.minimum(zeta, 1.0), arm


def _entry_point(W, q, d):
    """The point of each wrench axis nearest the line ``q + s d`` (its point nearest ``q``
    where the two are parallel or ``d`` is 0); ``W (..., 6)``."""
    f, m = W[..., :3], W[..., 3:]
    ff = np.sum(f * f, axis=-1, keepdims=True)
    ff = np.where(ff > 0, ff, 1.0)
    p0 = cross(f, m) / ff
    u = f / np.sqrt(ff)
    dn = np.sqrt(np.sum(d * d, axis=-1, keepdims=True))
    dh = d / np.where(dn > 0, dn, 1.0)
    w0 = p0 - q
    b = np.sum(u * dh, axis=-1, keepdims=True)
    dd, e = np.sum(u * w0, axis=-1, keepdims=True), np.sum(dh * w0, axis=-1, keepdims=True)
    den = 1.0 - b * b
    skew = den > 1e-12
    t = np.where(skew, (b * e - dd) / np.where(skew, den, 1.0), -dd)
    return p0 + t * u


#: A row whose leverage in its rows' range is below ``1 - LEVERAGE_RTOL`` is redundant: the
#: other rows keep the rank without it (their smallest singular value stays above about
#: ``1e-4`` of the largest).
LEVERAGE_RTOL = 1e-8


def _leverage(U, s):
    """Each row's leverage ``sum_j U[k, j]^2`` over the directions of rank (``s`` above
    :data:`~screwkit.engine._conditioning.RANK_RTOL` of the largest): 1 where the row is
    needed for the rank, below 1 where the other rows span it."""
    live = s > RANK_RTOL * np.maximum(s[..., :1], 1e-300)
    return np.sum(U * U * live[:, None, :], axis=-1)


def _null_twists(Wu):
    """For each row ``k`` of ``Wu (N, K, 6)`` (unit, normalised rows of a regular ``J``): the
    twist (normalised coordinates, unit) reciprocal to every other row, the column ``k`` of
    the pseudo-inverse, and whether the row is redundant (no such twist: the other rows
    have the rank without it).  Singular poses are the caller's."""
    N, K = Wu.shape[:2]
    if K < 6:                       # never regular: every twist set is larger than a line
        return np.zeros((N, K, 6)), np.zeros((N, K), bool)
    if K == 6:                      # square: the columns of the inverse, no row redundant
        try:
            V = np.linalg.inv(Wu).transpose(0, 2, 1)
        except np.linalg.LinAlgError:                       # an exactly singular pose
            pass
        else:
            V /= np.maximum(np.linalg.norm(V, axis=-1, keepdims=True), 1e-300)
            return V, np.zeros((N, K), bool)
    U, s, Vt = np.linalg.svd(Wu, full_matrices=False)      # (N, K, 6), (N, 6), (N, 6, 6)
    inv = 1.0 / np.maximum(s, 1e-300 * np.maximum(s[:, :1], 1e-300))
    V = np.einsum("nji,nj,nkj->nki", Vt, inv, U)
    V /= np.maximum(np.linalg.norm(V, axis=-1, keepdims=True), 1e-300)
    return V, 1.0 - _leverage(U, s) > LEVERAGE_RTOL


def _redundant(Wu, rank=None):
    """``(N, k)``: True where removing the row leaves the rank of the rows ``Wu (N, k, 6)``
    unchanged (a redundant row, decided by its leverage); ``rank (N,)``, optional: the
    rank of the rows where known (all ``k``: none is redundant)."""
    N, k = Wu.shape[:2]
    if k < 2 or (rank is not None and np.all(np.asarray(rank) >= k)):
        return np.zeros((N, k), bool)
    U, s, _ = np.linalg.svd(Wu, full_matrices=False)
    return 1.0 - _leverage(U, s) > LEVERAGE_RTOL


def transmission_indices(J, couple, act_rows, con_rows, V_in, in_line, out_line, row_leg,
                         centre, length, constraint_rank=None):
    """The index arrays of N poses from plain arrays (the engine-independent core).

    Parameters
    ----------
    J : ndarray (N, m, 6)
        Rows ``[f; m]`` about O.
    couple : ndarray (m,) of bool
        Pure-couple rows.
    act_rows, con_rows : sequence of int
        The actuation rows of the active legs and the constraint rows.
    V_in : ndarray (N, n_a, 6)
        Each active leg's actuated-joint unit twist (about O), in ``act_rows`` order.
    in_line : (ndarray (N, n_a, 3), ndarray (N, n_a, 3))
        Point and direction of the joint through which each transmission wrench enters the
        actuated link (direction 0: a point).
    out_line : (ndarray (N, n, 3), ndarray (N, n, 3))
        The same for the platform, per leg (all legs).
    row_leg : ndarray (m,) of int
    centre, length : ndarray (N, 3), (N,)
        The normalisation of the poses (centroid, characteristic length).
    constraint_rank : ndarray (N,), optional
        The rank of the constraint rows where known (it spares the redundancy test).

    Returns
    -------
    iti, oti, input_arm, output_arm : ndarray (N, n_a)
    cti, constraint_arm : ndarray (N, k)
    redundant : ndarray (N, k) of bool
        Constraint rows whose removal leaves the rank of the constraint rows unchanged
        (their index is NaN).
    """
    J = np.asarray(J, float)
    act, con = list(act_rows), list(con_rows)
    keep = act + con
    c, L = np.asarray(centre, float), np.asarray(length, float)
    Lc = L[:, None, None]
    # normalised coordinates: wrenches [f; m_c / L], twists [v_c; L w], points (x - c) / L
    f = J[..., :3]
    Wn = np.concatenate([f, (J[..., 3:] - cross(c[:, None, :], f)) / Lc], axis=-1)
    size = np.linalg.norm(Wn, axis=-1, keepdims=True)
    Wu = Wn / np.where(size > 0, size, 1.0)
    Vn, none = _null_twists(Wu[:, keep])

    def to_norm(x):
        return (x - c[:, None, :]) / Lc

    W_keep = Wn[:, keep]
    cpl = np.asarray(couple, bool)[keep]
    legs = np.asarray(row_leg, int)[keep]
    q_out, d_out = (np.asarray(a, float) for a in out_line)
    p = _entry_point(W_keep, to_norm(q_out[:, legs]), d_out[:, legs])
    zeta, arm = power_coefficient(W_keep, Vn, p, cpl[None, :])
    na = len(act)
    redundant = _redundant(Wu[:, con], constraint_rank)
    none[:, na:] |= redundant
    zeta = np.where(none, np.nan, zeta)
    arm = np.where(none, np.nan, arm * L[:, None])
    # input: the transmission wrench on the actuated joint's unit twist
    V_in = np.asarray(V_in, float)
    v, w = V_in[..., :3], V_in[..., 3:]
    Vin_n = np.concatenate([v + cross(w, c[:, None, :]), w * Lc], axis=-1)
    q_in, d_in = (np.asarray(a, float) for a in in_line)
    Wa = W_keep[:, :na]
    p_in = _entry_point(Wa, to_norm(q_in), d_in)
    iti, in_arm = power_coefficient(Wa, Vin_n, p_in, cpl[None, :na])
    bad_row = ~np.all(np.isfinite(J[:, act]), axis=-1)
    iti = np.where(bad_row, 0.0, iti)
    return (iti, zeta[:, :na], in_arm * L[:, None], arm[:, :na], zeta[:, na:], arm[:, na:],
            redundant)


def leg_screws(solution, active):
    """``(V_in (N, n_a, 6), in_line, out_line)`` of :func:`transmission_indices` at the poses
    of a :class:`~screwkit.engine.PoseSolution`: the actuated joint's unit twist of each
    active leg (``active``: 0-based legs), the joint through which its transmission wrench
    enters the actuated link, and each leg's last non-prismatic joint (its platform side),
    from the engine's link frames (:func:`~screwkit.engine.link_frames`), or, for legs with
    a parallelogram (which the link frames do not cover), from the legs placed pose by pose."""
    from ._links import link_frames
    ch = solution.closures.chains
    if ch.bars is not None and ch.bars.any():
        return _placed_leg_screws(solution, active)
    lf = link_frames(solution)
    N = lf.N
    rot = np.asarray(lf.rotation, float)                  # (n, m)
    n = rot.shape[0]
    a = np.asarray(solution._platform[2], float)         # (N, n, 3)

    def line(i, slot):
        if slot is None:
            return a[:, i], np.zeros((N, 3))
        return lf.points[slot, :, i].T, lf.twists[slot, 3:, i].T

    def non_prismatic(i, slots):
        return next((j for j in slots if rot[i, j] != 0), None)

    out_q, out_d = np.empty((N, n, 3)), np.empty((N, n, 3))
    for i in range(n):
        out_q[:, i], out_d[:, i] = line(i, non_prismatic(i, range(lf.sizes[i] - 1, -1, -1)))
    V_in = np.empty((N, len(active), 6))
    in_q, in_d = np.empty((N, len(active), 3)), np.empty((N, len(active), 3))
    for k, i in enumerate(active):
        j = int(lf.actuated[i])
        V_in[:, k] = lf.twists[j, :, i].T
        nxt = non_prismatic(i, range(j + 1, lf.sizes[i]))
        in_q[:, k], in_d[:, k] = line(i, nxt) if nxt is not None else (out_q[:, i], out_d[:, i])
    return V_in, (in_q, in_d), (out_q, out_d)


def _placed_leg_screws(solution, active):
    """:func:`leg_screws` from the placed legs of each pose (``PoseSolution.legs_at``: the
    joints' unit twists, a parallelogram's a translation); unreachable poses NaN."""
    N = len(solution.reachable_mask)
    n = solution.model.n_legs
    V_in = np.full((N, len(active), 6), np.nan)
    in_q, in_d = np.full((N, len(active), 3), np.nan), np.zeros((N, len(active), 3))
    out_q, out_d = np.full((N, n, 3), np.nan), np.zeros((N, n, 3))
    reach = np.asarray(solution.reachable_mask, bool)
    for p in np.flatnonzero(reach):
        legs = solution.legs_at(int(p))
        for i, lg in enumerate(legs):
            T = np.asarray(lg.twists, float)                     # (m, 6) about O
            turns = [j for j in range(len(T)) if np.any(T[j, 3:] != 0)]
            last = turns[-1] if turns else None
            out_q[p, i], out_d[p, i] = ((lg.joints[last].point, T[last, 3:]) if last is not None
                                        else (lg.a, np.zeros(3)))
            if i in active:
                k = list(active).index(i)
                j = lg.actuated_index
                V_in[p, k] = T[j]
                nxt = next((t for t in turns if t > j), None)
                in_q[p, k], in_d[p, k] = ((lg.joints[nxt].point, T[nxt, 3:]) if nxt is not None
                                          else (out_q[p, i], out_d[p, i]))
    return V_in, (in_q, in_d), (out_q, out_d)
