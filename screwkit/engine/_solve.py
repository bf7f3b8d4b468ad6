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
from ._closure import ACCEPTED, CONVERGED, STOP, _assign, gauss_newton

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

    chains: Chains
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
    """A function ``fixed (dict of (N,)) -> X0 (n_unknowns, N)``: a polynomial fit (cubic up
    to four independent parameters, quadratic beyond) of the
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
        """The monomials of the fit, ``(n_features, N)`` (poses last: the product below
        runs along contiguous rows)."""
        cols = [np.ones(Zs.shape[0])] + [Zs[:, k] for k in range(nf)]
        cols += [Zs[:, a] * Zs[:, b] for a in range(nf) for b in range(a, nf)]
        if degree == 3:
            cols += [Zs[:, a] * Zs[:, b] * Zs[:, c] for a in range(nf) for b in range(a, nf)
                     for c in range(b, nf)]
        return np.stack(cols)

    if good.sum() >= 2 * features(Z[:1]).shape[0]:
        C = np.linalg.lstsq(features(Z[good]).T, res.X[:, good].T, rcond=None)[0]
    else:                                     # too few reachable points: start at home
        C = None

    def predict(fx):
        N = len(next(iter(fx.values())))
        if C is None:
            return np.repeat(X0[:, None], N, axis=1)
        Zs = np.stack([(np.asarray(fx[p], float) - home[k]) / span[k]
                       for k, p in enumerate(ch.fixed)], axis=1)
        far = np.max(np.abs(Zs), axis=1) > 4.0          # far outside the fit: home itself
        # einsum, not a BLAS product: a threaded BLAS call here leaves OpenBLAS's threads
        # spinning on the cores that the engine's chunk threads need
        out = np.einsum("fn,fk->kn", features(Zs), C)
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


def _newton_with_continuation(ch: Chains, fixed: dict, X0, continuation: bool = True):
    """Newton from ``X0``; the poses that fail are solved again by continuation from home
    (unless ``continuation`` is False)."""
    res = gauss_newton(ch, fixed, X0, tol=_tolerance(ch, fixed, X0))
    fail = ~(res.residual <= CONVERGED)
    how = np.zeros(len(res.residual), int)
    if fail.any() and continuation:
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
                if not alive.any():
                    break
            if not alive.any():
                continue            # every pose lost the track on the way: try finer steps
            done = alive & (r.residual <= CONVERGED)
            better = r.residual < res.residual[idx]
            upd = idx[better]
            res.X[:, upd] = X[:, better]
            res.residual[upd] = r.residual[better]
            res.iterations[upd] += r.iterations[better]
            how[upd] = 1
            idx, target = idx[~done], {p: v[~done] for p, v in target.items()}
    # a pose left just short of convergence (its steps stalled on the way, e.g. along a
    # continuation) is polished by a fresh Newton run from where it stands
    polished = np.zeros(len(res.residual), bool)
    short = np.flatnonzero((res.residual > CONVERGED) & (res.residual <= ACCEPTED))
    if short.size:
        sub = {p: np.asarray(v, float)[short] for p, v in fixed.items()}
        Xs = res.X[:, short]
        r = gauss_newton(ch, sub, Xs, tol=_tolerance(ch, sub, Xs))
        better = r.residual < res.residual[short]
        upd = short[better]
        res.X[:, upd] = r.X[:, better]
        res.residual[upd] = r.residual[better]
        res.iterations[upd] += r.iterations[better]
        polished[upd] = True
    how[~(res.residual <= ACCEPTED)] = 2
    res.how = how
    res.polished = polished
    return res


def solve_closures(model, fixed: dict, start=None, *, side=None,
                   continuation: bool = True) -> Closure:
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
    continuation : bool
        Solve the poses where Newton fails again by continuation from home (default); a
        path's retries from a neighbour do without (its level solve did that already).
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
    res = _newton_with_continuation(ch, fixed, X0, continuation) if not near.all() else None
    if res is None:
        X = X0.copy()
        residual, its, how = np.full(N, np.inf), np.zeros(N, int), np.full(N, 2)
    else:
        X, residual, its, how = res.X, res.residual, res.iterations, res.how
    if near.any():
        Xs, rs, its_s, how_s = _resolve_singular(ch, fixed, X0, near, pair, side)
        X[:, near], residual[near], its[near], how[near] = Xs, rs, its_s, how_s
    # the frames of Newton's last iterates, recomputed where something else set the unknowns
    redo = near | (how == 1) | res.polished if res is not None else np.ones(N, bool)
    if redo.all():
        frames = forward(ch, fixed, X)
    else:
        frames = res.frames
        if redo.any():
            idx = np.flatnonzero(redo)
            frames = _assign(frames, idx, forward(ch, {p: v[idx] for p, v in fixed.items()},
                                                  X[:, idx]), tuple(fixed))
    resid = frames.residual
    if near.any():                 # an unreachable side makes the limit meaningless
        resid = np.where(near & ~np.isfinite(residual), np.inf, resid)
    return Closure(ch, X, frames, resid, its, how, sing)


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
    steps = (_SING_STEP, -_SING_STEP, 2 * _SING_STEP, -2 * _SING_STEP)
    k = idx.size
    # the four neighbouring solves as one batch
    fx = {p: np.tile(v, 4) for p, v in sub.items()}
    fx["beta"] = np.concatenate([b0 + db for db in steps])
    r = _newton_with_continuation(ch, fx, np.tile(X0[:, idx], 4))
    side_ok = np.all((r.residual <= ACCEPTED).reshape(4, k), axis=0)
    for m, db in enumerate(steps):
        vals[db] = {p: r.X[ch.unknown.index(p), m * k:(m + 1) * k] for p in pair}
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
    residual = np.where(side_ok, r.residual, np.inf)
    how = np.where(side_ok, r.how, 2)
    return X, residual, r.iterations, how


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
