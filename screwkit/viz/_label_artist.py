"""The text artist of the 3D drawings' labels: a 3D anchor plus an offset in points on the
screen (set by the placement pass of :mod:`screwkit.viz._labels`), with an optional leader
line from the anchor to the text, and a window extent that is right in 3D."""

from __future__ import annotations

from functools import lru_cache

import numpy as np


def _anchor_display(ax, xyz) -> np.ndarray:
    """Display (pixel) coordinates of the 3D points ``xyz`` (k, 3) in ``ax``'s current view."""
    from mpl_toolkits.mplot3d import proj3d

    M = getattr(ax, "M", None)
    if M is None:
        M = ax.get_proj()
    P = np.atleast_2d(np.asarray(xyz, float))
    x, y, _ = proj3d.proj_transform(P[:, 0], P[:, 1], P[:, 2], M)
    return ax.transData.transform(np.column_stack([x, y]))


@lru_cache(maxsize=1)
def _label_class():
    from matplotlib.lines import Line2D
    from matplotlib.text import Text
    from matplotlib.transforms import IdentityTransform, ScaledTranslation
    from mpl_toolkits.mplot3d import art3d

    class Label3D(art3d.Text3D):
        """A label at a 3D ``anchor`` shifted by ``offset`` points on the screen."""

        def __init__(self, anchor, text, **kw):
            anchor = np.asarray(anchor, float)
            super().__init__(anchor[0], anchor[1], anchor[2], text, zdir=None, **kw)
            #: the 3D point the label belongs to
            self.anchor = anchor.copy()
            #: screen offset (points) of the text's alignment point from the anchor
            self.offset = (0.0, 0.0)
            #: draw a thin line from the anchor to the text
            self.leader = False

        def set_offset(self, dx, dy, leader=False):
            self.offset = (float(dx), float(dy))
            self.leader = bool(leader)
            self._offset_transform()
            self.stale = True

        def _offset_transform(self):
            if self.axes is None:
                return
            fig = self.axes.figure
            self.set_transform(self.axes.transData + ScaledTranslation(
                self.offset[0] / 72.0, self.offset[1] / 72.0, fig.dpi_scale_trans))

        def _projected(self):
            from mpl_toolkits.mplot3d import proj3d

            M = self.axes.M if getattr(self.axes, "M", None) is not None else \
                self.axes.get_proj()
            x, y, _ = proj3d.proj_transform(*([c] for c in self.anchor), M)
            return float(x[0]), float(y[0])

        def get_window_extent(self, renderer=None, dpi=None):
            """The text's box in display coordinates at the axes' current projection."""
            self._offset_transform()
            old = self._x, self._y
            self._x, self._y = self._projected()
            try:
                return Text.get_window_extent(self, renderer, dpi)
            finally:
                self._x, self._y = old

        def draw(self, renderer):
            self._offset_transform()
            super().draw(renderer)
            if not (self.leader and self.get_visible()):
                return
            box = self.get_window_extent(renderer)
            a = _anchor_display(self.axes, self.anchor)[0]
            end = np.clip(a, [box.x0, box.y0], [box.x1, box.y1])
            if np.linalg.norm(end - a) < 2.0:
                return
            line = Line2D([a[0], end[0]], [a[1], end[1]], transform=IdentityTransform(),
                          color=self.get_color(), lw=0.6, alpha=0.7)
            line.set_figure(self.figure)
            line.draw(renderer)

    return Label3D


#: A translucent white backing of every label, so that a line crossing it does not hide the
#: text (its pad, 5 % of the font size, about the gap the placement pass keeps between boxes).
_BACKING = dict(boxstyle="square,pad=0.05", facecolor="white", edgecolor="none", alpha=0.7)


def _add_label(ax, anchor, text, color="k", size=7, ha="left", va="center"):
    """A :class:`Label3D` added to ``ax`` (drawn above every other artist, on a translucent
    white backing)."""
    lab = _label_class()(anchor, text, color=color, fontsize=size, ha=ha, va=va, zorder=1000,
                         bbox=_BACKING)
    ax.add_artist(lab)
    lab.set_clip_on(False)
    lab.set_gid("label")
    lab._offset_transform()
    return lab
