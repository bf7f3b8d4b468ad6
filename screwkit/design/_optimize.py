"""Dimensional synthesis: the dimensions of a PM that are best over a task (``screwkit
optimize``; ``docs/design.md``).

One objective: scipy's differential evolution (seeded, the population evaluated a
generation at a time, the task's feasibility as a constraint handled by Lampinen's
feasibility rules), then a bounded Nelder-Mead polish from its best; the best design is
the best feasible candidate evaluated.  Several objectives: pymoo's NSGA-II (an optional
dependency, ``pip install 'screwkit[optimize]'``) and the Pareto front of every feasible
candidate evaluated.  Every candidate is :func:`~screwkit.design._evaluate.evaluate`: the
model with those dimensions (:meth:`~screwkit.pm.PMModel.with_dimensions`), one batched
analysis of the task's cells, the objectives as ``screwkit size`` counts them.  Candidates
are evaluated serially or on a Dask cluster (the same function on the same inputs: the
result is the same), and cached by their dimensions.
"""

from __future__ import annotations

import numpy as np

from ..errors import InputError
from ._evaluate import OBJECTIVES, evaluate
from ._result import OptimizationResult, pareto

__all__ = ["optimize", "Evaluator", "MAX_EVALUATIONS", "MAX_GENERATIONS", "MAX_POPSIZE"]

#: Bounds on the work of one optimisation.
MAX_GENERATIONS = 10_000
MAX_POPSIZE = 200
MAX_EVALUATIONS = 1_000_000
_BIG = 1e300


class Evaluator:
    """The candidates evaluated so far, cached by their dimensions, in batches (one per
    generation); ``mapper(dims_list) -> results`` runs a batch elsewhere (Dask)."""

    def __init__(self, prob, mapper=None, first=0):
        self.prob, self.mapper, self.first = prob, mapper, first
        self.cache, self.order, self.batches, self.pending = {}, [], [], []

    def mark(self) -> None:
        """Close a generation: the candidates evaluated since the last mark."""
        self.batches.append(self.pending)
        self.pending = []

    def batch(self, X) -> list:
        X = np.atleast_2d(np.asarray(X, float))
        keys = [tuple(float(v) for v in x) for x in X]
        todo = [k for k in dict.fromkeys(keys) if k not in self.cache]
        if todo:
            dims = [self.prob.dims(k) for k in todo]
            got = (self.mapper(dims) if self.mapper is not None else
                   [evaluate(self.prob.base, d, self.prob.task) for d in dims])
            for k, r in zip(todo, got):
                r = dict(r, violation=self._violation(r))
                r["feasible"] = r["violation"] == 0.0
                self.cache[k] = r
                self.order.append(k)
            self.pending += todo
            if not self.batches and self.first and len(self.pending) >= self.first:
                self.mark()                         # generation 0: the initial population
        return [self.cache[k] for k in keys]

    def _violation(self, r) -> float:
        v = float(r["violation"])
        for name, op, bound in self.prob.constraints:
            x = r["objectives"][name]
            if not np.isfinite(x):
                v += 1.0
                continue
            excess = (x - bound) if op == "<=" else (bound - x)
            v += max(0.0, excess) / max(abs(bound), 1e-12)
        return v

    def energy(self, r, k: int = 0) -> float:
        """The minimised value of objective ``k`` (maximised ones negated; NaN -> huge)."""
        name = self.prob.objectives[k]
        x = r["objectives"][name]
        if not np.isfinite(x):
            return _BIG
        return x if OBJECTIVES[name].sense == "min" else -x

    def feasible(self) -> list:
        return [(k, self.cache[k]) for k in self.order if self.cache[k]["feasible"]]


def _history(ev, k: int = 0) -> list:
    """Per generation: the best feasible value so far and the generation's median."""
    out, best = [], None
    name = ev.prob.objectives[k]
    sign = 1.0 if OBJECTIVES[name].sense == "min" else -1.0
    for g, keys in enumerate(ev.batches):
        vals = [ev.cache[key]["objectives"][name] for key in keys if ev.cache[key]["feasible"]]
        vals = [v for v in vals if np.isfinite(v)]
        if vals:
            b = min(vals, key=lambda v: sign * v)
            best = b if best is None or sign * b < sign * best else best
        out.append({"generation": g, "best": best, "median": float(np.median(vals))
                    if vals else None, "feasible": len(vals), "evaluated": len(keys)})
    return out


def _single(prob, ev, maxiter, popsize, seed, polish, progress):
    from scipy.optimize import NonlinearConstraint, differential_evolution, minimize
    n = len(prob.vary)

    def energies(X):                                # X (n, S): vectorised
        return np.array([ev.energy(r) for r in ev.batch(np.reshape(X, (n, -1)).T)])

    def violations(X):
        return np.array([[r["violation"] for r in ev.batch(np.reshape(X, (n, -1)).T)]])

    gen = [0]

    def callback(*_):
        ev.mark()
        gen[0] += 1
        if progress:
            progress(min(gen[0] + 1, maxiter + 1), maxiter + 1)
    if progress:
        progress(0, maxiter + 1)
    bounds = list(zip(prob.lower, prob.upper))
    ev.first = popsize * n
    differential_evolution(energies, bounds, maxiter=maxiter, popsize=popsize, tol=1e-4,
                           rng=seed, polish=False, updating="deferred", vectorized=True,
                           constraints=NonlinearConstraint(violations, -np.inf, 0.0),
                           callback=callback)
    if progress:
        progress(maxiter + 1, maxiter + 1)
    if ev.pending:
        ev.mark()
    feas = ev.feasible()
    if polish and feas:
        lo, span = prob.lower, prob.upper - prob.lower
        k0 = min(feas, key=lambda kr: ev.energy(kr[1]))[0]
        u0 = (np.array(k0) - lo) / span

        def f(u):
            r = ev.batch((lo + np.clip(u, 0, 1) * span)[None])[0]
            return ev.energy(r) if r["feasible"] else np.inf
        e0 = f(u0)
        minimize(f, u0, method="Nelder-Mead", bounds=[(0.0, 1.0)] * n,
                 options={"xatol": 1e-6, "fatol": 1e-9 * max(abs(e0), 1e-300),
                          "maxfev": 60 * n, "initial_simplex": _simplex(u0)})
        ev.mark()                                   # the polish: the last "generation"
    feas = ev.feasible()
    best = min(feas, key=lambda kr: ev.energy(kr[1])) if feas else None
    return best, []


def _simplex(u0):
    """A small initial simplex (5% of each range) that stays in [0, 1]."""
    n = len(u0)
    S = np.tile(u0, (n + 1, 1))
    for i in range(n):
        step = 0.05 if u0[i] + 0.05 <= 1 else -0.05
        S[i + 1, i] += step
    return S


def _several(prob, ev, maxiter, popsize, seed, progress):
    try:
        from pymoo.algorithms.moo.nsga2 import NSGA2
        from pymoo.core.callback import Callback
        from pymoo.core.problem import Problem
        from pymoo.optimize import minimize
    except ImportError:
        raise InputError("several objectives need pymoo (pip install 'screwkit[optimize]')") \
            from None
    m = len(prob.objectives)

    class _P(Problem):
        def __init__(self):
            super().__init__(n_var=len(prob.vary), n_obj=m, n_ieq_constr=1, xl=prob.lower,
                             xu=prob.upper)

        def _evaluate(self, X, out, *args, **kwargs):
            rs = ev.batch(X)
            out["F"] = np.array([[ev.energy(r, k) for k in range(m)] for r in rs])
            out["G"] = np.array([[r["violation"]] for r in rs])

    class _Progress(Callback):
        def notify(self, algorithm):
            ev.mark()
            if progress:
                progress(min(algorithm.n_gen, maxiter), maxiter)
    size = max(4, popsize * len(prob.vary))
    minimize(_P(), NSGA2(pop_size=size), ("n_gen", maxiter), seed=seed, verbose=False,
             callback=_Progress())
    feas = ev.feasible()
    if not feas:
        return None, []
    F = np.array([[ev.energy(r, k) for k in range(m)] for _, r in feas])
    front = [feas[i] for i in pareto(F)]
    front.sort(key=lambda kr: ev.energy(kr[1], 0))
    return front[0], front


def _check_budget(maxiter, popsize, n, several):
    for name, v, hi in (("maxiter", maxiter, MAX_GENERATIONS), ("popsize", popsize, MAX_POPSIZE)):
        if isinstance(v, bool) or not isinstance(v, (int, np.integer)) or not 1 <= v <= hi:
            raise InputError(f"{name} must be an integer from 1 to {hi}, got {v!r:.40}")
    if popsize < 2 and not several:
        raise InputError("popsize must be at least 2 for differential evolution")
    total = popsize * n * (maxiter + 1)
    if total > MAX_EVALUATIONS:
        raise InputError(f"popsize x varied dimensions x (maxiter + 1) = {total} evaluations, "
                         f"more than {MAX_EVALUATIONS}")


def optimize(pm, vary, grid, fix=None, *, samples=None, seed: int = 0, degrees: bool = False,
             force=None, torque=None, workloads=None, objective="max-actuator-force",
             constraints=(), max_level: str = "near-singular", lti_threshold: float = 0.7,
             maxiter: int = 40, popsize: int = 10, polish: bool = True, cluster=None,
             scheduler=None, progress=None, overrides=None) -> OptimizationResult:
    """The dimensions of ``pm`` in the bounds ``vary`` that are best over a task.

    Parameters
    ----------
    pm : PMModel or str
        A model loaded with :func:`screwkit.load_pm` (a catalog PM, a model file, a
        synthesized PM written by ``screwkit synthesize --write``), or its name or path.
    vary : mapping str -> (low, high)
        The varied dimensions and their bounds (model lengths).
    grid, fix, samples, seed, degrees
        The task's cells, as :func:`screwkit.size` takes them (``seed`` also seeds the
        optimiser: the same seed gives the same result).
    force, torque, workloads
        The workloads, as :func:`screwkit.size` (default: the model's declared workload;
        an :class:`InputError` when it declares none).
    objective : str or sequence of str
        One or several of :data:`~screwkit.design._evaluate.OBJECTIVES`.
    constraints : sequence of str
        Bounds on other objectives, ``"stroke<=40"``, ``"min-lti>=0.6"``.
    max_level : str
        The worst trust level of a cell (``ok``, ``ill-conditioned``, ``near-singular``):
        the whole task must be reachable, within the limits and of this level or better.
    lti_threshold : float
        The LTI bound of ``gtw-volume``.
    maxiter, popsize : int
        Generations, and the population per varied dimension.
    polish : bool
        One objective: polish the best of the differential evolution by Nelder-Mead.
    cluster, scheduler
        Evaluate the candidates on Dask (as :func:`screwkit.map`).
    progress : callable(done, total), optional
        Called per generation.
    overrides : mapping, optional
        Dimensions of ``pm`` (given by name) other than the model file's.
    """
    from ..maps._map import resolve_model, workload
    from ..maps._sizing import workload_list
    from ._problem import problem
    base = resolve_model(pm, overrides)
    if workloads is not None and (force is not None or torque is not None):
        raise InputError("give the workloads or force/torque, not both")
    if workloads is None:                  # given (one alone: the other zero), else declared
        F, T, source = workload(base, force, torque)
        loads = [(source, F, T)]
    else:
        loads = workload_list(base, workloads)
    objectives = (objective,) if isinstance(objective, str) else tuple(objective)
    prob = problem(base, vary, grid, fix, samples=samples, seed=seed, degrees=degrees,
                   loads=loads, objectives=objectives, constraints=constraints,
                   max_level=max_level, lti_threshold=lti_threshold)
    several = len(prob.objectives) > 1
    _check_budget(maxiter, popsize, len(prob.vary), several)
    if isinstance(seed, bool) or not isinstance(seed, (int, np.integer)) or seed < 0:
        raise InputError(f"seed must be a non-negative integer, got {seed!r:.40}")
    from ..maps._map import _cluster
    cl = _cluster(cluster, scheduler)
    # each candidate is a batch of the task's cells and a fit of its predictor, run in
    # blocks by the parallel kernel (on one thread for fewer than 512 poses) once it is
    # loaded: loaded here (on a first run compiled once, before any cluster's workers)
    from ..engine._run import load_block_kernel
    load_block_kernel(base)
    if cl is None:
        return _run(prob, Evaluator(prob), several, maxiter, popsize, seed, polish, progress)
    from ..maps import client_for
    with client_for(cl) as client:
        b, t = client.scatter([prob.base, prob.task], broadcast=True)

        def mapper(dims):
            futs = client.map(evaluate, [b] * len(dims), dims, [t] * len(dims), pure=False)
            return client.gather(futs)
        return _run(prob, Evaluator(prob, mapper), several, maxiter, popsize, seed, polish,
                    progress)


def _run(prob, ev, several, maxiter, popsize, seed, polish, progress):
    if several:
        best, front = _several(prob, ev, maxiter, popsize, int(seed), progress)
        method = "NSGA-II (pymoo)"
    else:
        best, front = _single(prob, ev, maxiter, popsize, int(seed), polish, progress)
        method = "differential evolution (scipy)" + (" + Nelder-Mead polish" if polish else "")
    return OptimizationResult.build(prob, ev, best, front, method, int(seed),
                                    _history(ev))
