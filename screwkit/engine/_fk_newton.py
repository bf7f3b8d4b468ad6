"""The forward kinematics' Gauss-Newton iteration and its continuation (private).

The state of a pose is the platform's rotation and centre and every joint value; the
actuated joints are frozen.  :func:`newton` and :func:`continuation` run the kernels of
:mod:`screwkit.engine._kernels._fk` (the inverse displacement's Newton step with the
platform's own twist as the columns and the actuated joints frozen, per-pose convergence
and step halving; the actuated values moved from a start to the targets in small steps);
:func:`nearest_solutions` searches seeds (random passive revolute joints, the platform where
the first leg then ends) for the solution nearest a start.  Used by
:mod:`screwkit.engine._forward` and :mod:`screwkit.engine._modes`.
"""

from __future__ import annotations

import numpy as np

from ._kernels._layout import CONVERGED

__all__ = ["newton", "continuation", "nearest_solutions", "seeds", "STEP", "TOL"]

#: Largest change of an actuated value per continuation step (``L`` or rad).
STEP = 0.05
#: Residual at which the forward iteration stops (below the inverse displacement's, so that
#: the poses it gives back keep their digits).
TOL = 1e-14


def _state(ch, R, o, q):
    """The kernels' state arrays ``(R (N, 3, 3), o (N, 3), X (N, 6 + n m))``."""
    N = R.shape[-1]
    X = np.zeros((N, 6 + ch.n * ch.m))
    X[:, 6:] = (q / ch.q_scale[:, :, None]).reshape(ch.n * ch.m, N).T
    # (copies: the kernels update the state in place, and a start taken from a result is
    # read-only)
    return (np.array(R.transpose(2, 0, 1), float, order="C"), np.array(o.T, float, order="C"),
            X)


def _back(ch, R, o, X):
    N = R.shape[0]
    q = X[:, 6:].T.reshape(ch.n, ch.m, N) * ch.q_scale[:, :, None]
    return np.ascontiguousarray(R.transpose(1, 2, 0)), np.ascontiguousarray(o.T), q


def newton(ch, R, o, q, *, tol=TOL, max_iter: int = 30):
    """Gauss-Newton from the states ``R (3, 3, N)``, ``o (3, N)``, ``q (n, m, N)`` with the
    actuated joints frozen (``tol``: a residual or one per pose).  Returns ``(R, o, q,
    residual (N,), iterations (N,))``."""
    from ._kernels import kernels
    from ._launch import _launch
    k = kernels()
    Rk, ok, X = _state(ch, R, o, q)
    N = Rk.shape[0]
    tol = np.ascontiguousarray(np.broadcast_to(np.asarray(tol, float), (N,)))
    res, its = np.empty(N), np.zeros(N, np.int64)
    _launch(k.newton_range, k.newton_parallel, (ch.flat.M, Rk, ok, X, tol, int(max_iter), res,
                                                 its), N, None)
    return (*_back(ch, Rk, ok, X), res, its)


def continuation(ch, start, qa0, target):
    """Move the actuated values from the start's (``start = (R, o, q)``, its actuated values
    ``qa0 (n, N)``) to ``target (n, N)`` in steps of at most :data:`STEP` (``L`` for linear
    actuators, rad for rotary ones), then 4 times finer where that fails, each step started
    from the last; where both fail, Newton straight from the start (``steps`` 0: it may land
    in another assembly mode).  Returns ``(R, o, q, residual, iterations, steps)``."""
    from ._kernels import kernels
    from ._launch import _launch
    k = kernels()
    R0, o0, X0 = _state(ch, *start)
    N = R0.shape[0]
    act = ch.actuator_slots
    unit = np.ascontiguousarray(np.where(ch.rotation[act] > 0, 1.0, ch.length))
    R, o, X = R0.copy(), o0.copy(), X0.copy()
    res, its, how = np.empty(N), np.zeros(N, np.int64), np.zeros(N, np.int64)
    _launch(k.continuation_range, k.continuation_parallel,
            (ch.flat.M, R0, o0, X0, np.ascontiguousarray(np.asarray(target, float).T), unit, R,
             o, X, res, its, how), N, None)
    return (*_back(ch, R, o, X), res, its, how)


def seeds(model, ch, target, K, rng):
    """``K`` seeds per row of ``target (P, n)``: random passive revolute joints, the platform
    where the first leg ends; ``(R (3, 3, P K), o (3, P K), q (n, m, P K))``, pose-major."""
    P = target.shape[0]
    q = np.zeros((ch.n, ch.m, P * K))
    rot = (ch.rotation > 0) & ch.real
    q[rot] = rng.uniform(-np.pi, np.pi, (int(rot.sum()), P * K))
    q[:, :, ::K] = 0.0                                       # the first seed is home
    q[ch.actuator_slots] = np.repeat(target, K, axis=0).T
    from ._launch import frames
    N = P * K
    X = np.zeros((N, ch.n_unknowns))
    X[:, len(ch.unknown):] = (q / ch.q_scale[:, :, None]).reshape(ch.n * ch.m, N).T
    fr = frames(ch.flat, ch.flat.Z, np.zeros((N, 6)), X, slots=True)
    Rl, tl = fr["R"][:, 0, -1], fr["t"][:, 0, -1]          # the first leg's end displacement
    Rh, ph = (np.asarray(x, float) for x in model.platform_home)
    R = np.einsum("Nij,jk->ikN", Rl, Rh)
    o = np.einsum("Nij,j->iN", Rl, ph) + tl.T
    return R, o, q


def nearest_solutions(model, ch, target, start, idx, K: int = 96, seed: int = 0):
    """For each row of ``target (P, n)``, the converged seed solution nearest the start's
    platform pose (``start``: the forward kinematics' start states, ``idx`` the poses')."""
    P = target.shape[0]
    R, o, q = seeds(model, ch, target, K, np.random.default_rng(seed))
    R, o, q, res, its = newton(ch, R, o, q, max_iter=80)
    R0, o0 = start[0][..., idx], start[1][:, idx]
    d = (np.max(np.abs(o - np.repeat(o0, K, axis=1)), axis=0) / ch.length +
         np.max(np.abs(R - np.repeat(R0, K, axis=2)), axis=(0, 1)))
    d = np.where(res <= CONVERGED, d, np.inf).reshape(P, K)
    best = np.argmin(d, axis=1) + K * np.arange(P)
    return R[..., best], o[:, best], q[..., best], res[best], its[best]


