"""Heatmaps of a map: quantities over one or two pose parameters (plain arrays in).

:func:`plot_heatmaps` draws one panel per quantity side by side: a heatmap with a
colourbar (labelled with the quantity's unit) over two grid parameters, or a curve over
one.  Colours: a signed force or torque takes the one diverging map (:data:`DIVERGING`,
white at 0) on a symmetric scale, and the panels of one ``group`` (the actuation forces
of every leg, the constraint forces, the couples) share that scale, so that one colour is
one value across the legs; the scale is the whole range of the regular cells where the
caller names them (arrows on the colourbar say that some cells lie beyond), else the 1st
to 99th percentiles.  Condition numbers and other positive quantities take the one
sequential map (:data:`SEQUENTIAL`, a log scale for ``log`` panels).  Cells where the
quantity is undefined are left grey; masked regions (unreachable, near-singular, outside
the limits) are hatched and outlined, each with its own pattern; singular curves are drawn
as points (the refined crossings), one style per kind.  Every hatch, outline, point style
and the grey of undefined cells has a legend entry.  matplotlib is optional.
"""

from __future__ import annotations

import textwrap

import numpy as np

from ..errors import InputError
from ._figure import new_figure, save_figure

__all__ = ["plot_heatmaps", "HATCHES", "DIVERGING", "SEQUENTIAL"]

#: Hatch patterns of masked regions, in order.
HATCHES = ("////", "xx", "\\\\\\\\", "..")     # (crossed near-singular bands read as no contour)
#: The colour map of signed forces and torques (white at 0) and of everything else.
DIVERGING, SEQUENTIAL = "RdBu_r", "viridis"
#: The colours of the hatch lines and outlines of the masked regions.
_MASK_EDGE = ("#303030", "#000000", "#6a3d9a", "#303030")
_POINT_STYLES = ({"color": "black", "marker": "o"}, {"color": "#d62728", "marker": "s"},
                 {"color": "#9467bd", "marker": "^"})


def _limits(z, log, clip=True, symmetric=False):
    f = z[np.isfinite(z)]
    if log:
        f = f[f > 0]
        if f.size == 0:
            return None
        return float(f.min()), float(f.max() if f.max() > f.min() else f.min() * 10)
    if f.size == 0:
        return None
    lo, hi = np.percentile(f, [1, 99]) if clip else (f.min(), f.max())
    if symmetric or lo < 0 < hi:
        m = max(abs(lo), abs(hi))
        return (-m, m) if m > 0 else (-1.0, 1.0)
    if lo == hi:
        return lo - 1.0, hi + 1.0
    return float(lo), float(hi)


def _panel_limits(panels):
    """The colour range and whether it is signed, per panel: a ``group`` of signed panels
    shares one symmetric range (the largest of its members')."""
    out = []
    for pan in panels:
        z = np.asarray(pan["z"], float)
        log = bool(pan.get("log"))
        base = pan.get("limits_from")
        zr = z if base is None else np.where(np.asarray(base, bool), z, np.nan)
        signed = bool(pan.get("signed")) and not log
        lim = _limits(zr, log, clip=base is None, symmetric=signed)
        if log and lim is not None and lim[1] < 10 * lim[0]:
            # less than a decade: a log axis would print ticks like "2.6x10^0"
            log, lim = False, _limits(zr, False, clip=base is None)
        if pan.get("limits") is not None:           # a fixed range (indices in [0, 1])
            lim = tuple(float(v) for v in pan["limits"])
        out.append([lim, log, signed or (lim is not None and lim[0] < 0 < lim[1])])
    for g in {pan.get("group") for pan in panels} - {None}:
        members = [k for k, pan in enumerate(panels) if pan.get("group") == g and out[k][0]]
        if members:
            m = max(abs(out[k][0][1]) for k in members)
            for k in members:
                out[k][0] = (-m, m)
    return out


def plot_heatmaps(out, x, y, panels, *, xlabel: str, ylabel: str = "", masks=(), points=(),
                  title: str | None = None, dpi: int = 150):
    """Draw heatmaps (two parameters) or curves (one) of a map's quantities.

    Parameters
    ----------
    out : str or path, or None
        The PNG to write (None: only return the figure).
    x : ndarray (nx,) ; y : ndarray (ny,) or None
        Grid values (None: a 1-D map).
    panels : list of dict
        ``z`` ``(nx, ny)`` (or ``(nx,)``), ``label`` (with its unit), ``log`` (bool),
        optionally ``limits_from`` (bool, like ``z``: the cells the colour range is taken
        from, so that near-singular efforts do not wash the picture out), ``signed``
        (a signed force or torque: the diverging map on a symmetric range), ``group``
        (panels of one group share their colour range: the forces of one kind) and
        ``limits`` (a fixed colour range, e.g. ``(0, 1)`` for an index).
    xlabel, ylabel : str
    masks : list of (ndarray bool, str)
        Regions to hatch (same shape as ``z``) and their legend text.
    points : list of (ndarray, ndarray, str)
        Points ``(xs, ys)`` of singular curves (``ys`` ignored for a 1-D map) and their
        legend text.
    title : str, optional

    Returns
    -------
    matplotlib.figure.Figure
    """
    if not panels:
        raise InputError("nothing to plot: name a quantity")
    x = np.asarray(x, float)
    one_d = y is None
    n = len(panels)
    cols = n if n <= 3 else -(-n // 2)
    rows = -(-n // cols)
    fig, _ = new_figure((5.2 * cols + 0.6, 4.3 * rows + 0.7), layout="constrained")
    from matplotlib.colors import LogNorm, Normalize
    from matplotlib.patches import Patch
    from matplotlib.lines import Line2D
    handles, grey = [], False
    limits = _panel_limits(panels)
    for k, pan in enumerate(panels):
        ax = fig.add_subplot(rows, cols, k + 1)
        z = np.asarray(pan["z"], float)
        lim, log, signed = limits[k]
        if one_d:
            ax.plot(x, z, color="#1f77b4", lw=1.5)
            if log:
                ax.set_yscale("log")
            if pan.get("limits") is not None:           # an index: its whole range [0, 1]
                lo, hi = (float(v) for v in pan["limits"])
                pad = 0.03 * (hi - lo)
                ax.set_ylim(lo - pad, hi + pad)
            ax.set_ylabel(pan["label"])
            for j, (m, text) in enumerate(masks):
                m = np.asarray(m, bool)
                if m.any():
                    ax.fill_between(x, 0, 1, where=m, transform=ax.get_xaxis_transform(),
                                    facecolor="0.85", edgecolor=_MASK_EDGE[j % 4],
                                    hatch=HATCHES[j % len(HATCHES)], lw=0, step="mid")
            for j, (xs, _, text) in enumerate(points):
                for xv in np.asarray(xs, float):
                    ax.axvline(xv, color=_POINT_STYLES[j % 3]["color"], lw=1.0, ls="--")
        else:
            y = np.asarray(y, float)
            ax.set_facecolor("0.85")
            norm = None if lim is None else (LogNorm(*lim) if log else Normalize(*lim))
            cmap = DIVERGING if signed else SEQUENTIAL
            mesh = ax.pcolormesh(x, y, z.T, shading="nearest", norm=norm, cmap=cmap)
            fin = z[np.isfinite(z)]
            grey |= fin.size < z.size
            extend = "neither" if log or lim is None or fin.size == 0 else \
                {(False, False): "neither", (True, False): "min", (False, True): "max",
                 (True, True): "both"}[(bool(fin.min() < lim[0]), bool(fin.max() > lim[1]))]
            cb = fig.colorbar(mesh, ax=ax, extend=extend, shrink=0.9)
            cb.set_label(pan["label"], fontsize=9)
            for j, (m, text) in enumerate(masks):
                m = np.asarray(m, bool)
                if m.any():
                    _hatch_cells(ax, x, y, m, HATCHES[j % len(HATCHES)], _MASK_EDGE[j % 4])
            for j, (xs, ys, text) in enumerate(points):
                ax.plot(xs, ys, ls="none", ms=3.2, mec="white", mew=0.6,
                        **_POINT_STYLES[j % 3])
            ax.set_ylabel(ylabel)
            ax.set_xlim(x.min() - 0.5 * _step(x), x.max() + 0.5 * _step(x))
            ax.set_ylim(y.min() - 0.5 * _step(y), y.max() + 0.5 * _step(y))
        ax.set_xlabel(xlabel)
        # (long names wrapped: a panel's title stays within its column)
        ax.set_title("\n".join(textwrap.fill(line, 58) for line in
                               str(pan.get("title", pan["label"])).split("\n")), fontsize=10)
    for j, (m, text) in enumerate(masks):
        if np.asarray(m, bool).any():
            handles.append(Patch(facecolor="0.85", edgecolor=_MASK_EDGE[j % 4],
                                 hatch=HATCHES[j % len(HATCHES)], lw=1.0,
                                 label=text + ("" if one_d else " (hatched, outlined)")))
    for j, (xs, ys, text) in enumerate(points):
        if len(xs):
            handles.append(Line2D([], [], ls="--" if one_d else "none", ms=4, label=text,
                                  **_POINT_STYLES[j % 3]))
    if grey and not one_d:
        handles.append(Patch(facecolor="0.85", edgecolor="none",
                             label="grey: no value (the quantity is undefined there)"))
    groups = sorted({pan.get("group") for pan in panels} - {None})
    if groups and not one_d:
        handles.append(Patch(facecolor="white", edgecolor="none",
                             label="one colour scale, symmetric about 0, for the "
                                   + ", ".join(_GROUP_TEXT.get(g, g) for g in groups)))
    if handles:
        fig.legend(handles=handles, loc="outside lower center",
                   ncol=min(2, len(handles)) if cols > 1 else 1, fontsize=8.5, frameon=False)
    if title:
        fig.suptitle(title, fontsize=11)
    save_figure(fig, out, dpi=dpi)
    return fig


_GROUP_TEXT = {"actuation": "actuation forces of every leg", "force": "constraint forces",
               "couple": "constraint couples"}


def _edges(v):
    """Cell edges ``(n + 1,)`` of cell centres ``v``: mid-way between centres, half a step
    beyond the outer ones."""
    v = np.asarray(v, float)
    if v.size < 2:
        return np.array([v[0] - 0.5, v[0] + 0.5])
    mid = 0.5 * (v[1:] + v[:-1])
    return np.concatenate([[2 * v[0] - mid[0]], mid, [2 * v[-1] - mid[-1]]])


def _hatch_cells(ax, x, y, mask, hatch, edge="black"):
    """Hatch the cells of ``mask (nx, ny)`` exactly: one rectangle per run of masked cells
    along y in each column (the hatch lines of neighbouring rectangles join up), and outline
    the region (its boundary between masked and unmasked cells)."""
    from matplotlib.collections import PatchCollection
    from matplotlib.patches import Rectangle
    ex, ey = _edges(x), _edges(y)
    rects = []
    for i in range(mask.shape[0]):
        col = np.concatenate([[False], mask[i], [False]])
        starts = np.flatnonzero(~col[:-1] & col[1:])
        ends = np.flatnonzero(col[:-1] & ~col[1:])
        rects += [Rectangle((ex[i], ey[a]), ex[i + 1] - ex[i], ey[b] - ey[a])
                  for a, b in zip(starts, ends)]
    ax.add_collection(PatchCollection(rects, facecolor="none", edgecolor=edge, lw=0,
                                      hatch=hatch, alpha=0.8))
    # the outline: the cell edges between a masked cell and an unmasked one (or the border)
    pad = np.pad(mask, 1, constant_values=False)
    segs = []
    for i in range(mask.shape[0]):
        for j in np.flatnonzero(mask[i]):
            if not pad[i, j + 1]:
                segs.append([(ex[i], ey[j]), (ex[i], ey[j + 1])])
            if not pad[i + 2, j + 1]:
                segs.append([(ex[i + 1], ey[j]), (ex[i + 1], ey[j + 1])])
            if not pad[i + 1, j]:
                segs.append([(ex[i], ey[j]), (ex[i + 1], ey[j])])
            if not pad[i + 1, j + 2]:
                segs.append([(ex[i], ey[j + 1]), (ex[i + 1], ey[j + 1])])
    from matplotlib.collections import LineCollection
    ax.add_collection(LineCollection(segs, colors=edge, linewidths=0.9))


def _step(v):
    return float(np.min(np.diff(v))) if v.size > 1 else 1.0
