"""Rates and accelerations at a representation singularity of the Euler angles.

Where ``beta`` is given at ``sin(beta) = 0`` (proper Euler orders) or ``cos(beta) = 0``
(Tait-Bryan) and ``alpha`` or ``gamma`` is dependent, the dependent angle is not determined
by the pose (the engine takes its limit, :mod:`screwkit.engine._solve`), and its rate is not
determined by the velocity equations: ``J_c Xi_dep`` loses its rank, its condition number
growing like ``1 / |beta - beta_s|``.  Within :data:`DELTA` of the singular ``beta_s`` the
dependent rates and accelerations are therefore taken as the limit along ``beta``: the
cubic through their values at ``beta_s + (-2, -1, 1, 2) DELTA`` (the same other parameters,
rates and accelerations), evaluated at the sample's ``beta``: an interpolation error of
order ``DELTA^4``, the four poses solved by the engine from the sample's solution.
"""

from __future__ import annotations

import dataclasses

import numpy as np

__all__ = ["DELTA", "near_singular", "limit_rates"]

#: Half-width (rad) of the zone around a representation singularity where the rates are
#: interpolated (the velocity system's condition number is about 300 / DELTA there for the
#: catalog's 3RRPRR).
DELTA = 2e-3
_NODES = np.array([-2.0, -1.0, 1.0, 2.0])


def near_singular(model, beta):
    """``(mask (N,), beta_s (N,))``: the samples within :data:`DELTA` of a representation
    singularity whose dependent angle follows by continuity only, and the singular value."""
    beta = np.asarray(beta, float)
    ind = set(model.independent)
    if "beta" not in ind or {"alpha", "gamma"} <= ind:
        return np.zeros(beta.shape, bool), np.zeros(beta.shape)
    o = model.order
    proper = o[0].lower() == o[2].lower()
    shift = 0.0 if proper else np.pi / 2
    bs = shift + np.round((beta - shift) / np.pi) * np.pi
    return np.abs(beta - bs) < DELTA, bs


def limit_rates(model, an, idx, bs, ctx, thd, thdd, chunk_dynamics, link_frames):
    """The limit rates and accelerations ``(k, n_dep)`` of the dependent parameters at the
    samples ``idx`` (module docstring), and a mask of those obtained."""
    from ..engine import analyze

    k = idx.size
    rep = np.repeat(idx, _NODES.size)
    params = an.solution._params
    pose = {p: np.asarray(params[p], float)[rep] for p in model.independent}
    pose["beta"] = np.repeat(bs, _NODES.size) + np.tile(_NODES * DELTA, k)
    guess = dataclasses.replace(an.solution, closures=an.solution.closures.take(rep),
                                pose_notes={})
    side = analyze(model, pose, guess=guess, force=ctx.F, torque=ctx.T)
    part = chunk_dynamics(ctx, link_frames(side.solution), side.jacobian.matrix, thd[rep],
                          thdd[rep])
    nd = ctx.dep.size
    td = part["theta_dot"][:, ctx.dep].reshape(k, _NODES.size, nd)
    tdd = part["theta_ddot"][:, ctx.dep].reshape(k, _NODES.size, nd)
    good = (side.solution.reachable_mask & ~side.jacobian.singular_mask
            & (part["kinematic_condition"] <= 1e8)).reshape(k, _NODES.size).all(axis=1)
    x0 = (np.asarray(params["beta"], float)[idx] - bs) / DELTA
    w = np.ones((k, _NODES.size))
    for j, xj in enumerate(_NODES):
        for m, xm in enumerate(_NODES):
            if m != j:
                w[:, j] *= (x0 - xm) / (xj - xm)
    return (np.einsum("kj,kjd->kd", w, td), np.einsum("kj,kjd->kd", w, tdd), good,
            part["kinematic_condition"].reshape(k, _NODES.size).max(axis=1))
