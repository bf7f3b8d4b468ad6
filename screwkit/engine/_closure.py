"""Batched Gauss-Newton on the loop closures (private).

Unknowns per pose: the dependent pose parameters (lengths divided by ``L``),
then every leg's joint values slot by slot (P joints divided by ``L``).  The
equations: each leg's closure error ``e_i = [d / L; w]`` vanishes.  Linearised,
``P dx - T_i dq_i = -e_i`` for every leg ``i`` (``P``: platform twists of the
dependent parameters, ``T_i``: the leg's joint twists, both length-normalised).

The step is solved leg by leg (a Schur complement): with ``G_i = T_i^T T_i``,
``dq_i = G_i^-1 T_i^T (e_i + P dx)``, and ``dx`` makes every ``e_i + P dx`` lie
in the span of ``T_i``: ``sum_i P^T (I - T_i G_i^-1 T_i^T) (P dx + e_i) = 0``.
For a square, regular system this is the Gauss-Newton step; for a leg with
more joints than its rank (the spin of an S-S leg) a small Tikhonov shift of
``G_i`` gives the least-norm joint motion.  Every pose has its own convergence
test and step halving; a pose whose residual stalls is flagged, not dropped.
"""

from __future__ import annotations

import numpy as np

from . import _algebra as alg
from ._chains import Chains, forward, normalised_twists, platform_columns

__all__ = ["CONVERGED", "ACCEPTED", "newton_step", "gauss_newton", "NewtonResult"]

#: Length-normalised closure residual regarded as converged (success).
CONVERGED = 1e-10
#: Largest residual returned as a (poor) solution rather than unreachable.
ACCEPTED = 1e-6
#: Residual at which the iteration stops.
STOP = 1e-12
#: Relative Tikhonov shift of a leg's Gram matrix (exact legs) and of a leg with
#: more joints than twist-space dimensions (idle motions: least-norm steps).
_SHIFT, _SHIFT_IDLE = 1e-13, 1e-7
_HALVINGS = 6
#: Shift of the reduced system: only guards against a zero pivot (a representation
#: singularity is resolved before, see _solve.py), so that ill-conditioned poses keep
#: their digits.
_SHIFT_REDUCED = 1e-20


def _gram(ch: Chains, T, frozen=None):
    """Every leg's Gram matrix ``T^T T`` ``(m, m, n, N)`` (padded and frozen slots: identity)
    and its Tikhonov shift ``(n, N)``."""
    G = np.einsum("ialN,jalN->ijlN", T, T)
    pad = ~ch.real if frozen is None else ~ch.real | frozen
    if pad.any():
        idx = np.arange(ch.m)
        G[idx, idx] += pad.T[:, :, None]
    tr = np.einsum("iilN->lN", G)
    idle = (np.array(ch.sizes) > 6)[:, None]
    shift = tr / np.array(ch.sizes)[:, None] * np.where(idle, _SHIFT_IDLE, _SHIFT)
    return G, shift


def newton_step(ch: Chains, fr, e=None, *, Pt=None, frozen=None):
    """The Gauss-Newton step ``dX (n_unknowns, N)`` at the frames ``fr``.

    ``e (6, n, N)`` replaces the closure error (the sensitivities of the
    predictor solve the same system for other right-hand sides).  ``Pt (6, nu, N)``
    replaces the platform columns of the dependent pose parameters, and the joints of
    ``frozen (n, m)`` do not move (the forward kinematics, :mod:`screwkit.engine._forward`,
    gives the platform's own twist and freezes the actuated joints).
    """
    n, m = ch.n, ch.m
    e = fr.error if e is None else e
    N = e.shape[-1]
    T = normalised_twists(ch, fr)                                  # (m, 6, n, N)
    if frozen is not None:
        T = T * ~frozen.T[:, None, :, None]
    if Pt is None:
        Pt = platform_columns(ch, fr, ch.unknown)                  # (6, nu, N)
    nu = Pt.shape[1]
    G, shift = _gram(ch, T, frozen)
    B = np.empty((m, 1 + nu, n, N))                                # T_j^T [e | P]
    B[:, 0] = np.einsum("jalN,alN->jlN", T, e)
    if nu:
        B[:, 1:] = np.einsum("jalN,akN->jklN", T, Pt)
    Xs = alg.sym_solve(G, list(B), shift)
    Xs = np.stack(Xs)                                              # (m, 1 + nu, n, N)
    if nu:
        # reduced system: sum_i P^T (I - T_i G_i^-1 T_i^T) (P dx + e_i) = 0
        A = n * np.einsum("akN,abN->kbN", Pt, Pt) - np.einsum("jalN,jblN->abN", B[:, 1:],
                                                                Xs[:, 1:])
        r = np.einsum("akN,alN->kN", Pt, e) - np.einsum("jalN,jlN->aN", Xs[:, 1:], B[:, 0])
        trA = np.einsum("aaN->N", A)
        dx, _ = alg.spd_solve(A, list(-r), trA * (_SHIFT_REDUCED / nu))
        dx = np.stack(dx)
        dq = Xs[:, 0] + np.einsum("jalN,aN->jlN", Xs[:, 1:], dx)  # (m, n, N)
    else:
        dx, dq = np.zeros((0, N)), Xs[:, 0]
    return np.concatenate([dx, dq.transpose(1, 0, 2).reshape(n * m, N)])


class NewtonResult:
    """Solutions of N loop-closure problems.

    Attributes
    ----------
    X : ndarray (n_unknowns, N)
    residual : ndarray (N,)
        Largest length-normalised closure error.
    iterations : ndarray (N,) of int
    stalled : ndarray (N,) of bool
        The residual stopped decreasing before reaching :data:`STOP`.
    """

    def __init__(self, X, residual, iterations, stalled):
        self.X, self.residual, self.iterations, self.stalled = X, residual, iterations, stalled


def _take(fixed, idx):
    return {k: v[idx] for k, v in fixed.items()}


def _sq(e):
    return (e * e).sum(axis=(0, 1))


def gauss_newton(ch: Chains, fixed: dict, X0, *, tol: float = STOP, max_iter: int = 30):
    """Solve the loop closures of ``N`` poses from the starts ``X0 (n_unknowns, N)``.

    Returns
    -------
    NewtonResult

    Notes
    -----
    An iterate that runs away (an absurd target far outside the workspace) may overflow:
    its residual is then not finite, the pose stops and is flagged (``stalled``, then
    unreachable), so numpy's overflow warnings are silenced here rather than printed.
    """
    with np.errstate(over="ignore", invalid="ignore", divide="ignore"):
        return _gauss_newton(ch, fixed, X0, tol, max_iter)


def _gauss_newton(ch: Chains, fixed: dict, X0, tol, max_iter):
    X = np.array(X0, float)
    N = X.shape[1]
    tol = np.broadcast_to(np.asarray(tol, float), (N,))
    tol_a = tol
    res = np.full(N, np.inf)
    its = np.zeros(N, int)
    stalled = np.zeros(N, bool)
    idx = np.arange(N)
    fx = fixed
    fr = forward(ch, fx, X)
    final = fr                              # frames of every pose at its last iterate
    f = fr.residual
    res[:] = f
    for _ in range(max_iter):
        keep = np.isfinite(f) & (f > tol_a)
        stalled[idx[~np.isfinite(f)]] = True
        if not keep.any():
            break
        if not keep.all():
            idx = idx[keep]
            fx = _take(fx, keep)
            fr = _subset(fr, keep)
            tol_a = tol_a[keep]
        Xa = X[:, idx]
        step = newton_step(ch, fr)
        e2 = _sq(fr.error)
        Xn = Xa + step
        frn = forward(ch, fx, Xn)
        ok = np.isfinite(frn.error).all(axis=(0, 1)) & (_sq(frn.error) < e2)
        for _ in range(_HALVINGS):
            if ok.all():
                break
            bad = ~ok
            step[:, bad] *= 0.5
            Xb = Xa[:, bad] + step[:, bad]
            frb = forward(ch, _take(fx, bad), Xb)
            okb = np.isfinite(frb.error).all(axis=(0, 1)) & (_sq(frb.error) < e2[bad])
            where = np.flatnonzero(bad)[okb]
            Xn[:, where] = Xb[:, okb]
            frn = _assign(frn, where, _subset(frb, okb), fixed)
            ok[where] = True
        X[:, idx[ok]] = Xn[:, ok]
        final = _assign(final, idx[ok], _subset(frn, ok), fixed) if not ok.all() or idx.size < N \
            else frn
        its[idx] += 1
        stalled[idx[~ok]] = True
        # poses that could not decrease keep their last values and leave
        if not ok.all():
            idx, fx, frn, tol_a = idx[ok], _take(fx, ok), _subset(frn, ok), tol_a[ok]
        fr = frn
        f = fr.residual
        res[idx] = f
    out = NewtonResult(X, res, its, stalled & (res > tol))
    out.frames = final
    return out


def _subset(fr, mask):
    from ._chains import Frames
    return Frames({k: v[..., mask] for k, v in fr.params.items()}, fr.q[..., mask],
                  fr.axes[..., mask], fr.points[..., mask], fr.R_p[..., mask], fr.o[..., mask],
                  fr.E[..., mask], fr.error[..., mask])


def _assign(fr, where, other, skip=()):
    for k in fr.params:
        if k not in skip:               # the given parameters are the same in both
            fr.params[k][..., where] = other.params[k]
    for name in ("q", "axes", "points", "R_p", "o", "E", "error"):
        getattr(fr, name)[..., where] = getattr(other, name)
    return fr
