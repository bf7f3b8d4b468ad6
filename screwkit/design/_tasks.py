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

__all__ = ["VerifyTask", "TaskResult", "monotonic_progress", "run_round", "serial_map",
           "task_catalog", "verify_candidate"]


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
    """

    geometry: int | None
    definition: dict | None
    verdict: Verdict | None
    reason: str
    engine_runs: int


def verify_candidate(task: VerifyTask) -> TaskResult:
    """Load the candidate on each of its geometries and verify it with the engine
    (:func:`~screwkit.design.verify_model`) until one succeeds."""
    m = motion_pattern(task.motion)
    reason, runs = "", 0
    for g, d in task.definitions:
        runs += 1
        model, exc = load_candidate(task.name, synthesis_catalog(task.catalog, {task.name: d}))
        if model is None:
            reason = reason or f"cannot be assembled: {exc}"
            continue
        verdict = verify_model(model, m, task.passive)
        if verdict.success:
            return TaskResult(g, d, verdict, "", runs)
        reason = verdict.reason
    return TaskResult(None, None, None, reason, runs)


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
        batch = todo[:budget - spent]
        tasks = [VerifyTask(comps[i].name, m.name, comps[i].passive, (screened[i][step],),
                            task_catalog(catalog, comps[i])) for i in batch]
        prog = None
        if progress is not None and step == 0:
            prog = lambda d, _t: progress(base + d, total)         # noqa: E731
        results = (mapper or serial_map)(verify_candidate, tasks, prog)
        spent += len(batch)
        step += 1
        nxt = []
        for i, r in zip(batch, results):
            outcome[i] = r
            if r.geometry is None and step < len(screened[i]):
                nxt.append(i)                      # failed here: try its next geometry
            else:
                settled += 1
        for i in todo[len(batch):]:
            outcome.pop(i, None)                   # beyond the budget: not verified
        todo = nxt
        if progress is not None:
            progress(base + settled, total)
    for i in todo:
        outcome.pop(i, None)
    if progress is not None:
        progress(start + len(order), total)
    return spent


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
