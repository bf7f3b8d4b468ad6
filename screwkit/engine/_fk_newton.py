"""The forward kinematics' Gauss-Newton iteration and its continuation (private).

The state of a pose is the platform's rotation and centre and every joint value; the
actuated joints are frozen.  :func:`newton` is the engine's Gauss-Newton step
(:func:`~screwkit.engine._closure.newton_step` with the platform's own twist as the columns
and the actuated joints frozen) with per-pose convergence and step halving;
:func:`continuation` moves the actuated values from a start to the targets in small steps;
:func:`nearest_solutions` searches seeds (random passive revolute joints, the platform where
the first leg then ends) for the solution nearest a start.  Used by
:mod:`screwkit.engine._forward` and :mod:`screwkit.engine._modes`.
"""

from __future__ import annotations

import numpy as np

from . import _algebra as alg
from ._chains import chain_forward, closure_error
from ._closure import CONVERGED, newton_step

__all__ = ["newton", "continuation", "nearest_solutions", "seeds", "STEP", "TOL"]

#: Largest change of an actuated value per continuation step (``L`` or rad).
STEP = 0.05
#: The continuation is tried with 1 and 4 times as many steps.
REFINE_STEPS = (1, 4)
MAX_STEPS = 32
#: Residual at which the forward iteration stops (below the inverse displacement's, so that
#: the poses it gives back keep their digits).
TOL = 1e-14
_HALVINGS = 8


class _Frames:
    """What the Newton step needs of a forward-kinematics state."""

    def __init__(self, ch, R, o, q):
        self.axes, self.points, Rl, tl = chain_forward(ch.D, ch.P, ch.rotation, ch.translation,
                                                       q, bars=ch.bars)
        self.error = closure_error(ch, R, o, Rl, tl)
        self.residual = np.max(np.abs(self.error), axis=(0, 1))


def _frozen(ch):
    f = np.zeros((ch.n, ch.m), bool)
    f[ch.actuator_slots] = True
    return f


def _apply(ch, R, o, q, dX, scale):
    """The state moved by ``scale * dX`` (platform twist about the centroid, then joints)."""
    d = dX * scale
    w, v = d[3:6], d[:3] * ch.length
    ang = alg.norm(w)
    Rw = alg.rodrigues(w / np.where(ang > 0, ang, 1.0), ang)
    c = ch.centre[:, None]
    R2 = alg.matmul(Rw, R)
    o2 = alg.matvec(Rw, o - c) + c + v
    q2 = q + d[6:].reshape(ch.n, ch.m, -1) * ch.q_scale[:, :, None]
    return R2, o2, q2


def newton(ch, R, o, q, *, tol=TOL, max_iter: int = 30):
    """Gauss-Newton from the states ``R (3, 3, N)``, ``o (3, N)``, ``q (n, m, N)`` with the
    actuated joints frozen (``tol``: a residual or one per pose).  Returns ``(R, o, q,
    residual (N,), iterations (N,))``."""
    R, o, q = R.copy(), o.copy(), q.copy()
    N = R.shape[-1]
    tol = np.broadcast_to(np.asarray(tol, float), (N,))
    frozen = _frozen(ch)
    Pt = np.broadcast_to(np.eye(6)[:, :, None], (6, 6, N))
    res = _Frames(ch, R, o, q).residual
    its = np.zeros(N, int)
    live = np.flatnonzero(np.isfinite(res) & (res > tol))
    for _ in range(max_iter):
        if live.size == 0:
            break
        Ra, oa, qa = R[..., live], o[:, live], q[..., live]
        fr = _Frames(ch, Ra, oa, qa)
        step = newton_step(ch, fr, Pt=Pt[..., :live.size], frozen=frozen)
        e2 = np.sum(fr.error ** 2, axis=(0, 1))
        done = np.zeros(live.size, bool)
        for h in range(_HALVINGS):
            todo = np.flatnonzero(~done)
            if todo.size == 0:
                break
            Rn, on, qn = _apply(ch, Ra[..., todo], oa[:, todo], qa[..., todo], step[:, todo],
                                0.5 ** h)
            frn = _Frames(ch, Rn, on, qn)
            better = np.isfinite(frn.residual) & (np.sum(frn.error ** 2, axis=(0, 1))
                                                  < e2[todo])
            k = todo[better]
            R[..., live[k]], o[:, live[k]], q[..., live[k]] = Rn[..., better], on[:, better], \
                qn[..., better]
            res[live[k]] = frn.residual[better]
            done[k] = True
        its[live] += 1
        live = live[done & (res[live] > tol[live])]
    return R, o, q, res, its


def continuation(ch, start, qa0, target):
    """Move the actuated values from ``qa0`` to ``target`` ``(n, N)`` in steps of at most
    :data:`STEP` (``L`` for linear actuators, rad for rotary ones), then 4 times finer where
    that fails, each step started from the last; where both fail, Newton straight from the
    start (``steps`` 0: it may land in another assembly mode)."""
    R0, o0, q0 = start
    N = target.shape[1]
    R, o, q = R0.copy(), o0.copy(), q0.copy()
    res = np.full(N, np.inf)
    its = np.zeros(N, int)
    how = np.full(N, -1)
    act = ch.actuator_slots
    unit = np.where(ch.rotation[act] > 0, 1.0, ch.length)[:, None]
    delta = target - qa0
    S0 = np.clip(np.ceil(np.max(np.abs(delta) / unit, axis=0) / STEP), 1, MAX_STEPS)
    todo = np.arange(N)
    for mult in REFINE_STEPS + (0,):
        if todo.size == 0:
            break
        S = np.maximum(S0[todo] * mult, 1)
        live = todo.copy()                       # the poses of this pass still stepping
        Rs, os_, qs = R0[..., live].copy(), o0[:, live].copy(), q0[..., live].copy()
        Sl = S.copy()
        for s in range(1, int(S.max()) + 1):
            frac = np.minimum(1.0, s / Sl)
            qs[act] = qa0[:, live] + delta[:, live] * frac
            last = frac >= 1
            Rs, os_, qs, r, it = newton(ch, Rs, os_, qs, tol=np.where(last, TOL, 1e-8),
                                        max_iter=50 if mult == 0 else 30)
            its[live] += it
            fin = last & (r < res[live])
            k = live[fin]
            R[..., k], o[:, k], q[..., k], res[k] = Rs[..., fin], os_[:, fin], qs[..., fin], \
                r[fin]
            how[k] = Sl[fin] if mult else 0
            keep = ~last & (r <= 1e-4)           # still stepping, on the branch
            live, Sl = live[keep], Sl[keep]
            Rs, os_, qs = Rs[..., keep], os_[:, keep], qs[..., keep]
            if live.size == 0:
                break
        todo = todo[~(res[todo] <= CONVERGED)]
    return R, o, q, res, its, how


def seeds(model, ch, target, K, rng):
    """``K`` seeds per row of ``target (P, n)``: random passive revolute joints, the platform
    where the first leg ends; ``(R (3, 3, P K), o (3, P K), q (n, m, P K))``, pose-major."""
    P = target.shape[0]
    q = np.zeros((ch.n, ch.m, P * K))
    rot = (ch.rotation > 0) & ch.real
    q[rot] = rng.uniform(-np.pi, np.pi, (int(rot.sum()), P * K))
    q[:, :, ::K] = 0.0                                       # the first seed is home
    q[ch.actuator_slots] = np.repeat(target, K, axis=0).T
    _, _, Rl, tl = chain_forward(ch.D, ch.P, ch.rotation, ch.translation, q, bars=ch.bars)
    Rh, ph = (np.asarray(x, float) for x in model.platform_home)
    R = np.einsum("ijN,jk->ikN", Rl[:, :, 0], Rh)
    o = np.einsum("ijN,j->iN", Rl[:, :, 0], ph) + tl[:, 0]
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


