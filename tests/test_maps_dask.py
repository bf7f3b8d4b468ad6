"""A map on a Dask cluster equals the serial map bit for bit, and so do a sizing and a
validation (a LocalCluster the test starts on loopback and closes)."""

from __future__ import annotations

import json

import numpy as np
import pytest

import screwkit

# the paper's workload, stated (only 3RRPRR and 2SPS+2SPR declare it as their default)
PAPER_LOAD = {"force": (-20.0, -30.0, -60.0), "torque": (-30.0, -30.0, 100.0)}
PAPER_ARGS = ["--force=-20,-30,-60", "--torque=-30,-30,100"]

pytest.importorskip("xarray")
distributed = pytest.importorskip("distributed")


def _same(a, b):
    assert set(a.data_vars) == set(b.data_vars)
    for k in a.data_vars:
        assert np.array_equal(a[k].values, b[k].values, equal_nan=True), k


def test_dask_map_equals_the_serial_map_bit_for_bit(tmp_path):
    grid = {"alpha": (-20.0, 20.0, 61), "beta": (-20.0, 20.0, 41)}
    serial = screwkit.map("3RRPRR", grid, fix={"Zo": 75.0}, degrees=True, block=4096)
    with distributed.LocalCluster(n_workers=2, threads_per_worker=1, processes=True,
                                  host="127.0.0.1", dashboard_address=None) as cluster, \
            distributed.Client(cluster) as client:
        dask = screwkit.map("3RRPRR", grid, fix={"Zo": 75.0}, degrees=True, block=4096,
                            cluster=client)
        # five given parameters: the home predictor's fit solves 126 x 126 normal equations,
        # whose bits once depended on OpenBLAS's threads (one in a Dask worker)
        five = {"alpha": (-6.0, 6.0, 9), "beta": (-6.0, 6.0, 9), "gamma": (-4.0, 4.0, 5)}
        dask5 = screwkit.map("4SPS+SPR", five, degrees=True, block=4096, cluster=client)
        sizing = screwkit.size("3RRPRR", grid, fix={"Zo": 75.0}, degrees=True,
                               scheduler=cluster.scheduler_address)
        # validate on the same running cluster (--scheduler): one leg string per task
        from screwkit.cli import main
        args = ["validate", "SPR", "UPU", "RRPRR", "--no-catalog", "--format", "json",
                "--quiet", "--out"]
        assert main(args + [str(tmp_path / "v_dask.json"), "--scheduler",
                            cluster.scheduler_address]) == 0
        # a trajectory: its closures solved here, its chunks' rows and statics on the cluster
        traj = ["trajectory", "3RRPRR", "--expr", "alpha=20*sin(2*pi*t)", "--expr",
                "beta=15*cos(2*pi*t)", "--expr", "Zo=80+5*t", "--samples", "9000", "--quiet"]
        assert main(traj + ["--out", str(tmp_path / "t_dask.csv"), "--scheduler",
                            cluster.scheduler_address]) == 0
        from functools import partial

        from screwkit.maps import run_tasks
        from screwkit.paths import path_from_expressions, run_trajectory
        model = screwkit.load_pm("3RRPRR")
        path = path_from_expressions(["alpha=0.3*sin(t)", "beta=0.2*t", "Zo=75+3*t"],
                                     model.independent, samples=301)
        sent = []

        def on_cluster(fn, items):
            sent.append(len(items))
            return partial(run_tasks, client)(fn, items)
        t_dask = run_trajectory(model, path, chunk=40, mapper=on_cluster, **PAPER_LOAD)
        assert sent == [8]                        # 301 samples in chunks of 40, all sent
    assert main(args + [str(tmp_path / "v_serial.json")]) == 0
    assert main(traj + ["--out", str(tmp_path / "t_serial.csv")]) == 0
    assert (tmp_path / "t_dask.csv").read_text() == (tmp_path / "t_serial.csv").read_text()
    t_serial = run_trajectory(model, path, chunk=40, **PAPER_LOAD)
    for name in ("active", "constraint", "condition_number", "closure_residual"):
        assert np.array_equal(getattr(t_dask, name), getattr(t_serial, name), equal_nan=True)
    v_dask, v_serial = (json.loads((tmp_path / f"v_{k}.json").read_text())
                        for k in ("dask", "serial"))
    assert v_dask.pop("seconds") >= 0 and v_serial.pop("seconds") >= 0
    assert v_dask == v_serial and len(v_serial["legs"]) == 3
    assert dask.attrs["computed_on"] == "dask"
    _same(serial, dask)
    _same(screwkit.map("4SPS+SPR", five, degrees=True, block=4096), dask5)
    ref = screwkit.size("3RRPRR", grid, fix={"Zo": 75.0}, degrees=True)
    assert sizing.rows == ref.rows


def test_cli_workers_equal_serial(tmp_path):
    import xarray as xr

    from screwkit.cli import main
    args = ["map", "3RRPRR", "--grid", "alpha=-10:10:21", "--grid", "beta=-10:10:11",
            "--fix", "Zo=80", "--quiet"]
    assert main(args + ["--out", str(tmp_path / "a.nc")]) == 0
    assert main(args + ["--out", str(tmp_path / "b.nc"), "--workers", "2"]) == 0
    _same(xr.open_dataset(tmp_path / "a.nc").load(), xr.open_dataset(tmp_path / "b.nc").load())
    assert main(args + ["--workers", "0"]) == 2
    assert main(args + ["--workers", "2", "--scheduler", "tcp://127.0.0.1:1"]) == 2
    assert main(["validate", "SPR", "--workers", "2", "--scheduler", "tcp://127.0.0.1:1"]) == 2
    assert main(["validate", "SPR", "--scheduler", "127.0.0.1:1"]) == 2
    assert main(["trajectory", "3RRPRR", "--expr", "alpha=t", "--expr", "beta=0", "--expr",
                 "Zo=80", "--workers", "2", "--scheduler", "tcp://127.0.0.1:1"]) == 2


def test_a_dead_scheduler_address_fails_fast_with_the_address(monkeypatch):
    import socket
    import time

    from screwkit.maps import _dask

    with socket.socket() as s:                   # a free port nothing listens on
        s.bind(("127.0.0.1", 0))
        port = s.getsockname()[1]
    monkeypatch.setattr(_dask, "SCHEDULER_TIMEOUT", 1.0)
    t = time.perf_counter()
    with pytest.raises(screwkit.InputError, match=f"tcp://127.0.0.1:{port} within 1 s"):
        screwkit.map("3RRPRR", {"alpha": (-5.0, 5.0, 3)}, fix={"beta": 0.0, "Zo": 75.0},
                     degrees=True, scheduler=f"tcp://127.0.0.1:{port}")
    assert time.perf_counter() - t < 20
