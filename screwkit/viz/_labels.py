"""Placement of the text labels of a 3D drawing.

The drawing code asks for labels (:meth:`_Labeller.tip`, :meth:`~_Labeller.beside`,
:meth:`~_Labeller.around`) with the screen directions it prefers, and registers what a
label must not cover: markers (:meth:`~_Labeller.marker`: points, arrow heads) and drawn
segments (:meth:`~_Labeller.segment`).  Once the view and limits are final,
:meth:`_Labeller.place` projects everything to the screen and places the labels greedily,
twice over: each label takes, among 16 directions x 7 distances around its anchor, the
offset with the least cost (overlap with the boxes of the other labels and of the markers,
leaving the figure, drawn segments under the text, distance, and the preferred direction).
A label moved away from its anchor gets a thin leader line.
"""

from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np

from ._label_artist import _add_label, _anchor_display
from ._view import _View

_ANGLES = np.radians(np.arange(0.0, 360.0, 22.5))
_RADII = (0.0, 4.0, 9.0, 16.0, 26.0, 40.0, 58.0)       # points beyond the base gap
_PAD = 3.0                                              # pixels kept free around a box
_W_LABEL, _W_MARKER, _W_OUT, _W_AXES = 100.0, 60.0, 100.0, 4.0
_W_HARD = 500.0          # any overlap with a label, a marker or a text: a last resort
_W_HULL = 300.0          # a label leaving the box of the 3D axes (over the tick labels)
_W_SEGMENT, _W_DIST, _W_PREF, _W_TAKEN = 0.3, 0.07, 1.5, 1.2
_W_OWNER = 200.0         # a label nearer another arrow than its own (it would be misread)


def _cross2(u, v) -> float:
    return float(u[0] * v[1] - u[1] * v[0])


def _box_hull(ax):
    """The screen outline (a matplotlib Path) of the 3D axes' box of limits: its convex
    hull in display coordinates.  Labels inside it keep clear of the tick labels."""
    from matplotlib.path import Path

    lo = np.array([ax.get_xlim()[0], ax.get_ylim()[0], ax.get_zlim()[0]])
    hi = np.array([ax.get_xlim()[1], ax.get_ylim()[1], ax.get_zlim()[1]])
    corners = np.array([[(lo, hi)[i][0], (lo, hi)[j][1], (lo, hi)[k][2]]
                        for i in (0, 1) for j in (0, 1) for k in (0, 1)])
    P = _anchor_display(ax, corners)
    P = P[np.lexsort((P[:, 1], P[:, 0]))]

    def half(points):
        h = []
        for p in points:
            while len(h) >= 2 and _cross2(h[-1] - h[-2], p - h[-2]) <= 0:
                h.pop()
            h.append(p)
        return h

    hull = half(P)[:-1] + half(P[::-1])[:-1]
    return Path(np.vstack([hull, hull[:1]]), closed=True)


def _align(c):
    ha = "left" if c[0] > 0.38 else ("right" if c[0] < -0.38 else "center")
    va = "bottom" if c[1] > 0.38 else ("top" if c[1] < -0.38 else "center")
    return ha, va


_FX = {"left": 0.0, "center": 0.5, "right": 1.0}
_FY = {"bottom": 0.0, "center": 0.5, "top": 1.0}


@dataclass
class _Request:
    artist: object
    anchor: np.ndarray
    prefs: list            # preferred unit screen directions (any of them)
    key: tuple             # the anchor's key for the taken directions
    gap: float             # points between the anchor and the text
    priority: int
    box: tuple = field(default=None)
    owner: int | None = None    # the index of its arrow in _Labeller.arrows


def _overlaps(boxes, obstacles, area) -> np.ndarray:
    """Per box of ``boxes`` (c, 4): the area covered by ``obstacles`` (k, 4) over ``area``."""
    if len(obstacles) == 0:
        return np.zeros(len(boxes))
    dx = (np.minimum(boxes[:, None, 2], obstacles[None, :, 2])
          - np.maximum(boxes[:, None, 0], obstacles[None, :, 0]))
    dy = (np.minimum(boxes[:, None, 3], obstacles[None, :, 3])
          - np.maximum(boxes[:, None, 1], obstacles[None, :, 1]))
    return np.sum(np.clip(dx, 0, None) * np.clip(dy, 0, None), axis=1) / max(area, 1e-9)


def _leaders_cross(anchor, boxes, others, with_leader) -> np.ndarray:
    """Per candidate box of ``boxes`` (16 * r, 4; ``with_leader`` (r,) tells which distances
    get a leader line): True where the leader from ``anchor`` to the box crosses a box of
    ``others`` (k, 4), sampled at 12 points."""
    out = np.zeros(len(boxes), bool)
    if len(others) == 0 or not np.any(with_leader):
        return out
    lead = np.tile(np.asarray(with_leader, bool), len(boxes) // len(with_leader))
    end = np.clip(anchor[None, :], boxes[:, :2], boxes[:, 2:])           # (c, 2)
    s = np.linspace(0.05, 0.95, 12)[None, :, None]
    pts = anchor[None, None, :] + s * (end - anchor[None, :])[:, None, :]   # (c, 12, 2)
    x, y = pts[..., 0][..., None], pts[..., 1][..., None]                 # (c, 12, 1)
    hit = ((x > others[None, None, :, 0]) & (x < others[None, None, :, 2])
           & (y > others[None, None, :, 1]) & (y < others[None, None, :, 3]))
    return lead & hit.any(axis=(1, 2))


def _box_segment_distances(boxes, segments) -> np.ndarray:
    """Screen distance ``(c, k)`` from the centre of each box ``(c, 4)`` to each segment
    ``(k, 2, 2)``."""
    c = 0.5 * (boxes[:, :2] + boxes[:, 2:])                                # (c, 2)
    a, ab = segments[:, 0], segments[:, 1] - segments[:, 0]                # (k, 2)
    t = np.einsum("ckx,kx->ck", c[:, None, :] - a[None], ab) / np.maximum(
        np.einsum("kx,kx->k", ab, ab), 1e-12)[None]
    near = a[None] + np.clip(t, 0.0, 1.0)[..., None] * ab[None]
    return np.linalg.norm(c[:, None, :] - near, axis=-1)


def _text_boxes(fig, ax, renderer) -> np.ndarray:
    """Boxes (k, 4) of the texts already drawn that labels must not cover: the figure's
    titles, notes and legends, and the other texts of ``ax`` (the tick and axis labels of a
    3D axes lie outside its box, see :func:`_box_hull`)."""
    items = [t for t in fig.texts if t.get_text()]
    if getattr(fig, "_suptitle", None) is not None:
        items.append(fig._suptitle)
    items += list(fig.legends) + ([ax.get_legend()] if ax.get_legend() else [])
    items += [t for t in ax.texts if t.get_gid() != "label" and t.get_text()]
    out = []
    for t in items:
        try:
            bb = t.get_window_extent(renderer)
        except (RuntimeError, ValueError, TypeError):
            continue
        if bb.width > 0 and bb.height > 0:
            out.append((bb.x0 - _PAD, bb.y0 - _PAD, bb.x1 + _PAD, bb.y1 + _PAD))
    return np.array(out).reshape(-1, 4)


class _Labeller:
    """Collects the labels and obstacles of one 3D drawing and places the labels.

    ``scale`` is the drawing's characteristic length (for the keys of the directions
    taken at a point).  ``span`` and ``width_pt`` are kept for compatibility (unused).
    """

    def __init__(self, ax, view: _View, scale: float, span: float = 1.6,
                 width_pt: float = 420.0):
        self.ax, self.view, self.scale = ax, view, scale
        self.taken = {}
        self.requests = []
        self.markers = []      # (point (3,), radius in points)
        self.segments = []     # (p0 (3,), p1 (3,))
        self.arrows = []       # (p0 (3,), p1 (3,)): arrows whose labels must sit by their own

    # -- what the labels must avoid --------------------------------------------------------
    def _key(self, p):
        return tuple(np.round(np.asarray(p, float) / self.scale, 3))

    def block(self, point, direction):
        """Mark the screen direction of ``direction`` at ``point`` as taken."""
        s = self.view.screen(direction)
        if np.any(s):
            self.taken.setdefault(self._key(point), []).append(s)

    def marker(self, point, radius_pt: float):
        """A marker (point, arrow head) of ``radius_pt`` points at ``point``."""
        self.markers.append((np.asarray(point, float), float(radius_pt)))

    def segment(self, p0, p1):
        """A drawn segment that a label should not lie on."""
        self.segments.append((np.asarray(p0, float), np.asarray(p1, float)))

    def arrow(self, p0, p1) -> int:
        """Register an arrow (3D tail and head); returns its index for a label's ``owner``."""
        self.arrows.append((np.asarray(p0, float), np.asarray(p1, float)))
        return len(self.arrows) - 1

    def _score(self, point, s):
        return min((-float(np.dot(s, t)) for t in self.taken.get(self._key(point), [])),
                   default=1.0)

    # -- label requests ----------------------------------------------------------------------
    def _request(self, anchor, text, color, size, prefs, gap_pt, priority):
        anchor = np.asarray(anchor, float)
        c = prefs[0] if prefs else np.array([1.0, 0.0])
        ha, va = _align(c)
        art = _add_label(self.ax, anchor, text, color, size, ha=ha, va=va)
        art.set_offset(*(gap_pt * c))
        self.requests.append(_Request(art, anchor, [np.asarray(p, float) for p in prefs],
                                      self._key(anchor), gap_pt, priority))
        return art

    def axis_end(self, point, d) -> float:
        """+1 or -1: the end of an axis through ``point`` to put its label at."""
        d = np.asarray(d, float)
        sp, sm = self.view.screen(d), self.view.screen(-d)
        sgn = 1.0 if self._score(point, sp) >= self._score(point, sm) - 1e-9 else -1.0
        self.block(point, d)   # the segment occupies both directions
        self.block(point, -d)
        return sgn

    def tip(self, tip, d, text, color, size, gap=None, priority=2):
        """Label beyond the tip of an arrow/segment pointing along ``d``."""
        s = self.view.screen(np.asarray(d, float))
        return self._request(tip, text, color, size, [s] if np.any(s) else [], 3.0, priority)

    def beside(self, tip, d, text, color, size, gap=None, priority=0, owner=None):
        """Label beside the head of an arrow along ``d`` (off its line): either side.
        ``owner``: the index of the arrow (:meth:`arrow`); the label is then kept nearer
        it than any other registered arrow."""
        s = self.view.screen(np.asarray(d, float))
        prefs = [np.array([-s[1], s[0]]), np.array([s[1], -s[0]])] if np.any(s) else []
        art = self._request(tip, text, color, size, prefs, 5.0, priority)
        self.requests[-1].owner = owner
        return art

    def around(self, point, text, color, size, dist=None, priority=1):
        """Label next to ``point``, in the screen direction freest of what is drawn there."""
        cands = [np.array([np.cos(t), np.sin(t)]) for t in _ANGLES]
        best = max(cands, key=lambda c: self._score(point, c))
        return self._request(point, text, color, size, [best], 4.0, priority)

    # -- the placement pass -----------------------------------------------------------------
    def place(self):
        """Place every label (call once the view, limits and figure layout are final).

        The figure is drawn once first, so that the tick labels, axis labels, legends and
        titles are where they will be; their boxes are obstacles too.
        """
        if not self.requests:
            return
        ax = self.ax
        fig = ax.figure
        fig.canvas.draw()
        renderer = fig.canvas.get_renderer()
        px = fig.dpi / 72.0
        anchors = _anchor_display(ax, [r.anchor for r in self.requests])
        fixed = [np.zeros((0, 4))]
        if self.markers:
            c = _anchor_display(ax, [m[0] for m in self.markers])
            rad = np.array([m[1] for m in self.markers]) * px + _PAD
            fixed.append(np.column_stack([c - rad[:, None], c + rad[:, None]]))
        fixed.append(_text_boxes(fig, ax, renderer))
        marks = np.vstack(fixed)
        seg_pts = self._segment_points(ax)
        arrows = (_anchor_display(ax, [p for a in self.arrows for p in a]).reshape(-1, 2, 2)
                  if self.arrows else np.zeros((0, 2, 2)))
        fb, ab = fig.bbox, ax.bbox
        hull = _box_hull(ax) if getattr(ax, "name", "") == "3d" else None
        sizes = []
        for r in self.requests:
            r.artist.set_ha("left")
            r.artist.set_va("bottom")
            r.artist.set_offset(0.0, 0.0)
            bb = r.artist.get_window_extent(renderer)
            sizes.append((bb.width, bb.height))
        C = np.column_stack([np.cos(_ANGLES), np.sin(_ANGLES)])          # (16, 2)
        al = [_align(c) for c in C]
        fx = np.array([_FX[h] for h, _ in al])
        fy = np.array([_FY[v] for _, v in al])
        extra = np.array(_RADII)
        order = sorted(range(len(self.requests)), key=lambda i: self.requests[i].priority)
        for _ in range(2):
            for i in order:
                r, (w, h), a = self.requests[i], sizes[i], anchors[i]
                others = np.array([self.requests[k].box for k in order
                                   if k != i and self.requests[k].box is not None]
                                  ).reshape(-1, 4) + np.array([-_PAD, -_PAD, _PAD, _PAD])
                dist = r.gap + extra                                        # (7,)
                o = a + px * dist[None, :, None] * C[:, None, :]            # (16, 7, 2)
                x0 = o[..., 0] - fx[:, None] * w
                y0 = o[..., 1] - fy[:, None] * h
                boxes = np.stack([x0, y0, x0 + w, y0 + h], axis=-1).reshape(-1, 4)
                pref = np.array([min((1.0 - float(c @ p) for p in r.prefs), default=0.0)
                                 for c in C])
                taken = np.array([max((max(0.0, float(c @ t)) for t in self.taken.get(r.key, [])),
                                      default=0.0) for c in C])
                ov_lab = _overlaps(boxes, others, w * h)
                ov_mark = _overlaps(boxes, marks, w * h)
                cost = (_W_LABEL * ov_lab + _W_MARKER * ov_mark
                        + _W_HARD * ((ov_lab > 0) | (ov_mark > 0))
                        + np.repeat(_W_PREF * pref + _W_TAKEN * taken, len(extra))
                        + np.tile(_W_DIST * extra, len(C)))
                cost += _W_OUT * ((boxes[:, 0] < fb.x0) | (boxes[:, 1] < fb.y0)
                                  | (boxes[:, 2] > fb.x1) | (boxes[:, 3] > fb.y1))
                cost += _W_AXES * ((boxes[:, 0] < ab.x0) | (boxes[:, 1] < ab.y0)
                                   | (boxes[:, 2] > ab.x1) | (boxes[:, 3] > ab.y1))
                if hull is not None:
                    corners = boxes[:, [0, 1, 2, 1, 2, 3, 0, 3]].reshape(-1, 2)
                    inside = hull.contains_points(corners).reshape(-1, 4).all(axis=1)
                    cost += _W_HULL * ~inside
                cost += _W_HARD * _leaders_cross(a, boxes, others, extra >= 9.0)
                if r.owner is not None and len(arrows) > 1:
                    d = _box_segment_distances(boxes, arrows)                # (c, k)
                    rival = np.delete(d, r.owner, axis=1).min(axis=1)
                    cost += _W_OWNER * (rival < d[:, r.owner])
                if len(seg_pts):
                    inside = ((seg_pts[None, :, 0] > boxes[:, None, 0])
                              & (seg_pts[None, :, 0] < boxes[:, None, 2])
                              & (seg_pts[None, :, 1] > boxes[:, None, 1])
                              & (seg_pts[None, :, 1] < boxes[:, None, 3]))
                    cost += _W_SEGMENT * np.minimum(inside.sum(axis=1), 24)
                b = int(np.argmin(cost))
                ia, ir = divmod(b, len(extra))
                r.box = tuple(boxes[b])
                r.artist.set_ha(al[ia][0])
                r.artist.set_va(al[ia][1])
                off = dist[ir] * C[ia]
                r.artist.set_offset(off[0], off[1], leader=extra[ir] >= 9.0)

    def _segment_points(self, ax) -> np.ndarray:
        """Display points every ~5 pixels along the registered segments."""
        if not self.segments:
            return np.zeros((0, 2))
        ends = _anchor_display(ax, [p for s in self.segments for p in s]).reshape(-1, 2, 2)
        pts = []
        for p0, p1 in ends:
            n = int(np.clip(np.linalg.norm(p1 - p0) / 5.0, 2, 400))
            s = np.linspace(0.0, 1.0, n)[:, None]
            pts.append(p0 + s * (p1 - p0))
        return np.vstack(pts)
