"""Cold-start time of `screwkit analyze` for the paper's two worked examples, and warm per-pose cost.

Run: python benchmarks/bench_analyze.py   (prints its figures; asserts nothing)
"""

from __future__ import annotations

import statistics
import subprocess
import sys
import time


def cold(argv, repeats=5):
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
