"""The load-dependent (geometric) stiffness of a PM under a preload.

At an equilibrium ``J(X)^T F_r + W(X) = 0`` (rows and workload about ``O``; the workload a
force ``F`` at the moving ``o`` and a couple ``T``), a small platform motion ``dX`` changes
both terms even at constant efforts ``F_r``: the rows turn and move with the legs, the
force's moment follows ``o``.  With ``G = d(J^T F_r + W)/dX`` at constant ``F_r``, the
tangent stiffness is ``K_t = J^T diag(k) J - G`` (``dX = K_t^-1 dW`` for a small extra load).

``G`` is formed by central differences of the engine's rows along the PM's own motion: the
poses ``theta +- h e_k`` of each independent parameter (``h = 1e-5`` rad, ``1e-5 L``),
solved by the engine from the nominal pose, give ``d(J^T F_r + W)/d theta_k``; with the
platform twists ``Xi_k`` of those parameters (:func:`screwkit.engine.link_frames`),
``G Xi = d(J^T F_r + W)/d theta`` and ``G = (...) Xi^+``.  For a PM with fewer than six
degrees of freedom this covers the directions its legs allow only: the constrained
directions move by the legs' own deformation, which the rigid-link model has no rows for.
A constant couple is not a conservative load, so ``K_t`` need not be symmetric.
"""

from __future__ import annotations

import dataclasses

import numpy as np

__all__ = ["geometric_stiffness", "STEP"]

#: Relative step of the central differences (rad for angles, ``L`` for lengths).
STEP = 1e-5


def _residual(J, F_r, o, F, T):
    """``J^T F_r + W`` about ``O``, ``(N, 6)``."""
    from ..engine._pipeline import workload_about_origin
    W = workload_about_origin(np.broadcast_to(F, o.shape), np.broadcast_to(T, o.shape), o)
    return np.einsum("nra,nr->na", J, F_r) + W


def geometric_stiffness(model, an):
    """``G`` about ``o`` (``[v; w] -> [f; m]``), ``(N, 6, 6)``, at the poses of ``an`` with its
    statics values as the preload (module docstring); NaN where a pose is flagged."""
    from ..engine import LENGTH_PARAMS, PARAMS, analyze, link_frames

    sol = an.solution
    N = len(sol)
    ind = list(model.independent)
    L = float(model.normalisation.length)
    steps = np.array([STEP * L if p in LENGTH_PARAMS else STEP for p in ind])
    d = len(ind)
    rep = np.repeat(np.arange(N), 2 * d)
    pose = {p: np.asarray(sol._params[p], float)[rep] for p in ind}
    which = np.tile(np.repeat(np.arange(d), 2), N)
    sign = np.tile(np.tile([1.0, -1.0], d), N)
    for k, p in enumerate(ind):
        pose[p] = pose[p] + np.where(which == k, sign * steps[k], 0.0)
    guess = dataclasses.replace(sol, closures=sol.closures.take(rep), pose_notes={})
    side = analyze(model, pose, guess=guess, force=an.force, torque=an.torque)
    F_r = np.asarray(an.statics.F_r, float)[rep]
    r = _residual(side.jacobian.matrix, F_r, side.solution._platform[1], an.force, an.torque)
    r = r.reshape(N, d, 2, 6)
    dr = (r[:, :, 0] - r[:, :, 1]) / (2.0 * steps[None, :, None])          # (N, d, 6)
    Xi = link_frames(sol).columns.transpose(2, 0, 1)[:, :, [PARAMS.index(p) for p in ind]]
    o = sol._platform[1]
    ox = np.zeros((N, 3, 3))
    ox[:, 0, 1], ox[:, 0, 2], ox[:, 1, 2] = -o[:, 2], o[:, 1], -o[:, 0]
    ox = ox - ox.transpose(0, 2, 1)
    Xi_o = Xi.copy()
    Xi_o[:, :3] -= ox @ Xi[:, 3:]                   # the twists about o: v_o = v_O - o x w
    dr_o = dr.copy()
    dr_o[:, :, 3:] -= np.einsum("nab,nkb->nka", ox, dr[:, :, :3])    # wrenches about o
    # G Xi_o = dr_o^T on the PM's own motions; with fewer than six the other directions
    # are those orthogonal to them in the length-normalised twists about o (about O they
    # would move with the origin: the result would depend on where the base frame is)
    D = np.array([1 / L, 1 / L, 1 / L, 1.0, 1.0, 1.0])
    G = np.einsum("nka,nkb->nab", dr_o, np.linalg.pinv(Xi_o * D[:, None])) * D
    bad = ~(side.solution.reachable_mask & ~side.jacobian.singular_mask).reshape(N, 2 * d).all(1)
    G[bad | ~an.solution.reachable_mask | an.jacobian.singular_mask] = np.nan
    return G
