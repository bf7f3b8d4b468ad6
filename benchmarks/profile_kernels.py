"""A workload of the engine's kernels for ``perf``, with the kernels' names (a perf map).

numba's compiled functions have no symbols ``perf`` can see: its samples in them show as
``[JIT]`` addresses.  This script runs one workload in a loop for some seconds, then writes
``/tmp/perf-<pid>.map`` (the address, size and name of every function numba has loaded in
this process: linux perf's map of JIT code), so that ``perf report`` names them::

    perf record -F 2000 -o perf.data python benchmarks/profile_kernels.py path 8
    perf report -i perf.data --stdio --sort sym

Workloads (3RRPRR, ``bench_engine.py``'s poses): ``path`` (the 100,000-sample path),
``random`` (100,000 random poses, closures from the home predictor), ``warm`` (1,000 calls
of ``screwkit.analyze`` at one pose warm-started from a neighbour), ``given`` (50,000
random poses' rows, conditioning and statics from their solved unknowns, on one thread),
``map`` (``screwkit.map`` of 100 x 100 x 100 cells, ``bench_engine.py --map``'s).  Each
function's size in the map runs to the next one's start: a function's samples are exact,
the last one's may take in code after it.  Functions LLVM inlined are part of their callers
(``_jit.borrowing_inlined``); ``_jit.borrowing`` ones are functions of their own, as a rule.
"""

from __future__ import annotations

import os
import sys
import time

import numpy as np


def write_perf_map() -> int:
    """Write ``/tmp/perf-<pid>.map`` of every function numba has loaded; returns how many."""
    from numba.core.registry import cpu_target
    engine = cpu_target.target_context.codegen()._engine
    names = {}
    for name in list(engine._defined_symbols):
        address = engine._ee.get_function_address(name)
        if address:
            names.setdefault(address, name)
    addresses = sorted(names)
    with open(f"/tmp/perf-{os.getpid()}.map", "w") as f:
        for a, b in zip(addresses, addresses[1:] + [addresses[-1] + 0x10000]):
            f.write(f"{a:x} {min(b - a, 0x400000):x} {names[a]}\n")
    return len(addresses)


def workload(kind: str):
    import screwkit
    from screwkit.engine._chains import chains_of
    from screwkit.engine._launch import run_poses
    from screwkit.engine._solve import predictor_of
    pm = screwkit.load_pm("3RRPRR")
    load = dict(force=np.array([-20.0, -30.0, -60.0]), torque=np.array([-30.0, -30.0, 100.0]))
    if kind == "path":
        s = np.linspace(0.0, 1.0, 100_000)
        pose = {"alpha": np.radians(10 * np.sin(2 * np.pi * s)),
                "beta": np.radians(8 * np.cos(2 * np.pi * s)), "Zo": 70 + 20 * s}
        return lambda: screwkit.analyze(pm, pose, path=True, **load)
    if kind == "map":
        grid = {"alpha": (-15.0, 15.0, 100), "beta": (-15.0, 15.0, 100), "Zo": (60.0, 100.0, 100)}
        return lambda: screwkit.map(pm, grid, degrees=True)
    if kind == "warm":
        one = {"alpha": np.radians(5.0), "beta": np.radians(-3.0), "Zo": 80.0}
        near = {"alpha": np.radians(5.1), "beta": np.radians(-3.0), "Zo": 80.2}
        prev = screwkit.analyze(pm, one, **load).solution
        return lambda: [screwkit.analyze(pm, near, guess=prev, **load) for _ in range(1000)]
    rng = np.random.default_rng(1)
    n = 100_000 if kind == "random" else 50_000
    pose = {"alpha": np.radians(rng.uniform(-10, 10, n)),
            "beta": np.radians(rng.uniform(-10, 10, n)), "Zo": rng.uniform(60, 100, n)}
    if kind == "random":
        return lambda: screwkit.analyze(pm, pose, **load)
    if kind != "given":
        raise SystemExit(f"unknown workload {kind!r}: path, random, given, warm or map")
    X = np.ascontiguousarray(screwkit.analyze(pm, pose).solution.closures.X.T)
    ch = chains_of(pm)
    Z, P6 = predictor_of(ch), ch.full_params(pose, n)
    return lambda: run_poses(ch.flat, Z, P6, X=X, F=load["force"], T=load["torque"],
                             workers=1)


def main(argv):
    kind = argv[1] if len(argv) > 1 else "path"
    seconds = float(argv[2]) if len(argv) > 2 else 8.0
    run = workload(kind)
    run()                                 # (loaded, or compiled, before the loop)
    t0, runs = time.perf_counter(), 0
    while time.perf_counter() - t0 < seconds:
        run()
        runs += 1
    wall = (time.perf_counter() - t0) / runs
    print(f"{kind}: {runs} runs, {wall * 1e3:.1f} ms a run; perf map of "
          f"{write_perf_map()} functions in /tmp/perf-{os.getpid()}.map")


if __name__ == "__main__":
    main(sys.argv)
