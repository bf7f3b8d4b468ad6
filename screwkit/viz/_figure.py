"""matplotlib for off-screen drawing: import check, figures on an Agg canvas, PNG output, colours.

matplotlib is optional (``pip install "screwkit[plot]"``); it is imported inside
the functions, and figures are made on an Agg canvas (no display, no pyplot
global state).
"""

from __future__ import annotations

from ..errors import InputError

__all__ = ["require_matplotlib", "new_figure", "save_figure", "COLORS", "DEFAULT_VIEW"]


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
