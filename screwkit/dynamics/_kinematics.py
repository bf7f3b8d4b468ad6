"""Velocities, accelerations and inverse dynamics of a chunk of solved poses (poses first).

The loop-closure velocity and acceleration equations, solved with the engine's Jacobian:

1. **Platform twist.**  ``V = Xi theta_dot`` with ``Xi`` the platform twist per unit rate of
   each pose parameter (:func:`screwkit.engine.link_frames`).  The dependent rates follow
   from the constraint rows of ``J = [J_a; J_c]``: every feasible twist is reciprocal to
   them (``J_c V = 0``), so ``(J_c Xi_dep) theta_dot_dep = -J_c Xi_ind theta_dot_ind``.
2. **Joint rates** of each leg from ``T qdot = V`` (:class:`~._legs.LegSolver`); an idle
   motion (the spin of an S-S leg) is given the rate of least kinetic energy, which for
   links symmetric about the spin axis is zero spin, the motion the dynamics keeps.
3. **Platform acceleration.**  ``A = Xi theta_ddot + Xi_dot theta_dot``; ``Xi_dot`` by the
   screw products of the platform's virtual chain (three translations, then the Euler
   angles as revolute joints through ``o``, :attr:`LinkFrames.euler_chain`).  Each leg gives
   ``T qddot + b = A`` (``b`` its bias, :func:`~._legs.bias_terms`); its constraint rows
   annihilate ``T qddot``, so ``J_c,i (Xi_dep theta_ddot_dep) = J_c,i b_i - J_c,i (Xi_ind
   theta_ddot_ind + Xi_dot theta_dot)`` row by row: the same matrix as for the rates.  No
   finite differences: every derivative is a screw product.
4. **Joint accelerations** from ``T qddot = A - b``; an idle motion's acceleration is the one
   that needs no effort (its generalised force vanishes), as the dynamics has it.
5. **Inverse dynamics** (:mod:`~._newton_euler`): each leg's joint efforts ``ID``, its mapped
   wrench ``u`` (``T^T u = -ID``, :meth:`~._legs.LegSolver.mapped_wrench`), the platform's
   own wrench ``W_p``; the dynamic workload of the unified statics is ``W_ext - W_p + sum u``.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from ..screws import RANK_RTOL
from ._legs import LegSolver, bias_terms
from ._newton_euler import leg_efforts, mass_product, platform_wrench
from ._parallelogram import pa_state
from ._spatial import cross3, cross_motion

__all__ = ["Context", "chunk_dynamics", "column_rates", "dependent_inverse"]

#: Largest condition number of the (equilibrated) dependent-rate system still solved.
KIN_COND = 1.0 / RANK_RTOL


@dataclass(frozen=True, eq=False)
class Context:
    """Constant inputs of the chunks: leg setups, which parameters are independent
    (indices into ``Xo Yo Zo alpha beta gamma``), the number of actuation rows, the leg of
    each constraint row, the platform body, gravity (world), the normalisation ``c, L``,
    the external workload ``F, T`` at ``o``."""

    setups: tuple
    ind: np.ndarray
    dep: np.ndarray
    n_act: int
    row_leg: np.ndarray
    platform: object
    g: np.ndarray
    c: np.ndarray
    L: float
    F: np.ndarray
    T: np.ndarray


def column_rates(Xi, thd, chain):
    """``Xi_dot theta_dot`` ``(N, 6)``: the screw products along the platform's virtual chain
    (translations first, then the angles in ``chain`` order)."""
    Vb = np.einsum("nak,nk->na", Xi[:, :, :3], thd[:, :3])
    out = np.zeros_like(Vb)
    for k in chain:
        col = Xi[:, :, 3 + k]
        out += thd[:, 3 + k, None] * cross_motion(Vb, col)
        Vb = Vb + thd[:, 3 + k, None] * col
    return out


def _unit_scales(Jc, Xi, c, L):
    """Row and column factors ``(N, mc)``, ``(N, nd)`` that make ``J_c Xi_dep`` scale as one
    under a change of length unit: a constraint row by ``1 / |[f; m_c / L]|`` (a couple
    row's entries are torques, a force row's forces or torques), a column by ``1 / |[v_c /
    L; w]|`` (a translation's rate is a length's, an angle's is not); about the
    normalisation centre ``c``, so that a move of the base frame changes neither."""
    f, m = Jc[..., :3], Jc[..., 3:] - np.cross(c, Jc[..., :3])
    rows = np.sqrt(np.sum(f * f, axis=-1) + np.sum(m * m, axis=-1) / L ** 2)
    Xt = Xi.transpose(0, 2, 1)                          # (N, nd, 6)
    v, w = Xt[..., :3] - np.cross(c, Xt[..., 3:]), Xt[..., 3:]
    cols = np.sqrt(np.sum(v * v, axis=-1) / L ** 2 + np.sum(w * w, axis=-1))
    return 1.0 / np.maximum(rows, 1e-300), 1.0 / np.maximum(cols, 1e-300)


def dependent_inverse(A, scales=None):
    """The equilibrated pseudo-inverse ``(N, nd, mc)`` of ``A = J_c Xi_dep (N, mc, nd)`` and
    its condition number ``(N,)`` (``inf`` where the rates are not determined: a
    representation singularity of the Euler angles, a constraint singularity).  ``scales``
    (rows, columns: :func:`_unit_scales`) first make ``A`` free of the length unit; its
    rows and columns are then equilibrated by their norms."""
    r0, s0 = scales if scales is not None else (np.ones(A.shape[:2]),
                                                 np.ones((A.shape[0], A.shape[2])))
    A = A * r0[:, :, None] * s0[:, None, :]
    r = r0 / np.maximum(np.linalg.norm(A, axis=2), 1e-300)
    s = s0 / np.maximum(np.linalg.norm(A, axis=1), 1e-300)
    An = A * (r / r0)[:, :, None] * (s / s0)[:, None, :]
    bad = ~np.all(np.isfinite(An), axis=(1, 2))
    An = np.where(bad[:, None, None], 0.0, An)
    U, S, Vt = np.linalg.svd(An, full_matrices=False)
    top = np.maximum(S[:, :1], 1e-300)
    keep = S > RANK_RTOL * top
    Sinv = np.where(keep, 1.0 / np.where(keep, S, 1.0), 0.0)
    P = np.einsum("nji,nj,nkj->nik", Vt, Sinv, U)
    cond = np.where(keep[:, -1], S[:, 0] / np.where(keep[:, -1], S[:, -1], 1.0), np.inf)
    cond[bad] = np.nan
    return P * s[:, :, None] * r[:, None, :], cond


def _idle_rates(st, solver, tw, Rs, ts, x, scale, pa=None):
    """The null-space component that makes ``x`` (rates or, with ``effort``, ...) of least
    kinetic energy: ``x - N (N^T M N)^-1 N^T M x`` (x unchanged where the idle motion
    carries no inertia)."""
    Nn = solver.null
    MN = mass_product(st, tw, Nn, Rs, ts, pa)                    # (N, m, k)
    K = np.einsum("nmk,nml->nkl", Nn, MN)
    rhs = np.einsum("nmk,nm->nk", Nn, mass_product(st, tw, x, Rs, ts, pa))
    return Nn, MN, K, rhs, _idle_solve(K, rhs, scale)


def _idle_solve(K, rhs, scale):
    """``-K^-1 rhs`` where ``K`` is significant, else 0 (an idle motion with no inertia)."""
    k = K.shape[-1]
    big = np.abs(np.einsum("nii->n", K)) > 1e-12 * scale
    Ks = np.where(big[:, None, None], K, np.eye(k))
    z = -np.linalg.solve(Ks, rhs[..., None])[..., 0]
    return np.where(big[:, None], z, 0.0)


def chunk_dynamics(ctx: Context, lf, J, thd_ind, thdd_ind, dependent=None) -> dict:
    """Rates, accelerations, efforts and the dynamic workload of one chunk.

    Parameters
    ----------
    ctx : Context
    lf : LinkFrames
        The chunk's poses (:func:`screwkit.engine.link_frames`).
    J : ndarray (N, m_rows, 6)
        The unified Jacobian at those poses.
    thd_ind, thdd_ind : ndarray (N, n_ind)
        Rates and accelerations of the independent parameters.
    dependent : (ndarray (N, n_dep), ndarray (N, n_dep)), optional
        The dependent parameters' rates and accelerations, when known otherwise (the limit
        at a representation singularity, :mod:`~._singular`).

    Returns
    -------
    dict of arrays (poses first); see :class:`~screwkit.dynamics.DynamicsResult`.
    """
    N = J.shape[0]
    n = len(ctx.setups)
    mmax = max(st.m for st in ctx.setups)
    Xi = np.ascontiguousarray(lf.columns.transpose(2, 0, 1))
    thd, thdd = np.zeros((N, 6)), np.zeros((N, 6))
    thd[:, ctx.ind], thdd[:, ctx.ind] = thd_ind, thdd_ind
    Jc = J[:, ctx.n_act:]
    cond = np.ones(N)
    if ctx.dep.size and dependent is not None:
        thd[:, ctx.dep], thdd[:, ctx.dep] = dependent
    elif ctx.dep.size:
        P, cond = dependent_inverse(np.einsum("nra,nak->nrk", Jc, Xi[:, :, ctx.dep]),
                                    _unit_scales(Jc, Xi[:, :, ctx.dep], ctx.c, ctx.L))
        rhs = -np.einsum("nra,nak,nk->nr", Jc, Xi[:, :, ctx.ind], thd_ind)
        thd[:, ctx.dep] = np.einsum("nkr,nr->nk", P, rhs)
    V = np.einsum("nak,nk->na", Xi, thd)
    # legs: rates (idle motions of least kinetic energy) and biases
    legs = []
    for i, st in enumerate(ctx.setups):
        m = st.m
        tw = np.ascontiguousarray(lf.twists[:m, :, i].transpose(2, 0, 1))
        Rs = lf.R[:m, :, :, i].transpose(3, 0, 1, 2)
        ts = lf.t[:m, :, i].transpose(2, 0, 1)
        pa = pa_state(st.pa, tw, lf.q[i, :m].T, Rs, ts)
        sol = LegSolver(st, tw, ctx.c, ctx.L)
        qd = sol.particular(V)
        idle = None
        if st.dep.size and not st.massless:
            scale = float(np.sum(st.mass) * ctx.L ** 2 + np.trace(st.inertia, axis1=1,
                                                                     axis2=2).sum())
            if st.pa is not None:
                scale += float(np.sum(st.pa.bar_mass) * ctx.L ** 2
                               + np.trace(st.pa.bar_inertia, axis1=1, axis2=2).sum())
            Nn, MN, K, _, z = _idle_rates(st, sol, tw, Rs, ts, qd, scale, pa)
            qd = qd + np.einsum("nmk,nk->nm", Nn, z)
            idle = (Nn, MN, K, scale)
        b = bias_terms(tw, qd, curv=None if pa is None else pa.curv).sum(axis=1)
        legs.append((st, tw, Rs, ts, sol, qd, b, idle, pa))
    colr = column_rates(Xi, thd, lf.euler_chain)
    if ctx.dep.size and dependent is None:
        rhs = (np.einsum("nra,nra->nr", Jc, np.stack([legs[k][6] for k in ctx.row_leg], axis=1))
               - np.einsum("nra,na->nr", Jc,
                           np.einsum("nak,nk->na", Xi[:, :, ctx.ind], thdd_ind) + colr))
        thdd[:, ctx.dep] = np.einsum("nkr,nr->nk", P, rhs)
    A = np.einsum("nak,nk->na", Xi, thdd) + colr
    g = ctx.g
    out = {k: np.full((N, n, mmax), np.nan) for k in ("qd", "qdd", "ID")}
    u = np.zeros((N, n, 6))
    kinetic, potential = np.zeros(N), np.zeros(N)
    vres, ares, bal = np.zeros(N), np.zeros(N), np.zeros(N)
    for i, (st, tw, Rs, ts, sol, qd, b, idle, pa) in enumerate(legs):
        target = A - b
        qdd = sol.particular(target)
        ID, ke, pe = leg_efforts(st, tw, qd, qdd, Rs, ts, g, pa=pa)
        if idle is not None:
            Nn, MN, K, scale = idle
            z = _idle_solve(K, np.einsum("nmk,nm->nk", Nn, ID), scale)
            qdd = qdd + np.einsum("nmk,nk->nm", Nn, z)
            ID = ID + np.einsum("nmk,nk->nm", MN, z)
        u[:, i] = sol.mapped_wrench(ID)
        resid = ID + np.einsum("nma,na->nm", tw, u[:, i])
        bal = np.maximum(bal, np.max(np.abs(resid), axis=1)
                         / np.maximum(np.max(np.abs(ID), axis=1), 1e-300))
        vres = np.maximum(vres, sol.residual(qd, V))
        ares = np.maximum(ares, sol.residual(qdd, target))
        out["qd"][:, i, :st.m], out["qdd"][:, i, :st.m], out["ID"][:, i, :st.m] = qd, qdd, ID
        kinetic += ke
        potential += pe
    Wp, kp, pp, com = platform_wrench(ctx.platform, lf.R_p.transpose(2, 0, 1), lf.o.T, V, A, g)
    o = lf.o.T
    W_ext = np.concatenate([np.broadcast_to(ctx.F, (N, 3)),
                            ctx.T + cross3(o, np.broadcast_to(ctx.F, (N, 3)))], axis=1)
    out.update(theta_dot=thd, theta_ddot=thdd, twist=V, acceleration=A, mapped=u,
               platform_wrench=Wp, workload=W_ext - Wp + u.sum(axis=1),
               kinetic=kinetic + kp, potential=potential + pp, kinetic_platform=kp,
               kinematic_condition=cond, velocity_residual=vres, acceleration_residual=ares,
               balance_residual=bal, platform_com=com)
    return out
