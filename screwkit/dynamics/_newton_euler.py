"""Newton-Euler of every leg and of the platform, batched over N poses (poses first).

For a leg (a serial chain from the base to the platform), the link after joint ``s`` moves
with the twist ``V_s = sum_(j <= s) xi_j qdot_j`` and the spatial acceleration ``A_s =
sum_(j <= s) (xi_j qddot_j + (V_(j-1) x xi_j) qdot_j)`` (about ``O``).  Its centre and
inertia follow its displacement from home (:func:`screwkit.engine.link_frames`).  The wrench
it needs, ``W_s`` (:func:`~._spatial.body_wrench`: inertia minus gravity), is passed
through every joint before it, so the effort each joint must supply for the leg's own
links is (the backward pass of the recursive Newton-Euler algorithm, in screw form)::

    ID_j = xi_j . sum_(s >= j) W_s + viscous_j qdot_j + coulomb_j sign(qdot_j)

The platform's own wrench is :func:`platform_wrench`.  Kinetic energy ``sum (m v_c^2 + w .
I w) / 2`` and potential energy ``- sum m g . c`` come with them.
"""

from __future__ import annotations

import numpy as np

from ._legs import LegSetup, bias_terms, cumulative_twists
from ._parallelogram import bar_efforts, bar_mass_product
from ._spatial import body_wrench, place_body

__all__ = ["leg_efforts", "mass_product", "platform_wrench", "friction_efforts"]


def friction_efforts(st: LegSetup, qd):
    """``viscous qdot + coulomb sign(qdot)`` per joint ``(N, m)`` (resisting the motion)."""
    return st.viscous * qd + st.coulomb * np.sign(qd)


def leg_efforts(st: LegSetup, tw, qd, qdd, Rs, ts, g, *, friction: bool = True, pa=None):
    """The joint efforts a leg's links need, with their energies.

    Parameters
    ----------
    st : LegSetup
    tw : ndarray (N, m, 6)
        Joint twists.
    qd, qdd : ndarray (N, m)
        Joint rates and accelerations.
    Rs, ts : ndarray (N, m, 3, 3), (N, m, 3)
        Displacement of the link after each joint from home.
    g : ndarray (3,)
        Gravity (world).
    pa : PaState, optional
        The leg's parallelograms at the poses (:func:`~._parallelogram.pa_state`): their own
        twist rate and their bars.

    Returns
    -------
    ID : ndarray (N, m)
    kinetic, potential : ndarray (N,)
    """
    N = tw.shape[0]
    ID = friction_efforts(st, qd) if friction else np.zeros((N, st.m))
    kin, pot = np.zeros(N), np.zeros(N)
    if st.massless:
        return ID, kin, pot
    Vc = cumulative_twists(tw, qd)
    curv = None if pa is None else pa.curv
    Ac = np.cumsum(tw * qdd[..., None] + bias_terms(tw, qd, Vc, curv), axis=1)
    for k, s in enumerate(st.slots):
        c, I = place_body(Rs[:, s], ts[:, s], st.com[k], st.inertia[k])
        W, ke, _ = body_wrench(st.mass[k], c, I, Vc[:, s], Ac[:, s], g)
        ID[:, :s + 1] += np.einsum("nja,na->nj", tw[:, :s + 1], W)
        kin += ke
        pot -= st.mass[k] * (c @ g)
    kb, pb = bar_efforts(pa, tw, qd, qdd, Vc, Ac, g, ID)
    return ID, kin + kb, pot + pb


def mass_product(st: LegSetup, tw, x, Rs, ts, pa=None):
    """``M x`` ``(N, m[, k])``: the joint efforts of the accelerations ``x (N, m[, k])`` alone
    (no velocity, gravity or friction): the leg's joint-space inertia times ``x`` (with
    the bars of its parallelograms ``pa``, a :class:`~._parallelogram.PaState`)."""
    vec = x.ndim == 2
    X = x[..., None] if vec else x
    N, m, K = X.shape
    out = np.zeros((N, m, K))
    if not st.massless:
        A = np.cumsum(tw[:, :, None, :] * X[..., None], axis=1)      # (N, m, K, 6)
        zero = np.zeros(3)
        for k, s in enumerate(st.slots):
            c, I = place_body(Rs[:, s], ts[:, s], st.com[k], st.inertia[k])
            Z = np.zeros((N, K, 6))
            W, _, _ = body_wrench(st.mass[k], c[:, None], I[:, None], Z, A[:, s], zero)
            out[:, :s + 1] += np.einsum("nja,nka->njk", tw[:, :s + 1], W)
        bar_mass_product(pa, tw, X, A, out)
    return out[..., 0] if vec else out


def platform_wrench(body, R_p, o, V, A, g):
    """The platform's own wrench (inertia minus gravity) about ``O``, its kinetic and
    potential energy; ``body`` in the platform frame, ``R_p (N, 3, 3)``, ``o (N, 3)``,
    ``V, A (N, 6)``."""
    c, I = place_body(R_p, o, body.com, body.inertia)
    W, kin, _ = body_wrench(body.mass, c, I, V, A, g)
    return W, kin, -body.mass * (c @ g), c
