"""Big maps at bounded memory: what a map computes chunk by chunk equals the whole.

Independent references: pandas' ``DataFrame.to_csv`` of the map's columns (the long-format
CSV, written here chunk by chunk, must be that text byte for byte); the link frames of
:func:`screwkit.engine.link_frames` (every joint's screws, all poses at once) for the
joints the transmission indices read, which the analysis kernel forms in chunks of poses.
"""

from __future__ import annotations

import numpy as np
import pytest

import screwkit

pytest.importorskip("xarray")


def _pandas_csv(ds):
    """The long format as one pandas table (the layout the map's CSV documents)."""
    import pandas as pd
    dims = ds["ok"].dims
    grids = np.meshgrid(*[ds[d].values for d in dims], indexing="ij")

    def head(k):
        u = ds[k].attrs.get("units", "")
        return f"{k} [{u}]" if u and u != "1" else k

    cols = {head(d): g.reshape(-1) for d, g in zip(dims, grids)}
    for k in ds.coords:
        if ds[k].ndim == 0:
            cols[head(k)] = np.full(grids[0].size, float(ds[k].values))
    for k, v in ds.data_vars.items():
        if v.dims == dims:
            a = v.values.reshape(-1)
            if "flag_meanings" in v.attrs:
                a = np.array(v.attrs["flag_meanings"].split())[a.astype(int)]
            cols[head(k)] = a
    return pd.DataFrame(cols).to_csv(index=False, float_format="%.15g")


def test_csv_in_chunks_is_pandas_text(monkeypatch, tmp_path):
    # 3RSR over a wide alpha: unreachable cells (NaN fields), flags, booleans
    ds = screwkit.map("3RSR", {"alpha": (-40.0, 40.0, 9), "beta": (-5.0, 5.0, 3)},
                      degrees=True)
    assert not bool(ds["reachable"].all())
    want = _pandas_csv(ds)
    assert ",," in want                                     # NaN cells are in the text
    from screwkit.maps import _dataset
    monkeypatch.setattr(_dataset, "CSV_ROWS", 5)            # 27 cells: 6 chunks
    assert screwkit.maps.to_csv(ds) == want
    path = screwkit.maps.write(ds, tmp_path / "m.csv")
    assert open(path, encoding="utf-8", newline="").read() == want


def test_index_lines_in_chunks_equal_the_link_frames():
    from screwkit.engine._links import index_lines
    pm = screwkit.load_pm("3RSR")
    rng = np.random.default_rng(5)
    n = 300
    pose = {"alpha": rng.uniform(-40, 40, n), "beta": rng.uniform(-40, 40, n)}
    sol = screwkit.solve(pm, pose, degrees=True)
    assert 0 < sol.reachable_mask.sum() < n                 # NaN frames where unreachable
    lf = screwkit.engine.link_frames(sol)
    lines, platform = index_lines(sol, chunk=64)
    # each leg's platform-side joint (slot 4: R-S-R as R, three R, R), the joint after its
    # actuator (slot 1), its actuated joint (slot 0)
    for i in range(3):
        for j, q, d in ((4, 0, 3), (1, 6, 9)):
            np.testing.assert_array_equal(lines[:, i, q:q + 3], lf.points[j, :, i].T)
            np.testing.assert_array_equal(lines[:, i, d:d + 3], lf.twists[j, 3:, i].T)
        np.testing.assert_array_equal(lines[:, i, 12:18], lf.twists[0, :, i].T)
    R, o, _ = sol._platform
    np.testing.assert_array_equal(platform[:, 6:15].reshape(-1, 3, 3), R)
    np.testing.assert_array_equal(platform[:, 15:18], o)


def test_indices_keep_the_platform_they_computed():
    # the indices' frames give the platform: the same bits as the platform computed alone
    pm = screwkit.load_pm("3RRPRR")
    pose = {"alpha": np.linspace(-10, 10, 50), "beta": 3.0, "Zo": np.linspace(60, 100, 50)}
    a = screwkit.analyze(pm, pose, degrees=True)
    b = screwkit.analyze(pm, pose, degrees=True)
    a.indices                                       # (first: keeps its platform)
    assert "_platform" in a.solution.__dict__
    for x, y in zip(a.solution._platform, b.solution._platform):
        np.testing.assert_array_equal(x, y)
    for k, v in a.indices.data.items():
        np.testing.assert_array_equal(v, b.indices.data[k])


def test_indices_from_the_analysis_run_equal_the_second_pass():
    # a map's analysis keeps the indices' joints and platform from its own run (prismatic
    # joints: the solution's q / QS rounds to other bits on some poses, formed again
    # there); the indices and the platform equal those of the pass over the solved poses
    pm = screwkit.load_pm("3RRPRR")
    rng = np.random.default_rng(7)
    n = 400
    pose = {"alpha": rng.uniform(-40, 40, n), "beta": rng.uniform(-40, 40, n),
            "Zo": rng.uniform(20, 140, n)}
    pose["Zo"][:20] = 5000.0                                # beyond reach: flagged
    a = screwkit.analyze(pm, pose, degrees=True, lines=True)
    b = screwkit.analyze(pm, pose, degrees=True)
    assert 0 < a.solution.reachable_mask.sum() < n
    assert a.diagnostics["lines"].shape == (n, 3, 18)
    for k, v in a.indices.data.items():
        np.testing.assert_array_equal(v, b.indices.data[k])
    for x, y in zip(a.solution._platform, b.solution._platform):
        np.testing.assert_array_equal(x, y)
