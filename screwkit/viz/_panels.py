"""The pieces of the Fig. 5 panels: the style of each leg's curves, coinciding curves, the
symmetric log scale of the force axes, the condition-number panel, shading and legends."""

from __future__ import annotations

import numpy as np

from ._figure import leg_color, leg_marker

#: Line styles of the first, second ... column of the same leg in one panel.
_FORCE_STYLES = ("-", "-.", (0, (1, 1.5)))
_TORQUE_STYLES = ("--", ":", (0, (4, 1.5, 1, 1.5, 1, 1.5)))


def curve_styles(legs, kind: str, n_samples: int, first: int = 0) -> list:
    """Keyword arguments of ``Axes.plot`` for columns belonging to ``legs``.

    The colour and marker are the leg's (:func:`~screwkit.viz.leg_color`,
    :func:`~screwkit.viz.leg_marker`); a torque curve is dashed with open markers, a second
    column of the same leg changes its line style.  Later curves are thinner and drawn on
    top, so that a curve equal to an earlier one shows inside it; the markers of the legs
    sit at staggered samples.  ``first`` counts curves already on the axes.
    """
    styles = _TORQUE_STYLES if kind == "torque" else _FORCE_STYLES
    step = max(1, n_samples // 8)
    seen, out = {}, []
    for j, leg in enumerate(legs):
        k = seen.get(leg, 0)
        seen[leg] = k + 1
        c = leg_color(leg)
        pos = first + j
        out.append(dict(color=c, ls=styles[k % len(styles)], lw=max(0.9, 2.6 - 0.35 * pos),
                        zorder=2.0 + 0.1 * pos, marker=leg_marker(leg), markersize=4.5,
                        markevery=(int(step * ((leg % 4) + 0.5 * k) / 4) % step, step),
                        markerfacecolor="white" if kind == "torque" else c,
                        markeredgecolor=c))
    return out


def coincident_names(data, names) -> list:
    """``names`` with ``(= earlier)`` appended to a column equal to an earlier one (to
    1e-9 of the largest value of ``data`` (N, k), at every sample where either is finite)."""
    data = np.asarray(data, float)
    scale = float(np.nanmax(np.abs(data), initial=0.0)) if np.isfinite(data).any() else 0.0
    out = list(names)
    for j in range(data.shape[1]):
        for i in range(j):
            a, b = data[:, i], data[:, j]
            fa, fb = np.isfinite(a), np.isfinite(b)
            if fa.any() and np.array_equal(fa, fb) and \
                    np.max(np.abs(a[fa] - b[fb])) <= 1e-9 * max(scale, 1e-300):
                out[j] = f"{names[j]} (= {names[i]})"
                break
    return out


def choose_scale(arrays, mode: str = "auto", spiky=None):
    """``("linear", None)`` or ``("symlog", linthresh)`` for an axis showing ``arrays``
    (each (N, k), a column per curve).

    ``auto`` takes a symmetric log scale where a curve peaks far above its median
    magnitude: by more than 5 times on a path whose condition number spikes (``spiky``
    True: its largest value over 10 times its median), never when it does not (False),
    by more than 10 times when the condition number is not known (None).  The scale is
    linear within the power of ten below the median magnitude of all the curves.
    """
    if mode == "linear":
        return "linear", None
    cols = [np.abs(np.asarray(a, float)).reshape(len(a), -1) for a in arrays]
    ratio, pooled = 0.0, []
    for c in cols:
        for v in c.T:
            v = v[np.isfinite(v) & (v > 0)]
            if v.size:
                ratio = max(ratio, float(v.max() / np.median(v)))
                pooled.append(v)
    if not pooled:
        return "linear", None
    if mode == "auto":
        limit = {True: 5.0, None: 10.0}.get(spiky)
        if limit is None or ratio <= limit:
            return "linear", None
    med = float(np.median(np.concatenate(pooled)))
    return "symlog", float(10.0 ** np.floor(np.log10(med)))


def spiky(cond) -> bool | None:
    """True when the condition number ``cond`` (N,) peaks above 10 times its median (the
    path passes near a singularity); None when it is not given."""
    if cond is None:
        return None
    c = np.asarray(cond, float)
    c = c[np.isfinite(c) & (c > 0)]
    return bool(c.size and c.max() > 10.0 * np.median(c))


def reserve_headroom(axes, frac: float = 0.3):
    """Raise the top of each axis of ``axes`` (twins of one panel) so that the top ``frac``
    of the panel is free of curves, for a legend there (in the axes' scale)."""
    for ax in axes:
        tr = ax.yaxis.get_transform()
        lo, hi = tr.transform(np.array(ax.get_ylim(), float))
        top = lo + (hi - lo) / (1.0 - frac)
        ax.set_ylim(ax.get_ylim()[0], float(tr.inverted().transform(np.array([top]))[0]))


def apply_scale(ax, scale, linthresh, unit: str) -> str:
    """Set the y scale of ``ax``; returns the words for its panel title ('' if linear)."""
    if scale != "symlog":
        return ""
    ax.set_yscale("symlog", linthresh=linthresh, linscale=0.5)
    u = f" {unit}" if unit else ""
    return f"; log scale beyond ±{linthresh:g}{u}"


def runs(mask):
    """(start, stop) index pairs of the runs of True in ``mask``."""
    m = np.concatenate([[False], np.asarray(mask, bool), [False]])
    d = np.diff(m.astype(int))
    return list(zip(np.flatnonzero(d == 1), np.flatnonzero(d == -1) - 1))


def shade(ax, t, flags):
    if flags is None or not flags.any():
        return
    dt = np.diff(t)
    for i0, i1 in runs(flags):
        left = t[i0] - (0.5 * dt[i0 - 1] if i0 > 0 else 0.0)
        right = t[i1] + (0.5 * dt[i1] if i1 < len(dt) else 0.0)
        if right <= left:  # a single isolated sample at an end: give it some width
            w = 0.5 * (dt.min() if dt.size else 1.0)
            left, right = t[i0] - w, t[i1] + w
        ax.axvspan(left, right, color="0.82", alpha=0.7, lw=0, zorder=0)


def _visible(label: str) -> str:
    """The characters of a (mathtext) label that are printed, roughly."""
    return "".join(c for c in label if c not in "${}_\\")


def band_legend(axes, handles, title=None, fontsize=8):
    """Legend of the panel whose twin axes are ``axes`` (the last drawn on top), in a band
    at the top of the panel that the curves are kept out of (:func:`reserve_headroom`):
    up to four entries a row (fewer when the names are long); ``title`` adds a line."""
    n = len(handles)
    longest = max((len(_visible(h.get_label())) for h in handles), default=0)
    ncol = max(1, min(n, 4))
    while ncol > 1 and ncol * (longest + 6) > 66:     # ~66 characters fit across a panel
        ncol -= 1
    rows = -(-n // ncol) + (title is not None)
    reserve_headroom(axes, 0.075 * rows + 0.05)
    leg = axes[-1].legend(handles=handles, loc="upper center", ncol=ncol, fontsize=fontsize,
                          framealpha=0.9, borderaxespad=0.3, columnspacing=1.0)
    if title is not None:
        leg.set_title(title, prop={"size": 7})
    return leg


def condition_panel(ax, t, cond, levels, flags, letter="e"):
    """Panel: the normalised condition number on a log axis, with the quality levels."""
    c = np.array(cond, dtype=float).reshape(-1)
    fin = np.isfinite(c)
    if np.isinf(c).any():          # an exactly singular sample: drawn above the others
        c[np.isinf(c)] = 10.0 * max(float(np.max(c[fin])), 1.0) if fin.any() else np.nan
    ok = np.isfinite(c) & (c > 0)
    ax.plot(t, np.where(ok, c, np.nan), color="k", lw=1.6, zorder=3, label="condition number")
    if flags is not None and ok.any():
        bad = flags & ok
        if bad.any():
            ax.plot(t[bad], c[bad], ls="none", marker="x", color="#b2182b", ms=6, zorder=4,
                    label="singular samples")
    ax.set_yscale("log")
    top = float(np.nanmax(c[ok])) if ok.any() else 10.0
    bottom = float(np.nanmin(c[ok])) if ok.any() else 1.0
    shown = {k: v for k, v in (levels or {}).items() if v <= 30.0 * top}
    for name, v in shown.items():
        ax.axhline(v, color="0.45", lw=0.8, ls=":", zorder=1)
        ax.annotate(f"{name} ({v:.0e})", (1.0, v), xycoords=("axes fraction", "data"),
                    xytext=(-4, 2), textcoords="offset points", ha="right", va="bottom",
                    fontsize=7, color="0.35")
    hi = max([1.6 * top] + [3.0 * v for v in shown.values()])
    lo = max(min(bottom / 1.6, 1.0) if bottom < 10.0 else bottom / 1.6, 0.5)   # 1: the best
    ax.set_ylim(lo, hi)
    if hi / lo < 1e3:                              # a narrow range: plain numbers
        from matplotlib.ticker import FuncFormatter

        plain = FuncFormatter(lambda v, _: f"{v:g}")
        ax.yaxis.set_major_formatter(plain)
        ax.yaxis.set_minor_formatter(plain if hi / lo < 30 else FuncFormatter(
            lambda v, _: ""))
    ax.set_ylabel("condition number [–]")
    ax.set_title(f"({letter}) normalised condition number of the unified Jacobian "
                 f"(max {top:.3g})", fontsize=10, loc="left")
    ax.legend(fontsize=8, loc="upper left", framealpha=0.9)   # the levels are named at the right
