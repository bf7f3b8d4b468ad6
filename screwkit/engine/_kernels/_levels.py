"""The levels of a path, compiled (private): each level's starts, interpolated from the
solved samples around it, and the check of its solutions against them.

:func:`screwkit.engine._path.solve_path` solves a path's samples level by level, halving the
spacing: the sample in the middle of each gap between two solved ones starts from the cubic
through the two solved samples on each side (where all four converged), else from the linear
interpolation of its two neighbours, or the one that converged; once the levels are smooth
and the gaps narrow, the *fill* starts every sample left in a gap from the same cubic at its
own place (:mod:`._path_loop`).  After the level's solve, a sample whose solution moved from
its start by more than half its neighbours' difference (the ends of its gap) has jumped to
another branch.

A level's starts are described by a *stencil* a sample (:func:`level_stencil`, formed from
the solved samples' indices alone): its kind, the four weights and the four rows of the
unknowns it reads (``ST_*``).  The engine's driver applies it in the launch that solves the
level (:func:`stencil_start`, into the sample's start), and forms the sample's *excess*
there (:func:`moved_beyond`: how much more than half its neighbours' difference its
solution moved from its start, :func:`allowance`; a jump where positive), each sample's
rows read while its pose is at hand; the tests apply the same functions to arrays
(:func:`level_starts`, :func:`level_check`).  The cubic's weights are Lagrange's, each the
product of the sample's differences from the other nodes over that of the node's, both
exact as integers (gaps below some 200,000 samples), divided once: correctly rounded.
"""

import math

import numpy as np

from ._jit import borrowing, borrowing_inlined, entry, inner, prefetch_read
from ._layout import SK_CUBIC, SK_LEFT, SK_LINEAR, SK_RIGHT, ST_KIND, ST_ROW, ST_W


@entry
def level_stencil(idx, k, good, mid, S):
    """The stencils ``S (G, STENCIL_WIDTH)`` of a level's samples ``mid (G,)`` (written: the
    middle of each gap ``idx[k[g]]``..``idx[k[g] + 1]``; :func:`stencils`)."""
    for g in range(k.shape[0]):
        mid[g] = (idx[k[g]] + idx[k[g] + 1]) // 2
    stencils(idx, k, good, mid, S)


@entry
def gap_stencils(idx, k, good, mid, S):
    """The stencils ``S (G, STENCIL_WIDTH)`` of the samples ``mid (G,)`` (given: a fill's,
    anywhere in their gaps ``idx[k[g]]``..``idx[k[g] + 1]``; :func:`stencils`)."""
    stencils(idx, k, good, mid, S)


@borrowing
def stencils(idx, k, good, mid, S):
    """The stencils ``S (G, STENCIL_WIDTH)`` of the samples ``mid (G,)``, each in the gap
    ``idx[k[g]]``..``idx[k[g] + 1]`` between solved samples (``idx`` the solved samples in
    order, ``good (N,)`` those converged): the cubic through the two solved samples on each
    side where all four converged, else the linear interpolation of the two neighbours, or
    the one that converged (the right one where neither did).  (The cubic's weights depend
    only on the spacing of its nodes and the sample's place among them, the same for most
    gaps of a level: formed again only where they change; the denominators only where the
    nodes' spacing does.)"""
    last = idx.shape[0] - 1
    w0 = w1 = w2 = w3 = 0.0
    d0 = d1 = d2 = d3 = 1.0
    s0 = s1 = s2 = s3 = -1
    for g in range(k.shape[0]):
        kg = k[g]
        left, right = idx[kg], idx[kg + 1]
        m = mid[g]
        k0, k3 = max(kg - 1, 0), min(kg + 2, last)
        p0, p3 = idx[k0], idx[k3]
        gl, gr = good[left], good[right]
        S[g, ST_ROW] = p0
        S[g, ST_ROW + 1] = left
        S[g, ST_ROW + 2] = right
        S[g, ST_ROW + 3] = p3
        if k0 < kg and k3 > kg + 1 and gl and gr and good[p0] and good[p3]:
            if left - p0 != s0 or right - left != s1 or p3 - right != s2:
                s0, s1, s2, s3 = left - p0, right - left, p3 - right, -1
                # (the nodes relative to the left one, exact as integers: so are the
                # products of their differences)
                d0, d1, d2, d3 = _denominators(float(-s0), float(s1), float(s1 + s2))
            if m - left != s3:
                s3 = m - left
                w0, w1, w2, w3 = _weights(float(-s0), float(s1), float(s1 + s2), float(s3),
                                          d0, d1, d2, d3)
            S[g, ST_KIND] = SK_CUBIC
            S[g, ST_W] = w0
            S[g, ST_W + 1] = w1
            S[g, ST_W + 2] = w2
            S[g, ST_W + 3] = w3
        else:
            S[g, ST_KIND] = SK_LINEAR if gl and gr else (SK_LEFT if gl else SK_RIGHT)
            S[g, ST_W] = (m - left) / (right - left)
            S[g, ST_W + 1] = S[g, ST_W + 2] = S[g, ST_W + 3] = 0.0


@borrowing_inlined
def stencil_start(S, g, XT, X0, p, allow, q, g0, q0):
    """Sample ``g``'s start (stencil ``S[g]``, of the rows of the unknowns ``XT (N, nx)``)
    into ``X0[p]``, and the move it allows (:func:`allowance`) into ``allow[q]``, the
    neighbours' rows at hand: NaN both where the stencil names a row ``XT`` does not
    have.  The allowance is ``allow[q0]`` where sample ``g0`` (``>= 0``, formed before)
    has the same neighbours (the samples of a fill's gap: one allowance a gap)."""
    if g0 >= 0 and S[g0, ST_ROW + 1] == S[g, ST_ROW + 1] and \
            S[g0, ST_ROW + 2] == S[g, ST_ROW + 2]:
        allow[q] = allow[q0]
    else:
        allow[q] = allowance(S, g, XT)
    if not _rows_in(S, g, XT.shape[0]):
        for x in range(XT.shape[1]):
            X0[p, x] = math.nan
        return
    kind = S[g, ST_KIND]
    r0, r1 = int(S[g, ST_ROW]), int(S[g, ST_ROW + 1])
    r2, r3 = int(S[g, ST_ROW + 2]), int(S[g, ST_ROW + 3])
    if kind == SK_CUBIC:
        w0, w1, w2, w3 = S[g, ST_W], S[g, ST_W + 1], S[g, ST_W + 2], S[g, ST_W + 3]
        for x in range(XT.shape[1]):
            c = XT[r0, x] * w0
            c += 0.0                    # (the sum starts from 0: -0 is +0)
            c += XT[r1, x] * w1
            c += XT[r2, x] * w2
            c += XT[r3, x] * w3
            X0[p, x] = c
    elif kind == SK_LINEAR:
        w = S[g, ST_W]
        for x in range(XT.shape[1]):
            X0[p, x] = (1 - w) * XT[r1, x] + w * XT[r2, x]
    else:
        r = r1 if kind == SK_LEFT else r2
        for x in range(XT.shape[1]):
            X0[p, x] = XT[r, x]


@borrowing_inlined
def prefetch_stencil(S, g, XT):
    """Ask for the cache lines of the rows of ``XT (N, nx)`` stencil ``S[g]`` reads (those
    of ``XT``'s rows: every line of each, a row of 18 values spanning three); none where
    sample ``g - 1`` reads the same rows (the samples of a fill's gap: asked for once)."""
    if g > 0 and S[g, ST_ROW + 1] == S[g - 1, ST_ROW + 1] and \
            S[g, ST_ROW + 2] == S[g - 1, ST_ROW + 2] and S[g, ST_ROW] == S[g - 1, ST_ROW] and \
            S[g, ST_ROW + 3] == S[g - 1, ST_ROW + 3]:
        return
    nx = XT.shape[1]
    for j in range(4):
        r = int(S[g, ST_ROW + j])
        if r >= 0 and r < XT.shape[0]:
            for e in range(0, nx, 8):
                prefetch_read(XT, r * nx + e)
            prefetch_read(XT, r * nx + nx - 1)


@borrowing
def allowance(S, g, XT):
    """The move sample ``g``'s solution may make from its start (stencil ``S[g]``, of the
    rows of ``XT (N, nx)``): half the largest difference of its two neighbours' unknowns,
    plus 1e-9; NaN where a difference is NaN or the stencil names a row ``XT`` does not
    have."""
    if not _rows_in(S, g, XT.shape[0]):
        return math.nan
    return 0.5 * _largest_difference(XT, int(S[g, ST_ROW + 2]), XT, int(S[g, ST_ROW + 1]),
                                     XT.shape[1]) + 1e-9


@borrowing
def moved_beyond(XT, q, X0, p, allowed):
    """The *excess* of a sample: how much more than ``allowed`` (:func:`allowance`) its
    solution ``XT[q]`` moved from its start ``X0[p]`` (largest difference over the
    unknowns): a jump to another branch where positive; NaN where a difference is NaN."""
    return _largest_difference(XT, q, X0, p, XT.shape[1]) - allowed


@borrowing
def _rows_in(S, g, N):
    """Whether the four rows of stencil ``S[g]`` are rows of ``N`` (never a read outside
    the unknowns, whatever the stencil)."""
    ok = True
    for j in range(4):
        r = S[g, ST_ROW + j]
        ok = ok & (r >= 0) & (r < N)
    return ok


@entry
def level_starts(S, XT, Xs):
    """The starts ``Xs (G, nx)`` of a level's samples, their stencils ``S (G, ...)`` applied
    to the unknowns ``XT (N, nx)`` (:func:`stencil_start`)."""
    allow = np.empty(S.shape[0])
    for g in range(S.shape[0]):
        stencil_start(S, g, XT, Xs, g, allow, g, -1, -1)


@entry
def level_check(S, XT, mid, Xs, excess):
    """After a level's solve (its solutions in their rows ``mid`` of ``XT``, from the starts
    ``Xs``): each sample's ``excess (G,)`` (:func:`moved_beyond`)."""
    for g in range(S.shape[0]):
        excess[g] = moved_beyond(XT, mid[g], Xs, g, allowance(S, g, XT))


@inner
def _denominators(t0, t2, t3):
    """The denominators of the Lagrange weights of the cubic through the nodes ``t0, 0, t2,
    t3`` (integers as floats: the products exact below some 2e5 apart)."""
    return ((t0 - 0.0) * (t0 - t2) * (t0 - t3), (0.0 - t0) * (0.0 - t2) * (0.0 - t3),
            (t2 - t0) * (t2 - 0.0) * (t2 - t3), (t3 - t0) * (t3 - 0.0) * (t3 - t2))


@inner
def _weights(t0, t2, t3, t, d0, d1, d2, d3):
    """The Lagrange weights at ``t`` of the cubic through the nodes ``t0, 0, t2, t3``
    (denominators ``d0..d3``, :func:`_denominators`): each a product of integers (exact
    below some 2e5 apart) divided once, so correctly rounded."""
    a, b, c, e = t - t0, t - 0.0, t - t2, t - t3
    return b * c * e / d0, a * c * e / d1, a * b * e / d2, a * b * c / d3


@borrowing
def _largest_difference(A, i, B, j, nx):
    """``max |A[i, :nx] - B[j, :nx]|``, NaN where a difference is NaN."""
    largest = 0.0
    nan = False
    for x in range(nx):
        d = abs(A[i, x] - B[j, x])
        nan = nan | (d != d)
        largest = max(largest, d)
    return math.nan if nan else largest
