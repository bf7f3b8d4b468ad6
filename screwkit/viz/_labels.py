"""Placement of the text labels of a drawing: beside arrow tips and points, away from the
drawn directions and from each other (in screen space)."""

from __future__ import annotations

import numpy as np

from ._view import _View


def _label(ax, p, text, color="k", size=7, offset=None, ha="left", va="center"):
    p = np.asarray(p, float) + (0 if offset is None else offset)
    ax.text(p[0], p[1], p[2], text, color=color, fontsize=size, zorder=10, ha=ha, va=va)


def _visible_length(text: str) -> int:
    """Rough number of printed characters of a (mathtext) label."""
    return max(1, len(text) - sum(text.count(c) for c in "${}_\\"))


class _Labeller:
    """Places labels: avoids screen directions already taken at a point (chain,
    axes, other labels) and overlaps with the boxes of labels already placed.

    ``scale`` is the drawing's characteristic length; ``pt`` the data length of one
    typographic point (estimated from the figure size: the drawing spans about
    ``span`` scales over ``width_pt`` points).
    """

    def __init__(self, ax, view: _View, scale: float, span: float = 1.6,
                 width_pt: float = 420.0):
        self.ax, self.view, self.scale = ax, view, scale
        self.pt = span * scale / width_pt
        self.taken = {}
        self.boxes = []

    def _key(self, p):
        return tuple(np.round(np.asarray(p, float) / self.scale, 3))

    def block(self, point, direction):
        """Mark the screen direction of ``direction`` at ``point`` as taken."""
        s = self.view.screen(direction)
        if np.any(s):
            self.taken.setdefault(self._key(point), []).append(s)

    def _score(self, point, s):
        return min((-float(np.dot(s, t)) for t in self.taken.get(self._key(point), [])),
                   default=1.0)

    def _box(self, pos, text, size, ha, va):
        xy = self.view.project(pos)
        w = 0.7 * size * _visible_length(text) * self.pt
        h = 1.3 * size * self.pt
        x0 = xy[0] - {"left": 0.0, "center": 0.5, "right": 1.0}[ha] * w
        y0 = xy[1] - {"bottom": 0.0, "center": 0.5, "top": 1.0}[va] * h
        return (x0, y0, x0 + w, y0 + h)

    def _overlap(self, box):
        area = (box[2] - box[0]) * (box[3] - box[1])
        tot = 0.0
        for b in self.boxes:
            dx = min(box[2], b[2]) - max(box[0], b[0])
            dy = min(box[3], b[3]) - max(box[1], b[1])
            if dx > 0 and dy > 0:
                tot += dx * dy
        return tot / area if area > 0 else 0.0

    def _put(self, candidates, text, color, size):
        """candidates: (position, ha, va, score); the best after overlap penalties."""
        best, best_score = None, -np.inf
        for pos, ha, va, sc in candidates:
            box = self._box(pos, text, size, ha, va)
            total = sc - 3.0 * self._overlap(box)
            if total > best_score + 1e-9:
                best, best_score = (pos, ha, va, box), total
        pos, ha, va, box = best
        self.boxes.append(box)
        _label(self.ax, pos, text, color, size, ha=ha, va=va)
        return pos

    @staticmethod
    def _align(xy):
        ha = "left" if xy[0] > 0.3 else ("right" if xy[0] < -0.3 else "center")
        va = "bottom" if xy[1] > 0.3 else ("top" if xy[1] < -0.3 else "center")
        return ha, va

    def axis_end(self, point, d) -> float:
        """+1 or -1: the end of an axis through ``point`` to put its label at."""
        d = np.asarray(d, float)
        sp, sm = self.view.screen(d), self.view.screen(-d)
        sgn = 1.0 if self._score(point, sp) >= self._score(point, sm) - 1e-9 else -1.0
        self.block(point, d)   # the segment occupies both directions
        self.block(point, -d)
        return sgn

    def tip(self, tip, d, text, color, size, gap):
        """Label beyond the tip of an arrow/segment pointing along ``d``."""
        d = np.asarray(d, float)
        ha, va = self._align(self.view.screen(d))
        if ha != "center":
            va = "center"
        self._put([(np.asarray(tip, float) + gap * d, ha, va, 0.0)], text, color, size)

    def beside(self, tip, d, text, color, size, gap):
        """Label beside the head of an arrow along ``d`` (off its line, which may be
        drawn dashed beyond the head): on either side, whichever is freer."""
        d = np.asarray(d, float)
        n = self.view.side(d)
        cands = []
        for sgn in (1.0, -1.0):
            xy = self.view.screen(sgn * n)
            ha, va = self._align(xy)
            cands.append((np.asarray(tip, float) + gap * sgn * n, ha, va,
                          0.1 if xy[0] > 0 else 0.0))
        self._put(cands, text, color, size)

    def around(self, point, text, color, size, dist=0.06):
        """Label next to ``point`` in the freest of 12 screen directions."""
        cands = []
        for k in range(12):
            th = np.radians(-90.0 - 30.0 * k)  # from below, clockwise
            c = np.array([np.cos(th), np.sin(th)])
            ha, va = self._align(c)
            pos = np.asarray(point, float) + dist * self.scale * self.view.offset(c)
            cands.append((pos, ha, va, self._score(point, c) - 1e-3 * k))
        pos = self._put(cands, text, color, size)
        off = self.view.project(pos - np.asarray(point, float))
        if np.linalg.norm(off) > 0:
            self.taken.setdefault(self._key(point), []).append(off / np.linalg.norm(off))
