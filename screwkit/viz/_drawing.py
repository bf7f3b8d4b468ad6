"""3D drawings of legs and of a PM at a pose, with their wrenches.

:func:`draw_leg` draws one :class:`~screwkit.legs.Leg` (its equivalent chain
and, given an analysis, its constraint and actuation wrenches);
:func:`draw_pm` draws a PM at one pose from plain arrays (base and platform
polygons, legs, and wrench rows with values).  Both return a matplotlib
``Figure`` and optionally save it as PNG.

matplotlib is optional (``pip install "screwkit[plot]"``); it is imported
inside the functions, and figures are made on an Agg canvas (no display, no
pyplot global state).

Drawing conventions
-------------------
* equivalent chain: grey polyline ``A -> joint points -> a``;
* R (and H) axis: dark segment of a quarter of the leg length centred at its point;
* P: orange double-headed arrow along its sliding direction;
* S centre: large purple ball; U centre: small purple dot (its two R axes drawn);
* constraint force: blue arrow at its named point, its line dashed across the drawing;
  where the point is the meeting point of two axes (``R1^R5``) the axes are
  extended to it (dotted);
* constraint couple: green arrow with two heads (a free vector: drawn from the
  leg's midpoint, or beside the leg when it is along the leg);
* actuation wrench: red (a force is drawn where its line is closest to ``a``).

Artists are tagged with matplotlib gids so that callers (and tests) can find
them: arrows ``"force:k"``, ``"couple:k"``, ``"screw:k"`` (k-th constraint
member), ``"actuation:<kind>"``, ``"joint:P2"`` (P joints), ``"row:i"`` (the
i-th wrench row of :func:`draw_pm`); polygons ``"base"`` and ``"platform"``.
Arrows carry their tail and head in data coordinates as ``arrow.xyz``.
"""

from __future__ import annotations

from dataclasses import dataclass
from functools import lru_cache

import numpy as np

from ..errors import InputError

__all__ = ["draw_leg", "draw_pm", "require_matplotlib", "new_figure", "save_figure",
           "COLORS", "DEFAULT_VIEW"]

#: Colours of the drawing elements.
COLORS = {
    "chain": "#9a9a9a", "R": "#262626", "P": "#e08214", "S": "#6a3d9a", "U": "#6a3d9a",
    "end": "#000000", "force": "#2166ac", "couple": "#1b7837", "screw": "#c51b7d",
    "actuation": "#d6261e", "base": "#bdbdbd", "platform": "#9ecae1",
}

#: Default (elevation, azimuth) in degrees of the PM drawings.
DEFAULT_VIEW = (20.0, -60.0)


def require_matplotlib():
    """Import matplotlib for off-screen (Agg) drawing.

    Returns
    -------
    module
        ``matplotlib``.

    Raises
    ------
    InputError
        When matplotlib is not installed.
    """
    try:
        import matplotlib
        from matplotlib.backends.backend_agg import FigureCanvasAgg  # noqa: F401
        import mpl_toolkits.mplot3d  # noqa: F401  (registers the 3d projection)
    except ImportError:
        raise InputError('drawing needs matplotlib: pip install "screwkit[plot]"') from None
    return matplotlib


def new_figure(figsize, projection=None, **figure_kw):
    """A Figure on an Agg canvas (no pyplot) and, if ``projection``, one axes.

    Parameters
    ----------
    figsize : (float, float)
        Inches.
    projection : str, optional
        E.g. ``"3d"``: add one axes with that projection.
    **figure_kw
        Passed to ``matplotlib.figure.Figure`` (e.g. ``layout="constrained"``).

    Returns
    -------
    (Figure, Axes or None)
    """
    require_matplotlib()
    from matplotlib.backends.backend_agg import FigureCanvasAgg
    from matplotlib.figure import Figure

    fig = Figure(figsize=figsize, **figure_kw)
    FigureCanvasAgg(fig)
    if projection is None:
        return fig, None
    return fig, fig.add_subplot(1, 1, 1, projection=projection)


def save_figure(fig, out, dpi=150) -> None:
    """Save ``fig`` to ``out`` (PNG unless the suffix says otherwise); no-op for None.

    Raises
    ------
    InputError
        When the file cannot be written.
    """
    if out is None:
        return
    try:
        fig.savefig(str(out), dpi=dpi)
    except (OSError, ValueError) as exc:
        raise InputError(f"cannot write figure {str(out)!r}: {exc}") from None


# ----------------------------------------------------------------------------- view geometry

@dataclass(frozen=True)
class _View:
    """Screen geometry of a 3D view (elevation, azimuth in degrees)."""

    elev: float
    azim: float

    @property
    def sight(self) -> np.ndarray:
        """Unit vector from the scene towards the camera."""
        el, az = np.radians(self.elev), np.radians(self.azim)
        return np.array([np.cos(el) * np.cos(az), np.cos(el) * np.sin(az), np.sin(el)])

    @property
    def right(self) -> np.ndarray:
        r = np.cross([0.0, 0.0, 1.0], self.sight)
        return r / np.linalg.norm(r)

    @property
    def up(self) -> np.ndarray:
        u = np.cross(self.sight, self.right)
        return u / np.linalg.norm(u)

    def project(self, v) -> np.ndarray:
        """Screen components (right, up) of the 3D vector ``v``."""
        v = np.asarray(v, float)
        return np.array([np.dot(v, self.right), np.dot(v, self.up)])

    def screen(self, v) -> np.ndarray:
        """Unit screen direction of ``v`` (zeros when ``v`` points at the camera)."""
        xy = self.project(v)
        n = np.linalg.norm(xy)
        return xy / n if n > 1e-9 * max(1.0, np.linalg.norm(v)) else np.zeros(2)

    def side(self, d) -> np.ndarray:
        """Unit 3D vector perpendicular to ``d`` and to the line of sight."""
        n = np.cross(np.asarray(d, float), self.sight)
        nn = np.linalg.norm(n)
        return n / nn if nn > 1e-9 else self.right

    def offset(self, xy) -> np.ndarray:
        """3D vector that appears as the screen vector ``xy``."""
        return xy[0] * self.right + xy[1] * self.up


def _view_score(view: _View, groups) -> float:
    """How well ``view`` separates directions drawn at the same point.

    ``groups`` is a list of lists of 3D directions (lines, sign irrelevant).  The
    score is the smallest screen angle (degrees) between two lines of a group,
    capped by the foreshortening of each line (a line seen end-on scores 0).
    """
    worst = 90.0
    for dirs in groups:
        proj = [view.project(d) for d in dirs]
        for p, d in zip(proj, dirs):
            ratio = min(1.0, float(np.linalg.norm(p) / np.linalg.norm(d)))
            worst = min(worst, float(np.degrees(np.arcsin(ratio))))  # angle off the sight line
        for i in range(len(proj)):
            for k in range(i + 1, len(proj)):
                d3 = abs(float(np.dot(dirs[i], dirs[k]))) / (np.linalg.norm(dirs[i]) *
                                                             np.linalg.norm(dirs[k]))
                if d3 > 0.999:  # the same line in space: no view separates them
                    continue
                a, b = proj[i], proj[k]
                na, nb = np.linalg.norm(a), np.linalg.norm(b)
                if na < 1e-9 or nb < 1e-9:
                    return 0.0
                c = abs(float(np.dot(a, b))) / (na * nb)
                worst = min(worst, float(np.degrees(np.arccos(min(1.0, c)))))
    return worst


def _choose_view(groups) -> _View:
    """The view (elevation 15-35 deg, azimuth -150..-20 deg) that best separates the
    directions of each group (30 deg counts as enough); ties go to the one nearest
    :data:`DEFAULT_VIEW`."""
    best, best_key = _View(*DEFAULT_VIEW), None
    for elev in (20.0, 25.0, 30.0, 35.0, 15.0):
        for azim in np.arange(-150.0, -19.0, 5.0):
            v = _View(elev, float(azim))
            score = round(_view_score(v, groups), 0)
            key = (min(score, 30.0),
                   -abs(azim - DEFAULT_VIEW[1]) - 0.5 * abs(elev - DEFAULT_VIEW[0]))
            if best_key is None or key > best_key:
                best, best_key = v, key
    return best


def _segment_distance(q, a, b) -> float:
    ab = b - a
    t = float(np.clip(np.dot(q - a, ab) / max(float(np.dot(ab, ab)), 1e-300), 0.0, 1.0))
    return float(np.linalg.norm(q - (a + t * ab)))


def _pm_view_clearance(view: _View, legs, B, P, o, size) -> float:
    """Smallest screen distance (in units of ``size``) between two of the points
    ``A_i, a_i, o``, or between one of them and another leg (extended by half its
    length beyond ``a_i``, where the actuation arrows go)."""
    pts = [(view.project(b) / size, i) for i, b in enumerate(B)]
    pts += [(view.project(p) / size, i) for i, p in enumerate(P)] + [(view.project(o) / size, -1)]
    segs = [(view.project(g.A) / size, view.project(g.a + 0.5 * (g.a - g.A)) / size)
            for g in legs]
    worst = np.inf
    for q, i in pts:
        for k, (a, b) in enumerate(segs):
            if k != i:
                worst = min(worst, _segment_distance(q, a, b))
    for x in range(len(pts)):
        for y in range(x + 1, len(pts)):
            worst = min(worst, float(np.linalg.norm(pts[x][0] - pts[y][0])))
    return float(worst)


def _choose_pm_view(legs, B, P, o, size) -> _View:
    """The view nearest :data:`DEFAULT_VIEW` in which no point ``A_i``, ``a_i``, ``o``
    is hidden by another or by a leg (clearance >= 0.1 ``size`` if possible)."""
    best, best_key = _View(*DEFAULT_VIEW), None
    for elev in (20.0, 25.0, 30.0, 15.0, 35.0):
        for azim in np.arange(-150.0, -19.0, 5.0):
            v = _View(elev, float(azim))
            c = round(min(_pm_view_clearance(v, legs, B, P, o, size), 0.1), 3)
            key = (c, -abs(azim - DEFAULT_VIEW[1]) - 0.5 * abs(elev - DEFAULT_VIEW[0]))
            if best_key is None or key > best_key:
                best, best_key = v, key
    return best


# ----------------------------------------------------------------------------- primitives

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


def _arrow(ax, p0, p1, color, style="-|>", lw=2.0, scale=14, zorder=5, alpha=1.0, gid=None):
    """A 3D arrow; ``gid`` tags it (``"force:..."``, ``"row:3"``...) for tests and users."""
    arrow = _arrow3d_class()(p0, p1, arrowstyle=style, mutation_scale=scale, lw=lw,
                             color=color, shrinkA=0, shrinkB=0, zorder=zorder, alpha=alpha)
    arrow.set_gid(gid)
    ax.add_artist(arrow)
    return arrow


def _double_head(ax, p0, p1, color, lw=2.0, scale=14, gid=None):
    """Couple symbol: an arrow with two heads at its tip."""
    p0, p1 = np.asarray(p0, float), np.asarray(p1, float)
    _arrow(ax, p0, p1, color, lw=lw, scale=scale, gid=gid)
    _arrow(ax, p0, p0 + 0.8 * (p1 - p0), color, lw=lw, scale=scale, gid=gid)


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


# ----------------------------------------------------------------------------- legs

def _leg_direction_groups(leg, extra=()):
    """Directions drawn at each point of a leg (for the choice of view)."""
    L = leg.length
    legdir = (leg.a - leg.A) / L
    groups = {}
    for j in leg.joints:
        if j.spec.origin == "S":
            continue
        key = tuple(np.round(j.point / L, 3))
        groups.setdefault(key, [legdir]).append(j.direction)
    for p, d in extra:
        groups.setdefault(tuple(np.round(np.asarray(p) / L, 3)), []).append(np.asarray(d))
    return list(groups.values()) or [[legdir]]


def _leg_geometry(ax, leg, ext: _Extent, view: _View, joint_labels=True,
                  end_labels=("A", "a"), label_size=7, labeller=None):
    """Draw a leg's chain and joints; returns the set of element kinds drawn."""
    L = leg.length
    seg = 0.25 * L
    kinds = {"chain", "end"}
    lab = labeller or _Labeller(ax, view, L)
    chain = [leg.A] + [j.point for j in leg.joints] + [leg.a]
    pts = [chain[0]]
    for p in chain[1:]:
        if np.linalg.norm(p - pts[-1]) > 1e-9 * L:
            pts.append(p)
    pts = np.array(pts)
    ax.plot(pts[:, 0], pts[:, 1], pts[:, 2], color=COLORS["chain"], lw=3.0, alpha=0.9,
            solid_capstyle="round", zorder=1)
    ext.add(pts)
    for i in range(len(pts) - 1):
        lab.block(pts[i], pts[i + 1] - pts[i])
        lab.block(pts[i + 1], pts[i] - pts[i + 1])
    centres_done, centre_labels = set(), []
    for j in leg.joints:
        origin = j.spec.origin
        group = f"{origin}{j.spec.position}"
        act = " (actuated)" if j.actuated else ""
        if origin == "S":
            if group not in centres_done:
                centres_done.add(group)
                ax.scatter(*j.point, s=140, color=COLORS["S"], depthshade=False, zorder=4,
                           edgecolors="white", linewidths=0.8)
                kinds.add("S")
                if joint_labels:
                    centre_labels.append((j.point, group + act, COLORS["S"]))
            continue
        if j.kind == "P":
            d = j.direction
            p0, p1 = j.point - 0.15 * L * d, j.point + 0.15 * L * d
            _arrow(ax, p0, p1, COLORS["P"], style="<|-|>", lw=2.2, scale=12,
                   gid=f"joint:{j.name}")
            ext.add(p0, p1)
            kinds.add("P")
            if joint_labels:
                lab.block(j.point, d)
                lab.block(j.point, -d)
                lab.around(j.point, j.name + act, COLORS["P"], label_size, dist=0.04)
            continue
        # R or H axis (also the axes of U and C)
        p0, p1 = j.point - 0.5 * seg * j.direction, j.point + 0.5 * seg * j.direction
        ax.plot(*np.array([p0, p1]).T, color=COLORS["R"], lw=2.4, zorder=3,
                solid_capstyle="butt")
        ext.add(p0, p1)
        kinds.add("H" if j.kind == "H" else "R")
        if origin == "U" and group not in centres_done:
            centres_done.add(group)
            ax.scatter(*j.point, s=45, color=COLORS["U"], depthshade=False, zorder=4)
            kinds.add("U")
            if joint_labels:
                centre_labels.append((j.point, group, COLORS["U"]))
        if joint_labels:
            tag = j.name + ("" if j.kind == "R" else f" ({j.kind}, pitch {j.pitch:.3g})") + act
            sgn = lab.axis_end(j.point, j.direction)
            lab.tip(j.point + sgn * 0.5 * seg * j.direction, sgn * j.direction, tag,
                    COLORS["R"], label_size, 0.02 * L)
        else:
            lab.block(j.point, j.direction)
            lab.block(j.point, -j.direction)
    ax.scatter(*np.array([leg.A, leg.a]).T, s=22, marker="s", color=COLORS["end"],
               depthshade=False, zorder=4)
    if end_labels:
        lab.around(leg.A, end_labels[0], "k", label_size + 1)
        lab.around(leg.a, end_labels[1], "k", label_size + 1)
    for q, text, color in centre_labels:
        lab.around(q, text, color, label_size)
    return kinds


def _legend_handles(kinds):
    from matplotlib.lines import Line2D

    def h(color, label, **kw):
        return Line2D([], [], color=color, label=label, **kw)

    spec = [
        ("base", h(COLORS["base"], "base", lw=8, alpha=0.6)),
        ("platform", h(COLORS["platform"], "platform", lw=8, alpha=0.8)),
        ("chain", h(COLORS["chain"], "equivalent chain", lw=3)),
        ("R", h(COLORS["R"], "R axis", lw=2.4)),
        ("H", h(COLORS["R"], "H axis", lw=2.4)),
        ("P", h(COLORS["P"], "P (sliding direction)", lw=2.2, marker=">", markersize=6)),
        ("S", h(COLORS["S"], "S centre", lw=0, marker="o", markersize=9)),
        ("U", h(COLORS["U"], "U centre", lw=0, marker="o", markersize=5)),
        ("end", h(COLORS["end"], "end points A (base), a (platform)", lw=0, marker="s",
                  markersize=4)),
        ("meet", h(COLORS["R"], "axes extended to where they meet", lw=0.9, ls=":")),
        ("force", h(COLORS["force"], "constraint force (line dashed)", lw=2, marker=">",
                    markersize=6)),
        ("couple", h(COLORS["couple"], "constraint couple (double head)", lw=2, marker=">",
                     markersize=6)),
        ("screw", h(COLORS["screw"], "constraint wrench, finite pitch", lw=2, marker=">",
                    markersize=6)),
        ("actuation", h(COLORS["actuation"], "actuation wrench (line dashed)", lw=2,
                        marker=">", markersize=6)),
        ("actuation-couple", h(COLORS["actuation"], "actuation torque (double head)", lw=2,
                               marker=">", markersize=6)),
    ]
    return [hd for k, hd in spec if k in kinds]


def _finish_axes(ax, box, view: _View, length_unit, title, legend_kinds, legend=True,
                 own_figure=False, note=None):
    unit = f" [{length_unit}]" if length_unit else ""
    ax.set_xlabel("x" + unit, fontsize=8, labelpad=2)
    ax.set_ylabel("y" + unit, fontsize=8, labelpad=2)
    ax.set_zlabel("z" + unit, fontsize=8, labelpad=2)
    ax.tick_params(labelsize=7, pad=0)
    ax.locator_params(nbins=5)
    lo, hi = box
    ax.set_xlim(lo[0], hi[0])
    ax.set_ylim(lo[1], hi[1])
    ax.set_zlim(lo[2], hi[2])
    ax.set_box_aspect(tuple(hi - lo))  # equal scale on the three axes
    ax.view_init(elev=view.elev, azim=view.azim)
    if own_figure:
        fig = ax.figure
        ax.set_position([0.0, 0.04, 0.72, 0.86])
        if title:
            fig.suptitle(title, fontsize=10, x=0.5, y=0.97)
        if legend and legend_kinds:
            fig.legend(handles=_legend_handles(legend_kinds), loc="center left", fontsize=7.5,
                       frameon=False, bbox_to_anchor=(0.72, 0.55))
        if note:
            fig.text(0.73, 0.06, note, fontsize=7, color="#555555", va="bottom")
        return
    if title:
        ax.set_title(title, fontsize=10)
    if legend and legend_kinds:
        ax.legend(handles=_legend_handles(legend_kinds), loc="upper left", fontsize=7,
                  framealpha=0.85)


def _check_3d_axes(ax):
    if ax is not None and getattr(ax, "name", "") != "3d":
        raise InputError("ax must be a 3D axes (projection='3d')")


def _check_view(view):
    if view is None:
        return None
    try:
        elev, azim = (float(x) for x in view)
    except (TypeError, ValueError):
        raise InputError(f"view must be (elevation, azimuth) in degrees, not {view!r}") from None
    return _View(elev, azim)


def draw_leg(leg, analysis=None, ax=None, out=None, *, dpi: int = 150, title: str | None = None,
             length_unit: str = "cm", joint_labels: bool = True, legend: bool = True,
             view=None):
    """Draw one leg with its constraint and actuation wrenches.

    Parameters
    ----------
    leg : Leg
        A placed leg (:func:`screwkit.leg`).
    analysis : LegAnalysis, optional
        ``leg.analyze()``; when given, its constraint wrenches (blue forces,
        green couples) and its actuation wrench (red) are drawn.
    ax : mpl_toolkits.mplot3d.axes3d.Axes3D, optional
        Draw into this axes (default: a new 9 x 6.4 inch figure with the legend
        beside the drawing).
    out : str or Path, optional
        Save the figure there (PNG).
    dpi : int
        Resolution of the saved file.
    title : str, optional
        Default: leg name, marked string and the analysis summary.
    length_unit : str
        Unit of the leg's coordinates, for the axis labels (display only).
    joint_labels, legend : bool
    view : (elev, azim) in degrees, optional
        Default: chosen so that the axes drawn at a common point do not overlap
        on screen (elevation 15-35 deg, azimuth near -60 deg).

    Returns
    -------
    matplotlib.figure.Figure
    """
    require_matplotlib()
    _check_3d_axes(ax)
    L = leg.length
    mid = 0.5 * (leg.A + leg.a)
    legdir = (leg.a - leg.A) / L
    items = []  # (kind, member, colour key, label, gid)
    if analysis is not None:
        nf = nc = ns = 0
        for c in analysis.constraints:
            if c.kind == "force":
                nf += 1
                items.append(("force", c, "force", f"$F_{{c{nf}}}$", f"force:{nf}"))
            elif c.kind == "couple":
                nc += 1
                items.append(("couple", c, "couple", f"$T_{{c{nc}}}$", f"couple:{nc}"))
            else:
                ns += 1
                items.append(("screw", c, "screw", f"$W_{{c{ns}}}$ (pitch {c.pitch:.3g})",
                              f"screw:{ns}"))
        act = analysis.actuation
        if act is not None:
            m = act.member
            sym = {"couple": "T_{a}", "force": "F_{a}"}.get(m.kind, "W_{a}")
            items.append((m.kind, m, "actuation", f"${sym}$ ({act.joint})",
                          f"actuation:{m.kind}"))
    v = _check_view(view)
    if v is None:
        extra = [(c.point, c.direction) for k, c, _, _, _ in items
                 if k != "couple" and c.point is not None]
        v = _choose_view(_leg_direction_groups(leg, extra))
    own = ax is None
    if own:
        fig, ax = new_figure((9.0, 6.4), "3d")
    else:
        fig = ax.figure
    ext = _Extent()
    labeller = _Labeller(ax, v, L)
    kinds = _leg_geometry(ax, leg, ext, v, joint_labels=joint_labels, labeller=labeller)
    arrow_len = 0.4 * L
    lines = []
    for kind, c, ckey, lab, gid in items:
        d = np.asarray(c.direction, float)
        color = COLORS[ckey]
        if kind == "couple":  # a free vector: drawn beside the leg if along it
            p0 = mid
            if abs(float(np.dot(d, legdir))) > 0.5:
                p0 = mid + 0.3 * L * v.side(legdir)
            p1 = p0 + arrow_len * d
            _double_head(ax, p0, p1, color, gid=gid)
            ext.add(p0, p1)
            labeller.tip(p1, d, lab, color, 8, 0.03 * L)
            kinds.add("actuation-couple" if ckey == "actuation" else "couple")
            continue
        p = np.asarray(c.point if c.point is not None else mid, float)
        if ckey == "actuation":  # drawn where it acts on the platform: nearest to a
            p = p + float(np.dot(leg.a - p, d)) * d
        p1 = p + arrow_len * d
        _arrow(ax, p, p1, color, lw=2.2, gid=gid)
        if kind == "screw":  # a second, thinner head marks the finite pitch
            _arrow(ax, p, p + 0.8 * arrow_len * d, color, lw=1.0, scale=10, gid=gid)
        ext.add(p, p1)
        if c.point_name and "^" in c.point_name:  # show where the two axes meet
            for jn in c.point_name.split("^"):
                try:
                    jp = leg.joint(jn).point
                except InputError:
                    continue
                ax.plot(*np.array([jp, c.point]).T, color=COLORS["R"], lw=0.9, ls=":",
                        zorder=2)
            ax.scatter(*c.point, s=14, color=color, depthshade=False, zorder=4)
            kinds.add("meet")
        where = f" through {c.point_name.replace('^', '∩')}" if c.point_name else ""
        labeller.beside(p1 - 0.1 * arrow_len * d, d, lab + where, color, 8, 0.04 * L)
        lines.append((p, d, color))
        kinds.add(ckey)
    box = ext.box()
    for p, d, color in lines:
        seg = _clip_line(p, d, *box)
        if seg is not None:
            ax.plot(*np.array(seg).T, color=color, lw=1.0, ls=(0, (5, 4)), alpha=0.8, zorder=2)
    if title is None:
        title = f"leg {leg.name}  [{leg.string.marked}]"
        if analysis is not None:
            title += f"\nconstraint: {analysis.summary()}; connectivity {analysis.connectivity}"
            if analysis.actuation is not None:
                a = analysis.actuation
                title += f"; actuation: {a.member.kind} ({a.joint})"
    note = f"view: elevation {v.elev:g}°, azimuth {v.azim:g}°"
    _finish_axes(ax, box, v, length_unit, title, kinds, legend, own, note)
    save_figure(fig, out, dpi)
    return fig


# ----------------------------------------------------------------------------- PMs

_ROW_KINDS = ("actuation", "force", "couple")


def _check_rows(rows, values, n_legs):
    rows = list(rows or [])
    if values is not None:
        values = np.asarray(values, float).reshape(-1)
        if values.size != len(rows):
            raise InputError(f"{values.size} values given for {len(rows)} wrench rows")
    out = []
    for i, r in enumerate(rows):
        if not isinstance(r, dict):
            raise InputError(f"wrench row {i}: expected a dict, got {type(r).__name__}")
        kind = r.get("kind")
        if kind not in _ROW_KINDS:
            raise InputError(f"wrench row {i}: kind {kind!r} is not one of "
                             f"{', '.join(_ROW_KINDS)}")
        leg = r.get("leg")
        if isinstance(leg, bool) or not isinstance(leg, (int, np.integer)) \
                or not 0 <= leg < n_legs:
            raise InputError(f"wrench row {i}: leg {leg!r} is not an index 0..{n_legs - 1}")
        try:
            d = np.asarray(r.get("direction"), float).reshape(-1)
        except (TypeError, ValueError):
            d = np.zeros(0)
        if d.shape != (3,) or not np.all(np.isfinite(d)) or np.linalg.norm(d) == 0:
            raise InputError(f"wrench row {i}: direction must be a non-zero finite 3-vector")
        d = d / np.linalg.norm(d)
        p = r.get("point")
        if p is not None:
            p = np.asarray(p, float).reshape(-1)
            if p.shape != (3,) or not np.all(np.isfinite(p)):
                raise InputError(f"wrench row {i}: point must be a finite 3-vector")
        elif kind != "couple":
            raise InputError(f"wrench row {i}: a {kind} needs a point on its line")
        v = float(values[i]) if values is not None else float(r.get("value", np.nan))
        out.append(dict(kind=kind, leg=int(leg), direction=d, point=p, value=v,
                        label=r.get("label")))
    return out


def _default_labels(rows):
    sym = {"actuation": "F_{{a{}}}", "force": "F_{{c{}}}", "couple": "T_{{r{}}}"}
    bases = [sym[r["kind"]].format(r["leg"] + 1) for r in rows]
    seen = {}
    for r, b in zip(rows, bases):
        if r["label"]:
            continue
        if bases.count(b) > 1:
            seen[b] = seen.get(b, 0) + 1
            b = b[:-1] + f",{seen[b]}}}"
        r["label"] = f"${b}$"


def _polygon(ax, pts, face, edge, alpha, ext, gid=None):
    from mpl_toolkits.mplot3d.art3d import Poly3DCollection

    P = np.asarray(pts, float)
    if len(P) >= 3:
        poly = Poly3DCollection([P], facecolors=face, edgecolors="none", alpha=alpha, zorder=0)
        poly.set_gid(gid)
        ax.add_collection3d(poly)
    loop = np.vstack([P, P[:1]])
    ax.plot(*loop.T, color=edge, lw=1.2, zorder=1)
    ext.add(P)


def _as_points(x, name):
    try:
        P = np.asarray(x, float)
    except (TypeError, ValueError):
        raise InputError(f"{name} must be an (n, 3) array of numbers") from None
    if P.ndim != 2 or P.shape[1] != 3 or P.shape[0] < 1 or not np.all(np.isfinite(P)):
        raise InputError(f"{name} must be a finite (n, 3) array of points, got shape "
                         f"{P.shape}")
    return P


def draw_pm(legs, base_points, platform_points_world, o, rows=None, values=None, ax=None,
            out=None, title=None, *, force_unit: str = "kN", torque_unit: str = "kN.cm",
            length_unit: str = "cm", dpi: int = 150, joint_labels: bool = False,
            value_format: str = "{:.3g}", view=None):
    """Draw a PM at one pose with its wrench rows.

    Parameters
    ----------
    legs : sequence of Leg
        The placed legs at this pose.
    base_points : array_like (n, 3)
        Base polygon vertices ``A_i`` (in order around the polygon).
    platform_points_world : array_like (n, 3)
        Platform polygon vertices ``a_i`` in world coordinates.
    o : array_like (3,)
        Platform centre.
    rows : sequence of dict, optional
        Wrenches to draw, each ``{"kind": "actuation"|"force"|"couple", "leg": i,
        "direction": (3,), "point": (3,) or None, "value": float}`` and
        optionally ``"label"`` (mathtext allowed; default ``F_a{i+1}``,
        ``F_c{i+1}``, ``T_r{i+1}``).  The drawn vector is ``value * direction``
        (direction normalised); arrow lengths are proportional to ``|value|``
        relative to the largest of the same unit (forces and couples scaled
        separately), with a floor of 15 % so that small values stay visible.
        A force is drawn on its line at the point nearest to its leg's
        platform point ``a``, its line dashed; a couple as a double-headed
        arrow from its leg's midpoint.  A NaN value is drawn at the floor
        length and labelled ``n/a``.
    values : array_like (len(rows),), optional
        Values overriding the rows' ``"value"`` (e.g. a statics solution).
    ax : Axes3D, optional
    out : str or Path, optional
        Save as PNG.
    title : str, optional
    force_unit, torque_unit, length_unit : str
        Units printed in the labels.
    dpi : int
    joint_labels : bool
        Label every joint (cluttered for a whole PM; default off).
    value_format : str
        Format of the values in the labels.
    view : (elev, azim) in degrees, optional
        Default: the view nearest (20, -60) in which no point ``A_i``, ``a_i``,
        ``o`` hides behind another or behind a leg.

    Returns
    -------
    matplotlib.figure.Figure
    """
    require_matplotlib()
    _check_3d_axes(ax)
    legs = list(legs)
    if not legs:
        raise InputError("draw_pm needs at least one leg")
    B = _as_points(base_points, "base_points")
    Pw = _as_points(platform_points_world, "platform_points_world")
    o = np.asarray(o, float).reshape(-1)
    if o.shape != (3,) or not np.all(np.isfinite(o)):
        raise InputError("o must be a finite 3-vector")
    rows = _check_rows(rows, values, len(legs))
    _default_labels(rows)
    size = float(np.max(np.linalg.norm(B - B.mean(axis=0), axis=1))) if len(B) > 1 else 0.0
    if size == 0.0:
        size = max(leg.length for leg in legs)
    v = _check_view(view)
    if v is None:
        v = _choose_pm_view(legs, B, Pw, o, size)
    own = ax is None
    if own:
        fig, ax = new_figure((10.0, 7.2), "3d")
    else:
        fig = ax.figure
    ext = _Extent()
    _polygon(ax, B, COLORS["base"], "#636363", 0.35, ext, gid="base")
    _polygon(ax, Pw, COLORS["platform"], "#3182bd", 0.5, ext, gid="platform")
    kinds = {"base", "platform"}
    labeller = _Labeller(ax, v, size, span=3.0, width_pt=470.0)
    for i, leg in enumerate(legs):
        kinds |= _leg_geometry(ax, leg, ext, v, joint_labels=joint_labels,
                               end_labels=(f"$A_{{{i + 1}}}$", f"$a_{{{i + 1}}}$"), label_size=7,
                               labeller=labeller)
    ax.scatter(*o, s=25, color="#3182bd", depthshade=False, zorder=4)
    labeller.around(o, "o", "#08519c", 8, dist=0.04)
    max_len = 0.6 * size
    vmax = {}
    for r in rows:
        key = "torque" if r["kind"] == "couple" else "force"
        if np.isfinite(r["value"]):
            vmax[key] = max(vmax.get(key, 0.0), abs(r["value"]))
    lines = []
    for irow, r in enumerate(rows):
        leg = legs[r["leg"]]
        is_couple = r["kind"] == "couple"
        key = "torque" if is_couple else "force"
        val = r["value"]
        color = COLORS["actuation"] if r["kind"] == "actuation" else \
            COLORS["couple"] if is_couple else COLORS["force"]
        kinds.add(r["kind"])
        unit = torque_unit if is_couple else force_unit
        text = f"{r['label']} = {value_format.format(val)} {unit}" if np.isfinite(val) \
            else f"{r['label']} = n/a"
        top = vmax.get(key, 0.0)
        if np.isfinite(val) and top > 0:
            frac, sgn = max(abs(val) / top, 0.15), (-1.0 if val < 0 else 1.0)
        else:
            frac, sgn = 0.15, 1.0
        vec = sgn * frac * max_len * r["direction"]
        if is_couple:
            p0 = 0.5 * (leg.A + leg.a)
            _double_head(ax, p0, p0 + vec, color, lw=2.0, scale=13, gid=f"row:{irow}")
        else:
            d, q = r["direction"], r["point"]
            p0 = q + float(np.dot(leg.a - q, d)) * d  # the line's point nearest to a
            _arrow(ax, p0, p0 + vec, color, lw=2.2, scale=13, gid=f"row:{irow}")
            lines.append((p0, d, color))
        ext.add(p0, p0 + vec)
        if is_couple:
            labeller.tip(p0 + vec, vec / np.linalg.norm(vec), text, color, 7.5, 0.03 * size)
        else:
            labeller.beside(p0 + 0.75 * vec, vec / np.linalg.norm(vec), text, color, 7.5,
                            0.05 * size)
    box = ext.box(pad=0.05)
    for p, d, color in lines:
        seg = _clip_line(p, d, *box)
        if seg is not None:
            ax.plot(*np.array(seg).T, color=color, lw=0.8, ls=(0, (5, 4)), alpha=0.6, zorder=2)
    _finish_axes(ax, box, v, length_unit, title, kinds, True, own,
                 "arrow lengths proportional to |value|\n(forces and torques scaled separately)"
                 if rows else None)
    save_figure(fig, out, dpi)
    return fig
