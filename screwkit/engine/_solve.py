"""Inverse displacement of N poses: starts, continuation, representation singularities (private).

Starts.  A pose without a warm start begins at a polynomial model of the
solution around home (cubic in up to four independent parameters, quadratic
beyond), fitted once per model to exact solutions on a small grid of
independent parameters (:func:`home_predictor`): the home assembly, carried
close to the pose, from where Newton converges in two or three steps.  A pose with a warm start (the neighbour on a path, a
previous solution) begins there.

Continuation.  A pose whose Newton iteration does not converge is solved again
from home by moving its independent parameters in 4, 16, then 64 steps, each
step started from the last.

Representation singularity.  Where ``beta`` is given at ``sin(beta) = 0``
(proper Euler orders) or ``cos(beta) = 0`` (Tait-Bryan) and ``alpha`` or
``gamma`` is dependent, the dependent angle is undetermined; it is taken as
its limit from both sides (average of the solutions at ``beta +- 1e-4``) or,
with a warm start, from the warm start's side (Richardson extrapolation), and
the pose is then solved with that angle given.
"""

from __future__ import annotations

import dataclasses
import itertools
import weakref

import numpy as np

from ._chains import LENGTH_PARAMS, PARAMS, Chains, chains_of, forward
from ._closure import ACCEPTED, CONVERGED, STOP, gauss_newton

__all__ = ["Closure", "Closures", "solve_closures", "home_predictor", "is_representation_singular"]

_SING_STEP = 1e-4
_SING_TOL = 1e-7
#: Within this |sin beta| (|cos beta|) of the singularity the closures determine the dependent
#: angle of the pair only to about residual / |sin beta|: it is interpolated between the
#: solutions at +-_SING_STEP instead (an error of order _SING_STEP^2).
_NEAR_TOL = 1e-5
#: Half-width of the predictor's fitting grid: radians, and fractions of ``L``.
_FIT_SPAN = 0.15


@dataclasses.dataclass(frozen=True, eq=False)
class Closure:
    """Solved loop closures of N poses.

    Attributes
    ----------
    chains : Chains
    X : ndarray (n_unknowns, N)
    frames : Frames
        Forward kinematics at ``X``.
    residual : ndarray (N,)
    iterations : ndarray (N,)
    how : ndarray (N,) of int
        0: Newton from the start; 1: continuation from home; 2: not solved.
    singular_beta : ndarray (N,) of bool
        The pose was at a representation singularity resolved by continuity.
    """

    chains: Chains
    X: np.ndarray
    frames: object
    residual: np.ndarray
    iterations: np.ndarray
    how: np.ndarray
    singular_beta: np.ndarray
    diagnostics: dict = dataclasses.field(default_factory=dict)


@dataclasses.dataclass(frozen=True, eq=False)
class Closures:
    """The solver's arrays for N poses: ``X (n_unknowns, N)``, ``fixed`` (the independent
    parameters, ``(N,)`` each), ``residual``, ``iterations``, ``how`` (0: Newton from the
    start, 1: continuation, 2: not solved), ``singular_beta``."""

    chains: object
    X: np.ndarray
    fixed: dict
    residual: np.ndarray
    iterations: np.ndarray
    how: np.ndarray
    singular_beta: np.ndarray

    def take(self, sl) -> "Closures":
        return Closures(self.chains, self.X[:, sl], {k: v[sl] for k, v in self.fixed.items()},
                        self.residual[sl], self.iterations[sl], self.how[sl],
                        self.singular_beta[sl])

    def frames(self, sl=slice(None)):
        """Forward kinematics at the poses ``sl``."""
        from ._chains import forward
        return forward(self.chains, {k: v[sl] for k, v in self.fixed.items()}, self.X[:, sl])


def is_representation_singular(order: str, beta, tol: float = _SING_TOL):
    proper = order[0].lower() == order[2].lower()
    return np.abs(np.sin(beta) if proper else np.cos(beta)) <= tol


_PREDICTORS: "weakref.WeakKeyDictionary" = weakref.WeakKeyDictionary()


def home_predictor(ch: Chains):
    """A function ``fixed (dict of (N,)) -> X0 (n_unknowns, N)``: a quadratic fit of the
    solutions around home (see the module docstring), cached per model."""
    pred = _PREDICTORS.get(ch)
    if pred is not None:
        return pred
    nf = len(ch.fixed)
    home = np.array([ch.home[p] for p in ch.fixed])
    span = np.array([_FIT_SPAN * ch.length if p in LENGTH_PARAMS else _FIT_SPAN for p in ch.fixed])
    # cubic fit on 4 levels up to 4 parameters, quadratic on 3 beyond (grid sizes 4^4, 3^6);
    # no level at 0, so that no fitting pose sits at a representation singularity of home
    degree = 3 if nf <= 4 else 2
    levels = (np.array([-1.0, -1.0 / 3.0, 1.0 / 3.0, 1.0]) if degree == 3
              else np.array([-1.0, 0.1, 1.0]))
    Z = np.array(list(itertools.product(levels, repeat=nf)))
    fixed = {p: home[k] + span[k] * Z[:, k] for k, p in enumerate(ch.fixed)}
    res = _newton_with_continuation(ch, fixed, ch.home_vector(len(Z)))
    good = res.residual <= CONVERGED
    X0 = ch.home_vector(1)[:, 0]

    def features(Zs):
        cols = [np.ones(Zs.shape[0])] + [Zs[:, k] for k in range(nf)]
        cols += [Zs[:, a] * Zs[:, b] for a in range(nf) for b in range(a, nf)]
        if degree == 3:
            cols += [Zs[:, a] * Zs[:, b] * Zs[:, c] for a in range(nf) for b in range(a, nf)
                     for c in range(b, nf)]
        return np.stack(cols, axis=1)

    if good.sum() >= 2 * features(Z[:1]).shape[1]:
        C = np.linalg.lstsq(features(Z[good]), res.X[:, good].T, rcond=None)[0]
    else:                                     # too few reachable points: start at home
        C = None

    def predict(fx):
        N = len(next(iter(fx.values())))
        if C is None:
            return np.repeat(X0[:, None], N, axis=1)
        Zs = np.stack([(np.asarray(fx[p], float) - home[k]) / span[k]
                       for k, p in enumerate(ch.fixed)], axis=1)
        far = np.max(np.abs(Zs), axis=1) > 4.0          # far outside the fit: home itself
        out = (features(Zs) @ C).T
        out[:, far] = X0[:, None]
        return out

    _PREDICTORS[ch] = predict
    return predict


def _tolerance(ch: Chains, fixed: dict, X0):
    """Stopping residual per pose: tighter near a representation singularity, where the
    dependent angle of the pair (alpha, gamma) is determined only to residual / sin(beta)."""
    if not any(p in ch.unknown for p in ("alpha", "gamma")):
        return STOP
    if "beta" in ch.fixed:
        b = fixed["beta"]
    elif "beta" in ch.unknown:
        b = X0[ch.unknown.index("beta")]
    else:
        return STOP
    proper = ch.order[0].lower() == ch.order[2].lower()
    s = np.abs(np.sin(b) if proper else np.cos(b))
    return np.maximum(STOP * np.minimum(1.0, s / 1e-2), 1e-16)


def _newton_with_continuation(ch: Chains, fixed: dict, X0):
    """Newton from ``X0``; the poses that fail are solved again by continuation from home."""
    res = gauss_newton(ch, fixed, X0, tol=_tolerance(ch, fixed, X0))
    fail = ~(res.residual <= CONVERGED)
    how = np.zeros(len(res.residual), int)
    if fail.any():
        idx = np.flatnonzero(fail)
        home = {p: ch.home[p] for p in ch.fixed}
        target = {p: np.asarray(v, float)[idx] for p, v in fixed.items()}
        for steps in (4, 16, 64):
            if idx.size == 0:
                break
            X = ch.home_vector(idx.size)
            alive = np.ones(idx.size, bool)
            for s in range(1, steps + 1):
                fx = {p: home[p] + (target[p] - home[p]) * s / steps for p in ch.fixed}
                r = gauss_newton(ch, fx, X, tol=1e-12 if s == steps else 1e-8)
                X = r.X
                alive &= r.residual <= (1e-4 if s < steps else np.inf)
            done = alive & (r.residual <= CONVERGED)
            better = r.residual < res.residual[idx]
            upd = idx[better]
            res.X[:, upd] = X[:, better]
            res.residual[upd] = r.residual[better]
            res.iterations[upd] += r.iterations[better]
            how[upd] = 1
            idx, target = idx[~done], {p: v[~done] for p, v in target.items()}
    how[~(res.residual <= ACCEPTED)] = 2
    res.how = how
    return res


def solve_closures(model, fixed: dict, start=None, *, side=None) -> Closure:
    """Solve N poses of ``model``.

    Parameters
    ----------
    model : PMModel
    fixed : dict str -> ndarray (N,)
        The independent pose parameters (radians, model lengths), finite.
    start : ndarray (n_unknowns, N), optional
        Warm starts; default the home predictor.
    side : ndarray (N,), optional
        Sign of ``beta - beta_singular`` of the warm start, for the one-sided limit at
        a representation singularity (0: both sides).
    """
    ch = chains_of(model)
    fixed = {p: np.asarray(fixed[p], float) for p in ch.fixed}
    N = len(next(iter(fixed.values())))
    X0 = home_predictor(ch)(fixed) if start is None else np.array(start, float)
    sing = near = np.zeros(N, bool)
    pair = [p for p in ("alpha", "gamma") if p in ch.unknown]
    if "beta" in ch.fixed and pair:
        sing = is_representation_singular(ch.order, fixed["beta"])
        near = is_representation_singular(ch.order, fixed["beta"], _NEAR_TOL)
    res = _newton_with_continuation(ch, fixed, X0) if not near.all() else None
    if res is None:
        X = X0.copy()
        residual, its, how = np.full(N, np.inf), np.zeros(N, int), np.full(N, 2)
    else:
        X, residual, its, how = res.X, res.residual, res.iterations, res.how
    if near.any():
        Xs, rs, its_s, how_s = _resolve_singular(ch, fixed, X0, near, pair, side)
        X[:, near], residual[near], its[near], how[near] = Xs, rs, its_s, how_s
    frames = res.frames if (res is not None and not near.any() and not (how == 1).any()) \
        else forward(ch, fixed, X)
    return Closure(ch, X, frames, frames.residual, its, how, sing)


def _resolve_singular(ch, fixed, X0, sing, pair, side):
    idx = np.flatnonzero(sing)
    sub = {p: v[idx] for p, v in fixed.items()}
    sd = np.zeros(idx.size) if side is None else np.sign(np.asarray(side, float)[idx])
    beta = sub["beta"]
    proper = ch.order[0].lower() == ch.order[2].lower()
    off = 0.0 if proper else 0.5 * np.pi
    b0 = np.round((beta - off) / np.pi) * np.pi + off          # the singular value nearby
    u = beta - b0
    lims = {}
    both = (sd == 0) | ~is_representation_singular(ch.order, beta)
    vals = {}
    for db in (_SING_STEP, -_SING_STEP, 2 * _SING_STEP, -2 * _SING_STEP):
        fx = dict(sub, beta=b0 + db)
        r = _newton_with_continuation(ch, fx, X0[:, idx])
        vals[db] = {p: r.X[ch.unknown.index(p)] for p in pair}
    for p in pair:
        avg = 0.5 * (vals[_SING_STEP][p] + vals[-_SING_STEP][p]) + \
            (vals[_SING_STEP][p] - vals[-_SING_STEP][p]) * (u / (2 * _SING_STEP))
        one = np.where(sd > 0, 2 * vals[_SING_STEP][p] - vals[2 * _SING_STEP][p],
                       2 * vals[-_SING_STEP][p] - vals[-2 * _SING_STEP][p])
        lims[p] = np.where(both, avg, one)
    # solve with the limiting angle(s) given
    sch = _with_fixed(ch, tuple(pair))
    fx = dict(sub, **lims)
    keep = [k for k, u in enumerate(ch.unknown) if u not in pair]
    Xs0 = np.concatenate([X0[keep][:, idx], X0[len(ch.unknown):][:, idx]])
    r = _newton_with_continuation(sch, fx, Xs0)
    X = np.zeros((ch.n_unknowns, idx.size))
    for k, u in enumerate(ch.unknown):
        X[k] = lims[u] if u in pair else r.X[keep.index(k)]
    X[len(ch.unknown):] = r.X[len(keep):]
    return X, r.residual, r.iterations, r.how


def _lagrange(ts, j, t):
    """Weight of node ``j`` of the cubic through the nodes ``ts (4, K)`` at ``t (K,)``."""
    w = np.ones_like(t)
    for i in range(4):
        if i != j:
            w = w * (t - ts[i]) / (ts[j] - ts[i])
    return w


_DERIVED: "weakref.WeakKeyDictionary" = weakref.WeakKeyDictionary()


def _with_fixed(ch: Chains, extra: tuple) -> Chains:
    """The same chains with more pose parameters given (cached)."""
    table = _DERIVED.setdefault(ch, {})
    if extra not in table:
        fixed = ch.fixed + tuple(p for p in extra if p not in ch.fixed)
        unknown = tuple(p for p in PARAMS if p not in fixed)
        table[extra] = dataclasses.replace(
            ch, fixed=fixed, unknown=unknown,
            x_scale=np.array([ch.length if u in LENGTH_PARAMS else 1.0 for u in unknown]))
    return table[extra]


#: Anchors of a path: about this many samples are solved one after the other.
PATH_ANCHORS = 64


def solve_path(model, fixed: dict, start=None, *, anchor_every=None, progress=None) -> Closure:
    """Solve N samples of a continuous path, each warm-started from its neighbours.

    About :data:`PATH_ANCHORS` anchor samples are solved in order, each from the
    previous one (the first from ``start`` or home, with continuation where Newton
    fails); the samples between two solved ones are then solved level by level,
    halving the spacing, from the linear interpolation of their solved neighbours,
    all of a level at once.  A sample whose solution is not close to that
    interpolation (a jump to another branch) or that does not converge is solved
    again from its left neighbour alone.
    """
    ch = chains_of(model)
    fixed = {p: np.asarray(fixed[p], float) for p in ch.fixed}
    N = len(next(iter(fixed.values())))
    K = max(1, -(-N // PATH_ANCHORS)) if anchor_every is None else max(1, int(anchor_every))
    anchors = list(range(0, N, K))
    if anchors[-1] != N - 1:
        anchors.append(N - 1)
    X = np.zeros((ch.n_unknowns, N))
    res = np.full(N, np.inf)
    its = np.zeros(N, int)
    how = np.full(N, 2)
    sing = np.zeros(N, bool)
    prev = None if start is None else np.array(start, float).reshape(ch.n_unknowns, -1)[:, :1]
    last = []                                   # the last two solved anchors (index, X)
    for i in anchors:
        fx = {p: v[i:i + 1] for p, v in fixed.items()}
        X0 = prev
        if len(last) == 2:
            # the secant through the last two anchors, where it starts closer than the last one
            (i1, X1), (i2, X2) = last
            cand = np.concatenate([X2, X2 + (X2 - X1) * ((i - i2) / (i2 - i1))], axis=1)
            fr = forward(ch, {p: np.repeat(v, 2) for p, v in fx.items()}, cand)
            X0 = cand[:, int(np.argmin(fr.residual))][:, None]
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
    while not solved.all():
        idx = np.flatnonzero(solved)
        k = np.flatnonzero(idx[1:] - idx[:-1] > 1)
        left, right = idx[k], idx[k + 1]
        mid = (left + right) // 2
        good = res <= ACCEPTED
        good_l, good_r = good[left], good[right]
        Xl, Xr = X[:, left], X[:, right]
        w = ((mid - left) / (right - left))[None]
        Xs = np.where(good_l & good_r, (1 - w) * Xl + w * Xr, np.where(good_l, Xl, Xr))
        # the cubic through the two solved neighbours on each side, where all four are good
        k0, k3 = np.maximum(k - 1, 0), np.minimum(k + 2, len(idx) - 1)
        p0, p3 = idx[k0], idx[k3]
        four = (k0 < k) & (k3 > k + 1) & good_l & good_r & good[p0] & good[p3]
        if four.any():
            ts = np.stack([p0, left, right, p3]).astype(float)[:, four]
            t = mid[four].astype(float)
            Xs[:, four] = sum(_lagrange(ts, j, t) * X[:, ts[j].astype(int)] for j in range(4))
        fx = {p: v[mid] for p, v in fixed.items()}
        c = solve_closures(model, fx, Xs)
        Xm, rm, hm = c.X, c.residual, c.how
        # a branch jump: the solution moved more than its neighbours differ
        span = np.max(np.abs(Xr - Xl), axis=0)
        moved = np.max(np.abs(Xm - Xs), axis=0)
        jump = (moved > 0.5 * span + 1e-9) & good_l & good_r & (hm == 0)
        X[:, mid], res[mid], its[mid], how[mid], sing[mid] = Xm, rm, c.iterations, hm, \
            c.singular_beta
        for k in np.flatnonzero(jump | ~(rm <= CONVERGED)):
            i = mid[k]
            src = left[k] if res[left[k]] <= ACCEPTED else right[k]
            c1 = solve_closures(model, {p: v[i:i + 1] for p, v in fixed.items()},
                                X[:, src:src + 1])
            retried += 1
            if c1.residual[0] <= res[i] or jump[k]:
                X[:, i], res[i], its[i], how[i], sing[i] = c1.X[:, 0], c1.residual[0], \
                    c1.iterations[0], c1.how[0], c1.singular_beta[0]
        solved[mid] = True
        if progress:
            progress(int(solved.sum()), N)
    diag = {"anchors": len(anchors), "batched": N, "retried": retried}
    return Closure(ch, X, None, res, its, how, sing, diag)
