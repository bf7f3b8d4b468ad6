"""Solving the samples of a continuous path, each warm-started from its neighbours (private)."""

from __future__ import annotations

import numpy as np

from ._chains import LENGTH_PARAMS, chains_of
from ._kernels._layout import ACCEPTED, CONVERGED, STENCIL_WIDTH
from ._memory import recycled_empty
from ._solve import Closure, predictor_of, solve_closures

__all__ = ["PATH_ANCHORS", "SCATTERED_STEP", "STEP_FLOOR", "balanced_chunk", "check_path", "solve_path"]


#: Anchors of a path: about this many samples are solved one after the other.
PATH_ANCHORS = 32


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
    steps = []
    for p, v in fixed.items():
        v = np.asarray(v, float)
        spread = float(np.max(v) - np.min(v))
        scale = length if p in LENGTH_PARAMS else 1.0
        if spread <= 1e-9 * max(float(np.max(np.abs(v))), scale):
            continue
        steps.append(np.abs(np.diff(v)) / max(spread, STEP_FLOOR * scale))
    if not steps:
        return True, ()
    median = float(np.median(np.max(steps, axis=0)))
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
    predictor (where it lies within one anchor step of the secant) that closes best (the first from ``start`` or home, with continuation
    where Newton fails); the samples between two solved ones are then solved level by level,
    halving the spacing, from the cubic through their two solved neighbours on each side
    (the linear interpolation where those are not all available),
    all of a level at once (a large level in chunks on ``workers`` threads, default 2: each
    sample's arithmetic is the same whatever chunk holds it).  A sample whose solution is
    not close to that interpolation (a jump to another branch) or that does not converge is
    solved again from its left neighbour alone (the right one when the left is unreachable), by
    Newton only (the level solve ran the continuation from home), all such samples at once;
    a sample with no solved neighbour keeps its level's result.

    ``levels`` (optional) solves the levels instead of :func:`solve_closures`: an object
    with ``solve(fixed, stencil, indices, workers) -> (Closure, excess)`` (the samples
    ``indices`` of the path, their starts described by ``stencil``, rows of
    :func:`~._kernels._levels.level_stencil`; ``excess (K,)`` as
    :func:`~._kernels._levels.stencil_excess`) and ``stale(indices)``, told of the samples
    solved again after their level (the retries taken): the engine's driver forms each
    level's starts, excess and rows in the launch that solves it
    (:class:`screwkit.engine._run.PathRows`); and ``unknowns() -> (N, n_unknowns)``: the
    path's unknowns sample by sample, which ``solve`` reads (the solved samples') and fills
    (its samples' rows; the ``Closure`` it returns need not hold them).
    """
    ch = chains_of(model)
    fixed = {p: np.asarray(fixed[p], float) for p in ch.fixed}
    N = len(next(iter(fixed.values())))
    K = max(1, -(-N // PATH_ANCHORS)) if anchor_every is None else max(1, int(anchor_every))
    anchors = list(range(0, N, K))
    if anchors[-1] != N - 1:
        anchors.append(N - 1)
    # the unknowns sample by sample (rows): the levels' launches write their samples' rows
    # in place where ``levels`` holds them (the path's outputs), else they are put here
    if levels is not None:
        XT = levels.unknowns()
    else:
        XT = recycled_empty(N * ch.n_unknowns).reshape(N, ch.n_unknowns)
        XT[...] = 0.0
    X = XT.T                                    # (n_unknowns, N): a view, as the API reads
    res = np.full(N, np.inf)
    its = np.zeros(N, int)
    how = np.full(N, 2)
    sing = np.zeros(N, bool)
    prev = None if start is None else np.array(start, float).reshape(ch.n_unknowns, -1)[:, :1]
    last = []                                   # the last two solved anchors (index, X)
    Z = predictor_of(ch)

    def residuals(fx, cand):
        from ._launch import frames
        return frames(ch.flat, Z, ch.full_params(fx, cand.shape[1]), cand.T)["residual"]

    def predict(fx):
        from ._kernels import kernels
        out = np.empty((1, ch.n_unknowns))
        kernels().predict_batch(Z, ch.full_params(fx, 1), out)
        return out.T
    # every anchor solved at once from home, as a random pose would be: an anchor whose
    # solution continues the last two along their secant (within one anchor step) is on
    # the branch followed and is taken as it is; the others are solved one by one below
    batch = solve_closures(model, {p: v[anchors] for p, v in fixed.items()}) \
        if len(anchors) > 3 else None
    for j, i in enumerate(anchors):
        fx = {p: v[i:i + 1] for p, v in fixed.items()}
        X0 = prev
        if len(last) == 2 and batch is not None and batch.residual[j] <= CONVERGED:
            (i1, X1), (i2, X2) = last
            step = X2 - X1
            secant = X2 + step * ((i - i2) / (i2 - i1))
            Xb = batch.X[:, j:j + 1]
            if np.max(np.abs(Xb - secant)) <= np.max(np.abs(step)):
                X[:, i], res[i], its[i], how[i], sing[i] = Xb[:, 0], batch.residual[j], \
                    batch.iterations[j], batch.how[j], batch.singular_beta[j]
                prev = Xb
                last = (last + [(i, Xb)])[-2:]
                continue
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
    if progress:
        progress(len(anchors), N)
    retried = 0
    solved = np.zeros(N, bool)
    solved[anchors] = True
    K_ = _kernels()
    while not solved.all():
        idx = np.flatnonzero(solved)
        k = np.flatnonzero(idx[1:] - idx[:-1] > 1)
        good = res <= ACCEPTED
        # each gap's middle sample and its start: the cubic through the two solved
        # neighbours on each side, where all four are good; elsewhere the linear
        # interpolation, or the one good neighbour (compiled: one pass over the samples)
        mid, S = np.empty(len(k), np.int64), np.empty((len(k), STENCIL_WIDTH))
        K_.level_stencil(idx, k, good, mid, S)
        left, right = idx[k], idx[k + 1]
        fx = {p: v[mid] for p, v in fixed.items()}
        if levels is None:
            Xs, excess = np.empty((len(k), ch.n_unknowns)), np.empty(len(k))
            K_.level_starts(S, XT, Xs)
            c = _solve_level(model, fx, Xs.T, workers)
            XT[mid] = c.X.T
            K_.level_check(S, XT, mid, Xs, excess)
        else:
            # (the starts formed, and the excess, in the launches that solve the level)
            c, excess = levels.solve(fx, S, mid, workers)
        rm, hm = c.residual, c.how
        # a branch jump: the solution moved from its start more than half its neighbours
        # differ (both converged, and solved by Newton from the start)
        jump = (excess > 0) & good[left] & good[right] & (hm == 0)
        res[mid], its[mid], how[mid], sing[mid] = rm, c.iterations, hm, c.singular_beta
        # the retries, all at once: from a solved neighbour only (with none, there is no
        # better start than the level's), Newton alone (the level solve already ran the
        # continuation from home for these samples)
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
            if levels is not None:
                levels.stale(t)
        solved[mid] = True
        if progress:
            progress(int(solved.sum()), N)
    diag = {"anchors": len(anchors), "batched": N, "retried": retried}
    # X: a view of the samples' rows XT (the engine's driver keeps them as they are)
    return Closure(ch, X, None, res, its, how, sing, diag)


def balanced_chunk(N: int, chunk: int, workers: int) -> int:
    """The chunk size, at most ``chunk``, that cuts ``N`` poses into a multiple of
    ``workers`` chunks of nearly equal size: 13 chunks on 2 threads leave one thread idle
    for the last; 14 smaller ones do not.  Each pose's arithmetic is the same whatever
    chunk holds it, so the results do not change."""
    n = -(-N // chunk)
    if workers > 1 and n > 1 and n % workers:
        n += workers - n % workers
    return max(1, -(-N // n))


def _solve_level(model, fx, X0, workers):
    """``solve_closures`` of one level's samples (the kernel runs them on ``workers``
    threads when they are many)."""
    return solve_closures(model, fx, X0, workers=workers)


def _kernels():
    from ._kernels import kernels
    return kernels()
