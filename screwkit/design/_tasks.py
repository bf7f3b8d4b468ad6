"""The engine verification of one candidate PM, as a picklable task (for a mapper).

:func:`synthesize_motion` screens its candidates serially (cheap: legs at home) and sends
each survivor to :func:`verify_candidate` through a *mapper*: a callable
``mapper(fn, items, progress) -> list`` with the results in the order of ``items`` (the serial
default is :func:`serial_map`; ``functools.partial(screwkit.maps.run_tasks, cluster)``
runs the tasks on a Dask cluster, see ``screwkit synthesize --workers``).  A task holds
only plain data (the candidate's name, the motion's name, the passive legs and its
``pms:`` definitions on the geometries where it passed the screen), so the result does
not depend on where it runs.
"""

from __future__ import annotations

from dataclasses import dataclass

from ..synthesis import motion_pattern, synthesis_catalog
from ._verify import Verdict, load_candidate, verify_model

__all__ = ["MOTION_CHECKS", "VerifyTask", "TaskResult", "monotonic_progress", "motion_key",
           "run_round", "serial_map", "task_catalog", "verify_candidate"]


@dataclass(frozen=True)
class VerifyTask:
    """One candidate to verify.

    Attributes
    ----------
    name : str
        The candidate's name (the model name).
    motion : str
        The motion pattern's name.
    passive : tuple of int
        0-based indices of its passive legs.
    definitions : tuple of (int, dict)
        ``(geometry index, pms: definition)``, tried in order until one verifies.
    catalog : Catalog or None
        The leg catalog (None: the packaged one).
    """

    name: str
    motion: str
    passive: tuple
    definitions: tuple
    catalog: object = None


@dataclass(frozen=True)
class TaskResult:
    """Result of :func:`verify_candidate`.

    Attributes
    ----------
    geometry : int or None
        The geometry it verified on (None: on none).
    definition : dict or None
    verdict : Verdict or None
    reason : str
        Why it failed on the last geometry tried (empty on success).
    engine_runs : int
        Geometries sent to the engine.
    check : str
        The failed check of the last geometry tried (:attr:`Verdict.check`; ``"assembly"``:
        the model could not be assembled at home).
    """

    geometry: int | None
    definition: dict | None
    verdict: Verdict | None
    reason: str
    engine_runs: int
    check: str = ""


def verify_candidate(task: VerifyTask) -> TaskResult:
    """Load the candidate on each of its geometries and verify it with the engine
    (:func:`~screwkit.design.verify_model`) until one succeeds."""
    m = motion_pattern(task.motion)
    reason, runs, check = "", 0, ""
    for g, d in task.definitions:
        runs += 1
        model, exc = load_candidate(task.name, synthesis_catalog(task.catalog, {task.name: d}))
        if model is None:
            reason, check = reason or f"cannot be assembled: {exc}", "assembly"
            continue
        verdict = verify_model(model, m, task.passive)
        if verdict.success:
            return TaskResult(g, d, verdict, "", runs)
        reason, check = verdict.reason, verdict.check
    return TaskResult(None, None, None, reason, runs, check)


def serial_map(fn, items, progress=None) -> list:
    """``[fn(x) for x in items]``: the serial mapper (``progress(done, total)`` after each)."""
    items = list(items)
    out = []
    for x in items:
        out.append(fn(x))
        if progress is not None:
            progress(len(out), len(items))
    return out


def run_round(m, comps, screened, order, budget, catalog, mapper, progress, outcome, start,
               total) -> int:
    """Verify the screened candidates of ``order`` through ``mapper``, geometry by
    geometry: every candidate on its first screened geometry, then the ones that failed
    there on their next, ...; at most ``budget`` engine verifications, taken in order.
    Fills ``outcome {index: TaskResult}`` (a candidate the budget stopped before it
    verified or ran out of geometries is left out: not verified); returns the
    verifications spent."""
    todo = [i for i in order if i in screened]
    base = start + len(order) - len(todo)          # the unscreened ones are done already
    step, spent, settled = 0, 0, 0
    while todo and spent < budget:
        pending, nxt = todo, []
        while pending and spent < budget:
            # candidates settled by an equivalent's run cost no budget: fill it up again
            batch, pending = pending[:budget - spent], pending[budget - spent:]
            prog = None
            if progress is not None and step == 0:
                prog = lambda d, _t, o=settled: progress(base + o + d, total)   # noqa: E731
            results, runs = _verify_batch(m, comps, screened, batch, step, catalog, mapper,
                                          prog)
            spent += runs
            for i, r in zip(batch, results):
                outcome[i] = r
                if r.geometry is None and step + 1 < len(screened[i]):
                    nxt.append(i)                  # failed here: try its next geometry
                else:
                    settled += 1
        for i in pending:
            outcome.pop(i, None)                   # beyond the budget: not verified
        todo = nxt
        step += 1
        if progress is not None:
            progress(base + settled, total)
    for i in todo:
        outcome.pop(i, None)
    if progress is not None:
        progress(start + len(order), total)
    return spent


#: Failed checks that concern the platform's motion only (:attr:`Verdict.check`): the same
#: for candidates that differ only in their unconstrained legs.
MOTION_CHECKS = frozenset({"workspace", "mobility", "finite"})


def motion_key(cand, definition) -> tuple:
    """Candidates with equal keys move their platform alike: the same constraining leg
    types at the same vertices of the same placement, their other legs unconstrained
    (SPS, UPS, SPU: six freedoms, no constraint wrench), which change neither the
    assembly, the mobility nor the finite motion, only the actuation (``J``)."""
    legs = tuple(k.name if k.constraints else "" for k in cand.legs)
    return legs, cand.passive, cand.central, cand.pair, repr(definition["base"]), \
        repr(definition["platform"]), repr(definition.get("home"))


def _verify_batch(m, comps, screened, batch, step, catalog, mapper, prog) -> tuple:
    """``(results, engine runs)`` of the candidates ``batch`` on their ``step``-th screened
    geometry.  Of candidates with one :func:`motion_key` the first is verified first; where
    it fails a check of :data:`MOTION_CHECKS`, the others fail it too (said so in their
    reason) without a run of their own; the rest are verified after."""
    def task(i):
        return VerifyTask(comps[i].name, m.name, comps[i].passive, (screened[i][step],),
                          task_catalog(catalog, comps[i]))

    first: dict = {}
    key = {i: motion_key(comps[i], screened[i][step][1]) for i in batch}
    for i in batch:
        first.setdefault(key[i], i)
    lead = [i for i in batch if first[key[i]] == i]
    out = dict(zip(lead, (mapper or serial_map)(verify_candidate, [task(i) for i in lead], prog)))
    rest = []
    for i in batch:
        if i in out:
            continue
        r = out[first[key[i]]]
        if r.geometry is None and r.check in MOTION_CHECKS:
            out[i] = TaskResult(None, None, None, f"{r.reason} (as {comps[first[key[i]]].name}: "
                                "the same constraining legs, the others unconstrained)", 0,
                                r.check)
        else:
            rest.append(i)
    if rest:
        out.update(zip(rest, (mapper or serial_map)(verify_candidate, [task(i) for i in rest])))
    return [out[i] for i in batch], len(lead) + len(rest)


def task_catalog(catalog, cand):
    """The leg types of ``cand`` only, from ``catalog`` (a task carries no more than it
    needs to a Dask worker); None stays None (the packaged catalog)."""
    if catalog is None:
        return None
    from ..pm import Catalog
    names = dict.fromkeys(k.name for k in cand.legs)
    return Catalog({n: catalog.legs[n] for n in names}, [], {}, "<task>")


def monotonic_progress(progress):
    """``progress`` called only when ``done`` grows (the retries on a next geometry come
    after the first pass has counted their candidates)."""
    top = [-1]

    def call(done, total):
        if done > top[0]:
            top[0] = done
            progress(done, total)
    return call
