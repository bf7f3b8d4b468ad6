"""Samples per second of the inverse dynamics along a 10,000-sample path, beside the statics.

Run: python benchmarks/bench_dynamics.py [--samples N] [--repeat R]   (prints, asserts nothing)

For each PM, in the same run and on the same path:

* static: ``run_trajectory`` (the batched engine along the path: closures, rows,
  conditioning, statics under the external workload);
* dynamic: ``screwkit.dynamics`` (the same engine run, then per chunk the loop-closure
  velocity and acceleration equations, Newton-Euler of every leg link and of the platform,
  and the unified statics under the dynamic workload), with massive legs.

The issue's target: the dynamic rate within 3x of the static one (ratio <= 3).
"""

from __future__ import annotations

import argparse
import statistics
import sys
import time
from pathlib import Path

MASS = {"platform": {"mass": 40, "com": [0, 0, 2], "inertia": {"disc": {"radius": 30,
                                                                          "thickness": 3}}},
        "legs": {"cylinder": {"mass": 4, "length": 50, "radius": 4},
                 "piston": {"mass": 2, "length": 50, "radius": 2.5}}}

CASES = [
    ("3RRPRR", ["alpha=8*sin(2*pi*t)", "beta=6*sin(4*pi*t+0.5)", "Zo=80+10*sin(2*pi*t)"]),
    ("2SPS+2SPR", ["alpha=5*sin(2*pi*t)", "beta=4*sin(2*pi*t+1)", "gamma=3*t",
                   "Zo=70+10*t"]),
    ("3UPU", ["Xo=5*sin(2*pi*t)", "Yo=4*sin(2*pi*t+1)", "Zo=ZO+5*t"]),
    (str(Path(__file__).resolve().parents[1] / "tests" / "data" / "stewart_6sps.yaml"),
     ["Xo=3*sin(2*pi*t)", "Yo=2*sin(2*pi*t+1)", "Zo=70+5*t", "alpha=4*sin(2*pi*t)",
      "beta=3*sin(2*pi*t+2)", "gamma=5*t"]),
    # legs with parallelograms: the bars' Newton-Euler and the Pa's own twist rate
    (str(Path(__file__).resolve().parents[1] / "tests" / "data" / "delta_3rrpar.yaml"),
     ["Xo=20*sin(2*pi*t)", "Yo=15*cos(2*pi*t)-15", "Zo=-160+10*sin(4*pi*t)"]),
]


def _time(f, repeat):
    times, out = [], None
    for _ in range(repeat):
        t0 = time.perf_counter()
        out = f()
        times.append(time.perf_counter() - t0)
    return statistics.median(times), out


def main(argv=None):
    import numpy as np

    import screwkit
    from screwkit.dynamics import dynamics, motion_from_expressions
    from screwkit.paths import run_trajectory

    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--samples", type=int, default=10_000)
    ap.add_argument("--repeat", type=int, default=3)
    args = ap.parse_args(argv)
    print(f"python {sys.version.split()[0]}, numpy {np.__version__}; {args.samples} samples, "
          f"median of {args.repeat}")
    print(f"{'PM':<10} {'static /s':>11} {'dynamic /s':>11} {'ratio':>6}  (target <= 3)")
    for name, exprs in CASES:
        pm = screwkit.load_pm(name)
        z = repr(pm.default_pose.get("Zo", 0.0))
        motion = motion_from_expressions([e.replace("ZO", z) for e in exprs], pm.independent,
                                         samples=args.samples)
        ts, st = _time(lambda: run_trajectory(pm, motion.path), args.repeat)
        mass = None if pm.dynamics is not None else MASS
        td, dy = _time(lambda: dynamics(pm, motion, params=mass), args.repeat)
        assert st.ok.sum() == dy.ok.sum(), (st.counts(), dy.counts())
        print(f"{pm.name:<10} {args.samples / ts:11.0f} {args.samples / td:11.0f} "
              f"{td / ts:6.2f}  ({ts:.2f} s, {td:.2f} s; {dy.counts()['ok']} ok, "
              f"{int(dy.data['limit'].sum())} at the Euler limit)")


if __name__ == "__main__":
    main()
