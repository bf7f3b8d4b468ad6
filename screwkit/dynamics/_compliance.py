"""The compliance of a PM from its rows, with rigid rows exact and singular poses named.

The platform, deflected by the small twist ``dX = [dp_o; dtheta]``, lengthens each row ``i``
by ``delta_i = J_i dX``; a row of stiffness ``k_i`` then carries ``f_i = k_i delta_i``, a
rigid row (no stiffness) any effort with ``delta_i = 0``.  Equilibrium with the workload
``W = [F; T]`` at ``o`` is ``J^T f = W``.  Written with the row compliances ``c_i = 1 / k_i``
(``c_i = 0``: rigid)::

    [ 0   J^T ] [dX]   [W]
    [ J  -c   ] [f ] = [0]

This *flexibility* form never inverts a stiffness: a rigid row has exactly zero compliance
(a PM rigid everywhere has ``C = 0`` and deflects by exactly 0), and the conditioning is
that of ``J``, not of ``J^T diag(k) J`` (its square), so a pose at a condition number of
``1e7`` still gives a finite, accurate deflection.

The columns of ``J`` are length-normalised (``dX`` as ``[dp / L; dtheta]``) and its rows
scaled to unit norm; the right singular vectors of that matrix whose singular values are
below ``s_max / threshold`` (the engine's singularity threshold, as ``analyze`` uses it) are
the **unrestrained** directions: twists the legs do not resist at all.  The compliance is
solved on the other, **held** directions (it is zero along the unrestrained ones, where the
platform is not in static equilibrium under a load that works on them), so every number is
finite; the unrestrained twists are returned to be named.
"""

from __future__ import annotations

import numpy as np

from ..screws import RANK_RTOL
from ..screws._echelon import canonical_twist_sign

__all__ = ["flexibility", "twist_text", "rows_about_o"]


def flexibility(Jo, k, L: float, singular, threshold: float) -> tuple:
    """Compliance and unrestrained directions at N poses.

    Parameters
    ----------
    Jo : ndarray (N, m, 6)
        The rows ``[f; m_o]`` about ``o`` (acting on ``[dp_o; dtheta]``).
    k : ndarray (N, m)
        Row stiffnesses (``inf``: rigid).
    L : float
        The model's characteristic length.
    singular : ndarray (N,) of bool
        The poses the engine flags singular (at least one unrestrained direction each).
    threshold : float
        The engine's condition-number threshold of a singular pose.

    Returns
    -------
    C : ndarray (N, 6, 6)
        ``dX = C W`` (symmetric, positive semi-definite; exact zeros for rigid rows).
    free : ndarray (N, 6, 6)
        Unit twists ``[v; w]`` about ``o`` (columns) of the unrestrained directions, the
        first ``n_free`` of each pose; zeros after them.
    n_free : ndarray (N,) of int
    """
    N, m, _ = Jo.shape
    S = np.array([L, L, L, 1.0, 1.0, 1.0])
    Js = Jo * S                                           # rows on x = [dp / L; dtheta]
    r = np.linalg.norm(Js, axis=-1)                       # (N, m)
    r = np.where(r > 0, r, 1.0)
    A = Js / r[..., None]
    c = np.where(np.isfinite(k), 1.0 / np.where(np.isfinite(k), k, 1.0), 0.0) / r ** 2
    _, s, Vt = np.linalg.svd(A, full_matrices=True)       # s (N, min(m, 6)), Vt (N, 6, 6)
    sv = np.zeros((N, 6))
    sv[:, :s.shape[1]] = s
    # the engine's flag decides whether a pose is singular (as analyze says it); there, the
    # directions below its threshold are unrestrained (at least the weakest one)
    sing = np.asarray(singular, bool).reshape(N)
    held = ~sing[:, None] | (sv > sv[:, :1] / float(threshold))
    held[:, 5] &= ~(sing & held.all(axis=1))
    n_free = 6 - held.sum(axis=1)
    C = np.zeros((N, 6, 6))
    free = np.zeros((N, 6, 6))
    for p in np.unique(6 - n_free):
        sel = np.flatnonzero(6 - n_free == p)
        V = Vt[sel].transpose(0, 2, 1)                    # columns: right singular vectors
        Vh, Vu = V[:, :, :p], V[:, :, p:]
        free[sel, :, :6 - p] = _unit_twists(Vu * S[None, :, None])
        if p == 0:
            continue
        C[sel] = _held_compliance(A[sel] @ Vh, c[sel], Vh)
    C = 0.5 * (C + C.transpose(0, 2, 1))
    C = S[None, :, None] * C * S[None, None, :]
    for x in (C, free):
        x.setflags(write=False)
    return C, free, n_free.astype(int)


def _held_compliance(Ah, c, Vh):
    """``C_x`` on the held directions (``Ah = A V_h`` of full column rank): the rigid rows'
    null space ``N`` (exact zero compliance across it), then the compliant rows scaled by
    ``1 / sqrt(c)`` on it, ``B = U s W^T``, and ``C_x = V_h N W s^-2 W^T N^T V_h^T``.  The
    singular values come from ``B`` itself, so a soft direction at a condition number of
    ``1e7`` keeps its digits (``B^T B``, the stiffness, would square it)."""
    n, m, p = Ah.shape
    out = np.zeros((n, 6, 6))
    rigid = c == 0.0
    for pattern in {tuple(row) for row in rigid}:
        rig = np.array(pattern, bool)
        sel = np.flatnonzero((rigid == rig).all(axis=1))
        if not (~rig).any():
            continue                                     # rigid everywhere: exactly zero
        if rig.any():
            _, sr, Vr = np.linalg.svd(Ah[sel][:, rig], full_matrices=True)
            rank = np.sum(sr > RANK_RTOL * np.maximum(sr[:, :1], 1e-300), axis=1)
        else:
            Vr, rank = np.tile(np.eye(p), (sel.size, 1, 1)), np.zeros(sel.size, int)
        for rho in np.unique(rank):
            g = rank == rho
            if rho >= p:
                continue
            idx = sel[g]
            N = Vr[g][:, rho:, :].transpose(0, 2, 1)      # (k, p, p - rho)
            if int((~rig).sum()) == p - rho:
                # as many compliant rows as held directions across the rigid rows: the
                # compliance is M^-1 diag(c) M^-T exactly (M = A_c N, as well conditioned
                # as J there), whatever the spread of the stiffnesses; the singular values
                # of B below would lose the soft rows' below 1e-16 of the stiff ones'
                Mi = np.linalg.inv(Ah[idx][:, ~rig] @ N)             # (k, q, q)
                P = Vh[idx] @ N @ Mi                              # (k, 6, q)
                out[idx] = np.einsum("nik,nk,njk->nij", P, c[idx][:, ~rig], P)
                continue
            B = (Ah[idx][:, ~rig] / np.sqrt(c[idx][:, ~rig])[..., None]) @ N
            _, sb, Wt = np.linalg.svd(B, full_matrices=False)
            keep = sb > 1e-14 * sb[:, :1]                 # below: no resolvable stiffness
            inv2 = np.where(keep, 1.0 / np.where(keep, sb, 1.0) ** 2, 0.0)
            P = Vh[idx] @ N @ Wt.transpose(0, 2, 1)       # (k, 6, q)
            out[idx] = np.einsum("nik,nk,njk->nij", P, inv2, P)
    return out


def _unit_twists(V):
    """Twists ``[v; w]`` (columns) scaled to ``|w| = 1``, or ``|v| = 1`` for a translation,
    with a canonical sign (an unrestrained direction is free both ways; a singular vector's
    sign is the SVD's, which the last bits of the rows flip): the first component of ``w``
    (of ``v`` for a translation) above ``1e-8`` of the largest is positive."""
    w = np.linalg.norm(V[:, 3:], axis=1, keepdims=True)
    v = np.linalg.norm(V[:, :3], axis=1, keepdims=True)
    rot = w > 1e-9 * np.maximum(v, 1e-300)
    den = np.where(rot, w, np.where(v > 0, v, 1.0))
    return canonical_twist_sign(V / den, axis=1)


def twist_text(t, length: str, digits: int = 4) -> str:
    """An unrestrained direction in words: ``rotation about the axis (..) through (..) cm``
    (with its pitch where there is one) or ``translation along (..)``."""
    t = np.asarray(t, float)
    v, w = t[:3], t[3:]

    def vec(x):
        top = float(np.abs(x).max()) if x.size else 0.0
        return "(" + ", ".join("0" if abs(a) <= 1e-9 * top else f"{a:.{digits}g}"
                               for a in x) + ")"
    nw = float(np.linalg.norm(w))
    if nw <= 1e-9 * max(float(np.linalg.norm(v)), 1e-300):
        return f"translation along {vec(v / np.linalg.norm(v))}"
    u = w / nw
    pitch = float(u @ v) / nw
    point = np.cross(u, v) / nw                          # the axis' point nearest o
    out = f"rotation about the axis {vec(u)} through o + {vec(point)} {length}"
    if abs(pitch) > 1e-9 * max(float(np.linalg.norm(v)), 1.0):
        out += f", pitch {pitch:.{digits}g} {length}/rad"
    return out


def _about_o(J, o):
    """Rows ``[f; m - o x f]`` (N, m, 6) about ``o (N, 3)``."""
    f = J[..., :3]
    return np.concatenate([f, J[..., 3:] - np.cross(o[:, None, :], f)], axis=-1)


def rows_about_o(an):
    """The rows of an analysis about its platform centres ``(N, m, 6)`` (zero at an
    unreachable pose: it has no rows of its own, only the last iterate's)."""
    J = an.jacobian.matrix
    o = an.solution._platform[1]
    reach = np.asarray(an.solution.reachable_mask, bool)
    return _about_o(np.where(reach[:, None, None], J, 0.0), np.where(reach[:, None], o, 0.0))
