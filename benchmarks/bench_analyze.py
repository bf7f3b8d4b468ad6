"""Cold-start time of `screwkit analyze` for the paper's two worked examples, and warm per-pose cost.

A cold start is a new interpreter that imports the package and runs the command, with the
modules' bytecode in place, as an installed package has it (pip compiles it at install
time).  With ``PYTHONDONTWRITEBYTECODE`` set (as on the development machines) an editable
checkout would compile every module on every start (~0.15 s), so the first, uncounted run
here writes the bytecode.  Target (issue "One engine"): ``screwkit analyze 3RRPRR`` <= 0.4 s.

Run: python benchmarks/bench_analyze.py   (prints its figures; asserts nothing)
"""

from __future__ import annotations

import os
import statistics
import subprocess
import sys
import time


def cold(argv, repeats=5):
    env = {k: v for k, v in os.environ.items() if k != "PYTHONDONTWRITEBYTECODE"}
    subprocess.run([sys.executable, "-m", "screwkit.cli", *argv], check=True, env=env,
                   stdout=subprocess.DEVNULL)            # writes the bytecode; not counted
    times = []
    for _ in range(repeats):
        t = time.perf_counter()
        subprocess.run([sys.executable, "-m", "screwkit.cli", *argv], check=True,
                       stdout=subprocess.DEVNULL)
        times.append(time.perf_counter() - t)
    return statistics.median(times), min(times), max(times)


def warm(name, n=200):
    import numpy as np
    import screwkit

    model = screwkit.load_pm(name)
    base = model.default_pose
    rng = np.random.default_rng(0)
    guess = None
    t = time.perf_counter()
    for _ in range(n):
        pose = {k: base[k] + (np.radians(rng.uniform(-2, 2)) if k in ("alpha", "beta", "gamma")
                              else rng.uniform(-2, 2)) for k in model.independent}
        res = screwkit.analyze(model, pose, guess=guess)
        guess = res.solution
    return (time.perf_counter() - t) / n


if __name__ == "__main__":
    print(f"python {sys.version.split()[0]}")
    for name in ("3RRPRR", "2SPS+2SPR"):
        med, lo, hi = cold(["analyze", name])
        print(f"screwkit analyze {name:<10} cold start: median {med:.3f} s (min {lo:.3f}, max {hi:.3f})")
    med, lo, hi = cold(["leg", "RRPRR"])
    print(f"screwkit leg RRPRR          cold start: median {med:.3f} s (min {lo:.3f}, max {hi:.3f})")
    for name in ("3RRPRR", "2SPS+2SPR"):
        print(f"analyze_pm({name!r}) warm, per pose (solve + mobility + J + statics): "
              f"{1e3 * warm(name):.2f} ms")
