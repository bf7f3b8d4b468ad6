"""The data of a 3D view: the states of a PM (one pose each) and what the page needs to draw them.

A :class:`Scene` is plain data, built by the callers (``PMAnalysis.show``,
``TrajectoryResult.show``, :func:`screwkit.view`) from their results; this layer never
calls a solver.  Every state (:class:`PoseState`) holds the placed legs, the base and
platform polygons, and the value, line and direction of every wrench row at one pose;
:class:`SceneRow` says what each row is (the same at every state).  The states are either
the cells of a grid over the independent pose parameters (:class:`GridControls`: one slider
per parameter, the last varying fastest) or the samples of a path (:class:`TimeControls`:
one time slider with play/pause).

:meth:`Scene.to_json` is what the page reads: lengths, forces and torques in the model's
units, angles in degrees, the label of every row at every state already written
(``F_a1 = 19.36 kN``).
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field

import numpy as np

from ..errors import InputError
from ._arrows import FLOOR, arrow_fractions, scale_key
from ._geometry import plate_outline
from ._palette import COLORS, leg_color

__all__ = ["SceneRow", "PoseState", "GridControls", "TimeControls", "Scene", "MAX_STATES",
           "format_value"]

#: At most this many states in one view (the page holds every state's data: about 4 kB each).
MAX_STATES = 4096

_ANGLES = ("alpha", "beta", "gamma")
_ROW_KINDS = ("actuation", "force", "couple")


def format_value(v: float, digits: int = 4) -> str:
    """``digits`` significant digits, without an exponent for 0.001 <= |v| < 1e6
    (``19.36``, ``-13.49``, ``1420``, ``0.003162``); ``n/a`` for NaN."""
    if not math.isfinite(v):
        return "n/a"
    a = abs(v)
    if a == 0.0:
        return "0"
    if not 1e-3 <= a < 1e6:
        return f"{v:.{digits - 1}e}"
    r = float(f"{v:.{digits}g}")
    places = max(digits - 1 - int(math.floor(math.log10(abs(r)))), 0)
    text = f"{r:.{places}f}"
    return text.rstrip("0").rstrip(".") if "." in text else text


@dataclass(frozen=True)
class SceneRow:
    """What one wrench row is, at every state.

    Attributes
    ----------
    label : str
        ``F_a1``, ``F_c2``, ``T_c3``, ``T_a1`` (a rotary actuator's torque) ...
    kind : str
        ``actuation`` (a force on its line), ``force`` (a constraint force) or ``couple``.
    leg : int
        0-based.
    quantity : str
        ``force`` or ``torque``: the unit of the value.
    actuation : bool
        An actuation wrench (drawn with a full head; a constraint wrench gets a pale one).
    """

    label: str
    kind: str
    leg: int
    quantity: str = "force"
    actuation: bool = False

    @property
    def scale_key(self) -> str:
        """The arrows this row's length is proportional with (``force-a``, ``force-c``,
        ``torque-c``...): its quantity and whether it is an actuation wrench."""
        return scale_key(self.quantity, self.actuation)

    def __post_init__(self):
        if self.kind not in _ROW_KINDS:
            raise InputError(f"row {self.label!r}: kind {self.kind!r} is not one of "
                             f"{', '.join(_ROW_KINDS)}")
        if self.quantity not in ("force", "torque"):
            raise InputError(f"row {self.label!r}: quantity must be 'force' or 'torque'")


@dataclass(frozen=True, eq=False)
class PoseState:
    """One pose of a view.

    Attributes
    ----------
    pose : dict str -> float
        The six pose parameters (angles in degrees, lengths in the model's unit).
    status : str
        ``ok`` (regular), ``near-singular``, ``singular`` or ``unreachable`` (then nothing
        is drawn): the engine's conditioning class, as every command says it.
    level : str
        ``ok``, ``ill-conditioned``, ``near-singular``, ``singular`` or ``unreachable``.
    condition_number : float
    legs : tuple of Leg
        The placed legs (empty when unreachable).
    base_points, platform_points : ndarray (n, 3)
    o : ndarray (3,)
    values : ndarray (m,)
        Row values (NaN where the statics is not solved).
    points : ndarray (m, 3)
        A point of each row's line (NaN for a couple).
    directions : ndarray (m, 3)
        Unit direction of each row's force or couple.
    determined : ndarray (m,) of bool
        False where statics does not fix the value (the least-norm choice, marked ``*``).
    notes : tuple of str
    """

    pose: dict
    status: str
    level: str
    condition_number: float
    legs: tuple
    base_points: np.ndarray
    platform_points: np.ndarray
    o: np.ndarray
    values: np.ndarray
    points: np.ndarray
    directions: np.ndarray
    determined: np.ndarray
    notes: tuple = ()


@dataclass(frozen=True)
class GridControls:
    """Sliders over a grid: ``params`` (names), ``values`` (one array each, display units:
    degrees, the model's length), ``units``; state ``k`` is the C-order cell ``k``."""

    params: tuple
    values: tuple
    units: tuple

    @property
    def shape(self) -> tuple:
        return tuple(len(v) for v in self.values)

    def index(self, cell) -> int:
        """The state of the cell ``cell`` (one index per parameter)."""
        return int(np.ravel_multi_index(tuple(cell), self.shape))


@dataclass(frozen=True)
class TimeControls:
    """A time slider with play/pause over the samples ``t (N,)`` of a path."""

    t: np.ndarray


@dataclass(frozen=True, eq=False)
class Scene:
    """Everything a 3D view shows (see the module docstring).

    Attributes
    ----------
    pm : str
    leg_names : tuple of str
    passive : tuple of int
        Legs without an actuator (marked passive; they have no actuation row).
    rows : tuple of SceneRow
    states : tuple of PoseState
    controls : GridControls or TimeControls
    units : dict
        ``length``, ``force``, ``torque``.
    force, torque : ndarray (3,) or None
        The workload at ``o``; None when the view has none (no efforts: the wrenches are
        drawn on their lines without values, and the page says so).
    workload_source : str
        Where the workload comes from (``the paper's workload``, ``given``...).
    start : int
        The state shown first.
    title : str
    """

    pm: str
    leg_names: tuple
    rows: tuple
    states: tuple
    controls: object
    units: dict
    force: np.ndarray | None
    torque: np.ndarray | None
    workload_source: str = ""
    passive: tuple = ()
    start: int = 0
    title: str = ""
    notes: tuple = field(default=())

    def __post_init__(self):
        n = len(self.states)
        if n == 0:
            raise InputError("a view needs at least one state")
        if n > MAX_STATES:
            raise InputError(f"a view holds at most {MAX_STATES} states, got {n}: use fewer "
                             "steps or samples")
        if not 0 <= int(self.start) < n:
            raise InputError(f"start state {self.start} is not in 0..{n - 1}")
        if isinstance(self.controls, GridControls) and int(np.prod(self.controls.shape)) != n:
            raise InputError(f"the grid has {int(np.prod(self.controls.shape))} cells for "
                             f"{n} states")
        if isinstance(self.controls, TimeControls) and len(self.controls.t) != n:
            raise InputError(f"{len(self.controls.t)} times for {n} states")

    @property
    def workload_text(self) -> str:
        u = self.units
        if self.force is None or self.torque is None:
            why = f" ({self.workload_source})" if self.workload_source else ""
            return (f"none{why}: no efforts; the wrenches are drawn on their lines without "
                    "values (give a force and a torque at o to see them)")
        F = ", ".join(format_value(float(x), 6) for x in self.force)
        T = ", ".join(format_value(float(x), 6) for x in self.torque)
        src = f" ({self.workload_source})" if self.workload_source else ""
        return f"F = [{F}] {u['force']}, T = [{T}] {u['torque']} at o{src}"

    def row_text(self, state: PoseState, k: int) -> str:
        """``F_a1 = 19.36 kN`` (``*`` when statics does not determine it)."""
        r = self.rows[k]
        v = float(state.values[k])
        if not math.isfinite(v):
            return f"{r.label} = n/a"
        star = "" if bool(state.determined[k]) else "*"
        return f"{r.label} = {format_value(v)} {self.units[r.quantity]}{star}"

    def to_json(self) -> dict:
        """The page's data (JSON-ready; NaN written as None)."""
        from ._geometry import leg_json, scene_box, scene_size

        size = scene_size(self.states)
        keys = [r.scale_key for r in self.rows]
        states = []
        for s in self.states:
            drawn = s.status != "unreachable"
            frac, floored = arrow_fractions(s.values, keys)
            states.append({
                "pose": {k: _num(v) for k, v in s.pose.items()},
                "status": s.status, "level": s.level,
                "condition_number": _num(s.condition_number),
                "notes": list(s.notes),
                "legs": [leg_json(lg, size) for lg in s.legs] if drawn else [],
                # (the plates' outlines: a central column's point is not a corner)
                "base": _arr(plate_outline(s.base_points)),
                "platform": _arr(plate_outline(s.platform_points)) if drawn else [],
                "o": _arr(s.o) if drawn else None,
                "values": _arr(s.values), "points": _arr(s.points),
                "directions": _arr(s.directions),
                "determined": [bool(x) for x in s.determined],
                "text": [self.row_text(s, k) for k in range(len(self.rows))],
                "frac": _arr(frac), "floored": [bool(x) for x in floored],
            })
        if isinstance(self.controls, GridControls):
            controls = {"type": "grid", "params": [
                {"name": p, "unit": u, "values": _arr(v)}
                for p, v, u in zip(self.controls.params, self.controls.values,
                                   self.controls.units)]}
        else:
            controls = {"type": "time", "t": _arr(self.controls.t)}
        lo, hi = scene_box(self.states, size)
        return {
            "format": "screwkit-view/1", "pm": self.pm, "title": self.title or self.pm,
            "units": dict(self.units), "workload": {
                "force": None if self.force is None else _arr(self.force),
                "torque": None if self.torque is None else _arr(self.torque),
                "source": self.workload_source, "text": self.workload_text},
            "legs": [{"name": n, "color": leg_color(i), "passive": i in self.passive,
                      "label": f"leg {i + 1} ({n})" + (" · passive" if i in self.passive
                                                        else "")}
                     for i, n in enumerate(self.leg_names)],
            "rows": [{"label": r.label, "kind": r.kind, "leg": r.leg, "quantity": r.quantity,
                      "actuation": r.actuation, "scale": r.scale_key} for r in self.rows],
            "colors": dict(COLORS), "size": size, "floor": FLOOR,
            "box": {"lo": _arr(lo), "hi": _arr(hi)},
            "controls": controls, "start": int(self.start), "states": states,
            "notes": list(self.notes),
        }


def _num(x):
    x = float(x)
    return x if math.isfinite(x) else None


def _arr(a):
    a = np.asarray(a, float)
    if a.ndim == 0:
        return _num(a)
    return [_arr(x) for x in a] if a.ndim > 1 else [_num(x) for x in a]
