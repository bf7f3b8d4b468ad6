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

from ._frozen import kernel_array
from ._chains import LENGTH_PARAMS, PARAMS

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


#: No given unknowns: the frames kernel takes the six pose parameters as they are.
_GIVEN = (np.zeros(0, np.int64), np.zeros(0))


def _joint_values(ch, X, bad):
    """``(q (n, m, N), X (N, n m))``: the joint values of the unknowns ``X (nx, N)`` (NaN at
    the ``bad`` poses), and as the frames kernel takes them (scaled back)."""
    nu, n, m = len(ch.unknown), ch.n, ch.m
    N = X.shape[-1]
    q = X[nu:].reshape(n, m, N) * ch.q_scale[:, :, None]
    if bad.any():
        q = np.array(q)
        q[:, :, bad] = np.nan
    return q, q.reshape(n * m, N).T / ch.q_scale.reshape(1, -1)


def _pose_matrix(solution) -> np.ndarray:
    """The six pose parameters ``(N, 6)`` of a solution in :data:`PARAMS` order (NaN as its
    ``params``)."""
    return np.stack([solution._params[p] for p in PARAMS], axis=1)


def platform_arrays(solution, fp=None, chunk: int = 32768) -> tuple:
    """``(R (N, 3, 3), o (N, 3), a (N, n, 3))`` of :attr:`PoseSolution.rotation`,
    ``position`` and ``platform_points``, read-only, from the kernels' platform ``fp (N,
    27)`` at the solution's pose parameters, or (None) from the frames kernel in chunks of
    ``chunk`` poses (every leg's frames are formed and dropped per chunk)."""
    if fp is None:
        from ._launch import platform_of
        flat, P6 = solution.closures.chains.flat, _pose_matrix(solution)
        parts = [platform_of(flat, P6[s:s + chunk]) for s in range(0, max(len(P6), 1), chunk)]
        fp = parts[0] if len(parts) == 1 else np.concatenate(parts)
    from ._kernels import kernels
    pts = kernel_array(solution.model.platform_points)
    N = len(fp)
    R, o, a = np.empty((N, 3, 3)), np.empty((N, 3)), np.empty((N, len(pts), 3))
    kernels().platform_points(np.ascontiguousarray(fp, float), pts, R, o, a)
    for x in (R, o, a):
        x.setflags(write=False)
    return R, o, a


def keep_platform(solution, fp) -> None:
    """Keep in a solution the platform its frames ``fp (N, 27)`` gave (the frames kernel on
    the same pose parameters as :func:`platform_arrays`: the same bits), so that it is not
    computed again."""
    if "_platform" not in solution.__dict__:            # (PoseSolution._platform's cache)
        solution.__dict__["_platform"] = platform_arrays(solution, fp)


def index_lines(solution, chunk: int = 32768) -> tuple:
    """``(lines (N, n, 18), platform (N, 27))``: the joints the transmission indices read
    (from NaN joint values where unreachable)
    (``_kernels/_indices.pose_lines``: per leg its platform-side joint's point and axis, the
    point and axis of the joint after its actuator, its actuated joint's unit twist) and
    the platform, by the analysis kernel on the solution's unknowns, ``chunk`` poses a
    launch (the platform as :func:`reached_platform` gives it).  The same kernel function
    gives them in the analysis run itself when it is
    asked to (``analyze(..., lines=True)``): the same bits."""
    from ._launch import run_poses
    c = solution.closures
    flat = c.chains.flat
    N = c.X.shape[-1]
    nu = len(c.chains.unknown)
    bad = ~np.asarray(solution.reachable_mask, bool)
    lines, plat = np.empty((N, flat.n, 18)), np.empty((N, 27))
    for s in range(0, N, chunk):
        sl = slice(s, min(s + chunk, N))
        X = np.array(c.X[:, sl].T)
        X[bad[sl], nu:] = np.nan              # no assembly: no joint values (as link_frames)
        o = run_poses(flat, flat.Z, c.params(sl), X=X, rows=False, statics=False,
                      lines=True)
        lines[sl], plat[sl] = o["lines"], o["platform"]
    return lines, reached_platform(solution, plat)


def reached_platform(solution, fp) -> np.ndarray:
    """The kernels' platform ``fp (N, 27)`` of a solution's poses, with the unreachable ones
    formed at the solution's pose parameters (NaN where it has none), as
    :func:`platform_arrays` forms them."""
    bad = ~np.asarray(solution.reachable_mask, bool)
    if not bad.any():
        return fp
    from ._launch import platform_of
    fp = np.array(fp)
    fp[bad] = platform_of(solution.closures.chains.flat, _pose_matrix(solution)[bad])
    return fp


def _frames_of(solution, sl, slots: bool) -> tuple:
    """``(params, q, frames)``: the pose parameters and joint values of the poses ``sl`` of a
    solution (NaN where unreachable) and the frames kernel's outputs there, the joint
    twists included (:func:`._launch.frames`)."""
    c = solution.closures
    ch = c.chains
    X = c.X[:, sl]
    params = {k: np.asarray(v, float)[sl] for k, v in c.fixed.items()}
    for k, u in enumerate(ch.unknown):
        params[u] = X[k] * ch.x_scale[k]
    bad = ~(c.residual[sl] <= 1e-6)
    q, Xq = _joint_values(ch, X, bad)
    if bad.any():
        for u in ch.unknown:
            params[u] = np.where(bad, np.nan, params[u])
    from ._launch import frames
    P6 = np.stack([np.asarray(params[k], float) for k in PARAMS], axis=1)
    return params, q, frames(ch.flat, _GIVEN, P6, Xq, slots=slots, twists=True)


def link_frames(solution, sl=slice(None), slots: bool = True) -> LinkFrames:
    """The :class:`LinkFrames` of the poses ``sl`` of a :class:`PoseSolution`.

    Unreachable poses have NaN joint values, hence NaN screws.  Without ``slots`` the
    links' displacements ``R``, ``t`` are not formed (empty arrays): the joint twists and
    points alone, for the transmission indices.
    """
    ch = solution.closures.chains
    params, q, fr = _frames_of(solution, sl, slots)
    N = len(fr["platform"])
    fa = fr["axes_points"]                                 # (N, n, m, 6)
    points = np.ascontiguousarray(fa[..., 3:].transpose(2, 3, 1, 0))
    twists = np.ascontiguousarray(fr["twists"].transpose(2, 3, 1, 0))
    Rs = np.ascontiguousarray(fr["R"].transpose(2, 3, 4, 1, 0))    # (empty without slots)
    ts = np.ascontiguousarray(fr["t"].transpose(2, 3, 1, 0))
    fp = fr["platform"]
    Rp = np.ascontiguousarray(fp[:, 6:15].reshape(N, 3, 3).transpose(1, 2, 0))
    o = np.ascontiguousarray(fp[:, 15:18].T)
    E = np.ascontiguousarray(fp[:, 18:27].reshape(N, 3, 3).transpose(1, 2, 0))
    cols = np.zeros((6, 6, N))
    for k, name in enumerate(PARAMS):          # the platform twist of each parameter's rate
        if name in LENGTH_PARAMS:
            cols[:3, k] = ch.frame[0][:, "XYZ".index(name[0]), None]
        else:
            a = E[:, k - 3]
            cols[:3, k] = np.cross(o, a, axis=0)
            cols[3:, k] = a
    chain = (0, 1, 2) if ch.order.isupper() else (2, 1, 0)
    return LinkFrames(q, twists, Rs, ts, points, Rp, o, E, cols, chain, params, ch.real,
                      ch.rotation, ch.translation, ch.sizes, ch.actuated, ch.length, ch.centre)
