"""Time of the type synthesis of PMs for each motion pattern (`screwkit synthesize`).

Per pattern: the wall time on 2 local processes (the CLI's default) beside the issue's
target (one pattern in at most 2 minutes on 2 cores), the CPU time of this process and its
workers, the generated leg types, the candidates tried, screened out at home, sent to the
engine, verified and listed, and which of the textbook families were listed (and which
not).  A reference measured in the same run: one engine verification of a catalog PM
(load the 3-UPU, walk its verification path, mobility at 7 poses), so a loaded machine
shows as a slower reference too (``= refs``: the pattern's CPU time in references), and
``load`` is the machine's one-minute load average when the pattern ends (2 cores: above 2,
other work shares them).

With ``--workers N`` each motion runs on a Dask LocalCluster of N processes instead (for
wider searches: ``--wide``), and ``--serial`` runs in this process only.

Run: python benchmarks/bench_synthesis.py [--workers N | --serial] [--wide] [MOTION ...]
(prints; asserts nothing)
"""

from __future__ import annotations

import os
import resource
import sys
import time

TARGET_S = 120.0

#: The textbook families of each pattern (issue 19), by their literature names.
TEXTBOOK = {
    "3T": ("3-PRRR", "3-CRR", "3-UPU", "3-RRPaR"),
    "3R": ("3-RRR", "3-UPU"),
    "1T2R": ("3-RPS", "3-PRS", "3-UPS+UP/passive", "2-UPR+SPR"),
    "3T1R": ("4-UPU", "4-RUU", "4-RRPaR"),
    "2T1R": ("3-RRR", "3-PRR", "3-RPR"),
    "2T2R": (),
    "2T3R": (),
    "1T3R": (),
}


def reference() -> float:
    from screwkit.design import verify_model
    from screwkit.pm import load_pm
    from screwkit.synthesis import motion_pattern

    t = time.perf_counter()
    verify_model(load_pm("3UPU"), motion_pattern("3T"))
    return time.perf_counter() - t


def cpu() -> float:
    me = resource.getrusage(resource.RUSAGE_SELF)
    kids = resource.getrusage(resource.RUSAGE_CHILDREN)
    return me.ru_utime + me.ru_stime + kids.ru_utime + kids.ru_stime


def main(motions, workers=None, serial=False, wide=False) -> None:
    t = time.perf_counter()
    import screwkit.design as design
    from screwkit.cli._commands._common import process_mapper
    setup = time.perf_counter() - t
    ref = min(reference() for _ in range(3))
    print(f"setup (imports): {setup:.2f} s; reference: one engine verification of the "
          f"catalog 3-UPU {ref * 1e3:.0f} ms")
    mapper, stack = (None if serial else process_mapper(2)), None
    how = "serial" if serial else "2 local processes"
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
        how = f"a Dask LocalCluster of {workers} processes"
        print(f"Dask LocalCluster started in {time.perf_counter() - t:.2f} s")
    print(f"engine verifications on {how}{', wide enumeration' if wide else ''}")
    print(f"{'motion':<6} {'wall s':>7} {'cpu s':>7} {'target':>6}  {'gen':>4} {'tried':>6} "
          f"{'screen':>6} {'engine':>6} {'verif':>5} {'listed':>6} {'= refs':>7} {'load':>5}  "
          "textbook found / missing")
    for m in motions:
        w, c = time.perf_counter(), cpu()
        res = design.synthesize_motion(m, mapper=mapper, wide=wide)
        wall, used = time.perf_counter() - w, cpu() - c
        names = set(res.names())
        found = [n for n in TEXTBOOK.get(m, ()) if n in names]
        missing = [n for n in TEXTBOOK.get(m, ()) if n not in names]
        print(f"{m:<6} {wall:>7.1f} {used:>7.1f} {TARGET_S:>6.0f}  {res.generated:>4} "
              f"{res.tried:>6} {res.screened_out:>6} {res.engine_runs:>6} {res.verified:>5} "
              f"{len(res.listed):>6} {used / ref:>7.0f} {os.getloadavg()[0]:>5.1f}  "
              f"{', '.join(found) or '-'} / "
              f"{', '.join(missing) or '-'}")
        print(f"       first listed: {', '.join(dict.fromkeys(res.names()[:12]))}")
    if stack is not None:
        stack.close()


if __name__ == "__main__":
    args = sys.argv[1:]
    n = None
    if "--workers" in args:
        k = args.index("--workers")
        n = int(args[k + 1])
        del args[k:k + 2]
    serial = "--serial" in args
    wide = "--wide" in args
    args = [a for a in args if a not in ("--serial", "--wide")]
    main(args or ["3T", "1T2R", "3R", "3T1R", "2T3R", "1T3R", "2T2R", "2T1R"], n, serial, wide)
