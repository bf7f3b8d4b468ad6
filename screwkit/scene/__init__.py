"""Scene layer: the interactive 3D view of a PM, from plain data (no solver is called here).

* :class:`Scene`, :class:`PoseState`, :class:`SceneRow`, :class:`GridControls`,
  :class:`TimeControls`: the states of a view (one pose each: placed legs, polygons, the
  value, line and direction of every wrench row) and how the page moves between them;
* :func:`page_html`, :class:`View`: the self-contained HTML page (plotly.js bundled, no
  network at view time) and its inline display in Jupyter;
* :func:`screenshot`, :func:`browser`, :func:`open_page`, :func:`find_chromium`: the page in a headless
  Chromium (Playwright), for ``screwkit view --png``, the docs' figures and the tests;
* :data:`LEG_COLORS`, :func:`leg_color`, :data:`COLORS`: the one palette of every picture
  (the drawings and plots of :mod:`screwkit.viz` take theirs from here);
* :func:`arrow_fractions`, :func:`scale_key`, :data:`FLOOR`: the one rule of the wrench
  arrows' lengths (per kind, with a floor), of the drawings and of the view.

The callers build the scenes from their results: ``PMAnalysis.show`` (the engine),
``TrajectoryResult.show`` and :func:`screwkit.view` (a grid of poses or a path).  plotly and
playwright are optional (``pip install "screwkit[view]"``), imported inside the functions.
"""

from ._palette import COLORS, LEG_COLORS, leg_color
from ._arrows import FLOOR, arrow_fractions, scale_key
from ._data import (MAX_STATES, GridControls, PoseState, Scene, SceneRow, TimeControls,
                    format_value)
from ._geometry import plate_outline
from ._page import View, page_html, require_plotly
from ._browser import CHROMIUM_ARGS, browser, find_chromium, open_page, screenshot

__all__ = [
    "LEG_COLORS", "COLORS", "leg_color", "FLOOR", "arrow_fractions", "scale_key",
    "Scene", "PoseState", "SceneRow", "GridControls", "TimeControls", "MAX_STATES",
    "format_value", "View", "page_html", "require_plotly", "plate_outline",
    "screenshot", "browser", "open_page", "find_chromium", "CHROMIUM_ARGS",
]
