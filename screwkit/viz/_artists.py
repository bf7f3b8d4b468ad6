"""Drawing primitives: 3D arrows (single and double headed, filled or open heads), the sleeve
of a prismatic joint, lines clipped to the drawing box, and the extent of the drawn points."""

from __future__ import annotations

from functools import lru_cache

import numpy as np


@lru_cache(maxsize=1)
def _arrow3d_class():
    from matplotlib.patches import FancyArrowPatch
    from mpl_toolkits.mplot3d import proj3d

    class Arrow3D(FancyArrowPatch):
        """A FancyArrowPatch between two 3D points."""

        def __init__(self, p0, p1, **kw):
            super().__init__((0.0, 0.0), (0.0, 0.0), **kw)
            #: tail and head in data (3D) coordinates
            self.xyz = (np.asarray(p0, float).copy(), np.asarray(p1, float).copy())

        def do_3d_projection(self, renderer=None):
            (x0, y0, z0), (x1, y1, z1) = self.xyz
            xs, ys, zs = proj3d.proj_transform((x0, x1), (y0, y1), (z0, z1), self.axes.M)
            self.set_positions((xs[0], ys[0]), (xs[1], ys[1]))
            return float(np.min(zs))

    return Arrow3D


def _arrow(ax, p0, p1, color, style="-|>", lw=2.0, scale=14, zorder=5, alpha=1.0, gid=None,
           hollow=False):
    """A 3D arrow; ``gid`` tags it (``"force:..."``, ``"row:3"``...) for tests and users.
    ``hollow``: an open (white-filled) head, the mark of a constraint wrench."""
    arrow = _arrow3d_class()(p0, p1, arrowstyle=style, mutation_scale=scale, lw=lw,
                             edgecolor=color, facecolor="white" if hollow else color,
                             shrinkA=0, shrinkB=0, zorder=zorder, alpha=alpha)
    arrow.set_gid(gid)
    ax.add_artist(arrow)
    return arrow


def _double_head(ax, p0, p1, color, lw=2.0, scale=14, gid=None, hollow=False):
    """Couple symbol: an arrow with two heads at its tip."""
    p0, p1 = np.asarray(p0, float), np.asarray(p1, float)
    _arrow(ax, p0, p1, color, lw=lw, scale=scale, gid=gid, hollow=hollow)
    _arrow(ax, p0, p0 + 0.8 * (p1 - p0), color, lw=lw, scale=scale, gid=gid, hollow=hollow)


def _perpendiculars(d):
    """Two unit vectors completing the unit vector ``d`` to a right-handed frame."""
    d = np.asarray(d, float) / np.linalg.norm(d)
    t = np.eye(3)[int(np.argmin(np.abs(d)))]
    e1 = np.cross(d, t)
    e1 /= np.linalg.norm(e1)
    return e1, np.cross(d, e1)


def _sleeve(ax, centre, d, half_length, half_width, edge, face, gid=None):
    """A prismatic joint: a square sleeve (box) of ``2 half_length`` along ``d`` around its
    centre; returns its 8 corners (4 at each end)."""
    from mpl_toolkits.mplot3d.art3d import Poly3DCollection

    d = np.asarray(d, float) / np.linalg.norm(d)
    e1, e2 = _perpendiculars(d)
    ring = [half_width * (s1 * e1 + s2 * e2) for s1, s2 in ((1, 1), (-1, 1), (-1, -1), (1, -1))]
    c = np.asarray(centre, float)
    lo = np.array([c - half_length * d + q for q in ring])
    hi = np.array([c + half_length * d + q for q in ring])
    faces = [[lo[k], lo[(k + 1) % 4], hi[(k + 1) % 4], hi[k]] for k in range(4)] + [lo, hi]
    poly = Poly3DCollection(faces, facecolors=face, edgecolors=edge, linewidths=0.8,
                            alpha=0.9)
    poly.set_gid(gid)
    poly.xyz = np.vstack([lo, hi])          # the corners in data coordinates (like arrows)
    ax.add_collection3d(poly)
    return poly.xyz


def _clip_line(point, direction, lo, hi):
    """Segment of the line ``point + s direction`` inside the box [lo, hi] (or None)."""
    s0, s1 = -np.inf, np.inf
    for k in range(3):
        if abs(direction[k]) < 1e-12:
            if point[k] < lo[k] or point[k] > hi[k]:
                return None
            continue
        a = (lo[k] - point[k]) / direction[k]
        b = (hi[k] - point[k]) / direction[k]
        s0, s1 = max(s0, min(a, b)), min(s1, max(a, b))
    if s1 <= s0:
        return None
    return point + s0 * direction, point + s1 * direction


class _Extent:
    """Collects points to fix equal-aspect limits."""

    def __init__(self):
        self.pts = []

    def add(self, *pts):
        for p in pts:
            self.pts.append(np.asarray(p, float).reshape(-1, 3))

    def box(self, pad=0.1, min_fraction=0.35):
        P = np.vstack(self.pts)
        lo, hi = P.min(axis=0), P.max(axis=0)
        span = float(np.max(hi - lo)) or 1.0
        centre = 0.5 * (lo + hi)
        half = np.maximum(0.5 * (hi - lo), 0.5 * min_fraction * span) + pad * span
        return centre - half, centre + half
