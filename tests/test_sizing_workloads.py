"""A sizing over several workloads (one map, the other workloads by linearity) equals the
largest efforts of one full map per workload, each analysed with its own workload."""

import numpy as np
import pytest

import screwkit
from screwkit.maps import extremes
from screwkit.maps._sizing import usable

pytest.importorskip("xarray")

LOADS = [("paper", (-20.0, -30.0, -60.0), (-30.0, -30.0, 100.0)),
         ("lift", (0.0, 0.0, -120.0), (0.0, 0.0, 0.0)),
         ("twist", (5.0, 0.0, 0.0), (0.0, 0.0, 300.0)),
         ("side", (40.0, 10.0, -10.0), (50.0, -20.0, 0.0))]


def _one_map_per_workload(pm, grid, fix, loads, max_level, **kw):
    best, union = None, None
    for name, F, T in loads:
        ds = screwkit.map(pm, grid, fix=fix, degrees=True, force=F, torque=T, locus=False,
                          **kw)
        ex = extremes(ds, name, max_level)
        use = usable(ds, max_level)
        union = use if union is None else union | use
        if best is None:
            best = ex
        else:
            for b, x in zip(best["rows"], ex["rows"]):
                if x["max_abs"] is not None and (b["max_abs"] is None or
                                                 x["max_abs"] > b["max_abs"]):
                    b.update(x)
    return best, int(union.sum())


@pytest.mark.parametrize("pm, grid, fix, max_level", [
    ("3RRPRR", {"alpha": (-10.0, 10.0, 21), "beta": (-8.0, 8.0, 17)}, {"Zo": 80.0},
     "near-singular"),
    # near the 2SPS+2SPR's singular surface: trust levels differ from workload to workload
    ("2SPS+2SPR", {"alpha": (-10.0, 30.0, 41), "gamma": (0.0, 10.0, 6)},
     {"beta": 0.0, "Zo": 75.0}, "ok"),
])
def test_sizing_equals_one_map_per_workload(pm, grid, fix, max_level):
    got = screwkit.size(pm, grid, fix=fix, workloads=LOADS, degrees=True,
                        max_level=max_level)
    want, union = _one_map_per_workload(pm, grid, fix, LOADS, max_level)
    assert got.usable_cells == union
    assert len(got.rows) == len(want["rows"])
    scale = max(b["max_abs"] for b in want["rows"])
    for a, b in zip(got.rows, want["rows"]):
        assert a["name"] == b["name"]
        # a row that vanishes at every cell (rounding noise, ~1e-13 of the others) is held
        # to the others' scale
        assert a["max_abs"] == pytest.approx(b["max_abs"], rel=1e-9, abs=1e-12 * scale)
        if b["max_abs"] > 1e-9 * scale:
            # the same cell and workload, or an exact tie between two (symmetric poses)
            if a["pose"] != b["pose"] or a["workload"] != b["workload"]:
                assert abs(a["max_abs"] - b["max_abs"]) <= 1e-9 * b["max_abs"]
            assert a["level"] == b["level"]
            assert np.sign(a["value"]) == np.sign(b["value"])


def test_sizing_with_row_stiffness_uses_the_same_compliances():
    grid, fix = {"alpha": (-8.0, 8.0, 9), "beta": (-6.0, 6.0, 7)}, {"Zo": 80.0}
    k = {"F_a1": 2e3, "F_a2": 5e3, "F_c3": 1e4}
    got = screwkit.size("3RRPRR", grid, fix=fix, workloads=LOADS[1:], degrees=True,
                        stiffness=k)
    want, _ = _one_map_per_workload("3RRPRR", grid, fix, LOADS[1:], "near-singular",
                                    stiffness=k)
    for a, b in zip(got.rows, want["rows"]):
        assert a["max_abs"] == pytest.approx(b["max_abs"], rel=1e-9)


def test_under_equals_an_analysis_with_that_workload():
    pm = screwkit.load_pm("2SPS+2SPR")
    from random_poses import random_pose
    pose = random_pose(pm, 40, seed=5)
    base = screwkit.analyze(pm, pose)
    F, T = (12.0, -3.0, 40.0), (0.0, 25.0, -8.0)
    direct = screwkit.analyze(pm, pose, force=F, torque=T)
    moved = base.under(F, T)
    np.testing.assert_allclose(moved.statics.values, direct.statics.values, rtol=1e-12,
                               atol=1e-12)
    np.testing.assert_allclose(moved.statics.T_r, direct.statics.T_r, rtol=1e-12, atol=1e-9)
    np.testing.assert_allclose(moved.quality.amplification, direct.quality.amplification,
                               rtol=1e-12)
    assert moved.level.tolist() == direct.level.tolist()
    assert np.max(moved.statics.equilibrium_residual) < 1e-10
    one = base[3].under(F, T)
    np.testing.assert_allclose(one.statics.values, direct.statics.values[3], rtol=1e-12)
    with pytest.raises(screwkit.InputError, match="force"):
        base.under((1.0, np.nan, 0.0), T)
