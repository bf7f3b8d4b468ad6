"""The colours every picture of screwkit shares: one colour per leg, one per drawn element.

The 3D view of this layer and the matplotlib drawings and plots of :mod:`screwkit.viz` take
their colours from here, so that leg 2 is the same orange in a Fig. 5 panel, a PM drawing
and the interactive view.
"""

from __future__ import annotations

__all__ = ["LEG_COLORS", "COLORS", "leg_color"]

#: The leg palette: leg i (0-based) is drawn in ``LEG_COLORS[i % len(LEG_COLORS)]`` in the PM
#: drawings, in every panel of the Fig. 5 plots (its r_i, F_ai, F_ci, T_ri curves) and in the
#: 3D view.
LEG_COLORS = ("#1f77b4", "#ff7f0e", "#2ca02c", "#d62728", "#9467bd", "#8c564b",
              "#e377c2", "#17becf")

#: Colours of the drawn elements (the wrenches of a one-leg drawing are coloured by kind;
#: a PM drawing and the 3D view colour every leg and its wrenches with :func:`leg_color`).
COLORS = {
    "chain": "#9a9a9a", "R": "#262626", "P": "#525252", "P_fill": "#e6e6e6", "S": "#6a3d9a",
    "U": "#6a3d9a", "end": "#000000", "force": "#2166ac", "couple": "#1b7837",
    "screw": "#c51b7d", "actuation": "#d6261e", "base": "#bdbdbd", "platform": "#8c8c8c",
}


def leg_color(i: int) -> str:
    """The colour of leg ``i`` (0-based) in every drawing, plot and view."""
    return LEG_COLORS[int(i) % len(LEG_COLORS)]
