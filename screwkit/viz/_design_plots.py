"""Pictures of dimensional synthesis (plain arrays in): the best objective over the
generations of a search, and the Pareto front of two objectives.  matplotlib is optional."""

from __future__ import annotations

import numpy as np

from ._figure import new_figure, save_figure

__all__ = ["plot_history", "plot_front"]


def plot_history(out, generations, best, median, ylabel: str, *, title: str | None = None,
                 dpi: int = 150):
    """The best feasible objective so far and each generation's median over the
    generations (None: no feasible design yet); written to ``out`` (PNG) when given."""
    fig, ax = new_figure((6.4, 4.2), layout="constrained")
    ax = fig.add_subplot(1, 1, 1)
    g = np.asarray(generations, float)
    b = np.array([np.nan if v is None else v for v in best], float)
    m = np.array([np.nan if v is None else v for v in median], float)
    ax.plot(g, m, ls="none", marker="o", ms=3.5, color="0.6",
            label="median of the generation's feasible designs")
    ax.step(g, b, where="post", color="#1f77b4", lw=2.0, label="best feasible design so far")
    fin = np.isfinite(b)
    if fin.any():
        k = int(np.flatnonzero(fin)[-1])
        ax.annotate(f"{b[k]:.6g}", (g[k], b[k]), textcoords="offset points", xytext=(-6, 8),
                    ha="right", fontsize=9, color="#1f77b4")
    from matplotlib.ticker import MaxNLocator
    ax.xaxis.set_major_locator(MaxNLocator(integer=True))      # (generations are whole)
    ax.set_xlabel("generation (0: the initial population; the last: the local polish)")
    ax.set_ylabel(ylabel)
    ax.grid(True, color="0.9")
    ax.legend(fontsize=8, frameon=False, loc="best")
    if title:
        ax.set_title(title, fontsize=10)
    save_figure(fig, out, dpi=dpi)
    return fig


def plot_front(out, points, front, xlabel: str, ylabel: str, *, title: str | None = None,
               dpi: int = 150):
    """Every feasible design evaluated (grey) and the Pareto front (blue, joined, the first
    objective's best marked) of two objectives."""
    fig, ax = new_figure((6.4, 4.6), layout="constrained")
    ax = fig.add_subplot(1, 1, 1)
    P = np.array([p for p in points if None not in p], float).reshape(-1, 2)
    F = np.array([p for p in front if None not in p], float).reshape(-1, 2)
    if len(P):
        ax.plot(P[:, 0], P[:, 1], ls="none", marker=".", ms=4, color="0.7",
                label=f"feasible designs evaluated ({len(P)})")
    if len(F):
        ax.plot(F[:, 0], F[:, 1], marker="o", ms=5, color="#1f77b4", lw=1.2,
                label=f"Pareto front ({len(F)})")
        # (drawn under the front's markers' outline: a one-design front stays visible)
        ax.plot(F[:1, 0], F[:1, 1], ls="none", marker="*", ms=14, color="#d62728",
                label="best in the first objective", zorder=1.5)
    ax.set_xlabel(xlabel)
    ax.set_ylabel(ylabel)
    ax.grid(True, color="0.9")
    ax.legend(fontsize=8, frameon=False, loc="best")
    if title:
        ax.set_title(title, fontsize=10)
    save_figure(fig, out, dpi=dpi)
    return fig
