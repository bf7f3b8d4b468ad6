"""Drawing layer: 3D drawings of legs and PMs, and the time plots of a path (matplotlib).

Drawings take legs, analyses or plain arrays; they never call the solvers of
:mod:`screwkit.engine`.  matplotlib is optional (``pip install "screwkit[plot]"``):
it is imported inside the functions, and figures are made on an Agg canvas.

* :func:`draw_leg`, :func:`draw_pm` (3D), with :func:`new_figure`,
  :func:`save_figure`, :func:`require_matplotlib`;
* :func:`plot_fig5`: the panels of the paper's Fig. 5 along a path (and the condition
  number);
* :data:`LEG_COLORS`, :func:`leg_color`: the one colour of each leg in every drawing and
  panel;
* :func:`plot_heatmaps`: heatmaps of a map's quantities over one or two pose parameters;
* :func:`plot_dynamics`: Fig. 5-style panels of a motion's dynamic and static efforts;
* :func:`plot_history`, :func:`plot_front`: a dimensional synthesis' search and Pareto front.
"""

from ._figure import (COLORS, DEFAULT_VIEW, LEG_COLORS, leg_color, new_figure,
                      require_matplotlib, save_figure)
from ._leg_drawing import draw_leg
from ._pm_drawing import draw_pm
from ._plots import DEFAULT_UNITS, POSE_LABELS, plot_fig5
from ._maps import plot_heatmaps
from ._dynamics_plot import plot_dynamics
from ._design_plots import plot_front, plot_history

__all__ = [
    "draw_leg", "draw_pm", "require_matplotlib", "new_figure", "save_figure", "COLORS",
    "DEFAULT_VIEW", "LEG_COLORS", "leg_color",
    "plot_fig5", "DEFAULT_UNITS", "POSE_LABELS", "plot_heatmaps", "plot_dynamics",
    "plot_history", "plot_front",
]
