"""The result of dimensional synthesis (private): the best design, the Pareto front, the
history of the search, the task it was sized for; JSON, a model file, a picture."""

from __future__ import annotations

import dataclasses
from dataclasses import dataclass, field

import numpy as np

from ._evaluate import OBJECTIVES

__all__ = ["OptimizationResult", "pareto"]


def pareto(F) -> list:
    """Indices of the non-dominated rows of ``F (k, m)`` (every column minimised; the first
    of equal rows)."""
    F = np.asarray(F, float)
    keep = []
    for i in range(len(F)):
        le = np.all(F <= F[i], axis=1)
        lt = np.any(F < F[i], axis=1)
        if np.any(le & lt):
            continue
        if any(np.array_equal(F[j], F[i]) for j in keep):
            continue
        keep.append(i)
    return keep


def _clean(objs: dict) -> dict:
    return {k: (float(v) if np.isfinite(v) else None) for k, v in objs.items()}


def _task(prob) -> dict:
    g, t = prob.grid, prob.task
    ang = "deg" if g.degrees else "rad"
    unit = {p: (prob.base.units.length if p in ("Xo", "Yo", "Zo") else ang)
            for p in tuple(g.coords) + tuple(g.fixed)}
    if g.samples:
        cells = {"samples": g.size, "seed": g.seed,
                 "box": {k: list(v) for k, v in (g.box or {}).items()}}
    else:
        cells = {"grid": {k: {"start": float(v[0]), "stop": float(v[-1]), "count": len(v)}
                          for k, v in g.coords.items()}}
    return {**cells, "fixed": dict(g.fixed), "units": unit, "cells": t.cells,
            "workloads": [{"name": n, "force": np.asarray(F).tolist(),
                           "torque": np.asarray(T).tolist(), "applied_at": "o",
                           "force_unit": prob.base.units.force,
                           "torque_unit": prob.base.units.torque} for n, F, T in t.loads],
            "max_level": ("ok", "ill-conditioned", "near-singular")[t.max_level],
            "lti_threshold": t.lti_threshold, "box_volume": t.box_volume}


def _task_in(task: dict, length: str, kl: float, kf: float, kt: float, kv: float) -> dict:
    """The task of a result (:func:`_task`) with its lengths, loads and volume in SI."""
    def scale(p):
        return kl if p in ("Xo", "Yo", "Zo") else 1.0
    units = task["units"]
    out = dict(task, units={p: ("m" if units[p] == length else units[p]) for p in units},
               fixed={p: v * scale(p) for p, v in task["fixed"].items()},
               workloads=[dict(w, force=[x * kf for x in w["force"]],
                               torque=[x * kt for x in w["torque"]], force_unit="N",
                               torque_unit="N.m") for w in task["workloads"]],
               box_volume=task["box_volume"] * kv)
    if "grid" in task:
        out["grid"] = {p: dict(g, start=g["start"] * scale(p), stop=g["stop"] * scale(p))
                       for p, g in task["grid"].items()}
    if task.get("box"):
        out["box"] = {p: [x * scale(p) for x in v] for p, v in task["box"].items()}
    return out


@dataclass(frozen=True, eq=False)
class OptimizationResult:
    """Dimensional synthesis of a PM (``screwkit.optimize``; ``docs/design.md``).

    Attributes
    ----------
    pm : str
    vary : dict str -> (low, high)
    objectives : tuple of str
        The first is ``best``'s objective.
    constraints : tuple of (str, str, float)
    units : dict
        The unit of each objective and of the dimensions (``length``).
    best : dict or None
        ``dimensions``, ``objective`` (the first objective's value), ``objectives`` (every
        objective at the best design; None where not defined), ``feasible``; None when no
        candidate made the whole task feasible.
    front : list of dict
        Several objectives: the Pareto front of the feasible candidates evaluated
        (``dimensions``, ``objectives``), by the first objective.
    evaluations : int
        The candidates evaluated (each once: they are cached).
    history : list of dict
        Per generation: ``best`` so far, the ``median`` of its feasible candidates, counts.
    method : str
    seed : int
    task : dict
        The cells (every independent parameter explicit), workloads, trust level.
    model : PMModel or None
        The best design (:meth:`write_model` writes it).
    """

    pm: str
    vary: dict
    objectives: tuple
    constraints: tuple
    units: dict
    best: dict | None
    front: list
    evaluations: int
    history: list
    method: str
    seed: int
    task: dict
    model: object = field(default=None, repr=False)
    evaluated: list = field(default_factory=list, repr=False)
    model_units: object = field(default=None, repr=False)

    @classmethod
    def build(cls, prob, ev, best, front, method, seed, history) -> "OptimizationResult":
        from ._evaluate import objectives_of

        def entry(kr, model=None):
            k, r = kr
            if model is not None:
                # the best design evaluated again on a model of its own (its own row
                # templates, as screwkit size builds it), not on the search's shared arrays;
                # its feasibility is this evaluation's, constraints included
                r = objectives_of(model, prob.task)
                r = dict(r, violation=ev._violation(r))
            out = {"dimensions": prob.dims(k), "objectives": _clean(r["objectives"])}
            if model is not None:
                out["feasible"] = bool(r["violation"] == 0.0)
            return out
        b = None
        model = None
        if best is not None:
            model = prob.base.with_dimensions(prob.dims(best[0]))
            b = entry(best, model)
            b["objective"] = b["objectives"][prob.objectives[0]]
        units = {o: prob.units[o] for o in OBJECTIVES}
        units["length"] = prob.base.units.length
        evaluated = [(prob.dims(k), _clean(ev.cache[k]["objectives"]), ev.cache[k]["feasible"])
                     for k in ev.order]
        return cls(prob.base.name, dict(prob.vary), tuple(prob.objectives),
                   tuple(prob.constraints), units, b, [entry(kr) for kr in front],
                   len(ev.order), history, method, seed, _task(prob), model, evaluated,
                   prob.base.units)

    def in_units(self, units=None) -> "OptimizationResult":
        """This result in the model's units (``units`` None or ``"model"``: itself) or in SI
        (``"SI"``: lengths in m, forces in N, torques in N.m; the dimensions and their
        bounds, every objective and constraint, the history, the front, the task's cells
        and workloads; angles and dimensionless objectives as they are).  The model
        ``model`` (written by :meth:`write_model`) keeps its own declared units."""
        if units is None or units == "model":
            return self
        from ..engine._report import output_scales
        u = self.model_units
        _, k = output_scales(u, units, self.pm)
        kl, kf, kt = k["length"], k["force"], k["torque"]

        def factor(unit):
            """``(factor, SI unit)`` of an objective's unit (a volume: lengths and angles)."""
            if unit is None or unit in ("1", "deg", "rad"):
                return 1.0, unit
            if unit == u.force:
                return kf, "N"
            if unit == u.torque:
                return kt, "N.m"
            f, parts = 1.0, []
            for part in unit.split("."):
                base, _, n = part.partition("^")
                if base == u.length:
                    f *= kl ** int(n or 1)
                    parts.append("m" + (f"^{n}" if n else ""))
                else:
                    parts.append(part)
            return f, ".".join(parts)
        fo = {o: factor(self.units[o]) for o in OBJECTIVES}

        def objs(d):
            return {o: (None if v is None else v * fo[o][0]) for o, v in d.items()}

        def dims(d):
            return {n: v * kl for n, v in d.items()}

        def entry(e):
            out = dict(e, dimensions=dims(e["dimensions"]), objectives=objs(e["objectives"]))
            if "objective" in e:
                out["objective"] = out["objectives"][self.objectives[0]]
            return out
        f0 = fo[self.objectives[0]][0]
        history = [dict(h, best=None if h["best"] is None else h["best"] * f0,
                        median=None if h["median"] is None else h["median"] * f0)
                   for h in self.history]
        return dataclasses.replace(
            self, vary={n: (lo * kl, hi * kl) for n, (lo, hi) in self.vary.items()},
            constraints=tuple((n, op, v * fo[n][0]) for n, op, v in self.constraints),
            units={**{o: fo[o][1] for o in OBJECTIVES}, "length": "m"},
            best=None if self.best is None else entry(self.best),
            front=[entry(e) for e in self.front], history=history,
            task=_task_in(self.task, u.length, kl, kf, kt, fo["gtw-volume"][0]),
            evaluated=[(dims(d), objs(o), ok) for d, o, ok in self.evaluated])

    def to_dict(self) -> dict:
        return {"pm": self.pm, "method": self.method, "seed": self.seed,
                "vary": {k: list(v) for k, v in self.vary.items()},
                "objective": self.objectives[0], "objectives_optimised": list(self.objectives),
                "senses": {o: OBJECTIVES[o].sense for o in self.objectives},
                "constraints": [f"{n}{op}{v:g}" for n, op, v in self.constraints],
                "units": self.units, "task": self.task, "best": self.best,
                "front": self.front, "evaluations": self.evaluations,
                "history": self.history,
                "not_computed": {o: "the transmission indices are computed only where an "
                                    "objective or a constraint names one (they need the "
                                    "joints' twists at every cell)"
                                 for o, v in (self.best or {}).get("objectives", {}).items()
                                 if v is None}}

    def write_model(self, path) -> str:
        """Write the best design as a model file (YAML) that :func:`screwkit.load_pm` reads."""
        from ..errors import InputError
        from ..pm import definition_yaml
        if self.model is None:
            raise InputError("no feasible design to write: every candidate left some cells of "
                             "the task unusable")
        dims = ", ".join(f"{k} = {v:.6g}" for k, v in self.best["dimensions"].items())
        text = definition_yaml(self.model, f"screwkit optimize of {self.pm} ({self.method}, "
                                           f"{self.objectives[0]}): {dims}")
        try:
            with open(path, "w", encoding="utf-8") as fh:
                fh.write(text)
        except OSError as exc:
            raise InputError(f"cannot write {str(path)!r}: {exc}") from None
        return str(path)

    def plot(self, out=None):
        """The Pareto front (several objectives) or the best objective over the generations
        (one), drawn by :mod:`screwkit.viz`; written to ``out`` (PNG) when given."""
        from ..viz import plot_front, plot_history

        def label(o):
            u = self.units[o]
            sense = "maximised" if OBJECTIVES[o].sense == "max" else "minimised"
            return f"{o} [{u if u not in ('1', None) else '–'}] ({sense})"
        title = f"{self.pm}: " + ", ".join(f"{k} in {lo:g}..{hi:g} {self.units['length']}"
                                          for k, (lo, hi) in self.vary.items())
        if self.constraints:
            title += "; subject to " + ", ".join(f"{n} {op} {v:g}"
                                                 for n, op, v in self.constraints)
        loads = self.task.get("workloads") or []
        if loads:                       # (every figure says its load)
            w = loads[0]
            title += (f"\nF = [{', '.join(f'{x:g}' for x in w['force'])}] {w['force_unit']}, "
                      f"T = [{', '.join(f'{x:g}' for x in w['torque'])}] {w['torque_unit']} "
                      "at o" + (f" and {len(loads) - 1} more workloads" if len(loads) > 1
                                else ""))
        if len(self.objectives) > 1:
            pts = [(e[1][self.objectives[0]], e[1][self.objectives[1]])
                   for e in self.evaluated if e[2]]
            front = [(f["objectives"][self.objectives[0]], f["objectives"][self.objectives[1]])
                     for f in self.front]
            return plot_front(out, pts, front, label(self.objectives[0]),
                              label(self.objectives[1]), title=title + f"\n{len(self.front)} "
                              f"design{'s' * (len(self.front) != 1)} on the Pareto front of "
                              f"{self.evaluations} evaluated")
        h = self.history
        return plot_history(out, [e["generation"] for e in h], [e["best"] for e in h],
                            [e["median"] for e in h], label(self.objectives[0]),
                            title=title + f"\n{self.method}; {self.evaluations} designs "
                            "evaluated")
