"""The levels of a path, compiled (private): each level's starts, interpolated from the
solved samples around it, and the check of its solutions against them.

:func:`screwkit.engine._path.solve_path` solves a path's samples level by level, halving the
spacing: the sample in the middle of each gap between two solved ones starts from the cubic
through the two solved samples on each side (where all four converged), else from the linear
interpolation of its two neighbours, or the one that converged.  After the level's solve, a
sample whose solution moved from its start by more than half its neighbours' difference has
jumped to another branch.  These are per-sample sums and maxima over the unknowns: one pass
over a level's samples here, where numpy made some twenty passes over whole arrays.  The
starts' operations are those the numpy code made, element by element and in the same order
(the cubic's sum from ``0.0``, the Lagrange weights as products left to right, of node
differences exact as integers): the same bits.
"""

import math

from ._jit import entry, inner


@entry
def level_starts(XT, idx, k, good, mid, four, Xs, span):
    """The starts ``Xs (G, nx)`` of the samples ``mid (G,)`` in the middle of the gaps
    ``idx[k[g]]``..``idx[k[g] + 1]`` between solved samples (``idx`` the solved samples in
    order, ``XT (N, nx)`` the unknowns sample by sample, ``good (N,)`` those converged);
    ``four (G,)`` whether the cubic through four solved samples gave it; ``span (G,)`` the
    largest difference of the two neighbours' unknowns (NaN where one is NaN), which
    :func:`level_check` reads (formed here, where the neighbours are read anyway).  (The
    cubic's weights depend only on the spacing of its nodes, the same for most gaps of a
    level: formed again only where it changes.)"""
    nx = XT.shape[1]
    last = idx.shape[0] - 1
    w0 = w1 = w2 = w3 = 0.0
    s0 = s1 = s2 = s3 = -1
    for g in range(k.shape[0]):
        kg = k[g]
        left, right = idx[kg], idx[kg + 1]
        m = (left + right) // 2
        mid[g] = m
        k0, k3 = max(kg - 1, 0), min(kg + 2, last)
        p0, p3 = idx[k0], idx[k3]
        gl, gr = good[left], good[right]
        span[g] = _largest_difference(XT, right, XT, left, nx)
        f = k0 < kg and k3 > kg + 1 and gl and gr and good[p0] and good[p3]
        four[g] = f
        if f:
            if left - p0 != s0 or right - left != s1 or p3 - right != s2 or m - left != s3:
                s0, s1, s2, s3 = left - p0, right - left, p3 - right, m - left
                # (the nodes relative to the left one: the same weights for every gap of
                # this spacing, and exact as integers)
                t0, t2, t3, t = float(-s0), float(s1), float(s1 + s2), float(s3)
                w0 = _lagrange(t0, 0.0, t2, t3, 0, t)
                w1 = _lagrange(t0, 0.0, t2, t3, 1, t)
                w2 = _lagrange(t0, 0.0, t2, t3, 2, t)
                w3 = _lagrange(t0, 0.0, t2, t3, 3, t)
            for x in range(nx):
                c = XT[p0, x] * w0
                c += 0.0                    # (the sum starts from 0: -0 is +0)
                c += XT[left, x] * w1
                c += XT[right, x] * w2
                c += XT[p3, x] * w3
                Xs[g, x] = c
        else:
            w = (m - left) / (right - left)
            for x in range(nx):
                a, b = XT[left, x], XT[right, x]
                if gl and gr:
                    Xs[g, x] = (1 - w) * a + w * b
                else:
                    Xs[g, x] = a if gl else b


@inner
def _lagrange(t0, t1, t2, t3, j, t):
    """The weight of node ``j`` of the cubic through the nodes ``t0..t3`` at ``t``."""
    ts = (t0, t1, t2, t3)
    w = 1.0
    for i in range(4):
        if i != j:
            w = w * (t - ts[i]) / (ts[j] - ts[i])
    return w


@entry
def level_check(XT, idx, k, mid, good, Xs, span, how, jump):
    """After a level's solve (its solutions in their rows of ``XT``): ``jump (G,)`` where the
    solution of sample ``mid[g]`` moved from its start ``Xs[g]`` by more than half the
    difference ``span[g]`` of its two neighbours (:func:`level_starts`; both converged, and
    solved by Newton from the start: ``how == 0``).  A NaN in either difference counts as no
    jump."""
    nx = XT.shape[1]
    for g in range(k.shape[0]):
        moved = _largest_difference(XT, mid[g], Xs, g, nx)
        # (False where either is NaN)
        jump[g] = (moved > 0.5 * span[g] + 1e-9) & good[idx[k[g]]] & good[idx[k[g] + 1]] & \
            (how[g] == 0)


@inner
def _largest_difference(A, i, B, j, nx):
    """``max |A[i, :nx] - B[j, :nx]|``, NaN where a difference is NaN."""
    largest = 0.0
    nan = False
    for x in range(nx):
        d = abs(A[i, x] - B[j, x])
        nan = nan | (d != d)
        largest = max(largest, d)
    return math.nan if nan else largest
