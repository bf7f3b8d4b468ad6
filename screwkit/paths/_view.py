"""The interactive 3D view of a PM over a grid of poses or along a path (:func:`view`).

A grid gets one slider per independent pose parameter: every cell is a pose solved by the
engine (one batched :func:`screwkit.engine.analyze`), and the page only moves between the
solved states.  A path gets a time slider with play/pause (the samples solved along the
path, warm-started as :func:`run_trajectory` solves them).  The page is drawn by
:mod:`screwkit.scene` (plotly.js bundled: no network at view time).
"""

from __future__ import annotations

from collections.abc import Callable, Mapping
from typing import TYPE_CHECKING, Any

import numpy as np

from ..engine import LENGTH_PARAMS
from ..errors import InputError

if TYPE_CHECKING:
    from numpy.typing import ArrayLike

    from ..pm import PMModel
    from ..scene import View
    from ._pathspec import PathSpec

__all__ = ["view", "default_steps", "VIEW_SPAN_DEG", "VIEW_SPAN_LENGTH"]

#: Default half-span of an angle's slider (degrees) and of a length's (times the model's
#: characteristic length) around the pose shown first.
VIEW_SPAN_DEG = 10.0
VIEW_SPAN_LENGTH = 0.1
#: The default grid holds at most this many poses (``steps`` per parameter, odd).
DEFAULT_STATES = 1000


def default_steps(k: int) -> int:
    """Values per parameter of a ``k``-parameter grid: the largest odd number up to 21 whose
    ``k``-th power is at most :data:`DEFAULT_STATES` (21, 21, 9, 5, 3, 3 for k = 1..6)."""
    n = 21
    while n > 3 and n ** k > DEFAULT_STATES:
        n -= 2
    return n


#: The most values of one parameter in a view (its slider's stops).
MAX_VIEW_STEPS = 101

def _centre(model, pose, degrees):
    """The independent parameters of the pose shown first, in the API's units (radians)."""
    pose = dict(pose or {})
    for k in pose:
        if k not in model.independent:
            raise InputError(f"{model.name}: {k!r} is not an independent pose parameter (the "
                             f"independent ones are {', '.join(model.independent)})")
    out = {}
    for k in model.independent:
        v = pose.get(k, model.default_pose.get(k, model.home_pose[k]))
        try:
            v = float(v)
        except (TypeError, ValueError):
            raise InputError(f"pose {k}: must be a number, got {v!r:.40}") from None
        if not np.isfinite(v):
            raise InputError(f"pose {k}: must be finite")
        out[k] = np.radians(v) if degrees and k not in LENGTH_PARAMS and k in pose else v
    from ..engine._inputs import pose_arrays
    # (the engine's limits, named in the caller's units: +-3600 deg, 1e12 model sizes)
    pose_arrays(model, {k: np.degrees(v) if degrees and k not in LENGTH_PARAMS else v
                        for k, v in out.items()}, degrees=degrees)
    return out


def _axes(model, centre, grid, steps, degrees):
    """Per independent parameter: its grid values in the API's units and in the page's."""
    grid = dict(grid or {})
    for k in grid:
        if k not in model.independent:
            raise InputError(f"{model.name}: grid {k!r} is not an independent pose parameter "
                             f"(the independent ones are {', '.join(model.independent)})")
    n = default_steps(len(model.independent)) if steps is None else steps
    if isinstance(n, bool) or not isinstance(n, (int, np.integer)) or \
            not 1 <= n <= MAX_VIEW_STEPS:
        raise InputError(f"steps must be an integer from 1 to {MAX_VIEW_STEPS}, got "
                         f"{steps!r:.40}")
    L = float(model.normalisation.length)
    api, shown = [], []
    for k in model.independent:
        length = k in LENGTH_PARAMS
        if k in grid:
            spec = grid[k]
            try:
                a, b, count = spec
                count = int(count)
                a, b = float(a), float(b)
            except (TypeError, ValueError):
                raise InputError(f"grid {k}: give (start, stop, count), got {spec!r:.60}") \
                    from None
            if not (np.isfinite(a) and np.isfinite(b)) or not 1 <= count <= MAX_VIEW_STEPS:
                raise InputError(f"grid {k}: start and stop must be finite and the count 1 to "
                                 f"{MAX_VIEW_STEPS}, got {spec!r:.60}")
            v = np.linspace(a, b, count)
            if degrees and not length:
                v = np.radians(v)
        else:
            half = VIEW_SPAN_LENGTH * L if length else np.radians(VIEW_SPAN_DEG)
            v = centre[k] + np.linspace(-half, half, n) if n > 1 else np.array([centre[k]])
        api.append(v)
        shown.append(v if length else np.degrees(v))
    return api, shown


def view(pm: "PMModel | str", pose: Mapping[str, float] | None = None, *,
         grid: Mapping[str, Any] | None = None, steps: int | None = None,
         path: "PathSpec | None" = None, force: "ArrayLike | None" = None,
         torque: "ArrayLike | None" = None, degrees: bool = False,
         overrides: Mapping[str, float] | None = None, title: str | None = None,
         start: int | None = None,
         progress: Callable[[int, int], None] | None = None) -> "View":
    """The interactive 3D view of a PM (:class:`screwkit.scene.View`: Jupyter shows it
    inline, ``.write_html(path)`` writes the self-contained page).

    Parameters
    ----------
    pm : PMModel or str
        A model, a catalog name or a YAML path.
    pose : dict, optional
        The independent pose parameters shown first (default: the model's default pose);
        the centre of the default grid.
    grid : dict, optional
        ``{name: (start, stop, count)}`` for the sliders of some parameters (the others:
        ``steps`` values over +-10 degrees or +-10 % of the characteristic length around
        ``pose``).
    steps : int, optional
        Values per slider (default: 21, 21, 9, 5, 3, 3 for 1 to 6 parameters: at most
        1000 poses).  The grid holds at most :data:`screwkit.scene.MAX_STATES` poses.
    path : PathSpec, optional
        A path instead of a grid: a time slider with play/pause over its samples.
    force, torque : array_like (3,), optional
        The workload at ``o`` (one without the other: the other is zero; neither: the
        model's declared default, else none: the page shows the kinematics without
        efforts and says so); the page states it and where it comes from.
    degrees : bool
        Angles of ``pose`` and ``grid`` in degrees.
    overrides : dict, optional
        Dimension overrides when ``pm`` is a name.
    title : str, optional
    start : int, optional
        The state shown first (default: the cell of ``pose``, or the first sample).
    progress : callable(done, total), optional

    Returns
    -------
    screwkit.scene.View
    """
    from ..engine import analyze, load_assembled_pm, scene_of
    from ..scene import MAX_STATES, GridControls, TimeControls, View, require_plotly

    require_plotly()
    from ..legs._guards import MAX_LABEL
    if title is not None and (not isinstance(title, str) or len(title) > MAX_LABEL):
        raise InputError(f"title must be a text of at most {MAX_LABEL} characters")
    model = load_assembled_pm(pm, dict(overrides or {}))
    if path is not None:
        if grid is not None or pose is not None:
            raise InputError("give either a path or a pose/grid, not both")
        from ._trajectory import _check_path
        path = _check_path(model, path)
        if len(path) > MAX_STATES:
            raise InputError(f"the path has {len(path)} samples; a view holds at most "
                             f"{MAX_STATES}: use fewer samples")
        res = analyze(model, {k: np.asarray(path.values[k], float) for k in model.independent},
                      force=force, torque=torque, path=True, progress=progress)
        return View(scene_of(res, TimeControls(np.asarray(path.t, float)),
                             start=_start(start, len(path)), title=title,
                             source=_source(res),
                             notes=(f"path: {path.source}",) if path.source else ()))
    centre = _centre(model, pose, degrees)
    api, shown = _axes(model, centre, grid, steps, degrees)
    total = int(np.prod([len(v) for v in api]))
    if total > MAX_STATES:
        raise InputError(f"the grid has {total} poses ({' x '.join(str(len(v)) for v in api)}); "
                         f"a view holds at most {MAX_STATES}: use fewer steps")
    mesh = np.meshgrid(*api, indexing="ij")
    poses = {k: m.reshape(-1) for k, m in zip(model.independent, mesh)}
    res = analyze(model, poses, force=force, torque=torque, progress=progress)
    cell = tuple(int(np.argmin(np.abs(v - centre[k])))
                 for k, v in zip(model.independent, api))
    controls = GridControls(tuple(model.independent), tuple(shown),
                            tuple(model.units.length if k in LENGTH_PARAMS else "deg"
                                  for k in model.independent))
    first = controls.index(cell) if start is None else _start(start, total)
    note = (f"{' x '.join(str(len(v)) for v in api)} poses solved by the engine; the sliders "
            "move between them")
    return View(scene_of(res, controls, start=first, title=title, source=_source(res),
                         notes=(note,)))


def _source(res) -> str:
    """Where the view's workload comes from (said once; the scene's text says 'none')."""
    from ..engine._scene import NO_WORKLOAD
    return res.workload_source if res.has_workload else NO_WORKLOAD


def _start(start, n):
    if start is None:
        return 0
    if isinstance(start, bool) or not isinstance(start, (int, np.integer)) or \
            not 0 <= start < n:
        raise InputError(f"start must be a state index from 0 to {n - 1}, got {start!r:.40}")
    return int(start)
