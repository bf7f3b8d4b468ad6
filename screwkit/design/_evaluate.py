"""One candidate design of dimensional synthesis: the objectives of a PM with given dimensions
over a task (private; ``docs/design.md``).

A :class:`Task` is what ``screwkit size`` takes: the cells (a grid or random samples of the
independent pose parameters, every other one fixed), the workloads and the worst trust
level a cell may have.  :func:`evaluate` builds the candidate with
:meth:`~screwkit.pm.PMModel.with_dimensions` (no file read again), analyses every cell in
one batched engine call, and reads every objective off that one analysis, counting the
cells exactly as :func:`screwkit.size` does: ``ok``, within the model's limits, and of
``max_level`` or better under each workload (the level depends on the workload through the
force amplification); the efforts of every workload after the first come from the cells'
responses to six unit workloads (the statics are linear in the load), as in ``size``.

The objectives (:data:`OBJECTIVES`), over the cells that count:

* ``max-actuator-force``: the largest ``|F_ai|`` over the cells, workloads and actuators
  (force or torque units: the model's);
* ``max-constraint-force``: the largest ``|value|`` of a constraint force row;
* ``min-lti``: the smallest local transmission index (maximised);
* ``gtw-volume``: the good-transmission workspace, the share of the task's cells that are
  reachable, within the limits and of ``LTI >= lti_threshold``, times the task box's
  volume (maximised; :func:`screwkit.maps.workspace`);
* ``condition``: the largest normalised condition number of ``J``;
* ``stroke``: the largest range ``max - min`` of an active leg's actuated joint value
  (model lengths; degrees for rotary actuators).

A candidate is feasible when every cell counts under every workload: the whole task is
reachable, regular at ``max_level``, within the limits and on home's side of every singular
surface (``det J`` of home's sign: a cell beyond one cannot be reached from home without
crossing it, and the efforts between cells on both sides grow without bound, so their
largest value over the cells would mean nothing; ``screwkit size`` counts such cells and
warns).  Its violation is the share of
(cell, workload) pairs that do not count (1 where the model cannot be built at all).
"""

from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np

from ..engine import analyze
from ..errors import ScrewkitError

__all__ = ["OBJECTIVES", "Objective", "Task", "evaluate", "MAX_OBJECTIVES"]


@dataclass(frozen=True)
class Objective:
    """An objective of dimensional synthesis: its name, ``sense`` (``min`` or ``max``), the
    kind of its unit (``force``, ``torque``, ``1``, ``volume``, ``stroke``) and what it is."""

    name: str
    sense: str
    unit: str
    text: str


OBJECTIVES = {o.name: o for o in (
    Objective("max-actuator-force", "min", "effort",
              "the largest |actuator force or torque| over the task and workloads"),
    Objective("max-constraint-force", "min", "force",
              "the largest |constraint force| over the task and workloads"),
    Objective("min-lti", "max", "1", "the smallest local transmission index over the task"),
    Objective("gtw-volume", "max", "volume",
              "the good-transmission workspace: the task box's volume with LTI >= threshold"),
    Objective("condition", "min", "1",
              "the largest normalised condition number of J over the task"),
    Objective("stroke", "min", "stroke",
              "the largest range of an actuated joint value over the task"),
)}
#: At most this many objectives at once.
MAX_OBJECTIVES = 4


@dataclass(frozen=True, eq=False)
class Task:
    """The cells, workloads and trust level of a sizing (see the module docstring).

    Attributes
    ----------
    poses : dict str -> ndarray (N,)
        Every independent pose parameter per cell (radians, model lengths).
    loads : tuple of (name, force (3,), torque (3,))
    max_level : int
        The worst level code a counted cell may have (``screwkit.maps.LEVEL_CODES``).
    lti_threshold : float
    box_volume : float
        The task box's volume (``gtw-volume``), in ``volume_units``.
    volume_units : str
    needs : frozenset of str
        The objectives the optimiser reads (the indices are computed only when needed).
    """

    poses: dict
    loads: tuple
    max_level: int
    lti_threshold: float
    box_volume: float
    volume_units: str
    needs: frozenset = field(default_factory=frozenset)

    @property
    def cells(self) -> int:
        return len(next(iter(self.poses.values())))


def _failed(reason: str) -> dict:
    return {"objectives": {k: float("nan") for k in OBJECTIVES}, "feasible": False,
            "violation": 1.0, "usable": 0, "reason": reason}


def evaluate(base, dims: dict, task: Task) -> dict:
    """The objectives of ``base`` with the dimensions ``dims`` over ``task``.

    Returns
    -------
    dict
        ``objectives`` (name -> value, NaN where no cell counts), ``feasible``,
        ``violation`` (0 when feasible), ``usable`` (the cells that count for every
        workload), ``reason`` (why it is infeasible, or "").
    """
    try:
        model = base.with_dimensions(dims) if dims else base
    except ScrewkitError as exc:
        return _failed(f"the model cannot be built: {str(exc).splitlines()[0]}")
    if model is not base:
        _same_legs(base, model)
    return objectives_of(model, task)


def _same_legs(base, model) -> None:
    """Give ``model`` (``base`` with other dimensions) the engine's arrays of ``base``'s legs:
    the joints, layout and row templates decided at ``base``'s home are kept, only the
    geometry is rebuilt (:func:`screwkit.engine.reflatten`); no leg is analysed again.  The
    reported designs are evaluated again on models of their own
    (:meth:`~screwkit.design.OptimizationResult.build`)."""
    from ..engine import reflatten
    try:
        reflatten(base, model)
    except ValueError:             # other legs (not expected of with_dimensions): its own
        pass


def objectives_of(model, task: Task) -> dict:
    """:func:`evaluate` for a built model."""
    from ..engine._pipeline import workload_about_origin
    from ..engine._quality import trust
    from ..maps import LEVEL_CODES
    from ..maps._loads import unit_responses

    name0, F0, T0 = task.loads[0]
    # the transmission indices read the actuated joints' twists: from the same kernel run
    res = analyze(model, task.poses, force=F0, torque=T0, raise_on_singular=False,
                  twists=bool(task.needs & {"min-lti", "gtw-volume"}))
    sol, jac, st = res.solution, res.jacobian, res.statics
    N = len(res)
    reach = np.asarray(sol.reachable_mask, bool)
    base_ok = np.asarray(res.ok, bool).copy()
    lim = model.limits
    within = np.ones(N, bool)
    if lim.declared:
        within = lim.check(sol.joint_values, np.asarray(sol.actuator_values, float),
                           np.asarray(sol._extensions, float), sol.base_points,
                           sol._platform[2])["within"]
    base_ok &= within
    # a cell where det J has the other sign than at home lies beyond a singular surface: the
    # task cannot be reached from home, nor crossed, without passing one (the efforts between
    # the cells grow without bound there: their maxima would be the cells' only)
    beyond = np.asarray(res.quality.beyond_singular_surface, bool) & reach
    base_ok &= ~beyond
    codes = {name: k for k, name in enumerate(LEVEL_CODES)}
    passive = set(getattr(model, "passive", ()) or ())
    info = jac.info
    act = np.array([r.kind == "actuation" and r.leg not in passive for r in info])
    from ..engine._report import row_quantity
    cforce = np.array([r.kind != "actuation" and row_quantity(r) == "force" for r in info])
    values = [np.asarray(st.F_r, float)]
    if len(task.loads) > 1:
        S, _ = unit_responses(res, np.zeros(model.n_legs, bool))
        values += [S @ np.concatenate([F, T]) for _, F, T in task.loads[1:]]
    max_act = max_con = -np.inf
    usable_all = np.ones(N, bool)
    usable_any = np.zeros(N, bool)
    for k, ((_, F, T), q) in enumerate(zip(task.loads, values)):
        if k == 0 and st.amp is not None and q.ndim == 2:
            # the analysis' own workload: the force amplification the kernel gave with the
            # values, as the analysis' quality (and so screwkit size) reads it
            _, lev = trust(jac, q, None, None, reach, np.nan_to_num(st.amp, nan=0.0))
        else:
            o = jac.origin
            W = workload_about_origin(np.broadcast_to(F, (N, 3)), np.broadcast_to(T, (N, 3)),
                                      o)
            _, lev = trust(jac, q, W, o, reach)
        code = np.array([codes[x] for x in lev.tolist()]) if N else np.zeros(0, int)
        use = base_ok & (code <= task.max_level)
        usable_all &= use
        usable_any |= use
        a = np.abs(q[use])
        if a.size:
            if act.any():
                max_act = max(max_act, float(np.nanmax(a[:, act])))
            if cforce.any():
                max_con = max(max_con, float(np.nanmax(a[:, cforce])))
    out = {k: float("nan") for k in OBJECTIVES}
    if np.isfinite(max_act):
        out["max-actuator-force"] = max_act
    if np.isfinite(max_con):
        out["max-constraint-force"] = max_con
    if usable_any.any():
        out["condition"] = float(np.max(jac.conditioning.condition_number[usable_any]))
        # the actuated legs' actuator values, in leg order (a passive leg has none)
        q_a = np.asarray(sol.actuator_values, float).reshape(N, -1)[usable_any]
        legs = [i for i in range(model.n_legs) if i not in passive]
        rot = np.array([model.home_legs[i].actuated_joint.kind != "P" for i in legs])
        span = np.ptp(q_a, axis=0) * np.where(rot, 180.0 / np.pi, 1.0)
        out["stroke"] = float(np.max(span)) if span.size else float("nan")
    if task.needs & {"min-lti", "gtw-volume"}:
        lti = np.asarray(res.indices.lti, float)
        if usable_any.any():
            out["min-lti"] = float(np.min(lti[usable_any]))
        with np.errstate(invalid="ignore"):
            good = reach & within & (lti >= task.lti_threshold)
        out["gtw-volume"] = float(np.sum(good)) / max(N, 1) * task.box_volume
    bad = N * len(task.loads) and 1.0 - float(np.sum(usable_all)) / N
    reason = "" if usable_all.all() else (
        f"{N - int(usable_all.sum())} of {N} cells do not count (unreachable, outside the "
        f"limits, beyond a singular surface from home ({int(beyond.sum())}), or worse than "
        f"{LEVEL_CODES[task.max_level]} under a workload)")
    return {"objectives": out, "feasible": bool(usable_all.all()), "violation": float(bad),
            "usable": int(usable_all.sum()), "reason": reason}
