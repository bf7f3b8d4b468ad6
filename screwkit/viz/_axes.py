"""The finish of a 3D drawing's axes (limits, view, title, legend) and the checks of the
caller's axes and view."""

from __future__ import annotations

from ..errors import InputError
from ._figure import COLORS
from ._view import _View


def _legend_handles(kinds, legs=None):
    """Legend entries of the elements drawn (``kinds``).  ``legs``: ``(colour, name)`` of
    each leg of a PM drawing, whose wrenches are then drawn in the leg's colour (the
    wrench entries show the head styles in black)."""
    from matplotlib.lines import Line2D

    def h(color, label, **kw):
        return Line2D([], [], color=color, label=label, **kw)

    def head(key, label, open_head, ls="-"):
        c = "k" if legs else COLORS[key]
        return h(c, label, lw=1.6, ls=ls, marker=">", markersize=7, markeredgecolor=c,
                 markerfacecolor="white" if open_head else c)

    spec = [
        ("base", h(COLORS["base"], "base", lw=8, alpha=0.6)),
        ("platform", h(COLORS["platform"], "platform", lw=8, alpha=0.6)),
        ("chain", h(COLORS["chain"], "equivalent chain", lw=3)),
        ("R", h(COLORS["R"], "R axis", lw=2.4)),
        ("H", h(COLORS["R"], "H axis", lw=2.4)),
        ("P", h(COLORS["P"], "P joint (sleeve along its axis)", lw=0, marker="s",
                markersize=9, markerfacecolor=COLORS["P_fill"], markeredgecolor=COLORS["P"])),
        ("Pa", h(COLORS["P"], "Pa (two bars, four hinges)", lw=1.8)),
        ("S", h(COLORS["S"], "S centre", lw=0, marker="o", markersize=9)),
        ("U", h(COLORS["U"], "U centre", lw=0, marker="o", markersize=5)),
        ("end", h(COLORS["end"], "end points A (base), a (platform)", lw=0, marker="s",
                  markersize=4)),
        ("meet", h(COLORS["R"], "axes extended to where they meet", lw=0.9, ls=":")),
        ("force", head("force", "constraint force (open head)", True, "--")),
        ("couple", head("couple", "constraint couple (two open heads)", True)),
        ("screw", head("screw", "constraint wrench, finite pitch", True)),
        ("actuation", head("actuation", "actuation force (filled head)", False, "-.")),
        ("actuation-couple", head("actuation", "actuation torque (two filled heads)", False)),
    ]
    if legs:
        spec = [(k, hd) for k, hd in spec if k != "chain"]
    out = [hd for k, hd in spec if k in kinds]
    for color, name in legs or ():
        out.append(h(color, name, lw=3, alpha=0.75))
    return out


def _finish_axes(ax, box, view: _View, length_unit, title, legend_kinds, legend=True,
                 own_figure=False, note=None, legs=None):
    unit = f" [{length_unit}]" if length_unit else ""
    ax.set_xlabel("x" + unit, fontsize=8, labelpad=2)
    ax.set_ylabel("y" + unit, fontsize=8, labelpad=2)
    ax.tick_params(labelsize=7, pad=0)
    # the z ticks point at their labels: without a gap the minus of -50 merges with the tick
    ax.tick_params(axis="z", pad=4)
    ax.set_zlabel("z" + unit, fontsize=8, labelpad=5)
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
            fig.legend(handles=_legend_handles(legend_kinds, legs), loc="center left",
                       fontsize=7.5,
                       frameon=False, bbox_to_anchor=(0.72, 0.55))
        if note:
            fig.text(0.73, 0.06, note, fontsize=7, color="#555555", va="bottom")
        return
    if title:
        ax.set_title(title, fontsize=10)
    if legend and legend_kinds:
        ax.legend(handles=_legend_handles(legend_kinds, legs), loc="upper left", fontsize=7,
                  framealpha=0.85)
    if note:
        ax.text2D(0.0, 0.0, note, transform=ax.transAxes, fontsize=6.5, color="#555555",
                  va="bottom")


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
