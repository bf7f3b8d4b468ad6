"""The generic rule for constraint members: projected reference wrenches (private).

Where a leg's members are not all pure couples and forces through named points
(or where the structure of home does not hold at a pose), its constraint system
is computed by SVD of the length-normalised joint twists and given a basis by
the Gram-Schmidt orthonormalisation (normalised metric) of reference wrenches
projected on it: unit forces through ``A`` along, then unit couples about, the
reference directions (chosen at home with remainder >= REF_MIN).
"""

from __future__ import annotations

import numpy as np

from . import _algebra as alg
from ._geometry import REF_FLAG, REF_MIN, LegGeometry, leg_centroid, leg_length
from ..screws import cross

__all__ = ["generic_references", "generic_members", "subset_geometry"]




def subset_geometry(geo, mask):
    return LegGeometry(geo.axes[..., mask], geo.points[..., mask], geo.rotation, geo.translation,
                       geo.A, geo.a[..., mask], geo.base_rotation, geo.O,
                       geo.platform_rotation[..., mask], geo.o[..., mask])


def _normalised_twists(geo):
    """Joint twists ``(N, m, 6)`` about the leg's centroid, linear parts over its length."""
    c, L = leg_centroid(geo), leg_length(geo)
    rows = []
    for j in range(geo.axes.shape[0]):
        v, w = geo.twist(j)
        rows.append(np.concatenate([(v - alg.cross(c, w)) / L, w]))
    return np.stack(rows).transpose(2, 0, 1), c, L


def _reference_wrenches(geo, refs, names):
    """Reference wrenches ``(len(refs), 6, N)`` (physical): ``("force", d)`` the unit force
    along ``d`` through ``A``, ``("couple", d)`` the unit couple along ``d``."""
    out = []
    A = np.broadcast_to(geo.A[:, None], (3, geo.N))
    for kind, r in refs:
        d = geo.direction(r, names)
        out.append(np.concatenate([d, alg.cross(A, d)]) if kind == "force"
                   else np.concatenate([np.zeros_like(d), d]))
    return np.stack(out) if out else np.zeros((0, 6, geo.N))


def _space(geo, k):
    """Orthonormal basis ``(N, k, 6)`` of the normalised constraint space (SVD)."""
    Tn, c, L = _normalised_twists(geo)
    Tn = Tn / np.maximum(np.linalg.norm(Tn, axis=2, keepdims=True), 1e-300)
    _, s, Vt = np.linalg.svd(Tn, full_matrices=True)
    rank = 6 - k
    ok = np.ones(geo.N, bool)
    tol = 1e-8 * np.maximum(1.0, s[:, 0])
    if rank > 0:
        ok &= s[:, rank - 1] > tol
    if s.shape[1] > rank:
        ok &= s[:, rank] <= tol
    return Vt[:, rank:], c, L, ok


def _project_references(B, R):
    """Gram-Schmidt of the references ``R (N, r, 6)`` projected on ``span(B (N, k, 6))``;
    returns ``(N, r, 6)`` and the remainders ``(N, r)``."""
    out, rems = [], []
    for i in range(R.shape[1]):
        p = np.einsum("nkj,nk->nj", B, np.einsum("nkj,nj->nk", B, R[:, i]))
        for e in out:
            p = p - e * np.sum(e * p, axis=1, keepdims=True)
        rem = np.linalg.norm(p, axis=1)
        out.append(p / np.maximum(rem, 1e-300)[:, None])
        rems.append(rem)
    return np.stack(out, 1), np.stack(rems, 1)


def _to_norm(W, c, L):
    """Physical wrenches ``(N, r, 6)`` to normalised about ``c (3, N)``, ``L (N,)``."""
    f = W[..., :3]
    m = (W[..., 3:] - cross(c.T[:, None], f)) / L[:, None, None]
    Wn = np.concatenate([f, m], axis=-1)
    return Wn / np.maximum(np.linalg.norm(Wn, axis=-1, keepdims=True), 1e-300)


def _from_norm(Wn, c, L):
    f = Wn[..., :3]
    m = Wn[..., 3:] * L[:, None, None] + cross(c.T[:, None], f)
    W = np.concatenate([f, m], axis=-1)
    nf = np.linalg.norm(f, axis=-1, keepdims=True)
    nm = np.linalg.norm(W[..., 3:], axis=-1, keepdims=True)
    couple = nf <= 1e-9 * np.linalg.norm(Wn, axis=-1, keepdims=True)
    return W / np.where(couple, np.maximum(nm, 1e-300), nf)


def generic_references(geo, k, cand, names):
    B, c, L, ok = _space(geo, k)
    chosen = []
    for kind in ("force", "couple"):
        for r in cand:
            try:
                R = _reference_wrenches(geo, chosen + [(kind, r)], names)
            except ValueError:
                continue
            _, rem = _project_references(B, _to_norm(R.transpose(2, 0, 1), c, L))
            if rem[0, -1] >= REF_MIN:
                chosen.append((kind, r))
            if len(chosen) == k:
                return tuple(chosen)
    raise ValueError("no reference wrenches give a basis of the constraint system")


def generic_members(geo, k, refs, names):
    """Constraint members ``(k, 6, N)`` by the generic rule (see the module docstring)."""
    B, c, L, ok = _space(geo, k)
    R = _to_norm(_reference_wrenches(geo, refs, names).transpose(2, 0, 1), c, L)
    P, rem = _project_references(B, R)
    ok &= np.min(rem, axis=1, initial=1.0) > REF_FLAG
    return _from_norm(P, c, L).transpose(1, 2, 0), ok
