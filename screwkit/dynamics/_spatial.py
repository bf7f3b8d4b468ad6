"""Batched screw algebra for the dynamics (poses first, the 6 components last).

Twists ``[v; w]`` (``v`` the velocity of the body point at ``O``), wrenches ``[f; m]``
about ``O``: the conventions of :mod:`screwkit.screws`.

* :func:`cross_motion` ``V x X``: the rate of change of a twist ``X`` carried by a body
  moving with ``V`` (the Lie bracket ``[V, X]``; ``d xi_j / dt = V_(j-1) x xi_j`` for the
  joints of a chain);
* :func:`body_wrench`: the wrench about ``O`` that a rigid body needs to move with the twist
  ``V`` and the spatial acceleration ``A = dV/dt`` under gravity ``g`` (Newton-Euler at the
  centre of mass, moved to ``O``), and its kinetic energy;
* :func:`normalise_twists`, :func:`denormalise_wrench`: the length-normalised
  coordinates about the centre ``c`` with the length ``L`` of :mod:`screwkit.screws`
  (``twist -> [(v - c x w) / L; w]``, ``wrench -> [f; (m - c x f) / L]``; the products
  of normalised screws are the physical ones divided by ``L``).

Examples
--------
>>> import numpy as np
>>> V = np.array([[0.0, 0, 0, 0, 0, 1.0]])          # spin about Z through O
>>> X = np.array([[0.0, 1, 0, 0, 0, 0]])            # a translation along Y
>>> cross_motion(V, X)                              # the translation turns: -X direction
array([[-1.,  0.,  0.,  0.,  0.,  0.]])
"""

from __future__ import annotations

import numpy as np

__all__ = ["cross3", "cross_motion", "body_wrench", "normalise_twists", "denormalise_wrench",
           "place_body"]


def cross3(a, b):
    """``a x b`` over the last axis (broadcast)."""
    a0, a1, a2 = a[..., 0], a[..., 1], a[..., 2]
    b0, b1, b2 = b[..., 0], b[..., 1], b[..., 2]
    return np.stack([a1 * b2 - a2 * b1, a2 * b0 - a0 * b2, a0 * b1 - a1 * b0], axis=-1)


def cross_motion(V, X):
    """``V x X = [w x x + v x y; w x y]`` for twists ``V = [v; w]``, ``X = [x; y]``."""
    v, w = V[..., :3], V[..., 3:]
    x, y = X[..., :3], X[..., 3:]
    return np.concatenate([cross3(w, x) + cross3(v, y), cross3(w, y)], axis=-1)


def place_body(R, t, com, inertia):
    """A body's centre and inertia after ``x -> R x + t``: ``(..., 3)``, ``(..., 3, 3)``."""
    c = np.einsum("...ij,j->...i", R, com) + t
    I = np.einsum("...ij,jk,...lk->...il", R, inertia, R)
    return c, I


def body_wrench(mass, c, I, V, A, g):
    """Newton-Euler of a rigid body, about ``O``.

    Parameters
    ----------
    mass : float
    c : ndarray (..., 3)
        Centre of mass; ``I (..., 3, 3)`` the inertia about it (world axes).
    V, A : ndarray (..., 6)
        Twist and spatial acceleration ``dV/dt`` (about ``O``).
    g : ndarray (3,)
        Gravity.

    Returns
    -------
    W : ndarray (..., 6)
        ``[m (a_c - g); I dw + w x I w + c x m (a_c - g)]``: the resultant wrench about ``O``
        that the rest of the mechanism must apply to the body (its inertia minus gravity).
    kinetic : ndarray (...)
        ``(m v_c . v_c + w . I w) / 2``.
    v_c : ndarray (..., 3)
        Velocity of the centre of mass.
    """
    v, w = V[..., :3], V[..., 3:]
    dw = A[..., 3:]
    vc = v + cross3(w, c)
    ac = A[..., :3] + cross3(dw, c) + cross3(w, vc)
    f = mass * (ac - g)
    Iw = np.einsum("...ij,...j->...i", I, w)
    n = np.einsum("...ij,...j->...i", I, dw) + cross3(w, Iw)
    W = np.concatenate([f, n + cross3(c, f)], axis=-1)
    kin = 0.5 * (mass * np.einsum("...i,...i->...", vc, vc) + np.einsum("...i,...i->...", w, Iw))
    return W, kin, vc


def normalise_twists(T, c, L):
    """Length-normalised twists ``[(v - c x w) / L; w]`` (last axis 6)."""
    v, w = T[..., :3], T[..., 3:]
    return np.concatenate([(v - cross3(c, w)) / L, w], axis=-1)


def denormalise_wrench(Wn, c, L):
    """The physical wrench of a normalised one: ``[f; L m_n + c x f]``."""
    f = Wn[..., :3]
    return np.concatenate([f, L * Wn[..., 3:] + cross3(c, f)], axis=-1)
