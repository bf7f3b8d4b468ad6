"""Review checks of the maps layer against values derived here, independently of it.

* the 2SPS+2SPR's J written from its geometry (paper section 4: SPS and SPR legs, the SPR
  constraint force through the S centre along the platform R axis) gives the singular
  angle by brentq and the statics at map cells;
* a change of units (cm, kN -> mm, N) scales every map variable and the loci by the unit
  factors;
* sizing over several workloads equals the superposition of six unit-wrench maps (the
  statics are linear in the load);
* the 3RRPRR forward kinematics equals a least-squares solve of its own closure equations
  (each leg's R1 axis meets the platform normal at a_i) and leg lengths;
* workload CSV files and plot/CLI arguments are refused with one line naming the place.
"""

from __future__ import annotations

import subprocess
import sys

import numpy as np
import pytest
from scipy.optimize import brentq, least_squares
from scipy.spatial.transform import Rotation

# the paper's workload, stated (only 3RRPRR and 2SPS+2SPR declare it as their default)
PAPER_LOAD = {"force": (-20.0, -30.0, -60.0), "torque": (-30.0, -30.0, 100.0)}
PAPER_ARGS = ["--force=-20,-30,-60", "--torque=-30,-30,100"]

pytest.importorskip("xarray")

import screwkit  # noqa: E402
from screwkit.errors import InputError  # noqa: E402
from screwkit.maps import locus_list, read_workloads  # noqa: E402

# --- the 2SPS+2SPR from its definition (L = 100, l1 = 60, l2 = 50 cm) -------------------
_SG = np.array([[1, -1], [1, 1], [-1, 1], [-1, -1]], float)
_A = np.c_[50.0 * _SG, np.zeros(4)]
_P = np.c_[30.0 * _SG[:, 0], 25.0 * _SG[:, 1], np.zeros(4)]


def _j_2sps2spr(alpha, beta, gamma, zo):
    """J (rows: leg forces along the legs, then the SPR constraint forces), about O, and o."""
    R = Rotation.from_euler("XYX", [alpha, beta, gamma]).as_matrix()
    c2 = R @ (_P[0] - _P[2])
    c3 = R @ (_P[1] - _P[3])
    c2, c3 = c2 / np.linalg.norm(c2), c3 / np.linalg.norm(c3)
    # SPR legs 2, 3: the leg is perpendicular to its R axis, (o + R p_i - A_i) . c_i = 0,
    # linear in (Xo, Yo)
    z = np.array([0.0, 0.0, zo])
    M = np.array([c2[:2], c3[:2]])
    rhs = -np.array([(z + R @ _P[1] - _A[1]) @ c2, (z + R @ _P[2] - _A[2]) @ c3])
    o = np.r_[np.linalg.solve(M, rhs), zo]
    a = o + _P @ R.T
    rows = []
    for i in range(4):
        s = (a[i] - _A[i]) / np.linalg.norm(a[i] - _A[i])
        rows.append(np.r_[s, np.cross(_A[i], s)])
    for i, c in ((1, c2), (2, c3)):
        rows.append(np.r_[c, np.cross(_A[i], c)])
    return np.array(rows), o


@pytest.mark.parametrize("zo", [50.0, 75.0, 100.0])
def test_2sps2spr_locus_is_the_root_of_an_independent_det_j(zo):
    root = brentq(lambda al: np.linalg.det(_j_2sps2spr(al, 0.0, 0.0, zo)[0]),
                  np.radians(5), np.radians(25), xtol=1e-15)
    ds = screwkit.map("2SPS+2SPR", {"alpha": (0, 30, 31)},
                      fix={"beta": 0, "gamma": 0, "Zo": zo}, degrees=True)
    loc = locus_list(ds)
    assert len(loc) == 1 and loc[0]["kind"] == "actuation"
    # refined to 1e-6 of the 1 deg cell: the midpoint is within half of that
    assert abs(loc[0]["pose"]["alpha"] - np.degrees(root)) <= 0.5e-6 + 1e-9


def test_2sps2spr_locus_along_a_length_and_in_another_unit(tmp_path):
    """Bisection along Zo (a length) finds the height where alpha* is singular; the same
    model in mm gives the same angle and ten times the height."""
    a_star = brentq(lambda al: np.linalg.det(_j_2sps2spr(al, 0.0, 0.0, 75.0)[0]),
                    np.radians(5), np.radians(25), xtol=1e-15)
    ds = screwkit.map("2SPS+2SPR", {"Zo": (60, 90, 7)},
                      fix={"alpha": a_star, "beta": 0, "gamma": 0})
    loc = locus_list(ds)
    assert len(loc) == 1 and loc[0]["along"] == "Zo"
    assert abs(loc[0]["pose"]["Zo"] - 75.0) <= 0.5e-6 * 5.0 + 1e-6
    path = tmp_path / "mm.yaml"
    path.write_text("""units: {length: mm, force: N}
pms:
  S2mm:
    string: 2SPS+2SPR
    dimensions: {L: 1000, l1: 600, l2: 500}
    base: {shape: square, side: L}
    platform: {shape: rectangle, sides: [l1, l2]}
    legs:
      - SPS
      - {leg: SPR, axes: {R3: {platform_toward: [a3, a1]}}}
      - {leg: SPR, axes: {R3: {platform_toward: [a4, a2]}}}
      - SPS
    euler: XYX
    independent: [alpha, beta, gamma, Zo]
    home: {alpha: 0, beta: 0, gamma: 0, Zo: 0.8*L}
    pose: {alpha: 4, beta: 3, gamma: 2, Zo: 0.8*L}
    dof: 4
""", encoding="utf-8")
    grid = {"alpha": (-10, 30, 9), "gamma": (-5, 5, 3)}
    cm = screwkit.map("2SPS+2SPR", grid, fix={"beta": 2, "Zo": 75}, degrees=True)
    mm = screwkit.map(str(path), grid, fix={"beta": 2, "Zo": 750}, degrees=True,
                      force=np.array([-20, -30, -60]) * 1e3,
                      torque=np.array([-30, -30, 100]) * 1e4)
    factor = {"kN": 1e3, "kN.cm": 1e4, "cm": 10.0}
    assert mm["F_a1"].attrs["units"] == "N" and mm["T_r2"].attrs["units"] == "N.mm"
    for k, v in cm.data_vars.items():
        if k in ("residual", "equilibrium_residual", "locus_condition_number"):
            continue          # round-off, and cond ~ 1e9 at a crossing: not to 1e-8
        f = factor.get(v.attrs.get("units"), 1.0)
        x, y = v.values.astype(float) * f, mm[k].values.astype(float)
        scale = np.nanmax(np.abs(y)) if np.isfinite(y).any() else 1.0
        if v.attrs.get("units") == "kN.cm":       # T_r of an SPR leg is 0 up to round-off
            scale = max(scale, 1e6)               # of the load's 1e6 N.mm
        np.testing.assert_allclose(y, x, rtol=1e-8, atol=1e-9 * scale, equal_nan=True,
                                   err_msg=k)
    assert cm.sizes["crossing"] > 0


def test_2sps2spr_map_statics_equal_independent_j():
    ds = screwkit.map("2SPS+2SPR", {"alpha": (-5, 10, 4), "gamma": (0, 6, 3)},
                      fix={"beta": 3, "Zo": 80}, degrees=True, locus=False)
    F, T = np.array([-20.0, -30, -60]), np.array([-30.0, -30, 100])
    labels = ["F_a1", "F_a2", "F_a3", "F_a4", "F_c2", "F_c3"]
    for al in ds.alpha.values:
        for ga in ds.gamma.values:
            J, o = _j_2sps2spr(np.radians(al), np.radians(3), np.radians(ga), 80.0)
            # the workload acts at o: about O its moment is T + o x F
            fr = -np.linalg.solve(J.T, np.r_[F, T + np.cross(o, F)])
            cell = ds.sel(alpha=al, gamma=ga)
            got = np.array([float(cell[k]) for k in labels])
            np.testing.assert_allclose(got, fr, rtol=1e-9, atol=1e-9 * np.abs(fr).max())
            np.testing.assert_allclose([float(cell.Xo), float(cell.Yo)], o[:2], atol=1e-9)


_MOVED_BASE = """units: {length: cm, force: kN}
pms:
  S2z:
    string: 2SPS+2SPR
    dimensions: {L: 100, l1: 60, l2: 50}
    base: {shape: square, side: L, z: -10}
    platform: {shape: rectangle, sides: [l1, l2]}
    legs:
      - SPS
      - {leg: SPR, axes: {R3: {platform_toward: [a3, a1]}}}
      - {leg: SPR, axes: {R3: {platform_toward: [a4, a2]}}}
      - SPS
    euler: XYX
    independent: [alpha, beta, gamma, Zo]
    home: {alpha: 0, beta: 0, gamma: 0, Zo: 0.8*L-10}
    pose: {alpha: 4, beta: 3, gamma: 2, Zo: 0.8*L-10}
    dof: 4
"""


def _base_moved_maps(tmp_path):
    """The 2SPS+2SPR and the same machine with its base frame 10 cm higher (base plane at
    z = -10, Zo 10 cm less): the same poses and loads (at o), physically."""
    path = tmp_path / "moved.yaml"
    path.write_text(_MOVED_BASE, encoding="utf-8")
    grid = {"alpha": (-10, 30, 9), "gamma": (-5, 5, 3)}
    a = screwkit.map("2SPS+2SPR", grid, fix={"beta": 2, "Zo": 75}, degrees=True)
    b = screwkit.map(f"{path}#S2z", grid, fix={"beta": 2, "Zo": 65}, degrees=True, **PAPER_LOAD)
    return a, b


def test_map_is_invariant_under_a_base_frame_move(tmp_path):
    a, b = _base_moved_maps(tmp_path)
    assert a.sizes["crossing"] == b.sizes["crossing"] > 0
    for k, v in a.data_vars.items():
        if k in ("amplification", "level", "locus_condition_number"):
            continue                  # checked in the next test; cond ~ 1e9 at a crossing
        x, y = v.values.astype(float), b[k].values.astype(float)
        if k == "locus_Zo":
            x = x - 10.0                                  # the frame moved up by 10 cm
        np.testing.assert_allclose(y, x, rtol=1e-8, atol=1e-8 * max(1.0, np.nanmax(np.abs(x))),
                                   equal_nan=True, err_msg=k)


def test_trust_level_is_invariant_under_a_base_frame_move(tmp_path):
    a, b = _base_moved_maps(tmp_path)
    np.testing.assert_allclose(b["amplification"].values, a["amplification"].values,
                               rtol=1e-9)
    assert np.array_equal(a["level"].values, b["level"].values)


# --- sizing: linear in the load ---------------------------------------------------------

def test_sizing_over_workloads_equals_superposed_unit_maps():
    grid, fix = {"alpha": (-10, 10, 3), "beta": (-10, 10, 3)}, {"Zo": 80}
    loads = [("paper", [-20, -30, -60], [-30, -30, 100]), ("lift", [0, 0, -100], [0, 0, 0]),
             ("twist", [5, 0, 0], [0, 0, 400])]
    sz = screwkit.size("3RRPRR", grid, fix, workloads=loads, degrees=True)
    unit = []
    for j in range(6):
        w = np.eye(6)[j]
        unit.append(screwkit.map("3RRPRR", grid, fix, degrees=True, force=w[:3],
                                 torque=w[3:], locus=False))
    use = unit[0]["ok"].values
    for row in sz.rows:
        best = (-1.0, None, None)
        for name, F, T in loads:
            W = np.r_[F, T]
            v = sum(W[j] * unit[j][row["name"]].values for j in range(6))
            a = np.where(use, np.abs(v), -1.0)
            i = np.unravel_index(np.argmax(a), a.shape)
            if a[i] > best[0]:
                best = (a[i], name, float(v[i]))
        assert row["workload"] == best[1], row["name"]
        assert row["max_abs"] == pytest.approx(best[0], rel=1e-9)
        assert row["value"] == pytest.approx(best[2], rel=1e-9)


def test_workloads_csv_files(tmp_path):
    good = tmp_path / "bom.csv"                 # a spreadsheet's "CSV UTF-8" has a BOM
    good.write_bytes(b"\xef\xbb\xbfFx,Fy,Fz,Tx,Ty,Tz,name\n1,2,-3,4,5,6,up\n")
    (name, F, T), = read_workloads(good)
    assert name == "up" and F.tolist() == [1, 2, -3] and T.tolist() == [4, 5, 6]
    cases = {"long.csv": ("Fx,Fy,Fz,Tx,Ty,Tz\n0,0,-1,0,0,0\n0,0,-1,0,0,0,9\n",
                          "long.csv, line 3: 7 fields, but the header has 6"),
             "short.csv": ("Fx,Fy,Fz,Tx,Ty,Tz\n0,0,-1,0,0\n",
                           "short.csv, line 2: 5 fields, but the header has 6"),
             "huge.csv": ("Fx,Fy,Fz,Tx,Ty,Tz\n0,0,1e300,0,0,0\n",
                          "huge.csv, line 2, column Fz: 1e300 is beyond the limit"),
             "semi.csv": ("Fx;Fy;Fz;Tx;Ty;Tz\n0;0;-1;0;0;0\n", "separated by commas")}
    for fname, (text, msg) in cases.items():
        p = tmp_path / fname
        p.write_text(text, encoding="utf-8")
        with pytest.raises(InputError) as exc:
            read_workloads(p)
        assert msg in str(exc.value)
        assert "\n" not in str(exc.value)


# --- forward kinematics -----------------------------------------------------------------

def test_3rrprr_forward_equals_an_independent_solve():
    E, e = 120 / np.sqrt(3), 60 / np.sqrt(3)
    th = np.radians([-30, 90, 210])
    A = np.c_[E * np.cos(th), E * np.sin(th), 0 * th]
    p = np.c_[e * np.cos(th), e * np.sin(th), 0 * th]
    target = np.array([80.0, 85.0, 90.0])

    def eqs(x):
        Xo, Yo, Zo, al, be, ga = x
        R = Rotation.from_euler("XYX", [al, be, ga]).as_matrix()
        a = np.array([Xo, Yo, Zo]) + p @ R.T
        out = []
        for k in range(3):      # R1 (along A->O through A) meets the platform normal at a
            d = a[k] - A[k]
            out.append(d @ np.cross(-A[k] / E, R[:, 2]) / np.linalg.norm(d))
        return np.r_[out, (np.linalg.norm(a - A, axis=1) - target) / 80.0]

    ref = least_squares(eqs, [0, 0, 80, 0, 0, 0], xtol=1e-15, ftol=1e-15, gtol=1e-15)
    assert np.max(np.abs(ref.fun)) < 1e-12
    fk = screwkit.forward("3RRPRR", {"r1": 80, "r2": 85, "r3": 90})
    assert bool(fk.success[0])
    got = fk.pose(0, degrees=False)
    np.testing.assert_allclose([got[k] for k in ("Xo", "Yo", "Zo")], ref.x[:3], atol=1e-8)
    np.testing.assert_allclose([got[k] for k in ("alpha", "beta", "gamma")], ref.x[3:],
                               atol=1e-10)


# --- CLI arguments ----------------------------------------------------------------------

def _cli(*args):
    return subprocess.run([sys.executable, "-m", "screwkit", *args], capture_output=True,
                          text=True, timeout=120, env={"MPLBACKEND": "Agg", "PATH": ""})


def test_cli_refuses_meaningless_plot_and_thread_arguments(tmp_path):
    for args, msg in [(["--at", "alpha=3", "--plot", str(tmp_path / "a.png")], "3-D map"),
                      (["--threads", "0"], "--threads")]:
        r = _cli("map", "3RRPRR", "--grid", "alpha=-5:5:3", "-q", *args)
        assert r.returncode == 2, r.stderr
        assert msg in r.stderr and len(r.stderr.strip().splitlines()) == 1
        assert not (tmp_path / "a.png").exists()


def test_a_default_fixed_angle_is_shown_as_declared_and_solved_as_analyze():
    """The catalog declares beta = -3 deg for the 3RRPRR: the map shows -3.0 (not
    -3.0000000000000004) and its cells are analyze's at the default pose, bit for bit."""
    m = screwkit.load_pm("3RRPRR")
    ds = screwkit.map(m, {"alpha": [2.0]}, degrees=True, locus=False, **PAPER_LOAD)
    assert float(ds["beta"]) == -3.0
    one = screwkit.analyze(m, {"alpha": np.radians(2.0), "beta": m.default_pose["beta"],
                               "Zo": m.default_pose["Zo"]}, **PAPER_LOAD)
    assert float(ds["F_a1"][0]) == float(np.ravel(one.statics.values)[0])


def test_cli_fk_refuses_impossible_actuator_values():
    """|a_i - A_i| >= 0 by definition: r1 = -80 is no extension (the engine alone returns a
    pose with r1 = +80 and success); 1e300 cm would overflow the Newton iteration."""
    for act, msg in [("r1=-80,r2=85,r3=90", "must be positive"),
                     ("r1=1e300,r2=85,r3=90", "beyond the limit")]:
        r = _cli("fk", "3RRPRR", "--actuators", act)
        assert r.returncode == 2 and msg in r.stderr, r.stderr
        assert len(r.stderr.strip().splitlines()) == 1
    r = _cli("fk", "3RRPRR", "--actuators", "r1=80,r2=85,r3=90", "--json")
    assert r.returncode == 0
    import json
    ext = json.loads(r.stdout)["solutions"][0]["extensions"]
    np.testing.assert_allclose(ext, [80, 85, 90], rtol=1e-12)


def test_workloads_files_name_only_loads_once_each(tmp_path):
    from screwkit.maps._sizing import read_workloads
    extra = tmp_path / "extra.csv"
    extra.write_text("Fx,Fy,Fz,Tx,Ty,Tz,Fzz\n1,0,0,0,0,0,3\n")
    with pytest.raises(screwkit.InputError, match="unknown column.*'Fzz'"):
        read_workloads(extra)
    twice = tmp_path / "twice.csv"
    twice.write_text("Fx,Fy,Fz,Tx,Ty,Tz,name\n1,0,0,0,0,0,a\n2,0,0,0,0,0,a\n")
    with pytest.raises(screwkit.InputError, match="line 3: workload name 'a' is given twice"):
        read_workloads(twice)
    good = tmp_path / "good.csv"
    good.write_text("name,Fx,Fy,Fz,Tx,Ty,Tz\na,1,0,0,0,0,0\nb,2,0,0,0,0,0\n")
    assert [n for n, _, _ in read_workloads(good)] == ["a", "b"]


def test_map_marks_an_indeterminate_pms_least_norm_extremes(capsys):
    """4UPU: eight rows for six freedoms.  A row's extreme is fixed by statics exactly where
    no vector of the null space of J^T at its pose (numpy's SVD) loads it; `screwkit map`
    marks the others (text *, JSON determined False), as `size` and `trajectory` do."""
    import json

    import screwkit
    from screwkit.cli import main
    args = ["map", "4UPU", "--grid", "gamma=-2:2:3", "--force", "0,0,-1", "--torque",
            "0.1,0,0"]
    assert main(args + ["--json"]) == 0
    out = json.loads(capsys.readouterr().out)
    pm = screwkit.load_pm("4UPU")
    rows = [r for r in out["extremes"]["rows"] if not r["name"].startswith("T_r")]
    assert rows and all(r["determined"] is not None for r in rows)
    for r in rows:
        an = screwkit.analyze(pm, r["pose"], degrees=True, force=[0, 0, -1],
                              torque=[0.1, 0, 0])
        labels = list(an.jacobian.labels)
        _, sv, Vt = np.linalg.svd(np.asarray(an.jacobian.matrix).reshape(-1, 6).T)
        null = Vt[int(np.sum(sv > 1e-9 * sv[0])):]
        loaded = np.abs(null[:, labels.index(r["name"])]).max(initial=0.0) > 1e-9
        assert r["determined"] is (not loaded), r["name"]
    assert any(r["determined"] is False for r in rows)
    assert main(args) == 0
    text = capsys.readouterr().out
    starred = [ln.split()[0] for ln in text.splitlines() if "*" in ln and "at " in ln]
    assert starred == [r["name"] for r in out["extremes"]["rows"] if r["determined"] is False]
    assert "least-norm value" in text
