"""A path's levels solved in one launch of the parallel kernel (private).

:func:`screwkit.engine._path.solve_path` solves a path's samples level by level, halving
the spacing between solved samples (:mod:`._levels`).  The level loop runs here, inside
``_driver.run_parallel``: each level's samples, stencils and given parameters formed on the
launch's first thread (:func:`form_level`), its poses solved on the threads as any launch's
(their outputs into their rows of the path's outputs), then its results taken into the
path's state (:func:`take_level`), without Python between the levels.  Python (the
anchors before, the retries between) reads and writes the same state, which is packed into
two arrays (``_layout.LH_*``, ``LV_*``; :func:`path_state`):

* a level with samples to solve again (a branch jump, or Newton not converged where a
  neighbour is solved) ends the launch with its samples left unsolved and their count in
  ``LH_RETRY``: Python retries them (:func:`screwkit.engine._path.solve_path`), marks them
  solved and launches again;
* the launch also returns at the end of the level that reaches ``LH_BUDGET`` samples (the
  progress of a long path).

The bisection gives way to the *fill* once a level is smooth (at most half its samples took
a Newton step from their starts, and one in :data:`._layout.FILL_SHARE` more than one or
did not converge: on a smooth path the cubic's error falls sixteenfold as its spacing
halves, so the fill's starts, on the finer grid, then close almost all) and no gap
between the solved samples is wider than :data:`._layout.FILL_GAP`: every sample left is
then started from the cubic through the solved samples around its gap (the fill's grid,
which its samples do not join), in the path's order.  Its samples are the path's rows one
after the other (the bisection's last levels wrote every other row, their neighbours long
out of the caches) and read the few grid rows around them: the same solve of each sample
for about a sixth less time a sample.  Each sample's start depends on the grid alone, so the
fill's levels (the budget's portions) do not change a bit.

Each level is the same computation whatever launch holds it: the same samples, the same
stencils (:func:`._levels.stencils`), each pose solved alone in its lane, so the bits are
those of a launch a level (the tests' reference).
"""

from ._jit import borrowed, borrowing_inlined, inlined, inner
from ._layout import (ACCEPTED, CONVERGED, FILL_GAP, FILL_PORTION, FILL_SHARE, LH_BUDGET,
                      LH_FILL, LH_N, LH_RETRY, LH_SIZE, LH_SMOOTH, LV_GAPS, LV_GOOD, LV_HOW,
                      LV_IDX, LV_IDX2, LV_ITS, LV_KEPT, LV_ROWS, LV_SING, LV_SOLVED, OUT_EXCESS,
                      OUT_HOW, OUT_ITS, OUT_RES, OUT_SING, OUT_X, ST_ROW, SY_DONE, SY_G, SY_N,
                      SY_READY, SY_TAKEN, SY_WHICH)
from ._levels import moved_beyond, stencil_start, stencils
from ._pack import out_row
from ._threads import write_release


@inner
def path_state(Lf, Li):
    """The path's state as views: ``(header (LH_SIZE,), V (LV_ROWS, N) int, P6 (N, 6),
    res (N,), comp (N or 0, rows))`` (``LV_*`` the rows of ``V``)."""
    N = Li[LH_N] if Li.shape[0] else 0
    V = Li[LH_SIZE:LH_SIZE + LV_ROWS * N].reshape((LV_ROWS, N))
    P6 = Lf[:6 * N].reshape((N, 6))
    res = Lf[6 * N:7 * N]
    nc = Lf.shape[0] - 7 * N
    rows = nc // N if N else 0
    comp = Lf[7 * N:7 * N + (N if rows else 0) * rows].reshape((N if rows else 0, rows))
    return borrowed(Li[:LH_SIZE]), borrowed(V), borrowed(P6), borrowed(res), borrowed(comp)


@inner
def begin_levels(V, res, idx, good):
    """The solved samples ``idx`` in order (their count returned) and ``good`` (1 where a
    sample converged) from the state at the launch's start: the anchors and the levels'
    samples (a fill's stay out of ``idx``, the grid it interpolates)."""
    n = 0
    solved = V[LV_SOLVED]
    for i in range(res.shape[0]):
        if solved[i] == 1:
            # (``good`` is read of solved samples only, each set when it is solved: the
            # others' are left; the lead's pass, which the team waits for, reads no more)
            good[i] = 1 if res[i] <= ACCEPTED else 0
            idx[n] = i
            n += 1
    return n


@inner
def form_level(idx, n, gaps, mid):
    """The gaps between the solved samples ``idx[:n]`` (their indices in ``idx``) into
    ``gaps``, and the sample in the middle of each into ``mid``: the next level.  Returns
    their count (0: every sample solved)."""
    G = 0
    for j in range(n - 1):
        if idx[j + 1] - idx[j] > 1:
            gaps[G] = j
            mid[G] = (idx[j] + idx[j + 1]) // 2
            G += 1
    return G


@inner
def fill_level(idx, n, gaps, mid, solved, fill, cap):
    """The next level of a fill (:data:`._layout.FILL_GAP`): the samples not yet solved in
    the gaps of the grid ``idx[:n]`` from gap ``fill - 1`` on, in order, at most ``cap``,
    into ``mid`` (each one's gap into ``gaps``).  Returns their count and the fill's place
    to go on from (:data:`._layout.LH_FILL`)."""
    G = 0
    for j in range(fill - 1, n - 1):
        for q in range(idx[j] + 1, idx[j + 1]):
            if solved[q] == 0:
                if G == cap:
                    return G, j + 1
                gaps[G] = j
                mid[G] = q
                G += 1
    return G, max(n, 1)


@inner
def widest_gap(idx, n):
    """The widest gap between the solved samples ``idx[:n]`` (samples apart)."""
    widest = 0
    for j in range(n - 1):
        widest = max(widest, idx[j + 1] - idx[j])
    return widest


@inlined
def level_inputs(I, G, per_sample):
    """The inputs of a level of ``G`` samples: the leading rows of the launch's buffers."""
    comp = I[5][:G] if per_sample else I[5]
    return (I[0][:G], I[1][:G], I[2], I[3], I[4], comp, I[6], I[7][:G], I[8][:G])


@borrowing_inlined
def level_block(L, I, p0, nb):
    """A path's level (``L``: :func:`level_of`): its poses ``p0..p0+nb-1`` (in the gaps
    ``L[1][p0:p0+nb]``): their samples into the rows ``I[7]``, their stencils into ``I[8]``
    (:func:`._levels.stencils`), their given parameters into ``I[0]`` and their
    compliances into ``I[5]`` (where each sample has its own), formed by the thread that
    solves them."""
    idx, gaps, good, P6, comp = L[0], L[1], L[2], L[3], L[4]
    mid = I[7]
    stencils(idx, gaps[p0:p0 + nb], good, mid[p0:p0 + nb], I[8][p0:p0 + nb])
    P6l, C = I[0], I[5]
    for p in range(p0, p0 + nb):
        q = mid[p]
        for c in range(6):
            P6l[p, c] = P6[q, c]
    if comp.shape[0]:
        for p in range(p0, p0 + nb):
            q = mid[p]
            for c in range(comp.shape[1]):
                C[p, c] = comp[q, c]


@borrowing_inlined
def take_block(L, I, O, p0, nb):
    """A path's level's poses ``p0..p0+nb-1`` solved: each sample's residual, iterations,
    how and singular flag into the path's state, and whether its rows stay (converged from
    its start by Newton); ``H[LH_RETRY]`` set where one is to be solved again (its solution
    jumped to another branch, or Newton did not converge; a solved neighbour to start
    from); a fill's samples marked solved (2).  The samples read (their neighbours') are
    none of the level's, which the threads write."""
    good, V, res, H = L[2], L[5], L[6], L[7]
    mid, S = I[7], I[8]
    for p in range(p0, p0 + nb):
        q = mid[p]
        rm, hm = O[OUT_RES][q], O[OUT_HOW][q]
        res[q] = rm
        V[LV_ITS, q] = O[OUT_ITS][q]
        V[LV_HOW, q] = hm
        V[LV_SING, q] = O[OUT_SING][q]
        V[LV_KEPT, q] = 1 if (rm <= CONVERGED and hm == 0) else 0
        if H[LH_FILL]:
            # (a fill's sample is marked solved here, by its thread: no pass of the lead's)
            V[LV_SOLVED, q] = 2
            good[q] = 1 if rm <= ACCEPTED else 0
        left, right = int(S[p, ST_ROW + 1]), int(S[p, ST_ROW + 2])
        jump = O[OUT_EXCESS][q] > 0 and good[left] == 1 and good[right] == 1 and hm == 0
        if jump or not rm <= CONVERGED:
            src = left if res[left] <= ACCEPTED else right
            if res[src] <= ACCEPTED:
                H[LH_RETRY] = 1


@inlined
def level_of(H, V, P6, res, comp, sync, G):
    """The tuple of a path's level of ``G`` samples (published in ``sync`` by
    :func:`lead_level`) the blocks read and write (:func:`level_block`,
    :func:`take_block`): the solved samples, the level's gaps, whether each sample
    converged, the given parameters and compliances, the state's rows and residuals and
    its header (no solved samples outside a path: ``V`` has none)."""
    idx = V[LV_IDX] if sync[SY_WHICH] == 0 else V[LV_IDX2]
    return (idx[:sync[SY_N]], V[LV_GAPS][:G], V[LV_GOOD], P6, comp, V, res, H)


@inner
def take_level(H, V, res, I, G, idx, n, idx2, gaps, good):
    """A solved level of ``G`` samples (:func:`take_block` done): whether it was smooth
    (``H[LH_SMOOTH]``: at most half its samples took a Newton step from their starts, and
    one in :data:`._layout.FILL_SHARE` more than one or did not converge); where some
    sample is to be solved again, the level is left to Python (``H[LH_RETRY] = G``) and -1
    returned; otherwise its samples are marked solved and merged into ``idx`` (written to
    ``idx2``) and the count returned; a level of the fill (``H[LH_FILL]``: no smoothness,
    its samples marked solved 2 by :func:`take_block`) is left out of ``idx``, its grid
    (``n`` returned)."""
    if H[LH_FILL]:                      # (its samples marked by take_block)
        if H[LH_RETRY]:
            H[LH_RETRY] = G
            return -1
        return n
    mid = I[7]
    stepped, rough = 0, 0
    for g in range(G):
        q = mid[g]
        its = V[LV_ITS, q]
        stepped += 1 if its > 0 else 0
        rough += 1 if (its > 1 or V[LV_HOW, q] != 0 or not res[q] <= CONVERGED) else 0
    H[LH_SMOOTH] = 1 if 2 * stepped <= G and rough * FILL_SHARE <= G else 0
    if H[LH_RETRY]:
        H[LH_RETRY] = G
        return -1
    # the level's samples among the solved ones, in order
    g, m = 0, 0
    for j in range(n):
        idx2[m] = idx[j]
        m += 1
        if g < G and gaps[g] == j:
            q = mid[g]
            idx2[m] = q
            m += 1
            V[LV_SOLVED, q] = 1
            good[q] = 1 if res[q] <= ACCEPTED else 0
            g += 1
    return m


@inner
def over_budget(H, done):
    """Whether the launch has solved its budget of samples (``H[LH_BUDGET]``)."""
    return done >= H[LH_BUDGET]


@inlined
def path_level(L, I, first, stop):
    """A path's level (``L``: :func:`level_of`, empty otherwise): the samples,
    stencils and given parameters of the poses ``first..stop-1`` (formed by the thread
    that solves them, a block ahead of theirs: the prefetches read them; nothing where
    ``stop <= first``)."""
    if L[0].shape[0] and stop > first:
        level_block(L, I, first, stop - first)


@inlined
def path_starts(I, O, p0, nb):
    """A path level's launch (a stencil a pose): the starts of the poses ``p0..p0+nb-1``
    into their rows of ``X0``, from the solved samples' unknowns (rows of ``O[OUT_X]`` no
    pose of the launch writes), and the move each may make into its row of
    ``O[OUT_EXCESS]`` (:func:`._levels.stencil_start`; one allowance a gap of a fill)."""
    S = I[8]
    if S.shape[0]:
        for p in range(p0, p0 + nb):
            stencil_start(S, p, O[OUT_X], I[1], p, O[OUT_EXCESS], out_row(I, p),
                          p - 1 if p > p0 else -1, out_row(I, p - 1) if p > p0 else -1)


@inlined
def path_excess(L, I, O, p0, nb, same):
    """A path level's launch: each pose's excess (:func:`._levels.moved_beyond`: the move
    beyond the one allowed, :func:`path_starts`) into its row of ``O[OUT_EXCESS]``, its
    solution and start at hand; with a path's level ``L``, the poses' results into the
    path's state (:func:`take_block`).  ``same (nb,)``: 1 for a pose of a block whose
    unknowns are the start its block wrote (no Newton step, no rescue, no turn: its
    frames the block's, ``_block.K_SAME``, and no iteration), which moved by 0 (as
    ``moved_beyond`` finds: the fill's samples, nearly all), empty otherwise."""
    S = I[8]
    if S.shape[0]:
        its = O[OUT_ITS]
        for p in range(p0, p0 + nb):
            q = out_row(I, p)
            if same.shape[0] and same[p - p0] == 1 and its[q] == 0:
                O[OUT_EXCESS][q] = 0.0 - O[OUT_EXCESS][q]
            else:
                O[OUT_EXCESS][q] = moved_beyond(O[OUT_X], q, I[1], p, O[OUT_EXCESS][q])
        if L[0].shape[0]:
            take_block(L, I, O, p0, nb)


@inner
def lead_level(H, V, res, I, P6, comp, sync, level):
    """Between two levels of a path (the lead thread of a team, ``_driver.team_levels``;
    the one thread of a launch's level loop otherwise): the first
    level formed (``level`` 0), or the last one's results merged and the next one formed
    (:func:`take_level`, :func:`form_level`; none where it has retries or the budget is
    spent): once a level is smooth and no gap is wider than :data:`._layout.FILL_GAP`, the
    fill (:func:`fill_level`, in levels of the launch's budget left, at least
    :data:`._layout.FILL_PORTION`: each sample's start is the same whatever the levels);
    its samples, the solved ones and which list holds them published in ``sync``,
    the pieces' counter reset, and the level released to the team.  Returns its samples (0:
    the launch ends)."""
    which = sync[SY_WHICH]
    idx, idx2 = (V[LV_IDX], V[LV_IDX2]) if which == 0 else (V[LV_IDX2], V[LV_IDX])
    gaps, good, mid = V[LV_GAPS], V[LV_GOOD], I[7]
    go = True
    if level == 0:
        n = begin_levels(V, res, idx, good)
    else:
        last, n = sync[SY_G], sync[SY_N]
        m = take_level(H, V, res, I, last, idx, n, idx2, gaps, good)
        sync[SY_DONE] += last
        go = m >= 0 and not over_budget(H, sync[SY_DONE])
        if go and not H[LH_FILL]:
            which, idx, n = 1 - which, idx2, m
    G = 0
    if go:
        if not H[LH_FILL] and H[LH_SMOOTH] and widest_gap(idx, n) <= FILL_GAP:
            H[LH_FILL] = 1
        if H[LH_FILL]:
            cap = max(FILL_PORTION, H[LH_BUDGET] - sync[SY_DONE])
            G, H[LH_FILL] = fill_level(idx, n, gaps, mid, V[LV_SOLVED], H[LH_FILL], cap)
        else:
            G = form_level(idx, n, gaps, mid)
    sync[SY_G] = G
    sync[SY_N] = n
    sync[SY_WHICH] = which
    sync[SY_TAKEN] = 0
    write_release(sync[SY_READY:SY_READY + 1], level + 1)
    return G
