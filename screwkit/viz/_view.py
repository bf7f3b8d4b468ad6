"""The viewpoint of a 3D drawing: projection onto the screen and the choice of the view
that keeps the drawn directions and the legs apart."""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from ._figure import DEFAULT_VIEW
from ..screws import cross


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
        r = cross([0.0, 0.0, 1.0], self.sight)
        return r / np.linalg.norm(r)

    @property
    def up(self) -> np.ndarray:
        u = cross(self.sight, self.right)
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
        n = cross(np.asarray(d, float), self.sight)
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
