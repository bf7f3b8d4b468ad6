"""Time of the type synthesis of PMs for each motion pattern (`screwkit synthesize`).

Beside each figure: the issue's target (one motion type in under 30 s on 2 cores), the
counts (candidates, screened out at home, engine verifications, verified), and a
reference measured in the same run: the time of one engine verification of a catalog
PM (load the 3-UPU, walk its verification path, mobility at 7 poses), so a loaded
machine shows as a slower reference too.  ``user`` is the process CPU time.

``passive``: listed PMs with a passive constraining leg.  With ``--workers N`` each motion is
also run with the engine verifications on a Dask LocalCluster of N processes (started once,
its start-up time printed apart), and the column ``dask s`` shows that time and ``same``
whether the listing equals the serial one.

Run: python benchmarks/bench_synthesis.py [--workers N] [MOTION ...]   (prints; asserts nothing)
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


def main(motions, workers=None) -> None:
    t = time.perf_counter()
    import screwkit.design as design
    from screwkit.synthesis import leg_pool, motion_pattern
    leg_pool(motion_pattern("3T"))                 # the leg pool is built once per process
    setup = time.perf_counter() - t
    ref = min(reference() for _ in range(3))
    print(f"setup (imports, leg pool): "
          f"{setup:.2f} s; reference: one engine verification of the catalog 3-UPU "
          f"{ref * 1e3:.0f} ms")
    mapper, stack = None, None
    if workers:
        from contextlib import ExitStack
        from functools import partial

        import distributed

        from screwkit.maps import run_tasks
        t = time.perf_counter()
        stack = ExitStack()
        cluster = stack.enter_context(distributed.LocalCluster(
            n_workers=workers, threads_per_worker=1, processes=True, host="127.0.0.1",
            dashboard_address=None))
        client = stack.enter_context(distributed.Client(cluster))
        mapper = partial(run_tasks, client)
        print(f"Dask LocalCluster of {workers} processes started in {time.perf_counter() - t:.2f} s")
    print(f"{'motion':<6} {'wall s':>7} {'user s':>7} {'target s':>8}  {'tried':>5} "
          f"{'screened':>8} {'engine':>6} {'verified':>8} {'passive':>7}  {'= refs':>7}"
          f"{'  dask s  same' if mapper else ''}  best")
    for m in motions:
        w, c = time.perf_counter(), time.process_time()
        res = design.synthesize_motion(m, passive=True)
        wall, user = time.perf_counter() - w, time.process_time() - c
        engine = res.tried - res.screened_out - res.pruned - res.not_verified
        best = res.listed[0].name if res.listed else "-"
        passive = sum(1 for p in res.listed if p.passive)
        extra = ""
        if mapper:
            w = time.perf_counter()
            other = design.synthesize_motion(m, passive=True, mapper=mapper)
            extra = (f"  {time.perf_counter() - w:>6.2f}  "
                     f"{'yes' if other.to_dict() == res.to_dict() else 'NO'}")
        print(f"{m:<6} {wall:>7.2f} {user:>7.2f} {TARGET_S:>8.0f}  {res.tried:>5} "
              f"{res.screened_out:>8} {engine:>6} {res.verified:>8} {passive:>7}  "
              f"{wall / ref:>7.0f}{extra}  {best}")
    if stack is not None:
        stack.close()


if __name__ == "__main__":
    args = sys.argv[1:]
    n = None
    if "--workers" in args:
        k = args.index("--workers")
        n = int(args[k + 1])
        del args[k:k + 2]
    main(args or ["3T", "1T2R", "3R", "3T1R", "2T3R", "1T3R", "2T2R", "2T1R"], n)
