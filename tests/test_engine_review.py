"""Review checks of the batched engine against values derived outside it.

Independent references: joint twists written by hand from each placed joint's kind, axis,
point and pitch (``[p x u + h u; u]``, ``[u; 0]`` for P); the platform pose from scipy's
``Rotation.from_euler``; the workload wrench ``[F; T + o x F]`` formed here; one-pose analyses
against the batch; the scaling law of statics (forces unchanged, couples times the length
factor when every length and the torque are multiplied by it).
"""

import numpy as np
import pytest
from scipy.spatial.transform import Rotation

import screwkit
from random_poses import random_pose

# the paper's workload, stated (only 3RRPRR and 2SPS+2SPR declare it as their default)
PAPER_LOAD = {"force": (-20.0, -30.0, -60.0), "torque": (-30.0, -30.0, 100.0)}
PAPER_ARGS = ["--force=-20,-30,-60", "--torque=-30,-30,100"]

F = np.array([-20.0, -30.0, -60.0])
T = np.array([-30.0, -30.0, 100.0])


def _pose(pm, n, seed):
    return random_pose(pm, n, seed, span=6.0, frac=0.06)


def _twist(joint):
    """Unit twist [v; w] about O of a placed joint, from its axis, point and pitch."""
    u, p = np.asarray(joint.direction, float), np.asarray(joint.point, float)
    if joint.spec.kind == "P":
        return np.r_[u, 0.0, 0.0, 0.0]
    h = joint.pitch if joint.spec.kind == "H" else 0.0
    return np.r_[np.cross(p, u) + h * u, u]


@pytest.mark.parametrize("name", ["3RRPRR", "2SPS+2SPR", "3SPU+PRRR"])
def test_rows_closure_and_equilibrium_by_hand(name):
    pm = screwkit.load_pm(name)
    L = pm.normalisation.length
    pose = _pose(pm, 4, 5)
    res = screwkit.analyze(pm, pose, force=F, torque=T)
    assert res.ok.all()
    for i in range(len(res)):
        p = {k: float(v[i]) for k, v in res.solution.params.items()}
        R = Rotation.from_euler(pm.order, [p["alpha"], p["beta"], p["gamma"]]).as_matrix()
        o = np.array([p["Xo"], p["Yo"], p["Zo"]])
        J = res.jacobian.matrix[i]
        for k, lg in enumerate(res.solution.legs_at(i)):
            # closure: A_k on the first joint's axis, o + R a_k (scipy's R) on the last's
            for j, x in ((lg.joints[0], pm.base_points[k]),
                         (lg.joints[-1], o + R @ pm.platform_points[k])):
                if j.spec.kind != "P":
                    assert np.linalg.norm(np.cross(x - j.point, j.direction)) <= 1e-9 * L
            tw = np.array([_twist(j) for j in lg.joints])
            act, *cons = res.jacobian.leg_rows(k)
            prod = tw @ J[act]
            assert prod[lg.actuated_index] == pytest.approx(1.0, abs=1e-9)
            assert np.abs(np.delete(prod, lg.actuated_index)).max() <= 1e-9 * L
            if cons:
                assert np.abs(tw @ J[cons].T).max() <= 1e-9 * L
        # equilibrium of the platform: J^T F_r = -[F; T + o x F]
        W = np.r_[F, T + np.cross(o, F)]
        Fr = res.statics.values[i]
        assert np.abs(J.T @ Fr + W).max() <= 1e-9 * (np.abs(W).max() + np.abs(Fr).max() * L)


@pytest.mark.parametrize("name", ["3RRPRR", "3UPU", "4SPS+SPR"])
def test_lengths_times_ten_keep_forces_and_scale_couples(name):
    pm = screwkit.load_pm(name)
    s = 10.0
    big = screwkit.load_pm(name, {k: s * v for k, v in pm.dimensions.items()})
    pose = _pose(pm, 3, 2)
    a = screwkit.analyze(pm, pose, force=F, torque=T)
    b = screwkit.analyze(big, {k: s * v if k in ("Xo", "Yo", "Zo") else v
                               for k, v in pose.items()}, force=F, torque=s * T)
    couple = np.array([lab.startswith("T_") for lab in a.jacobian.labels])
    expected = a.statics.values * np.where(couple, s, 1.0)
    fs = np.abs(a.statics.values).max()
    np.testing.assert_allclose(b.statics.values, expected, rtol=0, atol=1e-9 * fs * s)
    np.testing.assert_allclose(b.jacobian.condition_number, a.jacobian.condition_number,
                               rtol=1e-8)


def test_a_base_frame_move_keeps_the_statics():
    pm = screwkit.load_pm("2SPS+2SPR")
    Rm = Rotation.from_euler("ZYX", [0.7, -0.3, 0.4]).as_matrix()
    moved = pm.moved(Rm, [123.0, -45.0, 17.0])
    pose = _pose(pm, 4, 9)
    a = screwkit.analyze(pm, pose, force=F, torque=T)
    b = screwkit.analyze(moved, pose, force=Rm @ F, torque=Rm @ T)   # the same load, turned
    fs = np.abs(a.statics.values).max()
    np.testing.assert_allclose(b.statics.values, a.statics.values, rtol=0, atol=1e-9 * fs)
    np.testing.assert_allclose(b.jacobian.condition_number, a.jacobian.condition_number,
                               rtol=1e-8)
    # the rows turn with the frame: J' = J Ad^*, i.e. [f; m] -> [R f; R m + p x R f]
    p = np.array([123.0, -45.0, 17.0])
    f, m = a.jacobian.matrix[..., :3] @ Rm.T, a.jacobian.matrix[..., 3:] @ Rm.T
    np.testing.assert_allclose(b.jacobian.matrix, np.concatenate([f, m + np.cross(p, f)], -1),
                               rtol=0, atol=1e-9 * np.abs(b.jacobian.matrix).max())


def test_the_force_amplification_does_not_depend_on_the_base_frame():
    pm = screwkit.load_pm("3RRPRR")
    pose = {"alpha": np.radians([20.0, -30.0]), "beta": np.radians([25.0, 10.0]),
            "Zo": np.array([60.0, 100.0])}
    a = screwkit.analyze(pm, pose, **PAPER_LOAD)
    b = screwkit.analyze(pm.moved(np.eye(3), [300.0, 0.0, 0.0]), pose, **PAPER_LOAD)
    np.testing.assert_allclose(b.statics.values, a.statics.values, rtol=1e-9)   # same efforts
    np.testing.assert_allclose(b.quality.amplification, a.quality.amplification, rtol=1e-9)


def test_bad_poses_in_a_batch_are_flagged_and_the_others_equal_single_poses():
    pm = screwkit.load_pm("3RSR")        # fixed-length links: Zo = 400 cannot be assembled
    good = _pose(pm, 6, 4)
    rows = [{k: float(v[i]) for k, v in good.items()} for i in range(6)]
    far = dict(rows[2], Zo=400.0)
    mixed = [far] + rows[:3] + [far] + rows[3:] + [far]
    kind = ["bad"] + ["good"] * 3 + ["bad"] + ["good"] * 3 + ["bad"]
    batch = {k: np.array([m[k] for m in mixed]) for k in pm.independent}
    res = screwkit.analyze(pm, batch, chunk=3, workers=2, **PAPER_LOAD)      # bad poses at chunk edges
    assert len(res) == len(mixed)
    bad = np.array([k == "bad" for k in kind])
    assert res.unreachable.tolist() == bad.tolist() and not res.ok[bad].any()
    assert (res.solution.status[bad] == "unreachable").all()
    assert (res.solution.residual[bad] > 1e-6).all()
    assert np.array_equal(res.solution.params["Zo"][bad], np.full(3, 400.0))   # kept as given
    for i in np.where(~bad)[0]:
        one = screwkit.analyze(pm, mixed[i], **PAPER_LOAD)
        assert res.ok[i]
        fs = np.abs(one.statics.values).max()
        np.testing.assert_allclose(res.statics.values[i], one.statics.values, rtol=0,
                                   atol=1e-10 * fs)
        np.testing.assert_allclose(res.jacobian.matrix[i], one.jacobian.matrix[0], rtol=0,
                                   atol=1e-10 * np.abs(one.jacobian.matrix).max())
        for arr in (res.statics.values[i], res.statics.T_r[i], res.solution.extensions[i],
                    res.jacobian.matrix[i]):
            assert np.isfinite(arr).all()         # NaN only where a pose is flagged


def test_an_unreachable_pose_has_no_condition_level_of_its_own():
    pm = screwkit.load_pm("3RSR")
    z = pm.default_pose["Zo"]
    res = screwkit.analyze(pm, {"alpha": 0.02, "beta": -0.01, "Zo": [z, 400.0]}, **PAPER_LOAD)
    assert res.unreachable.tolist() == [False, True]
    assert res.level[1] != "ok" and not np.isfinite(res.jacobian.condition_number[1])


def test_every_public_name_is_in_the_api_page():
    import pathlib
    page = (pathlib.Path(__file__).resolve().parents[1] / "docs" / "api.md").read_text()
    table = page.split("## The public names", 1)[1]
    missing = [n for n in screwkit.__all__ if f"`{n}`" not in table]
    assert not missing, f"screwkit.__all__ names missing from docs/api.md's table: {missing}"
    for n in screwkit.__all__:
        getattr(screwkit, n)                  # each listed name resolves


def test_a_path_that_leaves_the_workspace_and_comes_back():
    """Samples beyond the workspace are flagged unreachable; the ones back inside are solved
    again and equal one-pose analyses (the retries start only from a solved neighbour)."""
    pm = screwkit.load_pm("3RSR")
    z = pm.default_pose["Zo"]
    s = np.linspace(0.0, 1.0, 41)
    pose = {"alpha": np.full(41, 0.02), "beta": np.full(41, -0.01),
            "Zo": z + 300.0 * np.sin(np.pi * s) ** 2}          # out and back
    res = screwkit.analyze(pm, pose, path=True, raise_on_singular=False, **PAPER_LOAD)
    far = pose["Zo"] > z + 150.0
    assert res.unreachable[far].all() and res.ok[:3].all() and res.ok[-3:].all()
    for i in np.flatnonzero(res.ok):
        one = screwkit.analyze(pm, {k: float(v[i]) for k, v in pose.items()},
                               raise_on_singular=False, **PAPER_LOAD)
        np.testing.assert_allclose(res.statics.values[i], one.statics.values, rtol=0,
                                   atol=1e-9 * np.abs(one.statics.values).max())


@pytest.mark.parametrize("degrees", [False, True])
def test_a_batch_keeps_its_own_copy_of_the_pose_arrays(degrees):
    # the arrays given are read once: changing them after the call changes nothing the
    # result holds (the given parameters its closures keep, the pose it reports), and the
    # default put in a flagged pose's place goes into the copy, never the caller's array
    pm = screwkit.load_pm("3RRPRR")
    scale = 1.0 if degrees else np.pi / 180.0
    for flagged in (False, True):
        alpha = np.array([5.0, np.nan if flagged else 1.0, -3.0, 2.0]) * scale
        beta = np.array([2.0, 1.0, -4.0, 0.0]) * scale
        zo = [70, 80, 90, 75]                               # ints in a list
        res = screwkit.analyze(pm, {"alpha": alpha, "beta": beta, "Zo": zo},
                               degrees=degrees, **PAPER_LOAD)
        assert res.ok.tolist() == [True, not flagged, True, True]
        assert np.isnan(alpha[1]) == flagged                # (the caller's, as given)
        held = res.solution.closures.fixed
        assert not any(np.shares_memory(held[k], v) for k, v in
                       (("alpha", alpha), ("beta", beta)))
        kept = {k: np.array(v, copy=True) for k, v in held.items()}
        params = {k: np.array(v, copy=True) for k, v in res.solution.params.items()}
        alpha[:], beta[:], zo[0] = 0.0, 0.0, 10
        for k, v in kept.items():
            assert np.array_equal(held[k], v)
        for k, v in params.items():
            assert np.array_equal(res.solution.params[k], v, equal_nan=True)
        assert np.allclose(kept["beta"], np.radians([2.0, 1.0, -4.0, 0.0]))
        assert np.allclose(kept["Zo"], [70.0, 80.0, 90.0, 75.0])
