"""Session-5 review: batch indexing edge cases, PMAnalysis.under, sizing over many
workloads, the planar 3-PRR's statics and cos_sin, each against an independent derivation.

Independent checks used here: ``np.linalg.solve(J^T, -W)`` on the engine's raw J with
``W = [F; T + o x F]`` formed by hand (square J); the compliance-weighted least-squares
solution ``x = K J (J^T K J)^-1 (-W)`` (indeterminate J); a planar hand derivation of the
3-PRR (slider on a line, a two-force distal link); long-double cos and sin.
"""

import numpy as np
import pytest

import screwkit
from screwkit.engine._algebra import rodrigues
from screwkit.screws._euler import axis_rotation, cos_sin

# the paper's workload, stated (only 3RRPRR and 2SPS+2SPR declare it as their default)
PAPER_LOAD = {"force": (-20.0, -30.0, -60.0), "torque": (-30.0, -30.0, 100.0)}
PAPER_ARGS = ["--force=-20,-30,-60", "--torque=-30,-30,100"]


@pytest.fixture(scope="module")
def batch():
    # pose 5 is unreachable (alpha near 90 deg)
    pose = {"alpha": np.radians(np.linspace(-6.0, 6.0, 8)),
            "beta": np.radians(np.linspace(-4.0, 3.0, 8)), "Zo": np.linspace(72.0, 88.0, 8)}
    pose["alpha"][5] = np.radians(89.9)
    return pose, screwkit.analyze("3RRPRR", pose, raise_on_singular=False)


def _hand_values(res, F, T):
    """F_r from J^T F_r = -W, W = [F; T + o x F] about O, per pose (square J)."""
    J = np.asarray(res.jacobian.matrix)
    o = np.asarray(res.jacobian.origin)
    W = np.concatenate([np.broadcast_to(F, o.shape), T + np.cross(o, F)], axis=1)
    return np.linalg.solve(np.transpose(J, (0, 2, 1)), -W[..., None])[..., 0]


# -- batch indexing ------------------------------------------------------------------------

@pytest.mark.parametrize("key", [[], np.zeros(8, bool), slice(4, 4), np.array([], int)])
def test_an_empty_selection_is_a_clear_index_error(batch, key):
    _, res = batch
    with pytest.raises(IndexError, match="selects none of the 8 poses"):
        res[key]
    with pytest.raises(IndexError, match="selects none"):
        res.jacobian[key]


@pytest.mark.parametrize("key", [None, True, np.array(True), [[0, 1]], np.ones((2, 2), int)])
def test_an_index_that_adds_an_axis_is_an_index_error(batch, key):
    _, res = batch
    with pytest.raises(IndexError, match="one pose axis"):
        res[key]
    with pytest.raises(IndexError, match="one pose axis"):
        res.solution[key]


def test_negative_and_nested_indices_pick_the_same_poses(batch):
    pose, res = batch
    a, b = res[[-1, -3]], res[[7, 5]]
    np.testing.assert_array_equal(a.solution.params["alpha"], pose["alpha"][[7, 5]])
    np.testing.assert_array_equal(a.unreachable, [False, True])
    np.testing.assert_array_equal(a.statics.F_r, b.statics.F_r)
    nested = res[1:8][::2]                                # poses 1, 3, 5, 7
    np.testing.assert_array_equal(nested.solution.params["Zo"], pose["Zo"][[1, 3, 5, 7]])
    assert nested.unreachable.tolist() == [False, False, True, False]
    assert np.isnan(nested.statics.F_r[2]).all() and not np.isnan(nested.statics.F_r[3]).any()
    # one pose of a nested sub-batch: its numbers against the hand statics of that pose
    one = nested[3]
    F, T = np.asarray(res.force), np.asarray(res.torque)
    np.testing.assert_allclose(one.statics.values, _hand_values(res, F, T)[7], rtol=1e-9)
    assert one.level == str(res.level[7]) and one.warnings == res[7].warnings


# -- PMAnalysis.under ---------------------------------------------------------------------

def test_under_equals_the_hand_statics_and_flags_the_unreachable_pose(batch):
    _, res = batch
    F, T = np.array([3.0, -7.0, 11.0]), np.array([-40.0, 5.0, 25.0])
    u = res.under(F, T)
    want = _hand_values(res, F, T)
    ok = ~res.unreachable
    np.testing.assert_allclose(u.statics.F_r[ok], want[ok], rtol=1e-9,
                               atol=1e-10 * np.abs(want[ok]).max())
    assert np.isnan(u.statics.F_r[5]).all() and not u.ok[5] and u.level[5] == "unreachable"
    np.testing.assert_array_equal(u.force, F)
    # linear in the workload: twice the load, twice the efforts
    np.testing.assert_allclose(res.under(2 * F, 2 * T).statics.F_r[ok], 2 * u.statics.F_r[ok],
                               rtol=1e-12)
    # on a sub-batch: the same poses' numbers
    np.testing.assert_allclose(res[[6, 0]].under(F, T).statics.F_r, u.statics.F_r[[6, 0]],
                               rtol=1e-12)


def test_under_keeps_the_analysis_stiffness_weighted_least_squares():
    pose = {"Xo": np.array([-4.0, 2.0, 6.0]), "Yo": np.array([3.0, -1.0, 0.5]),
            "Zo": np.array([80.0, 78.0, 84.0]), "gamma": np.radians([0.0, 12.0, -9.0])}
    k = np.array([1e3, 2e3, 3e3, 4e3, 1e6, 4e6, 2e6, 9e6])
    res = screwkit.analyze("4UPU", pose, stiffness=k, **PAPER_LOAD)
    F, T = np.array([1.0, 2.0, -3.0]), np.array([0.5, -40.0, 7.0])
    u = res.under(F, T)
    J = np.asarray(res.jacobian.matrix)
    o = np.asarray(res.jacobian.origin)
    K = np.diag(k)
    for j in range(3):
        W = np.concatenate([F, T + np.cross(o[j], F)])
        x = K @ J[j] @ np.linalg.solve(J[j].T @ K @ J[j], -W)
        np.testing.assert_allclose(u.statics.F_r[j], x, rtol=1e-9, atol=1e-9 * np.abs(x).max())


# -- sizing over many workloads -----------------------------------------------------------

def test_sizing_over_many_workloads_equals_a_solve_per_workload_and_cell():
    pytest.importorskip("xarray")
    rng = np.random.default_rng(3)
    loads = [("rest", np.zeros(3), np.zeros(3))]          # a zero first workload
    loads += [(f"w{k}", rng.uniform(-100, 100, 3), rng.uniform(-100, 100, 3))
              for k in range(60)]
    grid = {"alpha": (-10.0, 10.0, 9), "beta": (-8.0, 8.0, 7)}
    got = screwkit.size("3RRPRR", grid, fix={"Zo": 80.0}, workloads=loads, degrees=True)
    a, b = np.meshgrid(np.linspace(-10, 10, 9), np.linspace(-8, 8, 7), indexing="ij")
    res = screwkit.analyze("3RRPRR", {"alpha": np.radians(a.ravel()),
                                      "beta": np.radians(b.ravel()),
                                      "Zo": np.full(a.size, 80.0)})
    assert res.ok.all() and got.usable_cells == a.size
    best = np.full(6, -1.0)
    who = [None] * 6
    for name, F, T in loads:
        m = np.abs(_hand_values(res, F, T)).max(axis=0)
        for q in range(6):
            if m[q] > best[q]:
                best[q], who[q] = m[q], name
    for q, row in enumerate(got.rows[:6]):
        assert row["max_abs"] == pytest.approx(best[q], rel=1e-9)
        assert row["workload"] == who[q]


# -- the planar 3-PRR written by the synthesis ---------------------------------------------

def test_the_synthesized_3prr_statics_equal_a_planar_hand_derivation(tmp_path):
    from screwkit.design import synthesize_motion
    cand = synthesize_motion("2T1R", asymmetric=False, limit=4, generate=False)
    prr = next(p for p in cand.listed if p.variant == "3PRR/planar")
    path = tmp_path / "3prr.yaml"
    path.write_text(prr.model_yaml())
    model = screwkit.load_pm(str(path))
    home = screwkit.analyze(model, {"Xo": 0.0, "Yo": 0.0, "gamma": 0.0}, **PAPER_LOAD)
    e0 = np.array([lg.joints[1].point[:2] for lg in home.jacobian.legs])
    A = np.asarray(model.base_points)[:, :2]
    ap = np.asarray(model.platform_points)[:, :2]
    p = -A / np.hypot(*A.T)[:, None]                       # each slider along A -> O
    l2 = np.hypot(*(e0 - ap).T)                            # distal link, in the plane
    F, Tz = np.array([10.0, -5.0]), 30.0
    cross = lambda u, v: u[..., 0] * v[..., 1] - u[..., 1] * v[..., 0]  # noqa: E731
    for x, y, g in [(4.0, -3.0, 0.2), (-6.0, 2.5, -0.15), (1.0, 7.0, 0.05)]:
        res = screwkit.analyze(model, {"Xo": x, "Yo": y, "gamma": g}, force=(*F, 0.0),
                               torque=(0.0, 0.0, Tz))
        c, s = np.cos(g), np.sin(g)
        o = np.array([x, y])
        a = o + ap @ np.array([[c, s], [-s, c]])
        e = []
        for i in range(3):                                 # |a - (e0 + t p)| = l2, t near 0
            d = a[i] - e0[i]
            h = d @ p[i]
            t = min((h - np.sqrt(h * h - d @ d + l2[i] ** 2),
                     h + np.sqrt(h * h - d @ d + l2[i] ** 2)), key=abs)
            e.append(e0[i] + t * p[i])
        e = np.array(e)
        u = (a - e) / np.hypot(*(a - e).T)[:, None]
        f = np.linalg.solve(np.vstack([u.T, cross(a - o, u)]), -np.r_[F, Tz])
        np.testing.assert_allclose(res.statics.active, f * np.sum(u * p, axis=1), rtol=1e-9)
        got = np.array([lg.joints[1].point[:2] for lg in res.jacobian.legs])
        np.testing.assert_allclose(got, e, atol=1e-9)


# -- cos_sin ------------------------------------------------------------------------------

def test_cos_sin_against_long_double_and_orthonormal_rotations():
    rng = np.random.default_rng(0)
    a = np.concatenate([rng.uniform(-np.pi, np.pi, 2000), np.pi + rng.uniform(-1e-6, 1e-6, 500),
                        np.pi / 2 + rng.uniform(-1e-6, 1e-6, 500), rng.uniform(-1e9, 1e9, 500),
                        [0.0, np.pi, -np.pi, np.pi / 2, 2 * np.pi, 3 * np.pi, 1e300]])
    c, s = cos_sin(a)
    ld = a.astype(np.longdouble)
    assert np.abs(c - np.cos(ld).astype(float)).max() <= 2.3e-16
    assert np.abs(s - np.sin(ld).astype(float)).max() <= 2.3e-16
    # near pi the sine keeps its relative accuracy (sin(pi - d) = d)
    d = np.abs(s[2000:2500] - np.sin(ld[2000:2500]).astype(float))
    assert (d <= 1e-15 * np.abs(np.sin(ld[2000:2500]).astype(float))).all()
    c0, s0 = cos_sin(np.array([-0.0]))
    assert c0[0] == 1.0 and s0[0] == 0.0 and np.signbit(s0[0])
    R = axis_rotation(1, a)
    assert np.abs(np.einsum("ijn,ikn->jkn", R, R) - np.eye(3)[:, :, None]).max() < 1e-15
    axis = np.array([0.36, -0.48, 0.8])
    Rr = rodrigues(axis[:, None, None], a[None, :])
    Rr = Rr.reshape(3, 3, -1)
    assert np.abs(np.einsum("ijn,ikn->jkn", Rr, Rr) - np.eye(3)[:, :, None]).max() < 1e-15
    # Rodrigues against scipy's rotation-vector formula
    from scipy.spatial.transform import Rotation
    want = Rotation.from_rotvec(a[:50, None] * axis).as_matrix()
    np.testing.assert_allclose(np.moveaxis(Rr[:, :, :50], -1, 0), want, atol=2e-15)


def test_sizing_says_which_rows_statics_alone_determines():
    """4UPU (2 redundant constraint couples): a row is flagged determined exactly when
    three different row stiffnesses give it the same value at its extreme's pose."""
    pytest.importorskip("xarray")
    pm = screwkit.load_pm("4UPU")
    s = screwkit.size(pm, {"Xo": (-5.0, 5.0, 3)}, fix={"Yo": 0.0, "Zo": 80.0, "gamma": 0.0},
                      degrees=True,
                      workloads=[("paper", PAPER_LOAD["force"], PAPER_LOAD["torque"])])
    labels = list(screwkit.analyze(pm, **PAPER_LOAD).jacobian.labels)
    L = pm.normalisation.length
    rng = np.random.default_rng(1)
    ks = [rng.uniform(0.5, 2.0, len(labels)) *
          np.array([1.0 if lab.startswith("F") else L ** 2 for lab in labels]) for _ in range(3)]
    flags = {}
    for row in s.rows:
        pose = dict(row["pose"], gamma=np.radians(row["pose"]["gamma"]))
        vals = []
        for k in ks:
            st = screwkit.analyze(pm, pose, stiffness=k, **PAPER_LOAD).statics
            vals.append(st.values[labels.index(row["name"])] if row["name"] in labels
                        else st.T_r[row["leg"] - 1])
        fixed = np.ptp(vals) <= 1e-9 * abs(vals[0])
        assert row["determined"] is bool(fixed), row["name"]
        flags[row["name"][:3]] = flags.get(row["name"][:3], set()) | {row["determined"]}
    assert flags == {"F_a": {True}, "T_c": {False}, "T_r": {False}}
    det = screwkit.size("3RRPRR", {"alpha": (-5.0, 5.0, 3)}, fix={"beta": 1.0, "Zo": 80.0},
                        degrees=True)
    assert all(r["determined"] is True for r in det.rows)          # a square J


def test_sizing_merges_blocks_as_one_map(monkeypatch):
    """Cells in two blocks (their reductions merged): the same extremes as the hand solve
    over all cells, with the extreme's pose."""
    pytest.importorskip("xarray")
    import screwkit.maps._compute as compute
    monkeypatch.setattr(compute, "BLOCK", 4096)
    rng = np.random.default_rng(4)
    loads = [(f"w{k}", rng.uniform(-100, 100, 3), rng.uniform(-100, 100, 3)) for k in range(4)]
    grid = {"alpha": (-15.0, 15.0, 71), "beta": (-12.0, 12.0, 61)}     # 4331 cells
    got = screwkit.size("3RRPRR", grid, fix={"Zo": 80.0}, workloads=loads, degrees=True)
    a, b = np.meshgrid(np.linspace(-15, 15, 71), np.linspace(-12, 12, 61), indexing="ij")
    res = screwkit.analyze("3RRPRR", {"alpha": np.radians(a.ravel()),
                                      "beta": np.radians(b.ravel()),
                                      "Zo": np.full(a.size, 80.0)})
    ok = np.asarray(res.ok)
    assert got.usable_cells == int(ok.sum())
    vals = np.stack([_hand_values(res, F, T) for _, F, T in loads])      # (K, N, 6)
    vals = np.where(ok[None, :, None], np.abs(vals), -1.0)
    for q, row in enumerate(got.rows[:6]):
        k, i = np.unravel_index(np.argmax(vals[:, :, q]), vals.shape[:2])
        assert row["max_abs"] == pytest.approx(vals[k, i, q], rel=1e-9)
        assert row["workload"] == loads[k][0]
        assert row["pose"]["alpha"] == pytest.approx(a.ravel()[i])
        assert row["pose"]["beta"] == pytest.approx(b.ravel()[i])
