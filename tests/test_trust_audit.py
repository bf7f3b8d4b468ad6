"""Issue 10 audit: every number canonical, in units and flagged.

Independent references used here:

* invariance: the same PM in a random rigid base frame (its rows must be the old rows moved
  by that frame, value for value) and with every length multiplied by 1000 (forces equal,
  torques 1000 times larger), to 1e-9 of the pose's largest effort;
* continuity: neighbouring samples of 1000-sample paths (no jump, swap or sign flip), and the
  same poses solved one by one (a map) giving the same values as the tracked path;
* leg resultants recomputed here from the row values and the rows of J; ``T_r`` as the
  resultant's moment about ``A_i`` along ``delta_i``; the 4UPU's self-stresses from an SVD
  of ``J^T`` computed here;
* motion types counted here from the independent pose parameters;
* symmetry: the legs of the 3SPR, turned by 120 degrees onto each other at home, have the
  same constraint signs;
* the singular surface of the 2SPS+2SPR located here by root finding on ``det J``;
* docs/conventions.md's sign table against the engine's row templates.
"""

from __future__ import annotations

import json
import re
import zlib
from pathlib import Path

import numpy as np
import pytest
from scipy.linalg import null_space
from scipy.optimize import brentq
from scipy.spatial.transform import Rotation

import screwkit
from screwkit.cli import main
from screwkit.engine import PAPER_FORCE, PAPER_TORQUE
from screwkit.pm import load_pm, pm_names

# the paper's workload, stated (only 3RRPRR and 2SPS+2SPR declare it as their default)
PAPER_LOAD = {"force": (-20.0, -30.0, -60.0), "torque": (-30.0, -30.0, 100.0)}
PAPER_ARGS = ["--force=-20,-30,-60", "--torque=-30,-30,100"]

F0, T0 = np.array(PAPER_FORCE, float), np.array(PAPER_TORQUE, float)
LENGTHS = ("Xo", "Yo", "Zo")


def _torque_rows(info):
    return np.array([r.member == "couple" or (r.kind == "actuation" and
                                              (r.joint or "P")[0] in "RH") for r in info])


def _random_poses(pm, n, rng):
    c = pm.default_pose
    z = abs(c.get("Zo", 0.0)) or 1.0
    return {p: c[p] + (rng.uniform(-0.05, 0.05, n) * z if p in LENGTHS
                       else np.radians(rng.uniform(-5, 5, n))) for p in pm.independent}


def _resultants(st, A):
    """Each leg's constraint resultant from the row values and J (by hand): (N, n, 3) x 2."""
    J, v = st.jacobian.matrix, st.values
    info = st.jacobian.info
    n = len(A)
    f = np.zeros(v.shape[:1] + (n, 3))
    m = np.zeros_like(f)
    for k, r in enumerate(info):
        if r.kind == "actuation":
            continue
        w = v[:, k, None] * J[:, k]
        f[:, r.leg] += w[:, :3]
        m[:, r.leg] += w[:, 3:] - np.cross(A[r.leg], w[:, :3])
    return f, m


# --------------------------------------------------------------------------- invariance

@pytest.mark.parametrize("name", pm_names())
def test_every_printed_value_is_invariant_under_a_random_frame_and_times_1000(name):
    pm = load_pm(name)
    rng = np.random.default_rng(zlib.crc32(name.encode()))
    pose = _random_poses(pm, 20, rng)
    ref = screwkit.analyze(pm, pose, **PAPER_LOAD)
    R = Rotation.random(random_state=int(rng.integers(1 << 31))).as_matrix()
    p = rng.uniform(-500, 500, 3)
    moved_pm = pm.moved(R, p)
    moved = screwkit.analyze(moved_pm, pose, force=R @ F0, torque=R @ T0)
    k = 1000.0
    big = load_pm(name, {d: v * k for d, v in pm.dimensions.items()})
    scaled = screwkit.analyze(big, {q: (v * k if q in LENGTHS else v) for q, v in pose.items()},
                              force=F0, torque=T0 * k)
    ok = ref.ok
    assert ok.sum() >= 15, (name, ok.sum())
    assert np.array_equal(moved.ok, ok) and np.array_equal(scaled.ok, ok)
    st, sm, ss = ref.statics, moved.statics, scaled.statics
    torque = _torque_rows(ref.jacobian.info)
    L = ref.jacobian.conditioning.length[:, None]
    v0 = st.values
    # the pose's largest effort in consistent units (torques over the characteristic length)
    size = np.nanmax(np.abs(v0) / np.where(torque, L, 1.0), axis=1)[:, None]
    tol = 1e-9 * size * np.where(torque, L, 1.0)                       # (N, m)
    assert np.all(np.abs(sm.values - v0)[ok] <= tol[ok]), name
    assert np.all(np.abs(ss.values / np.where(torque, k, 1.0) - v0)[ok] <= tol[ok]), name
    # the vectors on their lines turn with the frame
    vt = np.where(torque[None, :, None], L[..., None], 1.0)
    rot = np.einsum("ij,nmj->nmi", R, st.vectors)
    assert np.all((np.abs(sm.vectors - rot) / vt)[ok] <= 1e-9 * size[ok][..., None]), name
    # T_r (a torque) and each leg's resultant: force and moment about A_i
    Lm = L[:, 0]
    assert np.all((np.abs(sm.T_r - st.T_r) / Lm[:, None])[ok] <= 1e-9 * size[ok]), name
    assert np.all((np.abs(ss.T_r / k - st.T_r) / Lm[:, None])[ok] <= 1e-9 * size[ok]), name
    A = np.array([lg.A for lg in pm.home_legs])
    f0, m0 = _resultants(st, A)
    f1, m1 = _resultants(sm, np.array([lg.A for lg in moved_pm.home_legs]))
    f2, m2 = _resultants(ss, A * k)
    s3 = size[ok][..., None]
    assert np.all(np.abs(f1 - np.einsum("ij,nlj->nli", R, f0))[ok] <= 1e-9 * s3)
    assert np.all((np.abs(m1 - np.einsum("ij,nlj->nli", R, m0)) / Lm[:, None, None])[ok]
                  <= 1e-9 * s3)
    assert np.all(np.abs(f2 - f0)[ok] <= 1e-9 * s3)
    assert np.all((np.abs(m2 / k - m0) / Lm[:, None, None])[ok] <= 1e-9 * s3)


# --------------------------------------------------------------------------- continuity

def _steps_are_smooth(v, scale=None):
    """No jump: every step is at most 3x the largest neighbouring step (a swap or sign flip
    between two samples is hundreds of typical steps) and at most 2 % of the row's range.
    Rows that are zero to rounding (e.g. T_r of an SPU leg) are skipped."""
    v = v[:, np.abs(v).max(axis=0) > 1e-9 * (scale or np.abs(v).max())]
    if not v.size:
        return
    d = np.abs(np.diff(v, axis=0))
    rng = np.ptp(v, axis=0) + 1e-12 * np.abs(v).max()
    assert np.all(d.max(axis=0) <= 0.02 * np.maximum(rng, np.abs(v).max(axis=0))), \
        (d.max(axis=0), rng)
    nb = np.maximum(np.r_[d[1:2], d[:-1]], np.r_[d[1:], d[-2:-1]])
    big = d > 3 * nb + 1e-9 * np.abs(v).max()
    assert not big.any(), np.argwhere(big)[:5]


# amplitudes (deg, fraction of Zo) that stay on the default pose's side of every singular
# surface: the 3SPU+SP's default pose is a few degrees from its singular home
@pytest.mark.parametrize("name, deg, frac", [("3SPU+SP", 1.5, 0.03), ("3SPU+PRRR", 4.0, 0.1)])
def test_per_row_values_are_continuous_over_1000_samples_path_or_map(name, deg, frac):
    pm = load_pm(name)
    s = np.linspace(0.0, 1.0, 1000)
    c = pm.default_pose
    pose = {}
    for j, p in enumerate(pm.independent):
        if p in LENGTHS:
            pose[p] = c[p] + frac * abs(c.get("Zo", 1.0)) * np.sin(2 * np.pi * s + j)
        else:
            pose[p] = c[p] + np.radians(deg) * np.sin(2 * np.pi * s + j)
    path = screwkit.analyze(pm, pose, path=True, **PAPER_LOAD)
    grid = screwkit.analyze(pm, pose, **PAPER_LOAD)                 # every pose on its own, as in a map
    assert path.ok.all() and grid.ok.all()
    assert not path.quality.beyond_singular_surface.any()
    np.testing.assert_allclose(grid.statics.values, path.statics.values, rtol=0,
                               atol=1e-9 * np.abs(path.statics.values).max())
    _steps_are_smooth(path.statics.values)
    d = path.jacobian.directions
    assert np.min(np.sum(d[1:] * d[:-1], axis=-1)) > 0.99      # no direction flips
    L = float(np.max(path.jacobian.conditioning.length))
    _steps_are_smooth(path.statics.T_r, np.abs(path.statics.values).max() * L)


def test_3spu_sp_zo_steps_of_0025_move_the_forces_a_little():
    """The issue's case: the SP leg's two forces over 0.025 cm steps of Zo."""
    pm = load_pm("3SPU+SP")
    c = pm.default_pose
    zo = c["Zo"] + np.arange(-500, 500) * 0.025
    pose = {p: (zo if p == "Zo" else np.full(zo.shape, c[p])) for p in pm.independent}
    res = screwkit.analyze(pm, pose, **PAPER_LOAD)
    assert res.ok.all()
    cons = [k for k, r in enumerate(res.jacobian.info) if r.kind == "force"]
    assert len(cons) == 2
    v = res.statics.values[:, cons]
    _steps_are_smooth(v)
    assert np.abs(np.diff(v, axis=0)).max() < 0.05             # kN per 0.025 cm step


# --------------------------------------------------------------------------- resultants

def test_leg_resultants_in_text_and_json(capsys):
    assert main(["analyze", "3SPU+SP", "--json", *PAPER_ARGS]) == 0
    d = json.loads(capsys.readouterr().out)
    J = np.array(d["jacobian"])
    v = np.array(d["statics"]["values"])
    legs = d["legs"]
    # the rows of J: one actuation row per leg, then each leg's constraint rows (leg order)
    row_leg = list(range(len(legs))) + [i for i, leg in enumerate(legs)
                                        for _ in leg["constraints"]]
    for i, leg in enumerate(legs):
        A = np.array(leg["A"])
        w = sum(v[k] * J[k] for k in range(len(legs), len(v)) if row_leg[k] == i) \
            if leg["constraints"] else np.zeros(6)
        r = leg["constraint_resultant"]
        assert r["about"] == f"A{i + 1}" and r["force_unit"] == "kN" and r["moment_unit"] == "kN.cm"
        np.testing.assert_allclose(r["force"], w[:3], atol=1e-9 * np.abs(v).max())
        np.testing.assert_allclose(r["moment"], w[3:] - np.cross(A, w[:3]),
                                   atol=1e-9 * np.abs(v).max() * 100)
        delta = (np.array(leg["a"]) - A) / np.linalg.norm(np.array(leg["a"]) - A)
        assert r["moment"] @ delta == pytest.approx(leg["torque"], abs=1e-9 * 100 * np.abs(v).max())
        assert r["force_determined"] and r["moment_determined"]
    assert main(["analyze", "3SPU+SP", *PAPER_ARGS]) == 0
    text = capsys.readouterr().out
    assert "constraint resultant" in text and "moment about A4" in text and "(kN.cm)" in text


def test_4upu_resultant_moments_are_flagged_and_a_self_stress_moves_them(capsys):
    assert main(["analyze", "4UPU", "--json", *PAPER_ARGS]) == 0
    d = json.loads(capsys.readouterr().out)
    J = np.array(d["jacobian"])
    S = null_space(J.T).T                                # self-stresses, here by SVD
    assert S.shape[0] == d["statics"]["indeterminacy"] == 2
    for i, leg in enumerate(d["legs"]):
        r = leg["constraint_resultant"]
        assert r["force_determined"] and not r["moment_determined"]
        k = 4 + i                                        # the leg's couple row
        assert np.abs(S[:, k]).max() > 1e-3              # a self-stress moves it
    assert main(["analyze", "4UPU", *PAPER_ARGS]) == 0
    text = capsys.readouterr().out
    lines = [ln for ln in text.splitlines() if ln.startswith("  leg ") and "moment about A" in ln]
    assert len(lines) == 4 and all(ln.rstrip().endswith("*") for ln in lines)


# --------------------------------------------------------------------------- 4UPU via the CLI

def test_4upu_compliance_weighted_from_the_command_line(capsys):
    k = {"F_a1": 1e3, "F_a2": 1e3, "F_a3": 1e3, "F_a4": 1e3,
         "T_c1": 1e6, "T_c2": 4e6, "T_c3": 2e6, "T_c4": 9e6}
    args = [f"--stiffness={lab}={val}" for lab, val in k.items()]
    assert main(["analyze", "4UPU", "--json", *PAPER_ARGS]) == 0
    ln = json.loads(capsys.readouterr().out)
    assert main(["analyze", "4UPU", "--json", *args, *PAPER_ARGS]) == 0
    cw = json.loads(capsys.readouterr().out)
    assert ln["statics"]["solution"] == "least-norm"
    assert cw["statics"]["solution"] == "compliance-weighted"
    J = np.array(cw["jacobian"])
    x = np.array(cw["statics"]["values"])
    o = np.array([cw["pose"][p] for p in LENGTHS])
    W = np.r_[F0, T0 + np.cross(o, F0)]
    np.testing.assert_allclose(J.T @ x, -W, atol=1e-9 * np.abs(W).max() * 100)     # balances
    kk = np.array([k[lab] for lab in cw["statics"]["labels"]])
    S = null_space(J.T).T
    opt = S @ (x / kk)                                   # optimality: x/k orthogonal to S
    assert np.abs(opt).max() <= 1e-9 * np.abs(S).max() * np.abs(x / kk).max()
    assert np.abs(x - np.array(ln["statics"]["values"])).max() > 1.0             # differs
    assert cw["statics"]["determined"] == [True] * 4 + [False] * 4


# --------------------------------------------------------------------------- units

def _panel_labels(fig):
    out = []
    for ax in fig.axes:
        out += [ax.get_ylabel(), ax.get_title()]
        leg = ax.get_legend()
        if leg is not None:
            out += [t.get_text() for t in leg.get_texts()]
    return out


@pytest.mark.parametrize("name, expr, want", [
    ("3RRPRR", ["alpha=5*sin(2*pi*t)", "beta=-3", "Zo=80"], ("F_{ai}", "[kN]")),
    ("3UPU", ["Xo=3*sin(2*pi*t)", "Yo=2", "Zo=58"], ("T_{c", "kN·cm")),
])
def test_plot_labels_of_a_linear_pm_and_a_pm_with_couples(tmp_path, name, expr, want):
    pytest.importorskip("matplotlib")
    from screwkit.paths import path_from_expressions, run_trajectory
    pm = load_pm(name)
    path = path_from_expressions(expr, pm.independent, samples=9)
    fig = run_trajectory(pm, path, **PAPER_LOAD).plot()              # the figure, not written
    labels = _panel_labels(fig)
    ylabels = [ax.get_ylabel() for ax in fig.axes]
    assert any("[kN]" in y for y in ylabels), ylabels
    assert any("[cm]" in y for y in ylabels), ylabels
    assert any(want[0] in lab for lab in labels) and any(want[1] in y for y in ylabels), labels


def test_couples_in_text_carry_torque_units(capsys):
    assert main(["analyze", "3UPU", *PAPER_ARGS]) == 0
    text = capsys.readouterr().out
    rows = [ln for ln in text.splitlines() if ln.startswith("  leg ") and "constraint couple" in ln]
    assert len(rows) == 3 and all(" kN.cm " in ln and ln.rstrip().endswith("kN.cm") for ln in rows)
    act = [ln for ln in text.splitlines() if " active " in ln]
    assert len(act) == 3 and all(" kN " in ln for ln in act)


def test_rotary_trajectory_reports_no_T_r(tmp_path, capsys):
    pytest.importorskip("matplotlib")
    from screwkit.paths import path_from_expressions, run_trajectory
    pm = load_pm("3RSR")
    res = run_trajectory(pm, path_from_expressions(["alpha=2*sin(2*pi*t)", "beta=-1", "Zo=40"],
                                                   pm.independent, samples=9), **PAPER_LOAD)
    assert not any(name.startswith("T_r") for name, _ in res.columns())
    assert res.to_dict()["T_r"] == [None, None, None]
    fig = res.plot()
    assert not any("T_{r" in lab for lab in _panel_labels(fig))


# --------------------------------------------------------------------------- motion type

def _count(pm):
    t = sum(p in LENGTHS for p in pm.independent)
    r = len(pm.independent) - t
    return (f"{t}T" if t else "") + (f"{r}R" if r else "")


@pytest.mark.parametrize("name", pm_names())
def test_the_finite_motion_type_is_the_parametrisations_at_every_pose(name):
    pm = load_pm(name)
    assert pm.motion == _count(pm)                       # the catalog states the same
    res = screwkit.analyze(pm, _random_poses(pm, 2, np.random.default_rng(3)),
                           raise_on_singular=False, **PAPER_LOAD)
    params = res.solution.params
    L = float(pm.normalisation.length)
    for i in range(len(res)):
        m = res[i].mobility
        assert m.motion_type == _count(pm)
        assert m.finite.startswith(_count(pm) + ": independent " + ", ".join(pm.independent))
        # the parasitic motions are the dependent parameters that vary with the others
        # (computed from the finite motion: a translational PM has none; the translations
        # of a spherical PM are its rotations about the fixed point, not parasitic)
        named = m.finite.split("parasitic motion ")[1].split(" (")[0].split(", ") \
            if "; parasitic motion " in m.finite else []
        fixed_point = "a base-fixed point" in m.finite
        for p in pm.dependent:
            scale = 1.0 if p in ("alpha", "beta", "gamma") else L
            if fixed_point and p in LENGTHS:
                continue
            if np.ptp(np.asarray(params[p], float)) > 1e-6 * scale:
                assert p in named, (p, m.finite)


# --------------------------------------------------------------------------- signs

def test_the_3spr_legs_have_symmetric_constraint_signs():
    pm = load_pm("3SPR")
    res = screwkit.analyze(pm, {p: pm.home_pose[p] for p in pm.independent}, **PAPER_LOAD)
    legs = res.solution.legs
    rows = [r for r in res.jacobian.rows if r.kind == "force"]
    for i, j in ((0, 1), (1, 2), (2, 0)):
        t = np.arctan2(legs[j].A[1], legs[j].A[0]) - np.arctan2(legs[i].A[1], legs[i].A[0])
        Rz = Rotation.from_euler("z", t).as_matrix()
        np.testing.assert_allclose(Rz @ legs[i].a, legs[j].a, atol=1e-9)   # symmetric legs
        assert (Rz @ rows[i].direction) @ rows[j].direction > 1 - 1e-9
        R3 = legs[j].joint("R3").direction
        assert rows[j].direction @ R3 > 1 - 1e-9            # along the R axis (the convention)


def test_the_conventions_table_states_every_catalog_legs_sign():
    from screwkit.engine._pipeline import templates_of
    doc = (Path(__file__).resolve().parent.parent / "docs" / "conventions.md").read_text()
    table = {}
    for ln in doc.split("## Signs of the Jacobian rows")[1].split("## ")[0].splitlines():
        cells = [c.strip() for c in ln.strip().strip("|").split("|")]
        if len(cells) == 4 and cells[0] not in ("leg", "---"):
            table[cells[0]] = cells
    seen = {}
    for name in pm_names():
        pm = load_pm(name)
        for lg, t in zip(pm.home_legs, templates_of(pm)):
            seen.setdefault(lg.name, set()).add(
                tuple(r if isinstance(r, str) else
                      " x ".join({"base.OA": "OA"}.get(x, x) for x in r["perpendicular"])
                      for g in t.groups for r in g.refs))
            if not t.groups:
                continue
            row = table.get(lg.name)
            assert row is not None, f"docs/conventions.md: no sign for {lg.name}"
            assert name in row[3], (lg.name, name)
    for leg, refs in seen.items():
        assert len(refs) == 1, f"{leg}: different conventions in different PMs {refs}"
        refs = next(iter(refs))
        if not refs:
            continue
        said = table[leg][2]
        for r in refs:
            word = {"leg": "the leg"}.get(r, r)
            assert word in said, (leg, r, said)


# --------------------------------------------------------------------------- conditioning

def test_the_documented_thresholds_are_the_engines():
    from screwkit.engine import _quality as q
    from screwkit.engine import COND_THRESHOLD
    doc = (Path(__file__).resolve().parent.parent / "docs" / "conventions.md").read_text()
    sec = doc.split("## Conditioning levels and assembly mode")[1].split("\n## ")[0]
    assert f"> {q.ILL_CONDITIONED_COND:g} (`ILL_CONDITIONED_COND`)" in sec
    assert f"> {q.NEAR_SINGULAR_COND:g} (`NEAR_SINGULAR_COND`)" in sec
    assert f"> {q.ILL_CONDITIONED_AMPLIFICATION:g} (`ILL_CONDITIONED_AMPLIFICATION`)" in sec
    assert f"> {q.NEAR_SINGULAR_AMPLIFICATION:g} (`NEAR_SINGULAR_AMPLIFICATION`)" in sec
    assert COND_THRESHOLD == 1e8 and "> 1e8 (`COND_THRESHOLD" in sec


@pytest.mark.parametrize("name", pm_names())
def test_the_default_pose_is_in_the_reference_assembly_mode(name):
    pm = load_pm(name)
    home = screwkit.analyze(pm, {p: pm.home_pose[p] for p in pm.independent},
                            raise_on_singular=False, **PAPER_LOAD)
    res = screwkit.analyze(pm, raise_on_singular=False, **PAPER_LOAD)
    q = res.quality
    J = res.jacobian.J
    if J.shape != (6, 6):
        assert q.home_det_sign == 0 and q.reference == "none"
        return
    s_home = np.linalg.svd(home.jacobian.J, compute_uv=False)
    singular_home = bool(home.jacobian.singular)
    assert q.reference == ("default" if singular_home else "home")
    if singular_home:       # the sign of det J there would be rounding noise
        assert s_home[-1] < 1e-6 * s_home[0]
        assert q.home_det_sign == int(np.sign(np.linalg.det(J)))
    else:
        assert q.home_det_sign == int(np.sign(np.linalg.det(home.jacobian.J)))
    assert not q.beyond_singular_surface[0]
    assert not any("beyond a singular surface" in w for w in res.warnings)


def _sps_singular_sum():
    pm = load_pm("2SPS+2SPR")

    def det(x):
        r = screwkit.analyze(pm, {"alpha": x / 2, "beta": 0.0, "gamma": x / 2, "Zo": 75.0},
                             raise_on_singular=False, **PAPER_LOAD)
        return np.linalg.det(r.jacobian.J)

    return np.degrees(brentq(det, np.radians(15), np.radians(18), xtol=1e-15))


def test_2sps_2spr_at_a_hundredth_of_a_degree_from_its_singularity(capsys):
    x0 = _sps_singular_sum()
    for dx, beyond in ((-0.01, False), (0.01, True)):
        half = float(x0 + dx) / 2
        argv = ["analyze", "2SPS+2SPR", f"--pose=alpha={half!r}", "--pose=beta=0",
                f"--pose=gamma={half!r}", "--pose=Zo=75", "--json"]
        assert main(argv) == 0
        out, err = capsys.readouterr()
        d = json.loads(out)
        c = d["conditioning"]
        assert c["level"] == "near-singular" and c["force_amplification"] > 100
        assert c["beyond_singular_surface"] is beyond
        lines = err.strip().splitlines()
        assert any("near-singular pose" in ln for ln in lines)
        assert any("beyond a singular surface" in ln for ln in lines) is beyond
        assert all(ln.startswith("screwkit analyze: warning: ") for ln in lines)


def test_draw_warns_on_stderr(tmp_path, capsys):
    pytest.importorskip("matplotlib")
    x = 16.0
    argv = ["draw", "2SPS+2SPR", f"--pose=alpha={x / 2}", "--pose=beta=0",
            f"--pose=gamma={x / 2}", "--pose=Zo=75", "--dpi=20", "-o", str(tmp_path / "d.png")]
    assert main(argv) == 0
    err = capsys.readouterr().err
    assert re.search(r"screwkit draw: warning: near-singular pose", err), err


def test_the_twist_space_pitch_is_in_the_models_length_unit(capsys):
    assert main(["analyze", "3RRPRR"]) == 0
    line = next(ln for ln in capsys.readouterr().out.splitlines() if "twist space here" in ln)
    assert "pitch" in line and "(cm/rad)" in line and "length/rad" not in line


_UPU_WITH_STIFFNESS = """units: {length: cm, force: kN}
pms:
  4UPU:
    dimensions: {L: 100, l1: 60, l2: 40}
    base: {shape: square, side: L}
    platform: {shape: rectangle, sides: [l1, l2]}
    legs: [UPU/schoenflies, UPU/schoenflies, UPU/schoenflies, UPU/schoenflies]
    euler: XYZ
    independent: [Xo, Yo, Zo, gamma]
    home: {Xo: 0, Yo: 0, Zo: 0.8*L, gamma: 0}
    pose: {Xo: 5, Yo: -3, Zo: 0.8*L, gamma: 10}
    dof: 4
    motion: 3T1R
    dynamics:
      units: model
      stiffness:
        - {actuator: 1.0e3, couple: 1.0e6}
        - {actuator: 1.0e3, couple: 4.0e6}
        - {actuator: 1.0e3, couple: 2.0e6}
        - {actuator: 1.0e3, couple: 9.0e6}
"""


def test_stiffness_from_the_model_equals_the_same_stiffness_given_by_row(tmp_path, capsys):
    f = tmp_path / "upu.yaml"
    f.write_text(_UPU_WITH_STIFFNESS)
    assert main(["analyze", "--model", str(f), "--stiffness", "model", "--json", *PAPER_ARGS]) == 0
    from_model = json.loads(capsys.readouterr().out)["statics"]
    k = {"F_a1": 1e3, "F_a2": 1e3, "F_a3": 1e3, "F_a4": 1e3,
         "T_c1": 1e6, "T_c2": 4e6, "T_c3": 2e6, "T_c4": 9e6}
    by_row = screwkit.analyze("4UPU", stiffness=k, **PAPER_LOAD).statics.values
    assert from_model["solution"] == "compliance-weighted"
    np.testing.assert_allclose(from_model["values"], by_row, rtol=1e-12,
                               atol=1e-12 * np.abs(by_row).max())
    assert main(["analyze", "4UPU", "--stiffness", "model", *PAPER_ARGS]) == 2      # the catalog's has none
    assert "declares no stiffness" in capsys.readouterr().err
