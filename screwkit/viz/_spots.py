"""Where to draw a free vector (a couple): beside its leg, away from the joints, the chains
and the arrows already drawn (in screen space)."""

from __future__ import annotations

import numpy as np

from ._view import _View


def _clearance(view: _View, p0, p1, points, segments, scale) -> float:
    """Smallest screen distance (in units of ``scale``) from the segment ``p0 p1`` to the
    obstacle points (k, 3) and segments (s, 2, 3)."""
    S = np.array([view.right, view.up]).T                      # 3D -> screen
    x = (p0 + np.linspace(0.0, 1.0, 6)[:, None] * (p1 - p0)) @ S          # (6, 2)
    worst = np.inf
    if len(points):
        q = np.asarray(points, float) @ S
        worst = float(np.min(np.linalg.norm(x[:, None, :] - q[None], axis=-1)))
    if len(segments):
        seg = np.asarray(segments, float) @ S                    # (s, 2, 2)
        a, ab = seg[:, 0], seg[:, 1] - seg[:, 0]
        t = np.einsum("isk,sk->is", x[:, None, :] - a[None], ab) / np.maximum(
            np.einsum("sk,sk->s", ab, ab), 1e-300)[None]
        near = a[None] + np.clip(t, 0.0, 1.0)[..., None] * ab[None]
        worst = min(worst, float(np.min(np.linalg.norm(x[:, None, :] - near, axis=-1))))
    return worst / scale


def couple_tail(view: _View, A, a, vec, scale, points, segments):
    """Tail of a couple arrow ``vec`` of the leg ``A -> a`` and the point of the leg it is
    tied to: the candidate beside the leg (12 % to 35 % of ``scale`` off it, on either
    side, at 25 % to 75 % of its length) farthest on screen from ``points`` and
    ``segments`` (clearance counted up to 12 % of ``scale``; ties go near the middle).

    Returns
    -------
    (tail (3,), root (3,))
    """
    A, a, vec = (np.asarray(x, float) for x in (A, a, vec))
    L = np.linalg.norm(a - A)
    legdir = (a - A) / L if L > 0 else np.array([0.0, 0.0, 1.0])
    n = view.side(legdir)
    best, best_key = None, None
    for f in (0.5, 0.4, 0.6, 0.3, 0.7, 0.25, 0.75):
        root = A + f * (a - A)
        for k in (0.12, 0.2, 0.28, 0.35):
            for s in (1.0, -1.0):
                p0 = root + s * k * scale * n
                c = _clearance(view, p0, p0 + vec, points, segments, scale)
                c_root = _clearance(view, root + 0.5 * (p0 - root), p0, points, [], scale)
                key = (round(min(c, 0.12, 2.0 * c_root), 3), -abs(f - 0.5) - 0.3 * k)
                if best_key is None or key > best_key:
                    best, best_key = (p0, root), key
    return best
