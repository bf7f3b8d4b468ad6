"""Solving the samples of a continuous path, each warm-started from its neighbours (private)."""

from __future__ import annotations

import numpy as np

from ._chains import LENGTH_PARAMS, chains_of
from ._kernels._layout import ACCEPTED, CONVERGED, ST_ROW
from ._launch import output_buffers
from ._path_launch import LevelLaunches
from ._solve import Closure, predictor_of, solve_closures

__all__ = ["PATH_ANCHORS", "SCATTERED_STEP", "STEP_FLOOR", "check_path", "solve_path"]


#: Anchors of a path: about this many samples are solved first, one after the other (all
#: at once from home, then taken where each continues the secant of the last two).
PATH_ANCHORS = 32
#: A path solved with progress told: its levels in launches of at least this many samples.
PROGRESS_SAMPLES = 65536


#: ``path=True`` on at least 32 poses whose median step (the largest over the parameters,
#: each relative to its spread) exceeds this is taken for scattered poses: a smooth path
#: of that many samples steps a few percent, random poses about 40%.
SCATTERED_STEP = 0.25
#: The smallest spread a step is measured against: this fraction of a radian (angles) or of
#: the model's characteristic length (lengths).
STEP_FLOOR = 0.1


def check_path(fixed: dict, path: bool, length: float = 1.0) -> tuple:
    """``(path, notes)``: poses given as a path that are scattered are solved as scattered
    poses, each from home (warm starts from far neighbours would cost retries and can lose
    poses), with a note saying so.

    Each parameter's steps are measured against its spread, but never against less than
    :data:`STEP_FLOOR` of a radian for an angle or of ``length`` (the model's
    characteristic length) for a length: a fine raster of a small patch is a path.  A
    parameter constant up to rounding (spread below 1e-9 of its size) is left out."""
    if not path:
        return False, ()
    if not fixed or np.asarray(next(iter(fixed.values()))).size < 32:
        return True, ()
    largest = step = None                   # the largest relative step over the parameters
    for p, v in fixed.items():
        v = np.asarray(v, float)
        hi, lo = float(np.max(v)), float(np.min(v))
        spread = hi - lo
        scale = length if p in LENGTH_PARAMS else 1.0
        if spread <= 1e-9 * max(abs(hi), abs(lo), scale):
            continue
        if largest is None:
            largest, step = np.empty(v.size - 1), np.empty(v.size - 1)
            out = largest
        else:
            out = step
        np.subtract(v[1:], v[:-1], out=out)
        np.abs(out, out=out)
        np.divide(out, max(spread, STEP_FLOOR * scale), out=out)
        if out is step:
            np.maximum(largest, step, out=largest)
    if largest is None:
        return True, ()
    # the median against the threshold: counted where that settles it (as np.median's
    # verdict: more than half the steps on one side), else np.median's own value
    n, above = largest.size, int(np.count_nonzero(largest > SCATTERED_STEP))
    if above + int(np.count_nonzero(largest <= SCATTERED_STEP)) == n and (
            2 * above < n - 1 or 2 * above > n + 1):
        if 2 * above < n:
            return True, ()
        median = float(np.median(largest))
    else:
        median = float(np.median(largest))
        if median <= SCATTERED_STEP:
            return True, ()
    return False, (f"given as a path, but successive poses are far apart (median step "
                   f"{100 * median:.0f}% of their spread): solved as scattered poses, each "
                   "from home",)


def solve_path(model, fixed: dict, start=None, *, anchor_every=None, progress=None,
               workers=None, levels=None) -> Closure:
    """Solve N samples of a continuous path, each warm-started from its neighbours.

    About :data:`PATH_ANCHORS` anchor samples are solved in order, each from the
    start among the previous one, the secant through the last two and the home
    predictor (where it lies within one anchor step of the secant) that closes best (the
    first from ``start`` or home, with continuation where Newton fails); the samples
    between two solved ones are then solved level by level, halving the spacing, from the
    cubic through their two solved neighbours on each side (the linear interpolation where
    those are not all available), all of a level at once; once a level is smooth and the
    gaps narrow, every sample left from that cubic at its place, in order (the *fill*,
    :mod:`._kernels._path_loop`); the whole level loop in launches
    of the compiled kernels (:mod:`._kernels._path_loop`: no Python between the levels;
    a large level's samples on ``workers`` threads, default 2: each sample's arithmetic is
    the same whatever thread holds it).  A sample whose solution is not close to that
    interpolation (a jump to another branch) or that does not converge is solved again
    from its left neighbour alone (the right one when the left is unreachable), by Newton
    only (the level solve ran the continuation from home), all such samples of the level
    at once (here, between two launches); a sample with no solved neighbour keeps its
    level's result.

    ``levels`` (optional): an object whose ``begin(N, Z)`` returns the
    :class:`~._path_launch.LevelLaunches` of the path (``N`` its samples, ``Z`` the
    predictor), its output buffers holding more than the closures
    (the engine's rows, conditioning and statics: :class:`screwkit.engine._run.PathRows`);
    by default the closures alone.  The unknowns returned are a view of those buffers.
    """
    ch = chains_of(model)
    fixed = {p: np.asarray(fixed[p], float) for p in ch.fixed}
    N = len(next(iter(fixed.values())))
    K = max(1, -(-N // PATH_ANCHORS)) if anchor_every is None else max(1, int(anchor_every))
    anchors = np.arange(0, N, K)
    if anchors[-1] != N - 1:
        anchors = np.append(anchors, N - 1)
    Z = predictor_of(ch)
    if levels is None:
        L = LevelLaunches(ch.flat, Z, output_buffers(ch.flat, N, rows=False, statics=False,
                                                     excess=True), N, rows=False)
    else:
        L = levels.begin(N, Z)
    ch.full_params(fixed, N, out=L.P6)
    # the samples' unknowns (rows) and excess: the outputs the levels' launches write
    views = L.buffers.arrays(convert=False)
    XT, excess = views["X"], views["excess"]
    X = XT.T                                    # (n_unknowns, N): a view, as the API reads
    # the path's state, which the launches read and write (views)
    res, its, how, sing, solved = L.res, L.iterations, L.how, L.singular, L.solved
    how[:] = 2
    prev = None if start is None else np.array(start, float).reshape(ch.n_unknowns, -1)[:, :1]
    last = []                                   # the last two solved anchors (index, X)

    def residuals(fx, cand):
        from ._launch import frames
        return frames(ch.flat, Z, ch.full_params(fx, cand.shape[1]), cand.T)["residual"]

    def predict(fx):
        from ._kernels import kernels
        out = np.empty((1, ch.n_unknowns))
        kernels().predict_batch(Z, ch.full_params(fx, 1), out)
        return out.T
    # every anchor solved at once from home, as a random pose would be (with its rows, into
    # the path's outputs): an anchor whose solution continues the last two along their
    # secant (within one anchor step) is on the branch followed and is taken as it is (its
    # rows with it); the others are solved one by one below
    batch = None
    if len(anchors) > 3:
        bX, bres, bits, bhow, bsing = L.solve_at(anchors, workers)
        batch = Closure(ch, bX, None, bres, bits, bhow, bsing)
    taken = []
    j = 0
    while j < len(anchors):
        if len(last) == 2 and batch is not None:
            # the anchors from this one on that continue the secant of the last two each,
            # taken at once (as one by one: the same values)
            r = _on_secant(anchors, j, last, batch)
            if r:
                ii = anchors[j:j + r]
                X[:, ii], res[ii], its[ii], how[ii], sing[ii] = batch.X[:, j:j + r], \
                    batch.residual[j:j + r], batch.iterations[j:j + r], batch.how[j:j + r], \
                    batch.singular_beta[j:j + r]
                tail = [(anchors[k], batch.X[:, k:k + 1]) for k in range(max(j, j + r - 2), j + r)]
                taken.append(ii)
                last = (last + tail)[-2:]
                prev = last[-1][1]
                j += r
                continue
        i = anchors[j]
        if j == 0 and prev is None and batch is not None:
            # the first anchor from home: the batch solved it so (the same values; its rows
            # with it)
            X[:, i], res[i], its[i], how[i], sing[i] = batch.X[:, 0], batch.residual[0], \
                batch.iterations[0], batch.how[0], batch.singular_beta[0]
            taken.append(anchors[:1])
            if res[i] <= ACCEPTED:
                prev = batch.X[:, :1]
                last = [(i, prev)]
            j += 1
            continue
        fx = {p: v[i:i + 1] for p, v in fixed.items()}
        X0 = prev
        if len(last) == 2:
            # of the last anchor, the secant through the last two and the home predictor,
            # the start with the least closure residual; the predictor only where it lies
            # within one anchor step of the secant (the branch followed stays)
            (i1, X1), (i2, X2) = last
            step = X2 - X1
            secant = X2 + step * ((i - i2) / (i2 - i1))
            cand = [X2, secant]
            guess = predict(fx)
            if np.max(np.abs(guess - secant)) <= np.max(np.abs(step)):
                cand.append(guess)
            cand = np.concatenate(cand, axis=1)
            X0 = cand[:, int(np.argmin(residuals(fx, cand)))][:, None]
        c = solve_closures(model, fx, X0)
        X[:, i], res[i], its[i], how[i], sing[i] = c.X[:, 0], c.residual[0], c.iterations[0], \
            c.how[0], c.singular_beta[0]
        if c.residual[0] <= ACCEPTED:
            prev = c.X
            last = (last + [(i, c.X)])[-2:]
        j += 1
    if taken:
        # the anchors taken from the batch keep the rows formed with them, where Newton
        # closed from the predictor (their frames those of their unknowns)
        t = np.concatenate(taken)
        L.kept[t] = (res[t] <= CONVERGED) & (how[t] == 0)
    if progress:
        progress(len(anchors), N)
    retried = 0
    solved[anchors] = 1
    # the levels in launches: all of them in one, or (``progress``) about a tenth of the
    # path's samples in each, the progress told between
    budget = max(PROGRESS_SAMPLES, N // 10) if progress else N
    while not solved.all():
        G = L.run(budget, workers)
        if G:
            # a level with samples to solve again: the retries, all at once, from a solved
            # neighbour only (with none, there is no better start than the level's),
            # Newton alone (the level solve already ran the continuation from home for these
            # samples)
            mid = L.level_rows[:G].copy()
            S = L.level_stencils[:G]
            left, right = S[:, ST_ROW + 1].astype(np.int64), S[:, ST_ROW + 2].astype(np.int64)
            rm, hm = res[mid], how[mid]
            # a branch jump: the solution moved from its start more than half its
            # neighbours differ (both converged, and solved by Newton from the start)
            jump = (excess[mid] > 0) & (res[left] <= ACCEPTED) & (res[right] <= ACCEPTED) \
                & (hm == 0)
            ks = np.flatnonzero(jump | ~(rm <= CONVERGED))
            src = np.where(res[left[ks]] <= ACCEPTED, left[ks], right[ks])
            has = res[src] <= ACCEPTED
            ks, src = ks[has], src[has]
            if ks.size:
                ii = mid[ks]
                c1 = solve_closures(model, {p: v[ii] for p, v in fixed.items()}, XT[src].T,
                                    continuation=False)
                retried += ks.size
                take = (c1.residual <= res[ii]) | jump[ks]
                t = ii[take]
                XT[t], res[t], its[t], how[t], sing[t] = c1.X.T[take], c1.residual[take], \
                    c1.iterations[take], c1.how[take], c1.singular_beta[take]
                L.kept[t] = 0                   # (their rows formed again at the end)
            # (a sample of the fill is marked 2: the fill's grid stays the samples marked 1)
            solved[mid] = 2 if L.filling else 1
        if progress:
            progress(int(np.count_nonzero(solved)), N)
    diag = {"anchors": len(anchors), "batched": N, "retried": retried,
            "filled": int(np.count_nonzero(solved == 2))}
    # X: a view of the samples' rows XT (the engine's driver keeps them as they are)
    return Closure(ch, X, None, res.copy(), its.copy(), how.copy(), sing.astype(bool), diag)


def _on_secant(anchors, j, last, batch) -> int:
    """How many anchors from ``anchors[j]`` on the batch solved on the branch followed,
    one after the other: each converged, within one step (the largest difference of the
    previous two) of the secant through the previous two (``last``, the two solved before
    ``anchors[j]``; then the batch's own), as the one-by-one test of
    :func:`solve_path` (the same operations, element by element)."""
    (i1, X1), (i2, X2) = last
    idx = np.asarray(anchors[j:], np.int64)
    m = idx.size
    Xb = batch.X[:, j:]
    Xp1 = np.concatenate([X2, Xb[:, :m - 1]], axis=1)       # each one's previous anchor
    Xp2 = np.concatenate([X1, X2, Xb[:, :m - 2]], axis=1)[:, :m]   # and the one before
    ip1 = np.concatenate([[i2], idx[:m - 1]])
    ip2 = np.concatenate([[i1, i2], idx[:m - 2]])[:m]
    step = Xp1 - Xp2
    secant = Xp1 + step * ((idx - ip1) / (ip1 - ip2))
    ok = (batch.residual[j:] <= CONVERGED) & (
        np.max(np.abs(Xb - secant), axis=0) <= np.max(np.abs(step), axis=0))
    return m if ok.all() else int(np.argmin(ok))
