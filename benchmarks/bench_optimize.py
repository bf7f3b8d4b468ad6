"""The cost of one candidate of dimensional synthesis (``screwkit optimize``), beside the
plain engine analysis of the same cells in the same run.

A candidate is the 3RRPRR with another platform side ``l`` over a 1,000-cell task (alpha,
beta in +-10 deg and Zo in 60..100 cm on a 10 x 10 x 10 grid, the paper's load): the model
with those dimensions (``PMModel.with_dimensions``: no file read or parsed), one batched
analysis of the cells and every objective as ``screwkit size`` counts them
(``screwkit.design.evaluate``).  Printed, each the median of ``--repeat`` candidates (each
a new ``l``, as in a search):

* ``analyze (reference)``: ``screwkit.analyze`` of the same cells on one cached model, the
  engine's per-pose cost alone;
* ``model``: ``with_dimensions`` (geometry, home assembly, legs by their rules);
* ``candidate``: the whole evaluation (model, the engine's per-model set-up, analysis,
  objectives), and ``candidate + indices`` with the transmission indices (``min-lti``);
* ``per-model set-up``: ``candidate - reference - model - objectives`` (the row templates
  and start model the engine derives once per model object).

Target (issue "Design a PM"): one candidate on a 1,000-cell task <= 20 ms once the
compiled core exists, with no recompilation or model re-parsing per candidate.

Run: ``python benchmarks/bench_optimize.py [--repeat 7]``.
"""

from __future__ import annotations

import argparse
import time

import numpy as np


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--repeat", type=int, default=7)
    args = ap.parse_args()
    import screwkit
    from screwkit.design import evaluate, problem
    from screwkit.engine import PAPER_FORCE, PAPER_TORQUE, analyze

    base = screwkit.load_pm("3RRPRR")
    grid = {"alpha": (-10, 10, 10), "beta": (-10, 10, 10), "Zo": (60, 100, 10)}
    loads = [("paper", np.array(PAPER_FORCE), np.array(PAPER_TORQUE))]
    prob = problem(base, {"l": (30, 120)}, grid, degrees=True, loads=loads)
    prob_lti = problem(base, {"l": (30, 120)}, grid, degrees=True, loads=loads,
                       objectives=("min-lti",))
    poses = prob.task.poses
    analyze(base, poses, raise_on_singular=False)             # warm: imports, caches
    evaluate(base, {"l": 61.0}, prob.task)
    ls = np.linspace(45.0, 105.0, args.repeat)
    t = {"reference": [], "model": [], "candidate": [], "indices": []}
    for k, l in enumerate(ls):
        t0 = time.perf_counter()
        res = analyze(base, poses, raise_on_singular=False)
        res.ok
        t["reference"].append(time.perf_counter() - t0)
        t0 = time.perf_counter()
        base.with_dimensions({"l": float(l)})
        t["model"].append(time.perf_counter() - t0)
        t0 = time.perf_counter()
        r = evaluate(base, {"l": float(l) + 0.25}, prob.task)
        t["candidate"].append(time.perf_counter() - t0)
        t0 = time.perf_counter()
        evaluate(base, {"l": float(l) + 0.5}, prob_lti.task)
        t["indices"].append(time.perf_counter() - t0)
    med = {k: 1e3 * float(np.median(v)) for k, v in t.items()}
    cells = prob.task.cells
    print(f"3RRPRR, {cells} cells, median of {args.repeat} candidates (ms); last candidate "
          f"feasible: {r['feasible']}")
    print(f"  {'case':<28} {'ms':>8}")
    print(f"  {'analyze (reference)':<28} {med['reference']:8.1f}")
    print(f"  {'model (with_dimensions)':<28} {med['model']:8.1f}")
    print(f"  {'candidate':<28} {med['candidate']:8.1f}   target <= 20 ms (compiled core)")
    print(f"  {'candidate + indices':<28} {med['indices']:8.1f}")
    print(f"  {'per-model set-up (rest)':<28} "
          f"{med['candidate'] - med['reference'] - med['model']:8.1f}")
    print(f"  search cost at this rate: {med['candidate'] * 10 * 41 / 1e3:.1f} s for one varied "
          "dimension (population 10, 40 generations)")


if __name__ == "__main__":
    main()
