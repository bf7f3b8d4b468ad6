"""Issue 20 in the Python API: stiffness of rigid and (near-)singular PMs against independent
formulas, stated workloads, SI exports read back by Pinocchio, batches that flag bad poses,
one conditioning classification."""

from __future__ import annotations

import time

import numpy as np
import pytest

import screwkit
from screwkit.dynamics import stiffness
from screwkit.engine import classify
from screwkit.errors import InputError
from screwkit.pm import pm_names

PAPER = {"force": (-20.0, -30.0, -60.0), "torque": (-30.0, -30.0, 100.0)}
A0 = -43.12884710315615          # deg: the 3RPS's actuation singularity at beta = 0, Zo = 60


def about_o(res):
    """J's rows [f; m - o x f] about o, (m, 6): written out here, not the library's."""
    J = np.asarray(res.analysis.jacobian.J)
    o = np.asarray(res.analysis.solution.position)
    f = J[:, :3]
    return np.hstack([f, J[:, 3:] - np.cross(o, f)])


# --------------------------------------------------------------------------- stiffness

def test_a_pm_rigid_everywhere_has_exactly_zero_compliance_and_deflection():
    r = stiffness("3RRPRR")                       # no stiffness given: every row rigid
    assert r.rigid_everywhere and r.restrained[0]
    assert np.all(r.compliance == 0) and np.all(r.deflection == 0)
    kt, _ = r.principal("translational")
    assert np.all(np.isinf(kt))
    d = r.to_dict()
    assert d["stiffness"] is None and d["rigid_everywhere"]
    assert "every row is rigid" in d["notes"][0] and "=" not in d["notes"][0]


@pytest.mark.parametrize("dx", [1.0, 1e-2, 1.6e-6])
def test_square_j_compliance_is_j_inverse_times_row_compliances(dx):
    """C = J^-1 diag(1/k) J^-T (rows about o): the flexibility solve agrees to cond x eps,
    also 1.6e-6 deg from the singularity (condition 6e7), where the old K-inverse gave NaN."""
    k = {"actuator": 2000.0, "force_stiffness": 5000.0}
    r = stiffness("3RPS", {"alpha": A0 + dx, "beta": 0.0, "Zo": 60.0}, degrees=True,
                  force=[0, 0, -1], **k)
    Jo = about_o(r)
    Ji = np.linalg.inv(Jo)
    C = Ji @ np.diag(1.0 / r.k[0]) @ Ji.T
    cond = np.linalg.cond(Jo)
    assert np.abs(r.compliance[0] - C).max() <= 50 * cond * 2.2e-16 * np.abs(C).max()
    assert np.all(np.isfinite(r.deflection)) and r.restrained[0]
    expect = "regular" if dx == 1.0 else "near-singular"
    assert r.conditioning == expect == screwkit.analyze(
        "3RPS", {"alpha": A0 + dx, "beta": 0.0, "Zo": 60.0}, degrees=True).conditioning


def test_rigid_rows_do_not_deform():
    """Actuators compliant, constraint forces rigid: J_c dX = 0 for every load, while the
    actuator rows deform by their force over their stiffness (F_a = -(J^-T W)_a)."""
    r = stiffness("3RPS", actuator=2000.0, force=[3, -2, -7], torque=[10, 4, -6])
    Jo = about_o(r)
    d = Jo @ r.deflection[0]
    W = np.r_[r.force, r.torque]
    F = np.linalg.solve(Jo.T, W)                       # row efforts balancing W
    scale = np.abs(d).max()
    assert np.abs(d[3:]).max() <= 1e-12 * scale        # the rigid rows: no deformation
    np.testing.assert_allclose(d[:3], F[:3] / 2000.0, rtol=1e-9)
    _, ax = r.principal("rotational")
    assert np.isinf(r.principal("rotational")[0]).any()


def test_indeterminate_pm_compliance_is_the_inverse_of_k():
    """4UPU (8 rows), every row compliant: C = K^-1, K = J_o^T diag(k) J_o formed here."""
    r = stiffness("4UPU", actuator=3000.0, couple_stiffness=5e6,
                  **PAPER)
    Jo = about_o(r)
    K = Jo.T @ np.diag(r.k[0]) @ Jo
    np.testing.assert_allclose(r.compliance[0], np.linalg.inv(K), rtol=1e-8,
                               atol=1e-12 * np.abs(np.linalg.inv(K)).max())


def test_singular_pose_names_its_unrestrained_direction():
    """At the 3RPS singularity the unrestrained twist u is J's null vector (J_o u = 0,
    checked here with J's own SVD), the deflection stays finite, the pose is singular."""
    r = stiffness("3RPS", {"alpha": A0, "beta": 0.0, "Zo": 60.0}, degrees=True,
                  actuator=2000.0, force_stiffness=5000.0, force=[0, 0, -1],
                  raise_on_singular=False)
    assert r.conditioning == "singular" and not r.restrained[0] and r.n_free[0] == 1
    u = r.unrestrained(0)[0]
    Jo = about_o(r)
    L = screwkit.load_pm("3RPS").normalisation.length
    s = np.diag([L, L, L, 1, 1, 1])
    _, sv, vt = np.linalg.svd(Jo @ s)
    null = s @ vt[-1]
    cos = abs(u @ null) / np.linalg.norm(u) / np.linalg.norm(null)
    assert cos > 1 - 1e-9 and np.linalg.norm(Jo @ u) < 1e-6 * np.linalg.norm(Jo) * np.linalg.norm(u)
    assert np.all(np.isfinite(r.deflection)) and np.all(np.isfinite(r.compliance))
    assert r.load_on_free                      # F = (0, 0, -1) works on that rotation
    assert "rotation about the axis" in r.to_dict()["unrestrained"][0]["description"]



def test_an_unrestrained_direction_has_a_canonical_sign():
    """An unrestrained twist is free both ways, and its singular vector's sign is the SVD's:
    the named one has the first significant component of its axis (of its direction, for a
    translation) positive, whatever the sign of the vector it came from (the 3RPS
    singularity's axis is x: printed (1, 0, 0) cm, not as the last bits of the rows fall)."""
    from screwkit.dynamics._compliance import _unit_twists
    r = stiffness("3RPS", {"alpha": A0, "beta": 0.0, "Zo": 60.0}, degrees=True,
                  actuator=2000.0, force_stiffness=5000.0, force=[0, 0, -1],
                  raise_on_singular=False)
    w = r.unrestrained(0)[0][3:]
    np.testing.assert_allclose(w, [1.0, 0.0, 0.0], atol=1e-9)
    jac = screwkit.analyze("3RPS", {"alpha": A0, "beta": 0.0, "Zo": 60.0}, degrees=True,
                           raise_on_singular=False).jacobian
    u = jac.uncontrolled_twist                      # the same rule, [v_O; w] about O
    np.testing.assert_allclose(u[3:] / np.linalg.norm(u[3:]), [1.0, 0.0, 0.0], atol=1e-9)
    assert np.abs(np.asarray(jac.J) @ u).max() < 1e-6 * np.abs(jac.J).max() * np.abs(u).max()
    rng = np.random.default_rng(3)
    V = rng.normal(size=(5, 6, 3))
    V[1, 3:] = 0.0                                  # a translation
    V[2, 3, :] = 0.0                                # an axis in the y-z plane
    U = _unit_twists(V)
    np.testing.assert_array_equal(_unit_twists(-V), U)
    for n in range(5):
        for c in range(3):
            part = U[n, 3:, c] if np.any(V[n, 3:, c]) else U[n, :3, c]
            first = part[np.flatnonzero(np.abs(part) > 1e-8 * np.abs(part).max())[0]]
            assert first > 0 and np.isclose(np.linalg.norm(part), 1.0)
            cos = U[n, :, c] @ V[n, :, c] / np.linalg.norm(U[n, :, c]) / np.linalg.norm(V[n, :, c])
            assert np.isclose(abs(cos), 1.0)

def test_stiffness_for_rows_the_pm_does_not_have_and_out_of_range():
    with pytest.raises(InputError, match="no constraint couple rows"):
        stiffness("3RRPRR", couple_stiffness=5.0)
    for bad in (1e-320, 1e308, float("nan"), -1.0, float("inf")):
        with pytest.raises(InputError):
            stiffness("3RRPRR", actuator=bad)
    with pytest.raises(InputError, match="no row"):
        stiffness("3RRPRR", rows={"T_c9": 3.0})


def test_stiffness_without_a_workload_gives_k_but_no_deflection():
    r = stiffness("3RPS", actuator=2000.0)
    assert r.deflection is None and r.force is None and r.K.shape == (1, 6, 6)
    assert np.isfinite(r.principal("translational")[0]).any()
    with pytest.raises(InputError, match="declares no workload"):
        stiffness("3RPS", actuator=2000.0, geometric=True)


# --------------------------------------------------------------------------- workloads

def test_only_the_papers_two_pms_declare_the_papers_workload():
    for name in pm_names():
        w = screwkit.pm.load_pm(name).workload
        if name in ("3RRPRR", "2SPS+2SPR"):
            np.testing.assert_array_equal(w.force, PAPER["force"])
            np.testing.assert_array_equal(w.torque, PAPER["torque"])
            assert w.source == "declared default" and "5.1" in w.note
        else:
            assert w is None, name


def test_a_model_without_workload_has_kinematics_and_j_but_no_statics():
    res = screwkit.analyze("3RPS")
    assert res.workload is None and not res.has_workload and res.jacobian.J.shape == (6, 6)
    assert res.mobility.dof == 3 and res.ok
    with pytest.raises(InputError, match="force= and/or torque="):
        res.statics.active
    loaded = res.under([0, 0, -1], None)
    assert loaded.workload.source == "given" and np.all(np.isfinite(loaded.statics.active))
    pytest.importorskip("xarray")
    with pytest.raises(InputError, match="declares no workload"):
        screwkit.size("3RPS", {"alpha": (0, 1, 2)}, degrees=True)
    ds = screwkit.map("3RPS", {"alpha": (0, 1, 2)}, degrees=True)     # no forces, said so
    assert "F_a1" not in ds and ds.attrs["workload_source"].startswith("none")
    assert ds["ok"].all() and np.isfinite(ds["condition_number"]).all()


def test_a_declared_workload_is_converted_from_its_units(tmp_path):
    """A workload in N and N.m on a model in cm and kN: 1 N = 1e-3 kN, 1 N.m = 0.1 kN.cm
    (by hand)."""
    pytest.importorskip("pint")
    f = tmp_path / "w.yaml"
    f.write_text("""\
units: {length: cm, force: kN}
pms:
  W:
    dimensions: {R: 60, r: 30}
    base: {shape: triangle, circumradius: R}
    platform: {shape: triangle, circumradius: r}
    legs: [RPS, RPS, RPS]
    euler: XYZ
    independent: [alpha, beta, Zo]
    pose: {alpha: 5, beta: -3, Zo: R}
    dof: 3
    workload: {force: [100, 0, -500], torque: [0, 20, 0], units: {force: N, length: m},
               source: a test load}
""")
    pm = screwkit.load_pm(str(f))
    np.testing.assert_allclose(pm.workload.force, [0.1, 0, -0.5], rtol=1e-12)
    np.testing.assert_allclose(pm.workload.torque, [0, 2.0, 0], rtol=1e-12)
    res = screwkit.analyze(pm)
    ref = screwkit.analyze(pm, force=[0.1, 0, -0.5], torque=[0, 2.0, 0])
    np.testing.assert_allclose(res.statics.values, ref.statics.values, rtol=1e-12)
    assert res.workload_source == "declared default (a test load)"


def test_a_moved_base_turns_the_declared_workload_with_it():
    from scipy.spatial.transform import Rotation
    pm = screwkit.load_pm("3RRPRR")
    R = Rotation.from_euler("zyx", [30, -20, 50], degrees=True).as_matrix()
    moved = pm.moved(R, [10.0, -5.0, 3.0])
    np.testing.assert_allclose(moved.workload.force, R @ np.array(PAPER["force"]))
    a = screwkit.analyze(pm)
    b = screwkit.analyze(moved, {k: a.solution.params[k] for k in pm.independent})
    np.testing.assert_allclose(b.statics.values, a.statics.values, rtol=1e-8, atol=1e-9)


# --------------------------------------------------------------------------- exports

def test_urdf_is_in_metres_and_kilograms_with_the_dynamics_inertias(tmp_path):
    pin = pytest.importorskip("pinocchio")
    pytest.importorskip("pint")
    from pathlib import Path

    from screwkit.interop import write_urdf
    pm = screwkit.load_pm(str(Path(__file__).parent / "data" / "stewart_6sps.yaml"))
    assert pm.units.length == "cm" and pm.units.force == "kN"
    urdf, side = write_urdf(pm, tmp_path / "s.urdf")
    model = pin.buildModelFromUrdf(urdf)
    data = model.createData()
    q0 = pin.neutral(model)
    # by hand: 1 kN.s^2/cm = 1e5 kg, 1 cm = 0.01 m
    dyn = pm.dynamics
    bodies = [(dyn.platform, None)] + [(b, i) for i, lg in enumerate(dyn.legs)
                                       for _, b in lg.links]
    mass = sum(b.mass for b, _ in bodies) * 1e5
    assert pin.computeTotalMass(model) == pytest.approx(mass, rel=1e-12)
    R, o = pm.platform_home
    coms = [(R @ b.com + o) if leg is None else b.com for b, leg in bodies]
    com = sum(b.mass * c for (b, _), c in zip(bodies, coms)) / sum(b.mass for b, _ in bodies)
    np.testing.assert_allclose(pin.centerOfMass(model, data, q0), com * 0.01, rtol=1e-10,
                               atol=1e-12)
    # a joint's home point: the model's cm times 0.01
    pin.forwardKinematics(model, data, q0)
    j = pm.home_legs[1].joints[0]
    np.testing.assert_allclose(data.oMi[model.getJointId(f"leg2_{j.name}")].translation,
                               np.asarray(j.point) * 0.01, atol=1e-12)
    import json
    assert json.loads(Path(side).read_text())["units"]["length"] == "m"


def test_urdf_without_masses_says_so_and_a_unitless_model_is_refused(tmp_path):
    from pathlib import Path

    from screwkit.interop import urdf_text
    text = urdf_text(screwkit.load_pm("3RRPRR"))
    assert "lengths in m" in text and "every link is massless" in text
    assert "<inertial>" not in text
    with pytest.raises(InputError, match="declares no units"):
        urdf_text(screwkit.load_pm(str(Path(__file__).parent / "data" / "user_pm.yaml")))


# --------------------------------------------------------------------------- batches

def test_a_batch_flags_its_bad_poses_and_keeps_the_others():
    res = screwkit.analyze("3RRPRR", {"alpha": [5, np.nan, 0, 1e9, 2], "beta": -3,
                                      "Zo": [80, 80, np.inf, 80, 80]}, degrees=True)
    assert res.ok.tolist() == [True, False, False, False, True]
    assert res.solution.status.tolist()[1:4] == ["invalid input"] * 3
    assert res.conditioning.tolist()[1:4] == ["unreachable"] * 3
    assert np.isnan(res.statics.values[1:4]).all()
    assert "not a finite number" in res.solution.notes[1][0]
    assert "beyond the limit" in res.solution.notes[3][0]
    for i in (0, 4):
        one = screwkit.analyze("3RRPRR", {"alpha": [5, 0, 0, 0, 2][i], "beta": -3, "Zo": 80},
                               degrees=True)
        np.testing.assert_allclose(res.statics.values[i], one.statics.values, rtol=1e-10)


def test_sizes_are_checked_before_any_array_is_converted():
    t = time.perf_counter()
    with pytest.raises(InputError, match="at most"):
        screwkit.analyze("3RRPRR", {"alpha": np.broadcast_to(0.0, (10 ** 9,))})
    with pytest.raises(InputError, match="at most"):
        screwkit.analyze("3RRPRR", {"alpha": np.zeros(10 ** 8)})
    assert time.perf_counter() - t < 2.0


# --------------------------------------------------------------------------- classification

def test_one_classification_with_the_engines_thresholds():
    cond = np.array([1.0, 999.0, 1001.0, 9.9e7, 2e8, np.nan])
    sing = cond > 1e8
    assert classify(cond, sing).tolist() == ["regular", "regular", "near-singular",
                                             "near-singular", "singular", "near-singular"]
    assert classify(cond, sing, [True] * 5 + [False])[-1] == "unreachable"
    from screwkit.engine import COND_THRESHOLD, NEAR_SINGULAR_COND
    assert (NEAR_SINGULAR_COND, COND_THRESHOLD) == (1e3, 1e8)


@pytest.mark.parametrize("name", ["3RRPRR", "6SPS", "4SPS+SPR"])
def test_a_workload_given_later_gives_the_analysis_bits(name):
    """``res.under(F, T)`` equals ``analyze(..., force=F, torque=T)`` bit for bit: the
    workload about O is formed by the statics kernels' own arithmetic both ways (``under``
    formed it in numpy in another order: 736 of 2000 3-RRPRR poses differed in the last
    bits of their efforts)."""
    m = screwkit.load_pm(name)
    rng = np.random.default_rng(5)
    L = float(m.normalisation.length)
    pose = {p: v + rng.uniform(-0.05, 0.05, 400) * (1.0 if p in ("alpha", "beta", "gamma")
                                                    else L) for p, v in m.default_pose.items()}
    FA, TA, FB, TB = [1.0, -2, -30], [5.0, 1, 2], [-7.0, 3, -11], [2.0, -9, 4]
    direct = screwkit.analyze(m, pose, force=FB, torque=TB).statics
    later = screwkit.analyze(m, pose, force=FA, torque=TA).under(FB, TB).statics
    for a, b in ((direct.F_r, later.F_r), (direct.workload, later.workload)):
        assert np.array_equal(np.asarray(a), np.asarray(b), equal_nan=True)
