"""Time of the type synthesis of PMs for each motion pattern (`screwkit synthesize`).

Beside each figure: the issue's target (one motion type in under 30 s on 2 cores), the
counts (candidates, screened out at home, engine verifications, verified), and a
reference measured in the same run: the time of one engine verification of a catalog
PM (load the 3-UPU, walk its verification path, mobility at 7 poses), so a loaded
machine shows as a slower reference too.  ``user`` is the process CPU time.

Run: python benchmarks/bench_synthesis.py [MOTION ...]   (prints; asserts nothing)
"""

from __future__ import annotations

import sys
import time

TARGET_S = 30.0


def reference() -> float:
    from screwkit.design import verify_model
    from screwkit.pm import load_pm
    from screwkit.synthesis import motion_pattern

    t = time.perf_counter()
    verify_model(load_pm("3UPU"), motion_pattern("3T"))
    return time.perf_counter() - t


def main(motions) -> None:
    t = time.perf_counter()
    import screwkit.design as design
    from screwkit.synthesis import leg_pool, motion_pattern
    leg_pool(motion_pattern("3T"))                 # the leg pool is built once per process
    setup = time.perf_counter() - t
    ref = min(reference() for _ in range(3))
    print(f"setup (imports, leg pool): "
          f"{setup:.2f} s; reference: one engine verification of the catalog 3-UPU "
          f"{ref * 1e3:.0f} ms")
    print(f"{'motion':<6} {'wall s':>7} {'user s':>7} {'target s':>8}  {'tried':>5} "
          f"{'screened':>8} {'engine':>6} {'verified':>8}  {'= refs':>7}  best")
    for m in motions:
        w, c = time.perf_counter(), time.process_time()
        res = design.synthesize_motion(m)
        wall, user = time.perf_counter() - w, time.process_time() - c
        engine = res.tried - res.screened_out - res.pruned - res.not_verified
        best = res.listed[0].name if res.listed else "-"
        print(f"{m:<6} {wall:>7.2f} {user:>7.2f} {TARGET_S:>8.0f}  {res.tried:>5} "
              f"{res.screened_out:>8} {engine:>6} {res.verified:>8}  {wall / ref:>7.0f}  {best}")


if __name__ == "__main__":
    main(sys.argv[1:] or ["3T", "1T2R", "3R", "3T1R", "2T3R", "1T3R", "2T2R"])
