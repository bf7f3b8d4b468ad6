"""Where the time of a path goes: ``screwkit.analyze(..., path=True)`` beside launches of the
same samples' rows without the path's machinery, in the same run.

``bench_engine.py``'s 100,000-sample 3RRPRR path (paper workload), each figure the best of
``--repeat`` rounds, the variants alternated round by round (the machines are noisy):

* ``path``: ``screwkit.analyze(pm, path, path=True)``, all of it;
* ``path's levels kernel``: the launches of its levels alone (``LevelLaunches.run``); the
  rest of ``path`` is Python and the anchors' small launches (the inputs' checks, the
  anchors, the results' arrays);
* ``closures from their solutions, levels' order``: one launch solving every sample from
  its own solution as warm start (so Newton stops at once), the samples in the order the
  levels solve them and their rows written where the levels write them: the solve's lanes,
  rows, conditioning and statics without the stencils, the checks and the levels' barriers;
* ``given unknowns, levels' order``: the same without the solve (frames at the given
  unknowns: ``X=``);
* ``given unknowns, in order``: the same in the path's order (rows written one after the
  other): the floor of any route through the engine's rows;
* ``closures alone, the path's levels``: the path's levels without the rows, conditioning
  and statics (``_path.solve_path`` by default): with ``given unknowns, in order``, the
  two parts a path's analysis adds up to.

Each figure is the whole call's, with the time of its kernel launches alone in a second
column: a variant's call also pays Python's copies of its inputs into the kernel's buffers,
for ``given unknowns, levels' order`` a fancy-indexed copy of every sample's unknowns into
its scattered row.

The levels' order is that of ``_path.solve_path`` (anchors every ``N / PATH_ANCHORS``
samples, then the middle of every gap between solved samples, level by level), formed here
from that rule.  Prints milliseconds and samples per second; ``--json`` for a record.
``--levels``: also the path with each level in a launch of its own (the launch's budget one
sample), each level's samples, wall and CPU time (best of ``--repeat`` per level; a launch's
start included, about half a millisecond).

Run: ``python benchmarks/path_breakdown.py [--n 100000] [--repeat 7] [--workers 2] [--levels]
[--json]``.
"""

from __future__ import annotations

import argparse
import json
import time

import numpy as np


def levels_order(N: int, anchors_every: int) -> np.ndarray:
    """The samples of a path of ``N`` in the order its levels solve them (the anchors, then
    each level's midpoints of the gaps between solved samples, in order)."""
    anchors = np.arange(0, N, anchors_every)
    if anchors[-1] != N - 1:
        anchors = np.append(anchors, N - 1)
    solved = np.zeros(N, bool)
    solved[anchors] = True
    order = [anchors]
    while True:
        idx = np.flatnonzero(solved)
        gaps = np.flatnonzero(np.diff(idx) > 1)
        if not gaps.size:
            break
        mid = (idx[gaps] + idx[gaps + 1]) // 2
        solved[mid] = True
        order.append(mid)
    return np.concatenate(order)


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--n", type=int, default=100_000)
    ap.add_argument("--repeat", type=int, default=7)
    ap.add_argument("--workers", type=int, default=2)
    ap.add_argument("--levels", action="store_true", help="also each level in a launch")
    ap.add_argument("--json", action="store_true")
    args = ap.parse_args(argv)
    for name, lo, hi in (("n", 64, 10_000_000), ("repeat", 1, 1000), ("workers", 1, 256)):
        if not lo <= getattr(args, name) <= hi:
            ap.error(f"--{name} must be within {lo}..{hi}")

    import screwkit
    from screwkit.engine import _launch as launch_module, _path_launch
    from screwkit.engine._chains import chains_of
    from screwkit.engine._path import solve_path
    from screwkit.engine._launch import output_buffers, run_poses
    from screwkit.engine._path import PATH_ANCHORS
    from screwkit.engine._solve import predictor_of

    n, w = args.n, args.workers
    pm = screwkit.load_pm("3RRPRR")
    s = np.linspace(0, 1, n)
    path = {"alpha": np.radians(10 * np.sin(2 * np.pi * s)),
            "beta": np.radians(8 * np.cos(2 * np.pi * s)), "Zo": 70 + 20 * s}
    F, T = np.array([-20.0, -30.0, -60.0]), np.array([-30.0, -30.0, 100.0])
    r = screwkit.analyze(pm, path, path=True, force=F, torque=T, workers=w)
    X = np.ascontiguousarray(r.solution.closures.X.T)
    ch = chains_of(pm)
    Z, P6 = predictor_of(ch), ch.full_params(path, n)
    order = levels_order(n, max(1, -(-n // PATH_ANCHORS)))
    P6o, Xo = np.ascontiguousarray(P6[order]), np.ascontiguousarray(X[order])
    buf = output_buffers(ch.flat, n)

    # the kernels timed inside the calls: every launch (the levels' and the others), and
    # the levels' launches of the whole path's calls
    kernel, launches = [], [0.0]
    run, launch = _path_launch.LevelLaunches.run, launch_module._launch

    def timed_run(self, *a, **k):
        t0 = time.perf_counter()
        try:
            return run(self, *a, **k)
        finally:
            t = time.perf_counter() - t0
            launches[0] += t
            if in_path:
                kernel[-1] += t

    def timed_launch(*a, **k):
        t0 = time.perf_counter()
        try:
            return launch(*a, **k)
        finally:
            launches[0] += time.perf_counter() - t0

    in_path = False

    def whole_path():
        nonlocal in_path
        kernel.append(0.0)
        in_path = True
        try:
            screwkit.analyze(pm, path, path=True, force=F, torque=T, workers=w)
        finally:
            in_path = False

    variants = {
        "path": whole_path,
        "closures from their solutions, levels' order":
            lambda: run_poses(ch.flat, Z, P6o, X0=Xo, F=F, T=T, workers=w, out=(buf, order)),
        "given unknowns, levels' order":
            lambda: run_poses(ch.flat, Z, P6o, X=Xo, F=F, T=T, workers=w, out=(buf, order)),
        "given unknowns, in order":
            lambda: run_poses(ch.flat, Z, P6, X=X, F=F, T=T, workers=w, out=(buf, 0)),
        "closures alone, the path's levels": lambda: solve_path(pm, path, workers=w),
    }
    times = {k: [] for k in variants}
    inside = {k: [] for k in variants}
    _path_launch.LevelLaunches.run = timed_run
    launch_module._launch = timed_launch
    try:
        for f in variants.values():             # (loaded and warm before the rounds)
            f()
        kernel.clear()
        for _ in range(args.repeat):
            for key, f in variants.items():
                launches[0] = 0.0
                t0 = time.perf_counter()
                f()
                times[key].append(time.perf_counter() - t0)
                inside[key].append(launches[0])
    finally:
        _path_launch.LevelLaunches.run = run
        launch_module._launch = launch
    levels = _per_level(lambda: screwkit.analyze(pm, path, path=True, force=F, torque=T,
                                                 workers=w), args.repeat) if args.levels else []
    best = {k: min(v) for k, v in times.items()}
    # (the launches' time of the round whose call was the best)
    best_in = {k: inside[k][int(np.argmin(times[k]))] for k in variants}
    i = int(np.argmin(times["path"]))
    rows = [("path", best["path"], best_in["path"]), ("path's levels kernel", kernel[i], None),
            ("the rest: Python, the anchors' launches", best["path"] - kernel[i], None)]
    rows += [(k, best[k], best_in[k]) for k in list(variants)[1:]]
    if args.json:
        print(json.dumps({"n": n, "workers": w, "repeat": args.repeat,
                          "seconds": {k: v for k, v, _ in rows},
                          "kernels_seconds": {k: v for k, _, v in rows if v is not None},
                          "levels": [dict(zip(("samples", "wall", "cpu"), x))
                                     for x in levels]}, indent=1))
        return
    print(f"3RRPRR, {n} path samples, paper workload, {w} threads, best of {args.repeat} "
          f"(variants alternated)")
    print(f"  {'':48s} {'whole call':>10s} {'':16s} {'its launches':>12s}")
    for key, t, k in rows:
        launched = "" if k is None else f"{k * 1e3:9.1f} ms"
        print(f"  {key:48s} {t * 1e3:7.1f} ms  {n / t / 1e3:7.0f}k samples/s {launched}")
    if levels:
        print("each level in a launch of its own (its start included):")
        for k, (g, wall, cpu) in enumerate(levels):
            print(f"  level {k:2d} {g:7d} samples {wall * 1e3:7.2f} ms, CPU {cpu * 1e3:7.2f} ms"
                  f"  {g / wall / 1e3:7.0f}k samples/s")
        print(f"  all levels {sum(x[1] for x in levels) * 1e3:.1f} ms")


def _per_level(analyze, repeat):
    """``[(samples, wall s, CPU s)]`` of each level of the path ``analyze()`` solves, each
    level in a launch of its own (a budget of one sample), the best of ``repeat`` runs."""
    from screwkit.engine import _path_launch
    run = _path_launch.LevelLaunches.run
    log = []

    def one_level(self, budget, workers=None):
        before = int(np.count_nonzero(self.solved))
        t0, c0 = time.perf_counter(), time.process_time()
        G = run(self, 1, workers)
        log.append((int(np.count_nonzero(self.solved)) - before, time.perf_counter() - t0,
                    time.process_time() - c0))
        return G

    _path_launch.LevelLaunches.run = one_level
    try:
        analyze()
        best = None
        for _ in range(repeat):
            log.clear()
            analyze()
            best = list(log) if best is None or len(best) != len(log) else \
                [min(a, b, key=lambda x: x[1]) for a, b in zip(best, log)]
    finally:
        _path_launch.LevelLaunches.run = run
    return best


if __name__ == "__main__":
    main()
