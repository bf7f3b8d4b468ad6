"""The first batch after the first run: the compile a batch on threads adds.

In a fresh empty kernel cache: ``screwkit analyze 3RRPRR`` (the first run, one pose), then,
in a second process, ``screwkit.analyze`` of 1,000 random 3RRPRR poses with ``workers=2``
(the first batch on threads: the parallel kernel's compile, with the block closure's
kernels). Prints the wall and CPU time of each process and the load average; ``--repeat``
runs it that many times, ``--checkout`` measures another checkout of screwkit (its code, its
interpreter's packages) the same way, for a side-by-side run in the same minutes.

    python benchmarks/first_batch.py [--repeat 2] [--checkout /path/to/other/checkout]
"""

from __future__ import annotations

import argparse
import os
import resource
import shutil
import subprocess
import sys
import tempfile
import time

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))

BATCH = """\
import numpy as np, screwkit
rng = np.random.default_rng(0)
n = 1000
pose = {"alpha": np.radians(rng.uniform(-10, 10, n)),
        "beta": np.radians(rng.uniform(-10, 10, n)), "Zo": rng.uniform(60, 100, n)}
r = screwkit.analyze(screwkit.load_pm("3RRPRR"), pose, workers=2)
"""


def _timed(args, env, cwd):
    before = resource.getrusage(resource.RUSAGE_CHILDREN)
    t = time.perf_counter()
    out = subprocess.run(args, env=env, cwd=cwd, capture_output=True, text=True)
    wall = time.perf_counter() - t
    after = resource.getrusage(resource.RUSAGE_CHILDREN)
    if out.returncode:
        sys.exit(f"{' '.join(args[:3])} failed: {out.stderr.strip()}")
    cpu = (after.ru_utime - before.ru_utime) + (after.ru_stime - before.ru_stime)
    return wall, cpu, out.stderr.strip()


def measure(root: str) -> None:
    cache = tempfile.mkdtemp(prefix="screwkit-batch-")
    env = dict(os.environ, NUMBA_CACHE_DIR=cache, PYTHONPATH=root)
    env.pop("SCREWKIT_COMPILE_PROCESSES", None)
    try:
        for label, args in (("first run (one pose)", ["-m", "screwkit", "analyze", "3RRPRR"]),
                            ("then 1,000 poses, workers=2", ["-c", BATCH])):
            wall, cpu, note = _timed([sys.executable, *args], env, root)
            load = os.getloadavg()
            print(f"{label:28s}: wall {wall:6.1f} s  CPU {cpu:6.1f} s  "
                  f"(load {load[0]:.2f} {load[1]:.2f})  stderr: {note!r}", flush=True)
    finally:
        shutil.rmtree(cache, ignore_errors=True)


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--repeat", type=int, default=1)
    ap.add_argument("--checkout", default=ROOT, help="the screwkit checkout to measure")
    a = ap.parse_args()
    for _ in range(a.repeat):
        print(f"{os.path.abspath(a.checkout)}:", flush=True)
        measure(os.path.abspath(a.checkout))


if __name__ == "__main__":
    main()
