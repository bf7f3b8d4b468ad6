"""Samples per second of a 10,000-sample 3RRPRR trajectory (statics at every sample).

Run: python benchmarks/bench_trajectory.py [--samples N] [--full]   (prints figures, asserts nothing)

Three ways of computing the same table with the one engine (tests/test_trajectory.py checks
they agree):

* ``analyze_pm`` per sample, warm-started from the previous pose (one pose at a time, with
  the mobility of each pose);
* ``run_trajectory(vectorised=False)``: one pose at a time, each warm-started from the
  previous sample, without the mobility;
* ``run_trajectory()``: the batched engine along the path (about 64 anchors solved in
  order, the other samples level by level from their neighbours, then rows, conditioning
  and statics of all samples in chunks).

The two per-pose variants are timed on the first 300 samples (all of them with --full) and
their rate is extrapolated.
"""

from __future__ import annotations

import argparse
import statistics
import sys
import time

PATH = ["alpha=8*sin(2*pi*t)", "beta=6*sin(4*pi*t+0.5)", "Zo=80+10*sin(2*pi*t)"]


def main(argv=None):
    import numpy as np

    import screwkit
    from screwkit.paths import PathSpec, path_from_expressions
    from screwkit.engine import analyze_pm
    from screwkit.paths import run_trajectory

    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--samples", type=int, default=10_000)
    ap.add_argument("--full", action="store_true", help="time the per-pose variants on every sample")
    args = ap.parse_args(argv)

    print(f"python {sys.version.split()[0]}, numpy {np.__version__}")
    model = screwkit.load_pm("3RRPRR")
    path = path_from_expressions(PATH, model.independent, samples=args.samples)
    print(f"3RRPRR, {args.samples} samples of {'; '.join(PATH)} (deg, cm), paper workload")

    times = []
    for _ in range(3):
        t0 = time.perf_counter()
        res = run_trajectory(model, path)
        times.append(time.perf_counter() - t0)
    med = statistics.median(times)
    print(f"run_trajectory (vectorised):       {args.samples / med:9.0f} samples/s "
          f"({med:.2f} s; min {min(times):.2f} s; {res.counts()}; {res.diagnostics})")

    n = args.samples if args.full else min(300, args.samples)
    sub = PathSpec(path.t[:n], {k: v[:n] for k, v in path.values.items()})
    t0 = time.perf_counter()
    run_trajectory(model, sub, vectorised=False)
    dt = time.perf_counter() - t0
    print(f"run_trajectory (vectorised=False): {n / dt:9.0f} samples/s (on {n} samples)")

    t0 = time.perf_counter()
    guess = None
    for i in range(n):
        a = analyze_pm(model, sub.sample(i), guess=guess)
        guess = a.solution
    dt = time.perf_counter() - t0
    print(f"analyze_pm loop, warm-started:     {n / dt:9.0f} samples/s (on {n} samples; "
          f"{args.samples * dt / n:.0f} s for {args.samples})")


if __name__ == "__main__":
    main()
