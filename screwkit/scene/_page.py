"""The self-contained HTML page of a :class:`~screwkit.scene.Scene`, and :class:`View`.

The page holds everything it needs: plotly.js (from the ``plotly`` package, embedded as a
``data:`` script, so that the page fetches nothing and names no address), the scene's data
(JSON in ``<script type="application/json" id="screwkit-data">``) and the drawing code
(:data:`SCRIPTS` beside this module, joined in one function).  It opens from a file with
no network.  In Jupyter a
:class:`View` shows the same page inline (in an ``iframe``).
"""

from __future__ import annotations

import base64
import html
import json
from functools import lru_cache
from pathlib import Path

from ..errors import InputError

__all__ = ["View", "page_html", "require_plotly"]

_HERE = Path(__file__).resolve().parent
#: The page's code, in this order, joined inside one function (they share its scope): the
#: traces of a state, the labels' placement, the page around the plot and its controls.
SCRIPTS = ("view_draw.js", "view_labels.js", "view_page.js")

_STYLE = """
body { font-family: Arial, Helvetica, sans-serif; margin: 0; color: #222; background: #fff; }
#screwkit-view { padding: 8px 12px; }
#screwkit-view h1 { font-size: 18px; margin: 2px 0 2px 0; }
#sk-workload { font-size: 13px; color: #333; margin-bottom: 6px; }
#sk-controls label { display: inline-block; margin: 2px 18px 2px 0; font-size: 13px; }
#sk-controls input[type=range] { width: 180px; vertical-align: middle; }
#sk-controls output { display: inline-block; min-width: 70px; margin-left: 6px;
  font-variant-numeric: tabular-nums; }
#sk-controls button { font-size: 13px; min-width: 56px; }
#sk-status { font-size: 13px; margin: 4px 0; }
.sk-level { padding: 1px 6px; border-radius: 3px; color: #fff; background: #2e7d32; }
.sk-level-illconditioned { background: #b58900; }
.sk-level-nearsingular { background: #e65100; }
.sk-level-singular, .sk-level-unreachable { background: #b71c1c; }
#sk-main { display: flex; align-items: flex-start; }
#sk-plot { flex: 1 1 auto; min-width: 0; width: calc(100% - 250px); }
#sk-values { flex: 0 0 240px; border-collapse: collapse; font-size: 12px; margin-left: 8px; }
#sk-values td, #sk-values th { padding: 1px 6px; border-bottom: 1px solid #eee; text-align: left; }
#sk-values .sk-num { text-align: right; font-variant-numeric: tabular-nums; }
#sk-notes, #sk-scale { font-size: 11px; color: #555; margin-top: 4px; }
"""


def require_plotly():
    """Import plotly (the 3D library the page bundles); InputError naming the extra if missing."""
    try:
        import plotly  # noqa: F401
        from plotly.offline import get_plotlyjs  # noqa: F401
    except ImportError:
        raise InputError('the 3D view needs plotly: pip install "screwkit[view]"') from None


@lru_cache(maxsize=1)
def _library() -> str:
    """plotly.js as a base64 ``data:`` URI (read once per process)."""
    require_plotly()
    from plotly.offline import get_plotlyjs
    return "data:text/javascript;base64," + base64.b64encode(
        get_plotlyjs().encode("utf-8")).decode("ascii")


@lru_cache(maxsize=1)
def _app() -> str:
    parts = [(_HERE / name).read_text(encoding="utf-8") for name in SCRIPTS]
    return "(function () {\n\"use strict\";\n" + "\n".join(parts) + "\n})();"


def page_html(scene) -> str:
    """The page of ``scene`` (one self-contained HTML document)."""
    data = json.dumps(scene.to_json(), separators=(",", ":"), allow_nan=False)
    data = data.replace("</", "<\\/")          # never closes the script element early
    title = html.escape(f"screwkit view: {scene.title or scene.pm}")
    return (
        "<!DOCTYPE html>\n<html lang=\"en\">\n<head>\n<meta charset=\"utf-8\">\n"
        f"<title>{title}</title>\n<style>{_STYLE}</style>\n"
        f"<script src=\"{_library()}\"></script>\n</head>\n<body>\n"
        "<div id=\"screwkit-view\">\n<h1 id=\"sk-title\"></h1>\n<div id=\"sk-workload\"></div>\n"
        "<div id=\"sk-controls\"></div>\n<div id=\"sk-status\"></div>\n"
        "<div id=\"sk-main\"><div id=\"sk-plot\"></div><table id=\"sk-values\"></table></div>\n"
        "<div id=\"sk-scale\"></div>\n<div id=\"sk-notes\"></div>\n</div>\n"
        f"<script type=\"application/json\" id=\"screwkit-data\">{data}</script>\n"
        f"<script>\n{_app()}\n</script>\n</body>\n</html>\n")


class View:
    """An interactive 3D view of a PM (:func:`screwkit.view`, ``PMAnalysis.show``,
    ``TrajectoryResult.show``): shown inline by Jupyter, written by :meth:`write_html`.

    Attributes
    ----------
    scene : Scene
        The data drawn.
    """

    def __init__(self, scene, height: int = 820):
        self.scene = scene
        self.height = int(height)

    def __repr__(self) -> str:
        sc, n = self.scene, len(self.scene.states)
        if hasattr(sc.controls, "params"):
            what = f"{n} poses on sliders ({', '.join(sc.controls.params)})"
        else:
            what = "one pose" if n == 1 else f"{n} samples on a time slider"
        return f"View({sc.pm}: {what}; write_html(path), or display it in Jupyter)"

    @property
    def html(self) -> str:
        """The self-contained page."""
        return page_html(self.scene)

    def write_html(self, path) -> str:
        """Write the page to ``path`` (a text or a path-like); returns the path written."""
        import os
        if not isinstance(path, (str, os.PathLike)):
            raise InputError(f"the page's path must be a text or a path, got "
                             f"{type(path).__name__}")
        p = Path(path)
        try:
            p.parent.mkdir(parents=True, exist_ok=True)
            p.write_text(self.html, encoding="utf-8")
        except OSError as exc:
            raise InputError(f"cannot write {str(p)!r}: {exc.strerror or exc}") from None
        return str(p)

    def _repr_html_(self) -> str:
        """Jupyter's inline display: the page in an iframe (its scripts kept apart from the
        notebook's)."""
        return (f'<iframe srcdoc="{html.escape(self.html, quote=True)}" '
                f'style="width: 100%; height: {self.height}px; border: none;"></iframe>')
