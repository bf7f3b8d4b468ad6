"""The threads of the parallel launches: each on a CPU of its own where the process may use
no more CPUs than threads (``screwkit.engine._kernels._threads``), none pinned otherwise or
with ``SCREWKIT_PIN_THREADS=0``; the results are the same bits either way."""

import json
import os
import subprocess
import sys
from pathlib import Path

import numpy as np
import pytest

ROOT = Path(__file__).resolve().parents[1]

pytestmark = pytest.mark.skipif(not sys.platform.startswith("linux"),
                                reason="thread affinities are Linux's")

# a batch on two threads, then every native thread's CPUs (from /proc, not from screwkit)
_CHILD = r"""
import json, os, threading, numpy as np, screwkit
pm = screwkit.load_pm("3RRPRR")
n = 3000
pose = {"alpha": np.linspace(-0.1, 0.1, n), "beta": np.linspace(0.1, -0.1, n),
        "Zo": np.linspace(70.0, 90.0, n)}
r = screwkit.analyze(pm, pose, workers=2)
python = {t.native_id for t in threading.enumerate()}
cpus = {}
for tid in os.listdir("/proc/self/task"):
    if int(tid) in python:
        continue
    with open(f"/proc/self/task/{tid}/status") as f:
        line = [l for l in f if l.startswith("Cpus_allowed_list")][0]
    cpus[tid] = line.split()[1]
print(json.dumps({"cpus": cpus, "allowed": sorted(os.sched_getaffinity(0)),
                  "values": np.asarray(r.jacobian.condition_number).tolist()}))
"""


def _run(env_extra):
    env = dict(os.environ, PYTHONPATH=str(ROOT), **env_extra)
    out = subprocess.run([sys.executable, "-c", _CHILD], env=env, capture_output=True,
                         text=True, timeout=600, check=True)
    return json.loads(out.stdout.strip().splitlines()[-1])


def _single(spec):
    """The CPU of a one-CPU list such as ``"1"``, else None (``"0-1"``, ``"0,2"``)."""
    return int(spec) if spec.isdigit() else None


def test_two_threads_each_on_a_cpu_of_their_own_where_cpus_are_few():
    on = _run({})
    off = _run({"SCREWKIT_PIN_THREADS": "0"})
    allowed = on["allowed"]
    pinned_on = [_single(s) for s in on["cpus"].values() if _single(s) is not None]
    pinned_off = [_single(s) for s in off["cpus"].values() if _single(s) is not None]
    if len(allowed) == 1:
        pytest.skip("one CPU: nothing to spread")
    if len(allowed) <= 2:
        # two workers, one on each of the two CPUs
        assert sorted(pinned_on) == allowed[:2]
    else:
        # CPUs to spare: left to the scheduler
        assert pinned_on == []
    assert pinned_off == []
    # the same bits either way
    assert on["values"] == off["values"]
