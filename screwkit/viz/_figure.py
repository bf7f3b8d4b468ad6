"""matplotlib for off-screen drawing: import check, figures on an Agg canvas, PNG output, colours.

matplotlib is optional (``pip install "screwkit[plot]"``); it is imported inside
the functions, and figures are made on an Agg canvas (no display, no pyplot
global state).
"""

from __future__ import annotations

from pathlib import Path

from ..errors import InputError
from ..scene import COLORS, LEG_COLORS, leg_color   # one palette for every picture

__all__ = ["require_matplotlib", "new_figure", "save_figure", "COLORS", "DEFAULT_VIEW",
           "LEG_COLORS", "LEG_MARKERS", "POSE_COLORS", "leg_color", "leg_marker"]

#: The marker of leg i on the curves of the Fig. 5 plots (with its colour).
LEG_MARKERS = ("o", "s", "^", "D", "v", "P", "X", "*")

#: Colours of the pose parameters in panel (a) (none of them is a leg colour).
POSE_COLORS = {"alpha": "#000000", "beta": "#737373", "gamma": "#b8860b", "Xo": "#00838f",
               "Yo": "#ad1457", "Zo": "#5d4037"}


def leg_marker(i: int) -> str:
    """The curve marker of leg ``i`` (0-based) in the plots."""
    return LEG_MARKERS[int(i) % len(LEG_MARKERS)]

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
        Path(out).parent.mkdir(parents=True, exist_ok=True)      # --out dir/fig.png: make dir
        fig.savefig(str(out), dpi=dpi)
    except (OSError, ValueError) as exc:
        raise InputError(f"cannot write figure {str(out)!r}: {exc}") from None
