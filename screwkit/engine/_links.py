"""The moving links of a solved PM at N poses: joint screws, link displacements, platform
twist columns (for the dynamics layer).

:func:`link_frames` evaluates the engine's product of exponentials at the solved joint
values of a :class:`~screwkit.engine.PoseSolution` and keeps, per leg and slot, the current
unit joint twist and the displacement of the link that follows the joint (how it moved
from home), plus the platform's twist per unit rate of each pose parameter.  Arrays are in
the engine's structure-of-arrays layout: components first, then legs, poses last.

The platform as a virtual serial chain.  With ``o = R0 (Xo, Yo, Zo) + p0`` and ``R =
R0 R_euler(alpha, beta, gamma)``, the platform twist about ``O`` is ``V = sum_k xi_k
theta_dot_k``: ``xi = [R0 e_k; 0]`` for the three lengths and ``xi = [o x a_k; a_k]`` for
the angles (``a_k`` the columns of the angular Jacobian ``E``).  The angles act as three
revolute joints through ``o`` in the order :attr:`LinkFrames.euler_chain` (alpha, beta,
gamma for an intrinsic order; gamma, beta, alpha for an extrinsic one), after the three
translations; so the time derivative of the columns is the screw product ``xi_dot_k =
V_before_k x xi_k`` of the chain (:mod:`screwkit.dynamics`).

Examples
--------
>>> import numpy as np, screwkit
>>> from screwkit.engine import link_frames
>>> sol = screwkit.solve("3RRPRR", {"alpha": [0.05, 0.1], "beta": 0.02, "Zo": 80})
>>> lf = link_frames(sol)
>>> lf.twists.shape, lf.R.shape, lf.columns.shape       # (m, 6, n, N), (m, 3, 3, n, N), (6, 6, N)
((5, 6, 3, 2), (5, 3, 3, 3, 2), (6, 6, 2))
>>> lf.euler_chain
(0, 1, 2)
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from . import _algebra as alg
from ._chains import LENGTH_PARAMS, PARAMS, chain_forward, platform_pose

__all__ = ["LinkFrames", "link_frames"]


@dataclass(frozen=True, eq=False)
class LinkFrames:
    """Joint screws and link displacements of every leg at N poses (poses last).

    Attributes
    ----------
    q : ndarray (n, m, N)
        Joint values (radians for R and H, model lengths for P; 0 in padded slots).
    twists : ndarray (m, 6, n, N)
        Current unit joint twists ``[v; w]`` about ``O`` (zero in padded slots); a
        parallelogram Pa's is its current translation ``[d(theta); 0]``, whose own rate
        with ``theta`` the dynamics adds (:mod:`screwkit.dynamics._parallelogram`).
    R, t : ndarray (m, 3, 3, n, N), (m, 3, n, N)
        Displacement ``x -> R x + t`` of the link after each slot from its home pose.
    points : ndarray (m, 3, n, N)
        A point of each joint axis (current).
    R_p, o : ndarray (3, 3, N), (3, N)
        Platform rotation and centre; ``E (3, 3, N)`` the world angular Jacobian of the angles.
    columns : ndarray (6, 6, N)
        Platform twist per unit rate of ``Xo Yo Zo alpha beta gamma`` (about ``O``).
    euler_chain : tuple of int
        The angles (0, 1, 2 = alpha, beta, gamma) in chain order from the base.
    params : dict str -> ndarray (N,)
        The six pose parameters.
    real : ndarray (n, m) of bool ; rotation, translation : ndarray (n, m)
        As in the engine's chains (rotation and translation per unit joint value).
    sizes : tuple of int ; actuated : ndarray (n,)
    length : float
        The model's characteristic length.
    centre : ndarray (3,)
    """

    q: np.ndarray
    twists: np.ndarray
    R: np.ndarray
    t: np.ndarray
    points: np.ndarray
    R_p: np.ndarray
    o: np.ndarray
    E: np.ndarray
    columns: np.ndarray
    euler_chain: tuple
    params: dict
    real: np.ndarray
    rotation: np.ndarray
    translation: np.ndarray
    sizes: tuple
    actuated: np.ndarray
    length: float
    centre: np.ndarray

    @property
    def N(self) -> int:
        return self.q.shape[-1]


def link_frames(solution, sl=slice(None)) -> LinkFrames:
    """The :class:`LinkFrames` of the poses ``sl`` of a :class:`PoseSolution`.

    Unreachable poses have NaN joint values, hence NaN screws.
    """
    c = solution.closures
    ch = c.chains
    X = c.X[:, sl]
    N = X.shape[-1]
    nu, n, m = len(ch.unknown), ch.n, ch.m
    params = {k: np.asarray(v, float)[sl] for k, v in c.fixed.items()}
    for k, u in enumerate(ch.unknown):
        params[u] = X[k] * ch.x_scale[k]
    bad = ~(c.residual[sl] <= 1e-6)
    q = X[nu:].reshape(n, m, N) * ch.q_scale[:, :, None]
    if bad.any():
        q = np.array(q)
        q[:, :, bad] = np.nan
        for u in ch.unknown:
            params[u] = np.where(bad, np.nan, params[u])
    axes, points, _, _, Rs, ts = chain_forward(ch.D, ch.P, ch.rotation, ch.translation, q,
                                               slots=True, bars=ch.bars)
    rot = ch.rotation.T[:, None, :, None]                 # (m, 1, n, 1)
    tra = ch.translation.T[:, None, :, None]
    w = rot * axes
    v = np.cross(points, w, axis=1) + tra * axes
    twists = np.concatenate([v, w], axis=1)
    Rp, o, E = platform_pose(ch, {k: params[k] for k in PARAMS})
    R0 = ch.frame[0]
    cols = np.zeros((6, 6, N))
    for k, name in enumerate(PARAMS):
        if name in LENGTH_PARAMS:
            cols[:3, k] = R0[:, "XYZ".index(name[0]), None]
        else:
            a = E[:, k - 3]
            cols[:3, k] = alg.cross(o, a)
            cols[3:, k] = a
    chain = (0, 1, 2) if ch.order.isupper() else (2, 1, 0)
    return LinkFrames(q, twists, Rs, ts, points, Rp, o, E, cols, chain, params, ch.real,
                      ch.rotation, ch.translation, ch.sizes, ch.actuated, ch.length, ch.centre)
