"""Maps: every cell equals the analysis at its pose; units, files, limits, sizing, the CLI.

Independent references: ``screwkit.analyze`` at each sampled cell's pose alone (one pose,
its own solve; a few also through ``screwkit analyze --json``); the limits recomputed here from the cells' joint values, leg lengths and a
brute-force distance between the leg segments; the sizing extremes as the largest values
of one plain batched analysis per workload over the same poses.
"""

from __future__ import annotations

import json

import numpy as np
import pytest

import screwkit
from screwkit.cli import main

# the paper's workload, stated (only 3RRPRR and 2SPS+2SPR declare it as their default)
PAPER_LOAD = {"force": (-20.0, -30.0, -60.0), "torque": (-30.0, -30.0, 100.0)}
PAPER_ARGS = ["--force=-20,-30,-60", "--torque=-30,-30,100"]

pytest.importorskip("xarray")

GRID = {"alpha": (-12.0, 12.0, 25), "beta": (-12.0, 12.0, 17), "Zo": (60.0, 100.0, 12)}


@pytest.fixture(scope="module")
def rrprr():
    pm = screwkit.load_pm("3RRPRR")
    return pm, screwkit.map(pm, GRID, degrees=True, block=4096, **PAPER_LOAD)


def test_100_random_cells_equal_analyze_at_their_pose(rrprr, capsys):
    pm, ds = rrprr
    assert ds["F_a1"].dims == ("alpha", "beta", "Zo") and ds.sizes["Zo"] == 12
    rng = np.random.default_rng(3)
    shape = ds["ok"].shape
    L = pm.normalisation.length
    for flat in rng.choice(ds["ok"].size, 100, replace=False):
        i, j, k = np.unravel_index(flat, shape)
        pose = {"alpha": float(ds.alpha[i]), "beta": float(ds.beta[j]), "Zo": float(ds.Zo[k])}
        one = screwkit.analyze(pm, pose, degrees=True, raise_on_singular=False, **PAPER_LOAD)
        cell = ds.isel(alpha=i, beta=j, Zo=k)
        scale = max(1.0, float(np.max(np.abs(one.statics.values))))
        for lab, v in zip(one.jacobian.labels, one.statics.values):
            assert abs(float(cell[lab]) - v) <= 1e-10 * scale, (pose, lab)
        for n in range(3):
            assert abs(float(cell[f"r{n + 1}"]) - one.solution.extensions[n]) <= 1e-10 * L
            assert abs(float(cell[f"T_r{n + 1}"]) - one.statics.T_r[n]) <= 1e-10 * scale * L
            assert abs(float(cell[f"q_a{n + 1}"]) - one.solution.actuator_values[n]) <= 1e-10 * L
        # 1e-10 rad, as the lengths are held to 1e-10 L: at beta = 0 (a representation
        # singularity on the grid) gamma is a limit known to ~1e-12 rad (round-off / sin 1e-4)
        assert abs(float(cell["gamma"]) - np.degrees(one.solution.params["gamma"])) <= \
            np.degrees(1e-10)
        c = one.jacobian.condition_number
        assert abs(float(cell["condition_number"]) - c) <= 1e-10 * c
        assert int(cell["det_sign"]) == int(np.sign(np.linalg.det(one.jacobian.J)))
        assert bool(cell["ok"]) == one.ok and str(one.level) == \
            screwkit.maps.LEVEL_CODES[int(cell["level"])]
    # and the command line's `screwkit analyze --json` at a few of those poses
    for flat in rng.choice(ds["ok"].size, 5, replace=False):
        i, j, k = np.unravel_index(flat, shape)
        pose = {"alpha": float(ds.alpha[i]), "beta": float(ds.beta[j]), "Zo": float(ds.Zo[k])}
        assert main(["analyze", "3RRPRR", "--json"] +
                    [a for p, v in pose.items() for a in ("--pose", f"{p}={v!r}")]) == 0
        out = json.loads(capsys.readouterr().out)
        cell = ds.isel(alpha=i, beta=j, Zo=k)
        vals = out["statics"]["values"]
        scale = max(1.0, max(abs(v) for v in vals))
        for lab, v in zip(out["statics"]["labels"], vals):
            assert abs(float(cell[lab]) - v) <= 1e-10 * scale, (pose, lab)
        for n, e in enumerate(out["extensions"]):
            assert abs(float(cell[f"r{n + 1}"]) - e) <= 1e-10 * L
        assert float(cell["condition_number"]) == pytest.approx(out["condition_number"],
                                                                rel=1e-10)


def test_units_and_model_in_the_attributes(rrprr):
    pm, ds = rrprr
    assert ds.attrs["pm"] == "3RRPRR" and ds.attrs["units_length"] == "cm"
    assert ds["F_a2"].attrs["units"] == "kN" and ds["T_r1"].attrs["units"] == "kN.cm"
    assert ds["alpha"].attrs["units"] == "deg" and ds["Zo"].attrs["units"] == "cm"
    assert ds["gamma"].attrs["units"] == "deg"
    assert list(ds.attrs["force"]) == list(screwkit.PAPER_FORCE)
    assert ds["level"].attrs["flag_meanings"].split()[0] == "ok"


def test_files_round_trip(rrprr, tmp_path):
    import pandas as pd
    import xarray as xr
    _, ds = rrprr
    nc = screwkit.maps.write(ds, tmp_path / "m.nc")
    back = xr.open_dataset(nc).load()
    for k in ("F_a1", "condition_number", "ok", "level", "det_sign", "locus_alpha"):
        np.testing.assert_array_equal(back[k].values, ds[k].values)
    assert back["F_a1"].attrs["units"] == "kN" and back.attrs["pm"] == "3RRPRR"
    pytest.importorskip("zarr")
    z = screwkit.maps.write(ds, tmp_path / "m.zarr")
    np.testing.assert_array_equal(xr.open_zarr(z, consolidated=False)["F_c3"].values, ds["F_c3"].values)
    csv = screwkit.maps.write(ds.isel(Zo=slice(0, 2)), tmp_path / "m.csv")
    df = pd.read_csv(csv)
    assert len(df) == 25 * 17 * 2 and "F_a1 [kN]" in df.columns and "alpha [deg]" in df.columns
    row = df.iloc[37]
    i, j, k = np.unravel_index(37, (25, 17, 2))
    assert row["F_a1 [kN]"] == pytest.approx(float(ds["F_a1"][i, j, k]), rel=1e-14)
    assert row["level"] in screwkit.maps.LEVEL_CODES
    # the workload the map's statics are of, on every row (the paper's, declared by 3RRPRR)
    load = df[["workload_Fx [kN]", "workload_Fy [kN]", "workload_Fz [kN]",
               "workload_Tx [kN.cm]", "workload_Ty [kN.cm]", "workload_Tz [kN.cm]"]]
    assert (load.to_numpy() == [-20.0, -30.0, -60.0, -30.0, -30.0, 100.0]).all()
    with pytest.raises(screwkit.InputError, match="must end in"):
        screwkit.maps.write(ds, tmp_path / "m.txt")


def test_unreachable_cells_are_flagged_not_solved():
    ds = screwkit.map("3RSR", {"Zo": (20.0, 400.0, 20)}, degrees=True, **PAPER_LOAD)
    bad = ~ds["reachable"].values
    assert bad.any() and ds["reachable"].values.any()
    assert np.all(np.isnan(ds["T_a1"].values[bad])) and np.all(ds["level"].values[bad] == 4)
    one = screwkit.analyze("3RSR", {"Zo": np.array([float(ds.Zo[np.flatnonzero(bad)[0]])])}, **PAPER_LOAD)
    assert one.unreachable[0]
    # the plot hatches exactly those cells and says so
    pytest.importorskip("matplotlib")
    fig = screwkit.maps.plot_map(ds, None, ["conditioning"])
    hatched = [c for c in fig.axes[0].collections if c.get_hatch() == "////"]
    assert len(hatched) == 1
    assert "unreachable" in [t.get_text() for t in fig.legends[0].get_texts()]


def test_grid_errors():
    with pytest.raises(screwkit.InputError, match="dependent"):
        screwkit.map("3RRPRR", {"gamma": (0, 1, 3)})
    with pytest.raises(screwkit.InputError, match="1 to 3"):
        screwkit.map("2SPS+2SPR", {p: (0, 1, 2) for p in ("alpha", "beta", "gamma", "Zo")})
    with pytest.raises(screwkit.InputError, match="more than"):
        screwkit.map("3RRPRR", {"alpha": (0, 1, 5000), "beta": (0, 1, 5000)})
    with pytest.raises(screwkit.InputError, match="both"):
        screwkit.map("3RRPRR", {"alpha": (0, 1, 3)}, fix={"alpha": 0})


def test_samples_in_a_box_are_reproducible():
    box = {"alpha": (-5, 5), "beta": (-5, 5), "Zo": (70, 90)}
    a = screwkit.map("3RRPRR", box, samples=300, seed=4, degrees=True)
    b = screwkit.map("3RRPRR", box, samples=300, seed=4, degrees=True)
    assert a["F_a1"].dims == ("sample",) and a.attrs["locus"].startswith("none")
    np.testing.assert_array_equal(a["F_a1"].values, b["F_a1"].values)
    assert a["alpha"].values.min() >= -5 and a["Zo"].values.max() <= 90


LIMITED = """
pms:
  3RRPRR/limited:
    string: 3RRPRR
    dimensions: {L: 120, l: 60}
    base: {shape: triangle, side: L}
    platform: {shape: triangle, side: l}
    legs: [RRPRR, RRPRR, RRPRR]
    euler: XYX
    independent: [alpha, beta, Zo]
    home: {alpha: 0, beta: 0, Zo: 2*L/3}
    pose: {alpha: 5, beta: -3, Zo: 2*L/3}
    dof: 3
    units: {length: cm, force: kN}
    limits:
      extensions: [70, 95]
      joints: {R1: [-12, 12]}
      min_leg_distance: 8
"""


def test_limits_mark_the_cells_outside(tmp_path):
    f = tmp_path / "limited.yaml"
    f.write_text(LIMITED)
    pm = screwkit.load_pm(str(f))
    assert pm.limits.declared and pm.limits.min_leg_distance == 8.0
    grid = {"alpha": (-15.0, 15.0, 9), "Zo": (60.0, 110.0, 11)}
    ds = screwkit.map(pm, grid, fix={"beta": 4.0}, degrees=True, **PAPER_LOAD)
    poses = {"alpha": np.repeat(ds.alpha.values, 11), "beta": np.full(99, 4.0),
             "Zo": np.tile(ds.Zo.values, 9)}
    sol = screwkit.solve(pm, poses, degrees=True)
    r = sol.extensions
    ok_r = np.all((r >= 70) & (r <= 95), axis=1)
    q1 = np.stack([jv[:, 0] for jv in sol.joint_values], axis=1)
    ok_j = np.all(np.abs(np.degrees(q1)) <= 12, axis=1)
    # brute force: the closest points of 400 samples on each pair of leg segments
    t = np.linspace(0.0, 1.0, 400)
    A, a = sol.base_points, sol.platform_points
    seg = A[None, :, None, :] + t[None, None, :, None] * (a - A[None])[:, :, None, :]
    dmin = np.full(99, np.inf)
    for i in range(3):
        for j in range(i + 1, 3):
            d = np.linalg.norm(seg[:, i, :, None] - seg[:, j, None, :], axis=-1)
            dmin = np.minimum(dmin, d.min(axis=(1, 2)))
    np.testing.assert_allclose(ds["min_leg_distance"].values.reshape(-1), dmin, atol=0.3)
    want = ok_r & ok_j & (dmin >= 8)
    got = ds["within_limits"].values.reshape(-1)
    near = np.abs(dmin - 8) < 0.3                        # the brute force's resolution
    np.testing.assert_array_equal(got[~near], want[~near])
    assert got.any() and not got.all()
    # a key the loader does not know is refused, naming the field
    f.write_text(LIMITED.replace("min_leg_distance: 8", "min_distance: 8"))
    with pytest.raises(screwkit.CatalogError, match="min_distance"):
        screwkit.load_pm(str(f))


def test_sizing_equals_the_largest_values_of_plain_analyses(tmp_path):
    pm = screwkit.load_pm("2SPS+2SPR")
    csv = tmp_path / "loads.csv"
    csv.write_text("name,Fx,Fy,Fz,Tx,Ty,Tz\npaper,-20,-30,-60,-30,-30,100\n"
                   "lift,0,0,-100,0,0,0\n")
    loads = screwkit.maps.read_workloads(csv)
    grid = {"alpha": (-4.0, 4.0, 9), "gamma": (-4.0, 4.0, 9)}
    res = screwkit.size(pm, grid, fix={"beta": 2.0, "Zo": 80.0}, workloads=loads,
                        degrees=True)
    a, g = np.meshgrid(np.linspace(-4, 4, 9), np.linspace(-4, 4, 9), indexing="ij")
    pose = {"alpha": a.ravel(), "gamma": g.ravel(), "beta": np.full(81, 2.0),
            "Zo": np.full(81, 80.0)}
    best = {}
    for name, F, T in loads:
        an = screwkit.analyze(pm, pose, force=F, torque=T, degrees=True)
        for k, lab in enumerate(an.jacobian.labels):
            v = np.abs(an.statics.values[:, k])
            i = int(np.argmax(v))
            if lab not in best or v[i] > best[lab][0]:
                best[lab] = (v[i], name, a.ravel()[i], g.ravel()[i])
    rows = {r["name"]: r for r in res.rows}
    for lab, (v, name, ai, gi) in best.items():
        assert rows[lab]["max_abs"] == pytest.approx(v, rel=1e-10)
        assert rows[lab]["workload"] == name
        assert rows[lab]["pose"]["alpha"] == ai and rows[lab]["pose"]["gamma"] == gi
    bad = tmp_path / "bad.csv"
    bad.write_text("Fx,Fy,Fz\n1,2,3\n")
    with pytest.raises(screwkit.InputError, match="missing column"):
        screwkit.maps.read_workloads(bad)


def test_cli_map_and_size(tmp_path, capsys):
    out, png = tmp_path / "m.csv", tmp_path / "m.png"
    assert main(["map", "2SPS+2SPR", "--grid", "alpha=-10:30:21", "--grid", "gamma=0:10:3",
                 "--fix", "beta=0", "--fix", "Zo=75", "--out", str(out), "--plot", str(png),
                 "--quantity", "F_a1", "--json"]) == 0
    s = json.loads(capsys.readouterr().out)
    assert s["singular_locus"] and {x["kind"] for x in s["singular_locus"]} == {"actuation"}
    assert set(s["singular_locus"][0]["pose"]) == {"alpha", "beta", "gamma", "Zo"}
    assert s["singular_locus"][0]["pose_units"] == {"alpha": "deg", "beta": "deg",
                                                     "gamma": "deg", "Zo": "cm"}
    assert "extremes" in s and out.stat().st_size > 0 and png.stat().st_size > 10000
    assert main(["size", "3RRPRR", "--grid", "alpha=-5:5:5", "--fix", "Zo=80", "--json"]) == 0
    s = json.loads(capsys.readouterr().out)
    assert [r["name"] for r in s["extremes"]][:3] == ["F_a1", "F_a2", "F_a3"]
    assert s["extremes"][0]["unit"] == "kN"
    assert main(["map", "3RRPRR", "--grid", "gamma=0:1:3"]) == 2
    assert "dependent" in capsys.readouterr().err
    assert main(["map", "3RRPRR", "--grid", "alpha=0:1"]) == 2
    assert "START:STOP:COUNT" in capsys.readouterr().err
    assert main(["size", "3RRPRR", "--grid", "alpha=0:1:3", "--workloads",
                 str(tmp_path / "none.csv")]) == 2


def test_plot_colour_range_hatches_and_loci():
    """The picture says what the cells say: the colour range of a force is the range of the
    regular cells (computed here from the map) and the refined crossings are drawn where the
    locus says (the hatching of unreachable cells: the test above)."""
    pytest.importorskip("matplotlib")
    ds = screwkit.map("2SPS+2SPR", {"alpha": (-10.0, 30.0, 21), "gamma": (-5.0, 5.0, 3)},
                      fix={"beta": 0.0, "Zo": 75.0}, degrees=True)
    fig = screwkit.maps.plot_map(ds, None, ["F_a1"])
    ax = fig.axes[0]
    mesh = ax.collections[0]
    calm = ds["level"].values <= 1
    f = ds["F_a1"].values[calm]
    m = max(-f.min(), f.max())
    assert mesh.norm.vmin == pytest.approx(-m) and mesh.norm.vmax == pytest.approx(m)
    assert "active force of leg 1" in ax.get_title() and "[kN]" in ax.get_xlabel() + \
        fig.axes[1].get_ylabel()
    drawn = sorted(zip(np.concatenate([ln.get_xdata() for ln in ax.get_lines()]),
                       np.concatenate([ln.get_ydata() for ln in ax.get_lines()])))
    want = sorted((x["pose"]["alpha"], x["pose"]["gamma"]) for x in screwkit.maps.locus_list(ds))
    assert sum(1 for x in screwkit.maps.locus_list(ds) if x["along"] == "alpha") == 3
    np.testing.assert_allclose(np.array(drawn), np.array(want))


def test_forces_of_one_kind_share_one_diverging_scale():
    """Issue 22: the actuation forces of every leg take one diverging map on one symmetric
    scale (the largest |F_ai| of the regular cells over all legs, computed here from the
    map), the condition number the sequential map; every hatch and point style drawn has a
    legend entry."""
    pytest.importorskip("matplotlib")
    ds = screwkit.map("3RRPRR", {"alpha": (-20.0, 20.0, 9), "beta": (-20.0, 20.0, 7)},
                      fix={"Zo": 80.0}, degrees=True)
    fig = screwkit.maps.plot_map(ds, None, ["forces", "conditioning"])
    meshes = [ax.collections[0] for ax in fig.axes if ax.get_label() != "<colorbar>"]
    assert len(meshes) == 4
    calm = ds["level"].values <= 1
    m = max(np.abs(ds[f"F_a{i}"].values[calm]).max() for i in (1, 2, 3))
    for mesh in meshes[:3]:                # F_a3 > 0 everywhere: still the shared scale
        assert mesh.cmap.name == "RdBu_r"
        assert (mesh.norm.vmin, mesh.norm.vmax) == (pytest.approx(-m), pytest.approx(m))
    assert meshes[3].cmap.name == "viridis"
    legend = " ".join(t.get_text() for t in fig.legends[0].get_texts())
    assert "one colour scale, symmetric about 0, for the actuation forces of every leg" in legend
    # the 2SPS+2SPR near its singularity: the hatched band and the crossings are explained
    ds = screwkit.map("2SPS+2SPR", {"alpha": (-10.0, 30.0, 21), "gamma": (-5.0, 5.0, 3)},
                      fix={"beta": 0.0, "Zo": 75.0}, degrees=True)
    fig = screwkit.maps.plot_map(ds, None, ["F_a1"])
    legend = [t.get_text() for t in fig.legends[0].get_texts()]
    hatches = {c.get_hatch() for c in fig.axes[0].collections if c.get_hatch()}
    assert hatches == {"xx"}
    assert any(t.startswith("near-singular") and "hatched, outlined" in t for t in legend)
    assert any("actuation singularity" in t for t in legend)


def test_a_plot_without_a_workload_says_so_and_an_index_is_drawn_on_its_range():
    """The title of a map without a workload read ``load F = [nan, nan, nan]``; it says that
    there is none now.  A 1-D plot of the transmission indices auto-scaled ITI to 0.96..1.04
    (ticks above 1 for an index bounded by 1): each is drawn on [0, 1] now."""
    pytest.importorskip("matplotlib")
    ds = screwkit.map("3RPS", {"alpha": (-20.0, 20.0, 5), "Zo": (40.0, 80.0, 3)},
                      fix={"beta": 10.0}, degrees=True)
    fig = screwkit.maps.plot_map(ds, None, ["conditioning"])
    title = fig.get_suptitle() if hasattr(fig, "get_suptitle") else fig._suptitle.get_text()
    assert "nan" not in title and "no workload" in title
    ds = screwkit.map("3RRPRR", {"alpha": (-30.0, 30.0, 13)}, fix={"beta": 5.0, "Zo": 80.0},
                      degrees=True, force=(0, 0, -10))
    fig = screwkit.maps.plot_map(ds, None, ["transmission"])
    axes = [ax for ax in fig.axes if ax.get_lines()]
    assert len(axes) == 4
    for ax in axes:
        lo, hi = ax.get_ylim()
        assert lo < 0 <= 1 < hi <= 1.05 and lo >= -0.05
