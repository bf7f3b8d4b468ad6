"""Heatmaps of a map: quantities over one or two pose parameters (plain arrays in).

:func:`plot_heatmaps` draws one panel per quantity side by side: a heatmap with a
colourbar (labelled with the quantity's unit) over two grid parameters, or a curve over
one.  Cells where the quantity is undefined are left grey; masked regions (unreachable,
outside the limits) are hatched, each with its own pattern and a legend entry; singular
curves are drawn as points (the refined crossings), one style per kind.  Forces take a
diverging colour map centred on 0, clipped to the 1st..99th percentiles of the cells
given, or to the whole range of the regular cells where the caller names them (the arrows
of the colourbar say that some cells lie beyond), condition numbers a log scale.  matplotlib is optional.
"""

from __future__ import annotations

import numpy as np

from ..errors import InputError
from ._figure import new_figure, save_figure

__all__ = ["plot_heatmaps", "HATCHES"]

#: Hatch patterns of masked regions, in order.
HATCHES = ("////", "\\\\\\\\", "xx", "..")
_POINT_STYLES = ({"color": "black", "marker": "o"}, {"color": "#d62728", "marker": "s"},
                 {"color": "#9467bd", "marker": "^"})


def _limits(z, log, clip=True):
    f = z[np.isfinite(z)]
    if log:
        f = f[f > 0]
        if f.size == 0:
            return None
        return float(f.min()), float(f.max() if f.max() > f.min() else f.min() * 10)
    if f.size == 0:
        return None
    lo, hi = np.percentile(f, [1, 99]) if clip else (f.min(), f.max())
    if lo < 0 < hi:
        m = max(-lo, hi)
        return -m, m
    if lo == hi:
        return lo - 1.0, hi + 1.0
    return float(lo), float(hi)


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
        from, so that near-singular efforts do not wash the picture out) or ``limits``
        (a fixed colour range, e.g. ``(0, 1)`` for an index).
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
    fig, _ = new_figure((5.2 * cols + 0.6, 4.3 * rows + 0.5), layout="constrained")
    from matplotlib.colors import LogNorm, Normalize
    from matplotlib.patches import Patch
    from matplotlib.lines import Line2D
    handles = []
    for k, pan in enumerate(panels):
        ax = fig.add_subplot(rows, cols, k + 1)
        z = np.asarray(pan["z"], float)
        log = bool(pan.get("log"))
        base = pan.get("limits_from")
        # the colour range: the whole range of the cells ``limits_from`` names (the regular
        # ones), else the 1st..99th percentiles of every cell
        zr = z if base is None else np.where(np.asarray(base, bool), z, np.nan)
        lim = _limits(zr, log, clip=base is None)
        if pan.get("limits") is not None:           # a fixed range (indices in [0, 1])
            lim = tuple(float(v) for v in pan["limits"])
        if log and lim is not None and lim[1] < 10 * lim[0]:
            # less than a decade: a log axis would print ticks like "2.6x10^0"
            log, lim = False, _limits(zr, False, clip=base is None)
        if one_d:
            ax.plot(x, z, color="#1f77b4", lw=1.5)
            if log:
                ax.set_yscale("log")
            ax.set_ylabel(pan["label"])
            for j, (m, text) in enumerate(masks):
                m = np.asarray(m, bool)
                if m.any():
                    ax.fill_between(x, 0, 1, where=m, transform=ax.get_xaxis_transform(),
                                    facecolor="0.85", edgecolor="0.4",
                                    hatch=HATCHES[j % len(HATCHES)], lw=0, step="mid")
            for j, (xs, _, text) in enumerate(points):
                for xv in np.asarray(xs, float):
                    ax.axvline(xv, color=_POINT_STYLES[j % 3]["color"], lw=1.0, ls="--")
        else:
            y = np.asarray(y, float)
            ax.set_facecolor("0.85")
            if lim is None:
                norm = None
            elif log:
                norm = LogNorm(*lim)
            else:
                norm = Normalize(*lim)
            cmap = "viridis" if log or (lim and lim[0] >= 0) else "RdBu_r"
            mesh = ax.pcolormesh(x, y, z.T, shading="nearest", norm=norm, cmap=cmap)
            fin = z[np.isfinite(z)]
            extend = "neither" if log or lim is None or fin.size == 0 else \
                {(False, False): "neither", (True, False): "min", (False, True): "max",
                 (True, True): "both"}[(bool(fin.min() < lim[0]), bool(fin.max() > lim[1]))]
            cb = fig.colorbar(mesh, ax=ax, extend=extend, shrink=0.9)
            cb.set_label(pan["label"], fontsize=9)
            for j, (m, text) in enumerate(masks):
                m = np.asarray(m, bool)
                if m.any():
                    _hatch_cells(ax, x, y, m, HATCHES[j % len(HATCHES)])
            for j, (xs, ys, text) in enumerate(points):
                ax.plot(xs, ys, ls="none", ms=3.2, mec="white", mew=0.6,
                        **_POINT_STYLES[j % 3])
            ax.set_ylabel(ylabel)
            ax.set_xlim(x.min() - 0.5 * _step(x), x.max() + 0.5 * _step(x))
            ax.set_ylim(y.min() - 0.5 * _step(y), y.max() + 0.5 * _step(y))
        ax.set_xlabel(xlabel)
        ax.set_title(pan.get("title", pan["label"]), fontsize=10)
    for j, (m, text) in enumerate(masks):
        if np.asarray(m, bool).any():
            handles.append(Patch(facecolor="0.85", edgecolor="0.3",
                                 hatch=HATCHES[j % len(HATCHES)], label=text))
    for j, (xs, ys, text) in enumerate(points):
        if len(xs):
            handles.append(Line2D([], [], ls="--" if one_d else "none", ms=4, label=text,
                                  **_POINT_STYLES[j % 3]))
    if handles:
        fig.legend(handles=handles, loc="outside lower center", ncol=min(4, len(handles), cols),
                   fontsize=8, frameon=False)
    if title:
        fig.suptitle(title, fontsize=11)
    save_figure(fig, out, dpi=dpi)
    return fig


def _edges(v):
    """Cell edges ``(n + 1,)`` of cell centres ``v``: mid-way between centres, half a step
    beyond the outer ones."""
    v = np.asarray(v, float)
    if v.size < 2:
        return np.array([v[0] - 0.5, v[0] + 0.5])
    mid = 0.5 * (v[1:] + v[:-1])
    return np.concatenate([[2 * v[0] - mid[0]], mid, [2 * v[-1] - mid[-1]]])


def _hatch_cells(ax, x, y, mask, hatch):
    """Hatch the cells of ``mask (nx, ny)`` exactly: one rectangle per run of masked cells
    along y in each column (the hatch lines of neighbouring rectangles join up)."""
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
    ax.add_collection(PatchCollection(rects, facecolor="none", edgecolor="black", lw=0,
                                      hatch=hatch))


def _step(v):
    return float(np.min(np.diff(v))) if v.size > 1 else 1.0
