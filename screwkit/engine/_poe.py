"""The product of exponentials of chains of joints, batched (private).

Every leg of a PM (and every placed leg) is a chain of one-DOF joints; its
forward kinematics is ``G = exp(xi_1 q_1) ... exp(xi_m q_m)`` with the joints'
home twists ``xi_j``, evaluated here for ``n`` chains and ``N`` poses at once
(see :mod:`screwkit.engine._chains`).

A parallelogram ``Pa`` (a planar 4R loop whose bars ``b`` turn about the hinge ``h``) is
a one-DOF joint whose far link translates along a circle: with its value ``s`` the arc
length of the bars' ends (model lengths, ``theta = s / |b|``) its displacement is the pure
translation ``Rot(h, theta) b - b``, and its instantaneous twist ``[d(theta); 0]`` with
``d(theta) = Rot(h, theta) d_0 = h x Rot(h, theta) b / |b|``; at ``s = 0`` the same twist
as the equivalent prismatic joint ``d_0`` of a placed leg.
"""

from __future__ import annotations

import numpy as np

from . import _algebra as alg

__all__ = ["chain_forward"]


def chain_forward(D, P, rotation, translation, q, slots: bool = False, bars=None):
    """Product of exponentials of chains, slot by slot (the kinematics of every leg).

    Each joint's displacement ``exp(xi_j q_j)`` is formed about its home axis, and the
    chain is composed from the base, ``G_j = G_{j-1} exp(xi_j q_j)``: the current axis of
    slot ``j`` is ``G_{j-1}`` applied to its home axis, and a point ``p`` of that axis
    stays where it is: ``t_j = p - R_j P_j + h q_j d`` (``h`` the translation per unit
    value).  For a small batch the home rotations of every slot are formed at once
    (fewer array operations); for a large one slot by slot (working arrays that stay in
    cache).

    Parameters
    ----------
    D, P : ndarray (3, n, m)
        Home axes and points of ``n`` chains of ``m`` slots.
    rotation, translation : ndarray (n, m)
        Rotation and translation per unit joint value.
    q : ndarray (n, m, N)
        Joint values.
    bars : ndarray (3, n, m), optional
        Home bar vectors of the parallelograms (zero for every other joint, whose
        ``rotation`` is 0 and ``translation`` 1): their slots move along circles (module
        docstring) and their current axis is the current translation ``d(theta)``.

    Returns
    -------
    axes, points : ndarray (m, 3, n, N)
        Current joint axes and points.
    R : ndarray (3, 3, n, N) ; t : ndarray (3, n, N)
        The displacement ``G = prod exp(xi_j q_j)`` as ``x -> R x + t``.
    Rs, ts : ndarray (m, 3, 3, n, N), (m, 3, n, N)
        With ``slots``, also the displacement after each slot, ``prod_{k <= j}
        exp(xi_k q_k)``: how the link that follows joint ``j`` has moved from home.
    """
    n, m, N = q.shape
    angle = rotation[:, :, None] * q                           # (n, m, N)
    pa = None if bars is None else np.any(bars != 0, axis=0)   # (n, m) parallelograms
    if pa is not None and pa.any():
        blen = np.sqrt(np.einsum("inm,inm->nm", bars, bars))
        safe = np.where(pa, blen, 1.0)
        hinge = np.where(pa, np.cross(bars, D, axis=0) / safe, D)   # (3, n, m), unit
        theta = np.where(pa, 1.0, 0.0)[:, :, None] * q / safe[:, :, None]
        shift = np.where(pa, 0.0, translation)[:, :, None] * q
    else:
        pa, shift = None, translation[:, :, None] * q
    rotates = rotation.any(axis=0)
    E_all = None
    if n * N <= _SMALL:        # every slot's home rotation at once: fewer array operations
        E_all = alg.rodrigues(D[:, :, :, None], angle)         # (3, 3, n, m, N)
    axes = np.empty((m, 3, n, N))
    points = np.empty((m, 3, n, N))
    if slots:
        Rs, ts = np.empty((m, 3, 3, n, N)), np.empty((m, 3, n, N))
    R = t = None
    for j in range(m):
        Dj, Pj = D[:, :, j, None], P[:, :, j, None]
        if R is None:
            d = axes[j] = Dj
            p = points[j] = Pj
        else:
            d = axes[j] = alg.matvec(R, Dj)
            p = points[j] = alg.matvec(R, Pj) + t
        Rprev = R
        if rotates[j]:
            # G_j = G_{j-1} exp(xi_j q_j): the point p of the axis stays, plus the pitch shift
            Ej = E_all[:, :, :, j] if E_all is not None else alg.rodrigues(Dj, angle[:, j])
            R = Ej if R is None else alg.matmul(R, Ej)
            t = p - alg.matvec(R, Pj) + shift[:, j] * d
        elif R is None:
            t = shift[:, j] * d
            R = np.broadcast_to(np.eye(3)[:, :, None, None], (3, 3, n, N))
        else:
            t = t + shift[:, j] * d
        if pa is not None and pa[:, j].any():
            # a parallelogram: the far link translates by Rot(h, theta) b - b, and its current
            # axis is the translation Rot(h, theta) d_0 (both the identity for the other legs)
            Eh = alg.rodrigues(hinge[:, :, j, None], theta[:, j])
            bj = bars[:, :, j, None]
            move, dth = alg.matvec(Eh, bj) - bj, alg.matvec(Eh, Dj)
            if Rprev is None:
                axes[j], t = dth, t + move
            else:
                axes[j], t = alg.matvec(Rprev, dth), t + alg.matvec(Rprev, move)
        if slots:
            Rs[j], ts[j] = R, t
    if slots:
        return axes, points, R, t, Rs, ts
    return axes, points, R, t


#: Largest ``legs x poses`` for which :func:`chain_forward` forms every slot's home
#: displacement at once.
_SMALL = 512
