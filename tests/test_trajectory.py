"""Issue 6: trajectories (screwkit.paths, screwkit.engine).

Independent checks, sample by sample:
* the per-pose pipeline (`analyze_pm`, what `screwkit analyze` prints) at the same pose;
* closed forms: the 3RRPRR pose (gamma = alpha, X_o and the corrected Y_o of eq. 11e) and its
  extensions, the 2SPS+2SPR structure constraints (eq. 16a);
* each leg's own joint twists: its total wrench does no work on its passive joints and F_ai on
  the actuated one; the leg wrenches and the workload balance the platform;
* a singular sample located by a root of det of the paper's J built by hand (eqs. 18-19 with
  the corrections of NOTES.md).
"""

import csv
import io
import json

import numpy as np
import pytest
from scipy.optimize import brentq
from scipy.spatial.transform import Rotation

import screwkit
from screwkit.cli._commands._common import dump_json
from screwkit.engine import PAPER_FORCE, PAPER_TORQUE, analyze_pm
from screwkit.errors import InputError, SingularityError, UnreachablePoseError
from screwkit.paths import PathSpec, path_from_csv, path_from_expressions, run_trajectory

# the paper's workload, stated (only 3RRPRR and 2SPS+2SPR declare it as their default)
PAPER_LOAD = {"force": (-20.0, -30.0, -60.0), "torque": (-30.0, -30.0, 100.0)}
PAPER_ARGS = ["--force=-20,-30,-60", "--torque=-30,-30,100"]

F_LOAD, T_LOAD = np.array(PAPER_FORCE), np.array(PAPER_TORQUE)
PATHS = {
    "3RRPRR": ["alpha=8*sin(2*pi*t)", "beta=6*sin(2*pi*t+1)", "Zo=70+20*t"],
    "2SPS+2SPR": ["alpha=4*sin(2*pi*t)", "beta=4*sin(2*pi*t+1)", "gamma=-3*sin(2*pi*t+2)",
                  "Zo=70+20*t"],
}


@pytest.fixture(scope="module")
def models():
    return {name: screwkit.load_pm(name) for name in PATHS}


@pytest.fixture(scope="module")
def runs(models):
    out = {}
    for name, ex in PATHS.items():
        path = path_from_expressions(ex, models[name].independent, samples=33)
        out[name] = (path, run_trajectory(models[name], path, anchor_every=16, **PAPER_LOAD))
    return out


def _close(a, b, scale, rtol=1e-8):
    np.testing.assert_allclose(np.asarray(a, float), np.asarray(b, float), rtol=0,
                               atol=rtol * scale)


# ----------------------------------------------------------------------------- = analyze

@pytest.mark.parametrize("name", list(PATHS))
def test_every_sample_equals_analyze(models, runs, name):
    model = models[name]
    path, res = runs[name]
    assert res.status.tolist() == ["ok"] * len(path)
    # most samples went through the vectorised steps (the point of the test is to check them)
    assert res.diagnostics["batched"] >= len(path) - 3
    assert res.diagnostics["anchors"] < len(path) / 2
    for i in range(len(path)):
        a = analyze_pm(model, path.sample(i), **PAPER_LOAD)      # home start, like `screwkit analyze`
        st, sol = a.statics, a.solution
        fs = np.abs(st.values).max()
        L = model.normalisation.length
        for p in ("Xo", "Yo", "Zo"):
            assert res.params[p][i] == pytest.approx(sol.params[p], abs=1e-9 * L)
        for p in ("alpha", "beta", "gamma"):
            assert res.params[p][i] == pytest.approx(sol.params[p], abs=1e-10)
        _close(res.extensions[i], sol.extensions, L)
        _close(res.actuator_values[i], sol.actuator_values, L)
        _close(res.active[i], st.active, fs)
        _close(res.constraint[i], st.constraint, fs)
        _close(res.T_r[i], st.T_r, fs * L)
        _close(res.leg_wrenches[i], st.leg_wrenches, fs * L)
        assert res.condition_number[i] == pytest.approx(a.jacobian.condition_number, rel=1e-8)
        assert res.equilibrium_residual[i] < 1e-12
        assert res.closure_residual[i] < 1e-10
    kinds = tuple(r.kind for r in a.jacobian.rows if r.kind != "actuation")
    assert res.constraint_kinds == kinds


def test_per_pose_mode_and_refinement_levels_agree(models, runs):
    """vectorised=False (every sample by screwkit.solve + Leg.analyze) and a three-level
    refinement (anchors every 16, then 1) give the same numbers."""
    model = models["3RRPRR"]
    path, ref = runs["3RRPRR"]
    slow = run_trajectory(model, path, vectorised=False, **PAPER_LOAD)
    assert slow.diagnostics["batched"] == 0
    fine = run_trajectory(model, path, anchor_every=4, chunk=8, **PAPER_LOAD)
    for other in (slow, fine):
        assert other.status.tolist() == ref.status.tolist()
        for attr in ("extensions", "active", "constraint", "T_r", "condition_number"):
            a, b = getattr(other, attr), getattr(ref, attr)
            _close(a, b, np.abs(b).max(), rtol=1e-9)


def test_3upu_couples_match_analyze():
    """A PM whose legs exert constraint couples (the couple branch of the row templates)."""
    model = screwkit.load_pm("3UPU")
    path = path_from_expressions(["Xo=5*sin(2*pi*t)", "Yo=-3+4*t", "Zo=60+5*t"],
                                 model.independent, samples=17)
    res = run_trajectory(model, path, anchor_every=8, **PAPER_LOAD)
    assert res.constraint_kinds == ("couple",) * 3 and res.constraint_labels[0] == "T_c1"
    assert res.diagnostics["batched"] == len(path)
    for i in (0, 7, 16):
        st = analyze_pm(model, path.sample(i), **PAPER_LOAD).statics
        _close(res.active[i], st.active, np.abs(st.values).max())
        _close(res.constraint[i], st.constraint, np.abs(st.values).max() * 60)


# ----------------------------------------------------------------------------- closed forms

def test_3rrprr_pose_and_extensions_follow_the_closed_forms(runs):
    """gamma = alpha (eq. 11c), X_o of eq. 11e, Y_o of eq. 11e with its Z_o sign corrected
    (NOTES.md), a_i = R ma_i + o, r_i = |a_i - A_i| (L = 120, l = 60 cm)."""
    path, res = runs["3RRPRR"]
    e = 60.0 / np.sqrt(3)
    E = 120.0 / np.sqrt(3)
    ang = np.radians([-30.0, 90.0, 210.0])
    A = E * np.column_stack([np.cos(ang), np.sin(ang), np.zeros(3)])
    ma = e * np.column_stack([np.cos(ang), np.sin(ang), np.zeros(3)])
    for i in range(len(path)):
        al, be, Z = path.values["alpha"][i], path.values["beta"][i], path.values["Zo"][i]
        sa, ca, sb, cb = np.sin(al), np.cos(al), np.sin(be), np.cos(be)
        den = -sa ** 2 + ca ** 2 * cb
        Xo = (Z * ca + e * sa) * sb / den
        Yo = (-Z * sa * ca * (1 + cb) + e * (cb - ca ** 2 + sa ** 2 * cb) / 2) / den
        assert res.params["gamma"][i] == pytest.approx(al, abs=1e-10)
        assert res.params["Xo"][i] == pytest.approx(Xo, abs=1e-9)
        assert res.params["Yo"][i] == pytest.approx(Yo, abs=1e-9)
        R = Rotation.from_euler("XYX", [al, be, al]).as_matrix()
        a = ma @ R.T + [Xo, Yo, Z]
        np.testing.assert_allclose(res.extensions[i], np.linalg.norm(a - A, axis=1), atol=1e-9)


def _2sps2spr_points(res, i, L=100.0, l1=60.0, l2=50.0):
    A = 0.5 * L * np.array([[1, -1, 0], [1, 1, 0], [-1, 1, 0], [-1, -1, 0]], float)
    ma = 0.5 * np.array([[l1, -l2, 0], [l1, l2, 0], [-l1, l2, 0], [-l1, -l2, 0]], float)
    p = res.params
    R = Rotation.from_euler("XYX", [p["alpha"][i], p["beta"][i], p["gamma"][i]]).as_matrix()
    o = np.array([p["Xo"][i], p["Yo"][i], p["Zo"][i]])
    return A, ma @ R.T + o, o


def test_2sps2spr_poses_satisfy_the_structure_constraints(runs):
    """Eq. 16a: r_2 is perpendicular to a_1 a_3 and r_3 to a_2 a_4 (the SPR legs' R axes)."""
    path, res = runs["2SPS+2SPR"]
    for i in range(len(path)):
        A, a, o = _2sps2spr_points(res, i)
        for k in ("alpha", "beta", "gamma", "Zo"):
            assert res.params[k][i] == pytest.approx(path.values[k][i], abs=1e-12)
        assert abs((a[1] - A[1]) @ (a[0] - a[2])) < 1e-9 * 100 ** 2
        assert abs((a[2] - A[2]) @ (a[1] - a[3])) < 1e-9 * 100 ** 2
        np.testing.assert_allclose(res.extensions[i], np.linalg.norm(a - A, axis=1), atol=1e-9)


# ----------------------------------------------------------------------------- leg equilibrium

@pytest.mark.parametrize("name", list(PATHS))
def test_every_sample_leg_equilibrium_on_the_legs_own_joints(models, runs, name):
    """For each leg: its total wrench (from the trajectory's statics) dotted with the leg's own
    joint twists (Leg.twists of the solved pose) is 0 on passive joints and F_ai on the
    actuated one; the leg wrenches balance the workload."""
    model = models[name]
    path, res = runs[name]
    L = model.normalisation.length
    guess = None
    for k in range(len(path)):
        sol = screwkit.solve(model, path.sample(k), guess=guess)
        guess = sol
        o = sol.position
        W = np.r_[F_LOAD, T_LOAD + np.cross(o, F_LOAD)]
        scale = np.linalg.norm(F_LOAD) * L + np.linalg.norm(T_LOAD) + np.abs(res.active[k]).max() * L
        np.testing.assert_allclose(res.leg_wrenches[k].sum(axis=0) + W, 0.0, atol=1e-9 * scale)
        for i, leg in enumerate(sol.legs):
            work = leg.twists @ res.leg_wrenches[k, i]
            expected = np.zeros(len(work))
            expected[leg.actuated_index] = res.active[k, i]
            np.testing.assert_allclose(work, expected, atol=1e-9 * scale)


# ----------------------------------------------------------------------------- flagged samples

def _paper_det_2sps2spr(model, s):
    """det of the paper's J (eq. 18) at alpha = gamma = s (deg), beta = 0, Zo = 80: rows
    [delta_i; e_i x delta_i] and [c_j; rho_j x c_j] about o, e_i = a_i - o, rho_j = A_j - o,
    c2 = (a1 - a3)/|.|, c3 = (a2 - a4)/|.| (eq. 19 with NOTES.md's corrections)."""
    sol = screwkit.solve(model, {"alpha": s, "beta": 0.0, "gamma": s, "Zo": 80.0}, degrees=True)
    A, a, o = sol.base_points, sol.platform_points, sol.position
    rows = []
    for i in range(4):
        d = (a[i] - A[i]) / np.linalg.norm(a[i] - A[i])
        rows.append(np.r_[d, np.cross(a[i] - o, d)])
    for j, (p, q) in ((1, (0, 2)), (2, (1, 3))):
        c = (a[p] - a[q]) / np.linalg.norm(a[p] - a[q])
        rows.append(np.r_[c, np.cross(A[j] - o, c)])
    return np.linalg.det(np.array(rows))


def test_singular_sample_is_flagged_and_the_run_continues():
    model = screwkit.load_pm("2SPS+2SPR")
    s = brentq(lambda x: _paper_det_2sps2spr(model, x), 6.0, 10.0, xtol=1e-14, rtol=1e-15)
    assert 13.0 / 2 < s < 19.0 / 2                    # NOTES.md: alpha + gamma ~ 13-19 deg
    ang = np.radians([s - 1.0, s - 0.5, s, s + 0.5, s + 1.0])
    path = PathSpec(np.arange(5.0), {"alpha": ang, "beta": np.zeros(5), "gamma": ang,
                                     "Zo": np.full(5, 80.0)})
    res = run_trajectory(model, path, **PAPER_LOAD)
    assert res.status.tolist() == ["ok", "ok", "singular", "ok", "ok"]
    assert res.singularity[2] == "actuation" and res.condition_number[2] > 1e8
    assert "actuation singularity" in res.message[2]
    assert np.all(np.isnan(res.active[2])) and np.all(np.isnan(res.constraint[2]))
    assert np.all(np.isfinite(res.extensions[2]))        # the pose itself is assembled
    with pytest.raises(SingularityError):
        analyze_pm(model, path.sample(2), **PAPER_LOAD)
    # the active forces change sign through the singularity (they pass through infinity)
    assert np.all(np.sign(res.active[1]) == -np.sign(res.active[3]))
    assert res.flagged.tolist() == [False, False, True, False, False]


def test_samples_past_a_singular_surface_and_of_low_trust_say_so():
    # the path of the previous test: the samples past the singularity have det J of the
    # other sign than home's (numpy's determinant of each sample's J), and those whose
    # efforts exceed five times the load (their amplification, recomputed here from F_a
    # and the load) say their trust level
    model = screwkit.load_pm("2SPS+2SPR")
    s = brentq(lambda x: _paper_det_2sps2spr(model, x), 6.0, 10.0, xtol=1e-14, rtol=1e-15)
    ang = np.radians([s - 1.0, s - 0.5, s - 0.05, s + 0.05, s + 0.5, s + 1.0])
    path = PathSpec(np.arange(6.0), {"alpha": ang, "beta": np.zeros(6), "gamma": ang,
                                     "Zo": np.full(6, 80.0)})
    res = run_trajectory(model, path, **PAPER_LOAD)
    home = screwkit.analyze(model, {"alpha": 0.0, "beta": 0.0, "gamma": 0.0, "Zo": 80.0},
                            **PAPER_LOAD)
    sign0 = np.sign(np.linalg.det(home.jacobian.matrix))
    signs = np.sign(np.linalg.det(res.analysis.jacobian.matrix))
    assert (signs != sign0).tolist() == [False, False, False, True, True, True]
    for i in range(6):
        assert ("beyond a singular surface" in res.message[i]) == bool(signs[i] != sign0)
    F, T = np.array(PAPER_LOAD["force"]), np.array(PAPER_LOAD["torque"])
    L = res.analysis.jacobian.conditioning.length
    size = np.sqrt(F @ F + (T @ T) / L ** 2)
    amp = np.max(np.abs(res.active), axis=1) / size
    for i in range(6):
        if res.status[i] == "ok" and amp[i] > 5.0:
            assert "trust level near-singular" in res.message[i]
    assert amp[2] > 5.0 and amp[3] > 5.0             # (the two nearest the singularity)


def test_unreachable_samples_are_flagged_and_the_run_recovers(tmp_path):
    model = screwkit.load_pm("3RRPRR")
    f = tmp_path / "p.csv"
    f.write_text("t,alpha,beta,Zo\n0,20,-3,80\n1,30,-3,80\n2,60,-3,80\n3,70,-3,80\n"
                 "4,30,-3,80\n5,20,-3,80\n")
    path = path_from_csv(f, model.independent)
    res = run_trajectory(model, path, **PAPER_LOAD)
    assert res.status.tolist() == ["ok", "ok", "unreachable", "unreachable", "ok", "ok"]
    with pytest.raises(UnreachablePoseError):
        screwkit.solve(model, path.sample(3))
    for i in (2, 3):
        assert np.isnan(res.params["Xo"][i]) and np.isnan(res.condition_number[i])
        assert res.params["alpha"][i] == pytest.approx(path.values["alpha"][i])  # as given
        assert res.message[i].startswith("unreachable")
    _close(res.active[4], res.active[1], np.abs(res.active[1]).max(), rtol=1e-9)
    assert res.counts() == {"ok": 4, "near-singular": 0, "singular": 0, "unreachable": 2}


def test_representation_singularity_sample_takes_the_continuous_limit():
    """beta = 0 exactly at one sample of a 3RRPRR path: gamma = alpha (the limit, NOTES.md)."""
    model = screwkit.load_pm("3RRPRR")
    t = np.linspace(0.0, 1.0, 9)
    path = PathSpec(t, {"alpha": np.radians(6 * t), "beta": np.radians(4 - 8 * t),
                        "Zo": 80 + 0 * t})
    assert path.values["beta"][4] == 0.0
    res = run_trajectory(model, path, **PAPER_LOAD)
    assert res.ok.all()
    assert res.params["gamma"][4] == pytest.approx(path.values["alpha"][4], abs=1e-7)
    assert "representation singularity" in res.message[4]
    st = analyze_pm(model, path.sample(4), **PAPER_LOAD).statics
    _close(res.active[4], st.active, np.abs(st.values).max(), rtol=1e-6)


# ----------------------------------------------------------------------------- export, plot

def test_csv_has_the_columns_and_values(runs):
    path, res = runs["2SPS+2SPR"]
    rows = list(csv.reader(io.StringIO(res.to_csv())))
    units = rows[0]
    head = [c.split(" [")[0] for c in units]                # 'F_a1 [kN]' -> 'F_a1'
    assert units[2:9] == ["Xo [cm]", "Yo [cm]", "Zo [cm]", "alpha [deg]", "beta [deg]",
                          "gamma [deg]", "r1 [cm]"]
    assert units[12] == "F_a1 [kN]" and units[18] == "T_r1 [kN.cm]"
    assert head[:8] == ["t", "status", "Xo", "Yo", "Zo", "alpha", "beta", "gamma"]
    assert head[8:12] == ["r1", "r2", "r3", "r4"] and head[12:16] == ["F_a1", "F_a2", "F_a3", "F_a4"]
    assert head[16:18] == ["F_c2", "F_c3"]                 # the SPR legs' constraint forces
    assert head[18:22] == ["T_r1", "T_r2", "T_r3", "T_r4"]
    assert head[22:46] == [f"res{i}_{q}" for i in range(1, 5)       # the legs' resultants
                           for q in ("fx", "fy", "fz", "mx", "my", "mz")]
    assert head[46:49] == ["condition_number", "closure_residual", "equilibrium_residual"]
    # the workload the statics are of, at o, on every row (the table says which it used)
    assert units[49:55] == ["workload_Fx [kN]", "workload_Fy [kN]", "workload_Fz [kN]",
                            "workload_Tx [kN.cm]", "workload_Ty [kN.cm]", "workload_Tz [kN.cm]"]
    assert head[55:] == ["conditioning", "message"]
    assert len(rows) == len(path) + 1
    for row in rows[1:]:
        assert [float(x) for x in row[49:55]] == [*PAPER_LOAD["force"], *PAPER_LOAD["torque"]]
    k = 7
    vals = dict(zip(head, rows[k + 1]))
    assert vals["status"] == "ok"
    assert float(vals["alpha"]) == pytest.approx(np.degrees(path.values["alpha"][k]), rel=1e-11)
    assert float(vals["F_c3"]) == pytest.approx(res.constraint[k, 1], rel=1e-11)
    assert float(vals["T_r2"]) == pytest.approx(res.T_r[k, 1], abs=1e-9)


def test_json_is_column_oriented_with_nulls_for_nan():
    model = screwkit.load_pm("3RRPRR")
    path = PathSpec([0.0, 1.0], {"alpha": np.radians([5.0, 70.0]), "beta": np.radians([-3, -3.0]),
                                 "Zo": [80.0, 80.0]})
    res = run_trajectory(model, path, **PAPER_LOAD)
    d = json.loads(dump_json(res.to_dict()))
    assert d["status"] == ["ok", "unreachable"] and d["counts"]["unreachable"] == 1
    assert d["pose"]["alpha"] == [pytest.approx(5.0), pytest.approx(70.0)]
    assert d["active"][1] == [None, None, None] and len(d["active"][0]) == 3
    assert d["constraint"]["labels"] == ["F_c1", "F_c2", "F_c3"]
    assert d["constraint"]["legs"] == [1, 2, 3]


def _png(path):
    import matplotlib.image as mpimg
    return mpimg.imread(path)[..., :3].astype(float)


def test_plot_png_is_the_fig5_layout_and_not_blank(runs, tmp_path):
    path, res = runs["3RRPRR"]
    out = tmp_path / "fig5.png"
    fig = res.plot(out)
    img = _png(out)
    assert img.shape[0] > 800 and img.shape[1] > 1200
    assert np.mean(np.any(img < 0.9, axis=2)) > 0.05          # not a blank page
    titles = [ax.get_title(loc="left") for ax in fig.axes if ax.get_title(loc="left")]
    assert [t[:3] for t in titles] == ["(a)", "(b)", "(c)", "(d)", "(e)"]   # (e): conditioning
    ylabels = " ".join(ax.get_ylabel() for ax in fig.axes)
    for unit in ("[deg]", "[cm]", "[kN]", "[kN·cm]"):
        assert unit in ylabels
    # the active-force curves are the result's columns
    lines = fig.axes[2].get_lines()
    ys = [np.asarray(ln.get_ydata(), float) for ln in lines if len(ln.get_ydata()) == len(path)]
    for i in range(3):
        assert any(np.allclose(y, res.active[:, i]) for y in ys)


def test_plot_leaves_out_identically_zero_constraint_torques(runs, tmp_path):
    """2SPS+2SPR: every constraint force passes through A_i, so every T_ri is 0 (it is a
    constraint force the paper's section 5.1 calls T_ri, NOTES.md)."""
    path, res = runs["2SPS+2SPR"]
    assert np.abs(res.T_r).max() < 1e-9 * np.abs(res.leg_wrenches).max()
    fig = res.plot(tmp_path / "f.png")
    assert "all $T_{ri}$ = 0" in fig._suptitle.get_text()
    assert "constraint forces" in fig.axes[3].get_title(loc="left")


# ----------------------------------------------------------------------------- inputs, progress

def test_progress_is_reported_up_to_the_total(models):
    path = path_from_expressions(PATHS["3RRPRR"], models["3RRPRR"].independent, samples=20)
    seen = []
    run_trajectory(models["3RRPRR"], path, progress=lambda d, n: seen.append((d, n)), chunk=4,
                   anchor_every=2, **PAPER_LOAD)
    # 2 N steps: the closures of the path, then the rows and statics (run_trajectory's docstring)
    assert seen[-1] == (40, 40) and all(n == 40 for _, n in seen)
    assert [d for d, _ in seen] == sorted(d for d, _ in seen)


@pytest.mark.parametrize("kwargs, piece", [
    ({"path": "not a path"}, "PathSpec"),
    ({"path": PathSpec([0.0], {"alpha": [0.0], "Zo": [80.0]})}, "independent"),
    ({"force": [1, 2]}, "force"),
    ({"torque": [1, 2, np.nan]}, "torque"),
    ({"anchor_every": 0}, ">= 1"),
])
def test_bad_inputs_raise_input_errors(models, kwargs, piece):
    good = PathSpec([0.0], {"alpha": [0.0], "beta": [0.05], "Zo": [80.0]})
    args = {"path": good, **kwargs}
    with pytest.raises(InputError, match=piece.replace("(", r"\(")):
        run_trajectory(models["3RRPRR"], args.pop("path"), **args)


def test_an_indeterminate_pms_least_norm_values_are_marked():
    # 4UPU: eight rows for six freedoms, J^T has a null space of two: a row is determined by
    # statics exactly where no vector of that null space (numpy's SVD here) loads it; the
    # others are the least-norm choice, and each sample's message names them
    model = screwkit.load_pm("4UPU")
    d = model.default_pose
    t = np.linspace(0.0, 1.0, 4)
    path = PathSpec(t, {k: d[k] + (0.02 * t if k == "gamma" else 0.0 * t)
                        for k in model.independent})
    res = run_trajectory(model, path, force=[0.0, 0.0, -1.0], torque=[0.1, 0.0, 0.0])
    labels = [r.label for r in res.analysis.jacobian.info]
    for i in range(len(t)):
        J = res.analysis.jacobian.matrix[i]
        _, sv, Vt = np.linalg.svd(J.T)
        null = Vt[int(np.sum(sv > 1e-9 * sv[0])):]                 # (8 - rank, 8)
        free = [lab for lab, v in zip(labels, np.abs(null).max(axis=0)) if v > 1e-9]
        assert free and list(np.array(labels)[~res.determined[i]]) == free
        assert res.message[i].endswith("not determined by statics (the least-norm "
                                       f"choice): {', '.join(free)}")
    d = json.loads(dump_json(res.to_dict()))
    assert d["determined"]["constraint"][0] == res.determined[0, 4:].tolist()
