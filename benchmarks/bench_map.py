"""Throughput and memory of ``screwkit.map`` on the 3RRPRR, serial and on 2 local Dask workers.

Prints, side by side in one run (the machines are noisy):

* ``analyze (reference)``: one plain ``screwkit.analyze`` call on ``--n`` random poses of
  the same box (the engine alone, no map);
* ``map serial``: ``screwkit.map`` over a 100 x 100 x 100 grid (``--n`` cells: alpha and
  beta in +-15 deg, Zo in 60..100 cm), blocks of 65,536 cells, 2 threads per block;
* ``map dask 2 workers``: the same map on a LocalCluster of 2 worker processes (loopback,
  one thread each, the Dask settings of ``screwkit map --workers``; the cluster's start is
  timed apart) and a check that it equals the serial
  map bit for bit;
* ``cli map --out .nc``: ``screwkit map`` on the same grid as a fresh process writing a
  NetCDF file and the JSON summary (``--cli``);

each with cells per second and the peak resident memory of the process that ran it (the
Dask workers' own peak is reported by the workers); ``map serial`` also with its time split
into the engine's analysis of its blocks (``screwkit.analyze``: closures, rows,
statics) and the rest (indices, quality, the Dataset, the loci), and into the kernel
launches (all of them, wall) and the CPU time of the main thread outside them (the Python
and numpy around the kernels, per cell).  Targets (issue 11):
1,000,000 cells in <= 20 s serial on 2 cores, peak memory under 2 GB; (issue 23) <= 3 s
serial.  ``--reference DIR`` runs every case also with another checkout of screwkit
(``PYTHONPATH=DIR``, e.g. main's), alternating with this one, best of ``--repeat``; each
line gives the load average when it ran.

Run: ``python benchmarks/bench_map.py [--n 1000000] [--no-dask] [--cli] [--reference DIR]
[--repeat 1]``.
"""

from __future__ import annotations

import argparse
import resource
import subprocess
import sys
import time


def _peak_mb() -> float:
    return resource.getrusage(resource.RUSAGE_SELF).ru_maxrss / 1024.0


def _run(mode: str, n: int) -> None:
    """One case in this (fresh) process: prints 'seconds peak_MB [extra]'."""
    import numpy as np

    import screwkit
    side = max(2, round(n ** (1 / 3)))
    grid = {"alpha": (-15.0, 15.0, side), "beta": (-15.0, 15.0, side), "Zo": (60.0, 100.0, side)}
    pm = screwkit.load_pm("3RRPRR")
    screwkit.analyze(pm, {"alpha": np.zeros(8), "beta": np.zeros(8), "Zo": np.full(8, 80.0)})
    if mode == "analyze":
        rng = np.random.default_rng(0)
        N = side ** 3
        pose = {"alpha": np.radians(rng.uniform(-15, 15, N)),
                "beta": np.radians(rng.uniform(-15, 15, N)), "Zo": rng.uniform(60, 100, N)}
        t = time.perf_counter()
        res = screwkit.analyze(pm, pose)
        dt = time.perf_counter() - t
        print(dt, _peak_mb(), N, int(res.ok.sum()))
        return
    if mode == "serial":
        from screwkit.maps import _compute
        engine = [0.0]
        analyze = _compute.analyze

        def timed(*args, **kw):                   # the engine's analysis of each block
            t = time.perf_counter()
            try:
                return analyze(*args, **kw)
            finally:
                engine[0] += time.perf_counter() - t

        _compute.analyze = timed
        # every kernel launch (the analysis, the indices, the statics' extras): their wall
        # time, and this thread's CPU time outside them (the Python and numpy around the
        # kernels, which the load of other processes does not inflate)
        from screwkit.engine import _launch
        launches, inside_cpu = [0.0], [0.0]
        launch = _launch._launch

        def timed_launch(*args, **kw):
            t, c = time.perf_counter(), time.thread_time()
            try:
                return launch(*args, **kw)
            finally:
                launches[0] += time.perf_counter() - t
                inside_cpu[0] += time.thread_time() - c

        _launch._launch = timed_launch
        t, c = time.perf_counter(), time.thread_time()
        ds = screwkit.map(pm, grid, degrees=True)
        dt, cpu = time.perf_counter() - t, time.thread_time() - c
        ds.to_netcdf("/tmp/bench_map_serial.nc", engine="scipy")
        print(dt, _peak_mb(), ds["ok"].size, int(ds["ok"].sum()), engine[0], launches[0],
              cpu - inside_cpu[0])
        return
    import dask
    import distributed

    from screwkit.maps._dask import LOCAL_CONFIG
    dask.config.set(LOCAL_CONFIG)                # the settings of screwkit's local clusters
    t0 = time.perf_counter()
    with distributed.LocalCluster(n_workers=2, threads_per_worker=1, processes=True,
                                  host="127.0.0.1", dashboard_address=None) as cl, \
            distributed.Client(cl) as client:
        start = time.perf_counter() - t0
        t = time.perf_counter()
        ds = screwkit.map(pm, grid, degrees=True, cluster=client)
        dt = time.perf_counter() - t
        worker_mb = client.run(lambda: resource.getrusage(resource.RUSAGE_SELF).ru_maxrss / 1024)
    import xarray as xr
    ref = xr.open_dataset("/tmp/bench_map_serial.nc").load()
    same = all(np.array_equal(ref[k].values, ds[k].values, equal_nan=True)
               for k in ds.data_vars)
    print(dt, _peak_mb(), ds["ok"].size, int(ds["ok"].sum()), start,
          max(worker_mb.values()), same)


def _case(case, n, tree):
    """``(seconds, peak MB, cells, note)`` of one case in a fresh process (``tree``: the
    checkout on PYTHONPATH; None: this one)."""
    import os
    env = dict(os.environ, **({"PYTHONPATH": tree} if tree else {}))
    if case == "cli":
        side = max(2, round(n ** (1 / 3)))
        cmd = [sys.executable, "-m", "screwkit", "map", "3RRPRR", "-q", "--json",
               "--out", "/tmp/bench_map_cli.nc"] + \
            [f"--grid={p}={lo}:{hi}:{side}" for p, lo, hi in
             (("alpha", -15, 15), ("beta", -15, 15), ("Zo", 60, 100))]
        t = time.perf_counter()
        pid = subprocess.Popen(cmd, env=env, stdout=subprocess.DEVNULL,
                               stderr=subprocess.DEVNULL).pid
        _, status, usage = os.wait4(pid, 0)
        dt = time.perf_counter() - t
        if status:
            raise SystemExit(f"screwkit map failed ({status})")
        return dt, usage.ru_maxrss / 1024, side ** 3, "fresh process, --out .nc --json"
    out = subprocess.run([sys.executable, __file__, "--n", str(n), "--_case", case], env=env,
                         capture_output=True, text=True, check=True).stdout.split()
    dt, mb, cells = float(out[0]), float(out[1]), int(out[2])
    note = f"{out[3]} ok"
    if case == "serial":
        note += (f"; engine.analyze of the blocks {float(out[4]):.2f} s, the rest of the map "
                 f"{dt - float(out[4]):.2f} s; the kernel launches {float(out[5]):.2f} s, "
                 f"outside them {float(out[6]) / cells * 1e6:.2f} us of CPU a cell")
    if case == "dask":
        note += (f"; cluster start {float(out[4]):.1f} s; worker peak {float(out[5]):.0f} MB;"
                 f" equal to serial bit for bit: {out[6]}")
    return dt, mb, cells, note


def main(argv=None) -> int:
    import os
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--n", type=int, default=1_000_000, help="cells (a cube grid)")
    ap.add_argument("--no-dask", action="store_true")
    ap.add_argument("--cli", action="store_true", help="also time the command line")
    ap.add_argument("--reference", metavar="DIR",
                    help="another checkout of screwkit, timed beside this one")
    ap.add_argument("--repeat", type=int, default=1, help="best of this many runs per case")
    ap.add_argument("--_case", help=argparse.SUPPRESS)
    a = ap.parse_args(argv)
    if a._case:
        _run(a._case, a.n)
        return 0
    cases = ["analyze", "serial"] + ([] if a.no_dask else ["dask"]) + (["cli"] if a.cli else [])
    trees = [("this", None)] + ([("reference", a.reference)] if a.reference else [])
    print(f"screwkit.map, 3RRPRR, about {a.n} cells (each case in a fresh process)")
    print(f"{'case':<24} {'tree':<10} {'seconds':>8} {'cells/s':>10} {'peak MB':>8} "
          f"{'load':>5}  notes")
    labels = {"analyze": "analyze (reference)", "serial": "map serial",
              "dask": "map dask 2 workers", "cli": "cli map --out .nc"}
    best = {}
    for c in cases:
        for _ in range(max(1, a.repeat)):
            for name, tree in trees:                 # alternating: the same load for both
                load = os.getloadavg()[0]
                got = _case(c, a.n, tree) + (load,)
                if (c, name) not in best or got[0] < best[c, name][0]:
                    best[c, name] = got
        for name, _ in trees:
            dt, mb, n, note, load = best[c, name]
            print(f"{labels[c]:<24} {name:<10} {dt:8.2f} {n / dt:10.0f} {mb:8.0f} {load:5.1f}"
                  f"  {note}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
