"""The problem of dimensional synthesis: varied dimensions, objectives, constraints, task
(private; checked here so that every bad input is one clear error before any work).

:func:`problem` turns the arguments of :func:`screwkit.optimize` into a :class:`Problem`:
the base model, the bounds of each varied dimension, the objectives and the bounds on
other objectives (``"stroke<=40"``), and the :class:`~screwkit.design._evaluate.Task`
(cells, workloads, trust level) with every independent pose parameter given explicitly,
so that ``screwkit size`` at the chosen dimensions sees the same cells whatever the
chosen model's default pose is.
"""

from __future__ import annotations

import re
from dataclasses import dataclass

import numpy as np

from ..errors import InputError
from ._evaluate import MAX_OBJECTIVES, OBJECTIVES, Task

__all__ = ["Problem", "problem", "parse_constraint", "MAX_VARIED", "MAX_CONSTRAINTS"]

#: At most this many varied dimensions and constraints.
MAX_VARIED = 8
MAX_CONSTRAINTS = 8
_NUM = r"[-+]?(?:\d+\.?\d*|\.\d+)(?:[eE][-+]?\d+)?"


@dataclass(frozen=True, eq=False)
class Problem:
    """A checked dimensional-synthesis problem (module docstring).

    Attributes
    ----------
    base : PMModel
    vary : dict str -> (float, float)
        The bounds of each varied dimension (model lengths).
    objectives : tuple of str
    constraints : tuple of (str, str, float)
        ``(objective, "<=" or ">=", bound)``.
    task : Task
    grid : Grid
        The cells (for the report).
    units : dict str -> str
        The unit of each objective.
    """

    base: object
    vary: dict
    objectives: tuple
    constraints: tuple
    task: Task
    grid: object
    units: dict

    @property
    def names(self) -> tuple:
        return tuple(self.vary)

    @property
    def lower(self) -> np.ndarray:
        return np.array([lo for lo, _ in self.vary.values()])

    @property
    def upper(self) -> np.ndarray:
        return np.array([hi for _, hi in self.vary.values()])

    def dims(self, x) -> dict:
        return {k: float(v) for k, v in zip(self.vary, np.asarray(x, float).reshape(-1))}


def parse_constraint(text) -> tuple:
    """``"stroke<=40"`` -> ``("stroke", "<=", 40.0)`` (InputError on anything else)."""
    m = re.fullmatch(r"\s*([a-z-]+)\s*(<=|>=)\s*(" + _NUM + r")\s*", str(text))
    bound = re.fullmatch(r"\s*[a-z-]+\s*(<=|>=)\s*([-+]?(nan|inf|infinity))\s*", str(text),
                         re.IGNORECASE)
    if bound:
        raise InputError(f"constraint {str(text)[:60]!r}: the bound must be a finite number, "
                         f"not {bound.group(2)}")
    if not m:
        raise InputError(f"constraint {str(text)[:60]!r} must look like OBJECTIVE<=VALUE or "
                         f"OBJECTIVE>=VALUE (objectives: {', '.join(OBJECTIVES)})")
    name, op, val = m.group(1), m.group(2), float(m.group(3))
    if name not in OBJECTIVES:
        raise InputError(f"constraint {text!r}: unknown objective {name!r} (one of "
                         f"{', '.join(OBJECTIVES)})")
    if not np.isfinite(val) or abs(val) > 1e15:
        raise InputError(f"constraint {text!r}: the bound must be a finite number")
    return name, op, val


def _vary(base, vary) -> dict:
    from ..legs._guards import MAX_MAGNITUDE
    if not isinstance(vary, dict) or not vary:
        raise InputError("vary at least one dimension: {name: (low, high)}, e.g. "
                         "{'l': (30, 120)}")
    if len(vary) > MAX_VARIED:
        raise InputError(f"at most {MAX_VARIED} varied dimensions, got {len(vary)}")
    out = {}
    for k, b in vary.items():
        if k not in base.dimensions:
            raise InputError(f"{base.name}: {k!r} is not a dimension (its dimensions: "
                             f"{', '.join(base.dimensions) or 'none'})")
        try:
            lo, hi = (float(x) for x in b)
        except (TypeError, ValueError):
            raise InputError(f"vary {k}: give (low, high), got {b!r:.40}") from None
        if not (np.isfinite(lo) and np.isfinite(hi) and 0 < lo < hi <= MAX_MAGNITUDE):
            raise InputError(f"vary {k}: need 0 < low < high <= {MAX_MAGNITUDE:g} (model "
                             f"lengths), got {lo:g}:{hi:g}")
        out[k] = (lo, hi)
    return out


def _units(base, grid, degrees) -> dict:
    """The unit of each objective (``None`` where the actuators mix forces and torques)."""
    u = base.units
    passive = set(getattr(base, "passive", ()) or ())
    rot = {base.home_legs[i].actuated_joint.kind != "P" for i in range(base.n_legs)
           if i not in passive}
    effort = None if len(rot) > 1 else (u.torque if rot == {True} else u.force)
    stroke = None if len(rot) > 1 else ("deg" if rot == {True} else u.length)
    counts = {}
    for p in grid.params:
        unit = u.length if p in ("Xo", "Yo", "Zo") else ("deg" if degrees else "rad")
        counts[unit] = counts.get(unit, 0) + 1
    order = sorted(counts, key=lambda x: (x in ("deg", "rad"), x))
    volume = ".".join(x if counts[x] == 1 else f"{x}^{counts[x]}" for x in order)
    return {"max-actuator-force": effort, "max-constraint-force": u.force, "min-lti": "1",
            "gtw-volume": volume, "condition": "1", "stroke": stroke}


def problem(base, vary, grid, fix=None, *, samples=None, seed=0, degrees=False, loads,
            objectives=("max-actuator-force",), constraints=(), max_level="near-singular",
            lti_threshold=0.7) -> Problem:
    """Check the arguments of :func:`screwkit.optimize` and build the :class:`Problem`."""
    from ..maps import LEVEL_CODES, make_grid
    if isinstance(objectives, str):
        objectives = (objectives,)
    objectives = tuple(objectives)
    if not 1 <= len(objectives) <= MAX_OBJECTIVES:
        raise InputError(f"1 to {MAX_OBJECTIVES} objectives, got {len(objectives)}")
    for o in objectives:
        if o not in OBJECTIVES:
            raise InputError(f"unknown objective {str(o)[:40]!r} (one of "
                             f"{', '.join(OBJECTIVES)})")
    if len(set(objectives)) != len(objectives):
        raise InputError("an objective is given twice")
    if isinstance(constraints, str):             # (one constraint: not its letters)
        constraints = (constraints,)
    try:
        given = list(constraints or ())
    except TypeError:
        raise InputError(f"constraints must be a list of texts such as 'stroke<=40', got "
                         f"{str(constraints)[:40]}") from None
    if len(given) > MAX_CONSTRAINTS:
        raise InputError(f"at most {MAX_CONSTRAINTS} constraints, got {len(given)}")
    for c in given:
        if not isinstance(c, str) and not (isinstance(c, (tuple, list)) and len(c) == 3):
            raise InputError(f"a constraint is a text such as 'stroke<=40' or a triple (name, "
                             f"'<=' or '>=', value), got {str(c)[:40]}")
    cons = tuple(parse_constraint(c) if isinstance(c, str) else parse_constraint(
        f"{c[0]}{c[1]}{c[2]}") for c in given)
    if len(cons) > MAX_CONSTRAINTS:
        raise InputError(f"at most {MAX_CONSTRAINTS} constraints, got {len(cons)}")
    if max_level not in LEVEL_CODES[:3]:
        raise InputError(f"max_level must be one of {', '.join(LEVEL_CODES[:3])}, got "
                         f"{max_level!r:.40}")
    if isinstance(lti_threshold, bool) or not isinstance(lti_threshold, (int, float)) or \
            not 0 < lti_threshold <= 1:
        raise InputError(f"the LTI threshold must be in (0, 1], got {lti_threshold!r:.40}")
    bounds = _vary(base, vary)
    g = make_grid(base, grid, fix, samples=samples, seed=seed, degrees=degrees)
    units = _units(base, g, degrees)
    for o in objectives + tuple(c[0] for c in cons):
        if units[o] is None:
            raise InputError(f"{o}: the actuators of {base.name} mix linear and rotary ones "
                             "(forces and torques, lengths and angles): it compares unlike "
                             "quantities")
    if "max-constraint-force" in objectives + tuple(c[0] for c in cons):
        if not any(c.kind != "couple" for lg in base.home_legs
                   for c in lg.analyze().constraints):
            raise InputError(f"max-constraint-force: {base.name} has no constraint force "
                             "(its legs exert constraint couples only)")
    if samples is None:
        box = [(float(np.min(v)), float(np.max(v))) for v in g.coords.values()]
    else:
        box = list(g.box.values())
    volume = float(np.prod([hi - lo for lo, hi in box]))
    needs = frozenset(objectives) | frozenset(c[0] for c in cons)
    task = Task(g.poses(), tuple(loads), LEVEL_CODES.index(max_level), float(lti_threshold),
                volume, units["gtw-volume"], needs)
    return Problem(base, bounds, objectives, cons, task, g, units)
