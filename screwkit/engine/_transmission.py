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
length-normalised rows (the conditioning of :mod:`~screwkit.engine._kernels._statics`).  Where that null space has
more than one dimension (the other rows have lost rank: ``J`` is singular) the index is 0;
where it is empty (a redundant constraint row, as the shared planar constraints of a
planar 3-RRR) the row's index is NaN and left out of the minimum; both decided at
:data:`~screwkit.engine._kernels._layout.RANK_RTOL`.  At a pose the engine flags singular
(``J`` rank-deficient), every twist reciprocal to all rows but one does no work on that
row, so every ``OTI`` and ``CTI`` is exactly 0 there; an actuation row the engine could not
form (a dependent actuator: an input singularity) has ``ITI`` 0.  Unreachable poses: NaN.
"""

from __future__ import annotations

import numpy as np

from ._frozen import kernel_array
from ._kernels._layout import (  # noqa: F401  (RANK_RTOL: named in the docstring)
    LEVERAGE_RTOL, LINE_WIDTH, LN_IN_D, LN_IN_Q, LN_OUT_D, LN_OUT_Q, LN_V, RANK_RTOL,
    TRANSLATION_RTOL)

__all__ = ["transmission_indices", "lines_indices", "leg_screws", "leg_lines",
           "power_coefficient", "TRANSLATION_RTOL", "LEVERAGE_RTOL"]


def _c(a, dtype=float):
    return np.ascontiguousarray(a, dtype)


def power_coefficient(W, V, p, couple):
    """``(zeta, arm)``: the power coefficient of wrenches on twists (module docstring).

    ``W``, ``V (..., 6)`` about one origin, ``p (..., 3)`` a point of each wrench axis in
    the same frame, ``couple (...)`` True for pure couples (broadcast together).  ``arm`` is
    the distance from ``p`` to the twist axis (NaN for translations and couples).  A zero
    wrench or twist gives 0.  Computed by the kernel the indices use
    (``_kernels/_indices.power_one``).
    """
    from ._kernels import kernels
    W, V, p = (np.asarray(x, float) for x in (W, V, p))
    couple = np.asarray(couple, bool)
    shape = np.broadcast_shapes(W.shape[:-1], V.shape[:-1], p.shape[:-1], couple.shape)
    flat = [_c(np.broadcast_to(x, shape + x.shape[-1:]).reshape(-1, x.shape[-1]))
            for x in (W, V, p)]
    cp = _c(np.broadcast_to(couple, shape).reshape(-1), np.int64)
    zeta, arm = np.empty(len(cp)), np.empty(len(cp))
    kernels().power_batch(*flat, cp, zeta, arm)
    return zeta.reshape(shape), arm.reshape(shape)


def transmission_indices(J, couple, act_rows, con_rows, V_in, in_line, out_line, row_leg,
                         centre, length, constraint_rank=None, workers=None):
    """The index arrays of N poses from plain arrays (the engine-independent core), by the
    compiled kernel ``_kernels/_indices.indices_range`` (``prange`` over poses).

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
    workers : int, optional
        Threads (default: up to the two cores for large batches).

    Returns
    -------
    iti, oti, input_arm, output_arm : ndarray (N, n_a)
    cti, constraint_arm : ndarray (N, k)
    redundant : ndarray (N, k) of bool
        Constraint rows whose removal leaves the rank of the constraint rows unchanged
        (their index is NaN).
    """
    lines, in_leg = _pack_lines(V_in, in_line, out_line)
    return lines_indices(J, couple, act_rows, con_rows, lines, in_leg, row_leg, centre, length,
                         constraint_rank, workers)


def _pack_lines(V_in, in_line, out_line):
    """``(lines (N, n + n_a, LINE_WIDTH), in_leg (n_a,))``: the arrays of
    :func:`transmission_indices` as the kernel reads them (each leg's platform side at its
    own index, each active row's actuated joint after the legs)."""
    out_q = np.asarray(out_line[0], float)
    N, n = out_q.shape[:2]
    V_in = np.asarray(V_in, float).reshape(N, -1, 6)
    na = V_in.shape[1]
    lines = np.zeros((N, n + na, LINE_WIDTH))
    lines[:, :n, LN_OUT_Q:LN_OUT_Q + 3] = out_q
    lines[:, :n, LN_OUT_D:LN_OUT_D + 3] = np.reshape(out_line[1], (N, n, 3))
    lines[:, n:, LN_V:LN_V + 6] = V_in
    lines[:, n:, LN_IN_Q:LN_IN_Q + 3] = np.reshape(in_line[0], (N, na, 3))
    lines[:, n:, LN_IN_D:LN_IN_D + 3] = np.reshape(in_line[1], (N, na, 3))
    return lines, np.arange(n, n + na)


def lines_indices(J, couple, act_rows, con_rows, lines, in_leg, row_leg, centre, length,
                  constraint_rank=None, workers=None):
    """:func:`transmission_indices` from the joints' lines as the analysis kernel forms them
    (:func:`leg_lines`), read in place: ``lines (N, l, LINE_WIDTH)`` with the platform side
    of leg ``i`` at ``lines[:, i]`` and the actuated joint of the ``r``-th actuation row at
    ``lines[:, in_leg[r]]``."""
    from ._kernels import kernels
    from ._launch import _launch
    J = kernel_array(J)                 # (a result's read-only J: the same kernel)
    N = J.shape[0]
    act, con = [int(k) for k in act_rows], [int(k) for k in con_rows]
    na, kc = len(act), len(con)
    crank = (np.full(N, -1, np.int64) if constraint_rank is None
             else _c(np.broadcast_to(constraint_rank, (N,)), np.int64))
    out = (np.empty((N, na)), np.empty((N, na)), np.empty((N, na)), np.empty((N, na)),
           np.empty((N, kc)), np.empty((N, kc)), np.zeros((N, kc), bool))
    iti, oti, in_arm, out_arm, cti, c_arm, red = out
    k = kernels()
    args = (J, _c(couple, np.int64), _c(act + con, np.int64), na, _c(lines),
            _c(in_leg, np.int64), _c(row_leg, np.int64), kernel_array(centre),
            kernel_array(length), crank, iti,
            oti, in_arm, out_arm, cti, c_arm, red)
    _launch(k.indices_range, k.indices_parallel, args, N, workers)
    if not _all_finite(J):                  # (a sum is finite only if every term is)
        bad_row = ~np.all(np.isfinite(J[:, act]), axis=-1)
        iti[bad_row] = 0.0
    return iti, oti, in_arm, out_arm, cti, c_arm, red


def _all_finite(a) -> bool:
    """Whether every entry of ``a`` is finite: its sum is finite only then (or where it
    overflows: then the entries are checked one by one)."""
    with np.errstate(over="ignore", invalid="ignore"):
        if np.isfinite(np.sum(a)):
            return True
    return bool(np.isfinite(a).all())


def leg_screws(solution, active, lines=None, platform=None):
    """``(V_in (N, n_a, 6), in_line, out_line)`` of :func:`transmission_indices` at the poses
    of a :class:`~screwkit.engine.PoseSolution`: the actuated joint's unit twist of each
    active leg (``active``: 0-based legs), the joint through which its transmission wrench
    enters the actuated link, and each leg's last non-prismatic joint (its platform side);
    :func:`leg_lines` taken apart."""
    lines, in_leg = leg_lines(solution, active, lines, platform)
    n = solution.model.n_legs

    def part(legs, a, b):
        return np.ascontiguousarray(lines[:, legs, a:b])
    return (part(in_leg, LN_V, LN_V + 6),
            (part(in_leg, LN_IN_Q, LN_IN_Q + 3), part(in_leg, LN_IN_D, LN_IN_D + 3)),
            (part(slice(0, n), LN_OUT_Q, LN_OUT_Q + 3), part(slice(0, n), LN_OUT_D, LN_OUT_D + 3)))


def leg_lines(solution, active, lines=None, platform=None):
    """``(lines (N, l, LINE_WIDTH), in_leg (n_a,))`` of :func:`lines_indices` at the poses of
    a :class:`~screwkit.engine.PoseSolution` (``active``: the 0-based active legs): the
    analysis kernel's lines of the joints the indices read ``lines (N, n, LINE_WIDTH)`` and
    platform ``platform (N, 27)`` (kept by the analysis run, else formed by
    :func:`~screwkit.engine._links.index_lines`; the platform is kept by the solution), as
    they are where every leg turns after its actuator.  A leg with no turning joint enters
    the platform at its platform point ``a_i`` (direction 0), and one with none after its
    actuator enters the actuated link as it enters the platform: those entries are written
    into a copy.  Legs with a parallelogram (which the kernel's frames do not cover) are
    placed pose by pose."""
    from ._links import index_lines, keep_platform, reached_platform
    ch = solution.closures.chains
    if ch.bars is not None and ch.bars.any():
        return _pack_lines(*_placed_leg_screws(solution, active))
    if lines is None:
        lines, platform = index_lines(solution)
    keep_platform(solution, reached_platform(solution, platform))
    rot = np.asarray(ch.rotation, float)                  # (n, m)
    n = rot.shape[0]

    def turns(i, slots):
        return any(rot[i, j] != 0 for j in slots)

    act = list(active)
    no_out = [i for i in range(n) if not turns(i, range(ch.sizes[i]))]
    no_in = [i for i in act if not turns(i, range(int(ch.actuated[i]) + 1, ch.sizes[i]))]
    if no_out or no_in:
        lines = np.array(lines)
        for i in no_out:                   # no turning joint: the platform point a_i
            lines[:, i, LN_OUT_Q:LN_OUT_Q + 3] = solution._platform[2][:, i]
            lines[:, i, LN_OUT_D:LN_OUT_D + 3] = 0.0
        for i in no_in:                    # none after the actuator
            lines[:, i, LN_IN_Q:LN_IN_Q + 3] = lines[:, i, LN_OUT_Q:LN_OUT_Q + 3]
            lines[:, i, LN_IN_D:LN_IN_D + 3] = lines[:, i, LN_OUT_D:LN_OUT_D + 3]
    return lines, np.array(act, np.int64)


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
