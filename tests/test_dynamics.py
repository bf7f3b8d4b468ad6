"""Inverse dynamics along a motion (screwkit.dynamics): kinematics against finite differences
of solved poses, the static limit, the energy balance, invariance under a base-frame move and
a change of units, friction, and the result's columns."""

from __future__ import annotations

import numpy as np
import pytest
from scipy.integrate import simpson

import screwkit
from screwkit.dynamics import DynamicsResult, Motion, dynamics, motion_from_expressions

MASS = {"platform": {"mass": 40, "com": [1, 2, 3], "inertia": {"disc": {"radius": 30,
                                                                          "thickness": 3}}},
        "legs": {"cylinder": {"mass": 4, "length": 50, "radius": 4, "inner_radius": 3},
                 "piston": {"mass": 2, "length": 50, "radius": 2.5}}}

PATHS = {
    "3RRPRR": ["alpha=8*sin(2*pi*t)", "beta=6*sin(2*pi*t+1)+8", "Zo=75+10*t"],
    "2SPS+2SPR": ["alpha=5*sin(2*pi*t)", "beta=4*sin(2*pi*t+1)", "gamma=3*t", "Zo=70+10*t"],
    "3RPS": ["alpha=5*sin(2*pi*t)", "beta=4*sin(2*pi*t+1)", "Zo=ZO+5*t"],
    "3UPU": ["Xo=5*sin(2*pi*t)", "Yo=4*sin(2*pi*t+1)", "Zo=ZO+5*t"],
}


def _motion(pm, samples, t_range=(0.0, 1.0)):
    ex = [e.replace("ZO", repr(pm.default_pose.get("Zo", 0.0))) for e in PATHS[pm.name]]
    return motion_from_expressions(ex, pm.independent, samples=samples, t_range=t_range)


@pytest.fixture(scope="module")
def models():
    return {k: screwkit.load_pm(k) for k in PATHS}


def _rotvec(R):
    from scipy.spatial.transform import Rotation
    return Rotation.from_matrix(R).as_rotvec()


@pytest.mark.parametrize("name", ["3RRPRR", "3UPU", "2SPS+2SPR"])
def test_twist_and_acceleration_match_finite_differences_of_solved_poses(models, name):
    """The twist and acceleration from the closure velocity/acceleration equations equal the
    central differences of the poses solved by the engine at t +- h (an independent oracle)."""
    pm = models[name]
    t0 = np.array([0.13, 0.52, 0.81])
    h = 1e-4
    tt = np.concatenate([t0 - h, t0, t0 + h])
    base = _motion(pm, 3)
    exprs = [e.replace("ZO", repr(pm.default_pose.get("Zo", 0.0))) for e in PATHS[name]]
    from screwkit.dynamics import derivatives
    from screwkit.paths import parse_assignment
    vals, rates, accs = {}, {}, {}
    for e in exprs:
        k, text = parse_assignment(e)
        f, d1, d2 = derivatives(screwkit.pm.parse_expression(text), tt)
        s = np.pi / 180 if k in ("alpha", "beta", "gamma") else 1.0
        vals[k], rates[k], accs[k] = f * s, d1 * s, d2 * s
    order = np.argsort(tt)
    m = Motion.from_arrays(tt[order], {k: v[order] for k, v in vals.items()},
                           {k: v[order] for k, v in rates.items()},
                           {k: v[order] for k, v in accs.items()})
    assert set(m.names) == set(base.names)
    res = dynamics(pm, m, params=MASS, force=[0, 0, 0], torque=[0, 0, 0])
    assert res.ok.all()
    inv = np.argsort(order)
    R = res.analysis.solution.rotation[inv]
    o = res.analysis.solution.position[inv]
    V = res.twist[inv]
    A = res.acceleration[inv]
    n = len(t0)
    for j in range(n):
        lo, mid, hi = j, n + j, 2 * n + j
        w_fd = (_rotvec(R[hi] @ R[lo].T)) / (2 * h)
        vo_fd = (o[hi] - o[lo]) / (2 * h)
        ao_fd = (o[hi] - 2 * o[mid] + o[lo]) / h ** 2
        w = V[mid, 3:]
        vo = V[mid, :3] + np.cross(w, o[mid])
        wscale = max(np.abs(w).max(), np.abs(V[mid, :3]).max() / pm.normalisation.length)
        assert np.allclose(w, w_fd, rtol=1e-6, atol=1e-7 * wscale)
        assert np.allclose(vo, vo_fd, rtol=1e-6, atol=1e-6 * np.abs(vo).max())
        dw_fd = (V[hi, 3:] - V[lo, 3:]) / (2 * h)
        ascale = max(np.abs(A[mid, 3:]).max(), np.abs(A[mid, :3]).max() / pm.normalisation.length)
        assert np.allclose(A[mid, 3:], dw_fd, rtol=1e-5, atol=1e-6 * ascale)
        ao = A[mid, :3] + np.cross(A[mid, 3:], o[mid]) + np.cross(w, vo)
        assert np.allclose(ao, ao_fd, rtol=1e-3, atol=1e-4 * np.abs(ao_fd).max())
    # actuator rates are J_a V and equal the differences of the solved actuator values
    J = res.analysis.jacobian.matrix[inv]
    nact = res.analysis.jacobian.n_actuated
    assert np.allclose(np.einsum("nra,na->nr", J[:, :nact], V), res.actuator_rates[inv],
                       rtol=1e-10, atol=1e-10)
    q = res.analysis.solution.actuator_values[inv]
    assert np.allclose(res.actuator_rates[inv][n:2 * n], (q[2 * n:] - q[:n]) / (2 * h),
                       rtol=1e-6, atol=1e-6)
    assert np.allclose(res.actuator_accelerations[inv][n:2 * n],
                       (q[2 * n:] - 2 * q[n:2 * n] + q[:n]) / h ** 2, rtol=1e-3, atol=1e-3)


def test_static_limit_is_the_statics_of_the_weight(models):
    """No motion, massless legs, a platform of mass m: the dynamic forces are exactly the
    statics under F = m g at the centre of mass (plus the external load)."""
    pm = models["3RRPRR"]
    m = motion_from_expressions(["alpha=5", "beta=-3", "Zo=80"], pm.independent, samples=3)
    mass = {"platform": {"mass": 40, "com": [1, 2, 3], "inertia": [1, 2, 2.5]}}
    res = dynamics(pm, m, params=mass, force=[1, 2, 3], torque=[4, 5, 6])
    assert res.ok.all() and np.all(res.twist == 0) and np.all(res.acceleration == 0)
    mass_model = res.params.platform.mass
    assert mass_model == pytest.approx(40 * 1e-5)          # kg -> kN.s^2/cm
    g = res.params.gravity
    assert g == pytest.approx([0, 0, -980.665])             # cm/s^2
    R = res.analysis.solution.rotation[0]
    c = R @ np.array([1.0, 2.0, 3.0])                       # centre of mass - o
    W = mass_model * g
    ref = screwkit.analyze(pm, {"alpha": 5, "beta": -3, "Zo": 80}, degrees=True,
                           force=W + [1, 2, 3], torque=np.cross(c, W) + [4, 5, 6])
    for i in range(3):
        assert np.allclose(res.dynamic_active[i], ref.statics.active, rtol=1e-10, atol=0)
        assert np.allclose(res.dynamic_constraint[i], ref.statics.constraint, rtol=1e-10,
                           atol=1e-10 * np.abs(ref.statics.constraint).max())
    assert np.allclose(res.static_active[0], screwkit.analyze(
        pm, {"alpha": 5, "beta": -3, "Zo": 80}, degrees=True, force=[1, 2, 3],
        torque=[4, 5, 6]).statics.active, rtol=1e-12)


@pytest.mark.parametrize("name", list(PATHS))
def test_energy_balance_frictionless(models, name):
    """Along a frictionless motion the actuators' work equals the change of kinetic plus
    potential energy (Simpson's rule over 401 samples), to 1e-6."""
    pm = models[name]
    res = dynamics(pm, _motion(pm, 401), params=MASS, force=[0, 0, 0], torque=[0, 0, 0])
    assert res.ok.all()
    E = res.kinetic_energy + res.potential_energy
    work = simpson(res.actuator_power, x=res.t)
    assert abs(work - (E[-1] - E[0])) <= 1e-6 * np.abs(E - E[0]).max()
    r = res.residuals
    assert np.max(r["velocity"]) < 1e-9 and np.max(r["acceleration"]) < 1e-9
    assert np.max(r["balance"]) < 1e-9 and np.max(r["equilibrium"]) < 1e-9


def test_energy_balance_with_friction_and_a_load(models):
    """With viscous and Coulomb friction and an external workload: actuator work + external
    work = change of energy + the work dissipated in the joints."""
    pm = models["3RPS"]
    mass = {**MASS, "legs": {**MASS["legs"], "friction": {"P": {"viscous": 30, "coulomb": 2},
                                                          "R1": {"viscous": 5}}}}
    res = dynamics(pm, _motion(pm, 401), params=mass, force=[1, -2, 3], torque=[10, 20, -5])
    assert res.params.legs[0].viscous[1] == pytest.approx(30 * 1e-3)   # N.s/cm -> kN.s/cm
    loss = np.zeros(len(res))
    for ld, qd in zip(res.params.legs, res.joint_rates):
        loss += np.sum(ld.viscous * qd ** 2 + ld.coulomb * np.abs(qd), axis=1)
    E = res.kinetic_energy + res.potential_energy
    work = simpson(res.actuator_power + res.external_power - loss, x=res.t)
    assert abs(work - (E[-1] - E[0])) <= 1e-6 * np.abs(E - E[0]).max()
    assert simpson(loss, x=res.t) > 0


def test_invariant_under_a_base_frame_move(models):
    """Moving the base frame (and gravity with it) changes no force value."""
    from scipy.spatial.transform import Rotation
    pm = models["3UPU"]
    R = Rotation.from_euler("xyz", [0.3, -0.2, 0.5]).as_matrix()
    moved = pm.moved(R, [10.0, -5.0, 3.0])
    m = _motion(pm, 21)
    a = dynamics(pm, m, params=MASS, force=[0, 0, 0], torque=[0, 0, 0])
    b = dynamics(moved, m, params=MASS, force=[0, 0, 0], torque=[0, 0, 0])
    assert np.allclose(a.dynamic_active, b.dynamic_active, rtol=1e-9, atol=1e-12)
    assert np.allclose(a.kinetic_energy, b.kinetic_energy, rtol=1e-9)
    # the leg wrenches turn with the frame (about the moved origin)
    wa, wb = a.leg_wrenches, b.leg_wrenches
    p = np.array([10.0, -5.0, 3.0])
    f = np.einsum("ij,nlj->nli", R, wa[..., :3])
    mo = np.einsum("ij,nlj->nli", R, wa[..., 3:]) + np.cross(p, f)
    assert np.allclose(wb[..., :3], f, atol=1e-9 * np.abs(f).max())
    assert np.allclose(wb[..., 3:], mo, atol=1e-9 * np.abs(mo).max())


def _scaled(pose):
    """Lengths of a pose mapping / 100 (expressions of the dimensions scale with them)."""
    return {k: (v / 100 if k in ("Xo", "Yo", "Zo") and not isinstance(v, str) else v)
            for k, v in pose.items()}


def test_invariant_under_a_change_of_units(tmp_path):
    """The same PM in cm/kN and in m/N, the same masses in kg: the same physical forces."""
    from screwkit.pm import default_catalog
    import yaml
    d = dict(default_catalog().pms["3RPS"])
    cm = {**d, "units": {"length": "cm", "force": "kN"}}
    dims = d.get("dimensions") or {}
    m_ = {**d, "units": {"length": "m", "force": "N"},
          "dimensions": {k: v / 100 for k, v in dims.items()},
          "pose": _scaled(d["pose"])}
    if "home" in d:
        m_["home"] = _scaled(d["home"])
    for name, spec in (("cm", cm), ("m", m_)):
        (tmp_path / f"{name}.yaml").write_text(yaml.safe_dump({"pms": {"3RPS": spec}}))
    a_pm = screwkit.load_pm(str(tmp_path / "cm.yaml"))
    b_pm = screwkit.load_pm(str(tmp_path / "m.yaml"))
    mass_cm = {**MASS, "units": {"mass": "kg", "length": "cm", "force": "N"}}
    z = a_pm.default_pose["Zo"]
    ma = motion_from_expressions(["alpha=5*sin(2*pi*t)", "beta=4*t", f"Zo={z}+5*t"],
                                 a_pm.independent, samples=11)
    mb = motion_from_expressions(["alpha=5*sin(2*pi*t)", "beta=4*t", f"Zo={z / 100}+0.05*t"],
                                 b_pm.independent, samples=11)
    ra = dynamics(a_pm, ma, params=mass_cm, force=[0, 0, 0], torque=[0, 0, 0])
    rb = dynamics(b_pm, mb, params=mass_cm, force=[0, 0, 0], torque=[0, 0, 0])
    assert np.allclose(ra.dynamic_active * 1000.0, rb.dynamic_active, rtol=1e-8)   # kN -> N
    assert np.allclose(ra.kinetic_energy * 10.0, rb.kinetic_energy, rtol=1e-8)     # kN.cm -> J


def test_callable_module_result_and_columns(models, tmp_path):
    pm = models["3RRPRR"]
    res = screwkit.dynamics(pm, _motion(pm, 11), params=MASS)
    assert isinstance(res, DynamicsResult) and res.counts()["ok"] == 11
    names = [c for c, _, _ in res.columns()]
    for c in ("t", "F_a1", "F_a1_dyn", "F_c1", "F_c1_dyn", "rdot1", "rddot3",
              "kinetic_energy", "actuator_power"):
        assert c in names
    text = res.to_csv()
    assert text.splitlines()[0].startswith("t [s],status,Xo [cm]")
    assert "F_a1_dyn [kN]" in text.splitlines()[0]
    d = res.to_dict()
    assert d["units"]["mass"] == "kN.s^2/cm" and d["columns"]["F_a2_dyn"]["unit"] == "kN"
    assert len(res.joint_rates) == 3 and res.joint_rates[0].shape == (11, 5)


def test_csv_motion_spline_is_close_to_the_exact_derivatives(models, tmp_path):
    pm = models["3RRPRR"]
    exact = _motion(pm, 201)
    p = tmp_path / "path.csv"
    cols = ["t"] + list(pm.independent)
    rows = [",".join(cols)]
    for i, t in enumerate(exact.t):
        rows.append(",".join([repr(float(t))] + [
            repr(float(np.degrees(exact.values[k][i]) if k != "Zo" else exact.values[k][i]))
            for k in pm.independent]))
    p.write_text("\n".join(rows) + "\n")
    from screwkit.dynamics import motion_from_csv
    sp = motion_from_csv(p, pm.independent, smoothing=0.0)
    inner = slice(20, -20)
    for k in pm.independent:
        scale = max(np.abs(exact.rates[k]).max(), 1.0)
        assert np.allclose(sp.rates[k][inner], exact.rates[k][inner], atol=1e-5 * scale)
        scale = max(np.abs(exact.accelerations[k]).max(), 1.0)
        assert np.allclose(sp.accelerations[k][inner], exact.accelerations[k][inner],
                           atol=1e-3 * scale)
    assert "smoothing spline" in sp.method and sp.notes


def test_bad_inputs(models):
    pm = models["3RRPRR"]
    with pytest.raises(screwkit.InputError, match="declares no masses"):
        dynamics(pm, _motion(pm, 5))
    with pytest.raises(screwkit.InputError, match="independent pose parameters"):
        dynamics(pm, motion_from_expressions(["alpha=t", "beta=0", "Zo=80"],
                                             pm.independent, samples=5).path.__class__(
            np.arange(5.0), {"alpha": np.zeros(5)}), params=MASS)
    with pytest.raises(screwkit.CatalogError, match="dynamics.legs.piston.mass"):
        dynamics(pm, _motion(pm, 5), params={"legs": {"piston": {"mass": -1, "length": 3}}})
    with pytest.raises(screwkit.InputError, match="gravity"):
        dynamics(pm, _motion(pm, 5), params=MASS, gravity=[0, 0])


def test_a_given_gravity_is_the_one_the_notes_name(models):
    pm = models["3RRPRR"]
    default = dynamics(pm, _motion(pm, 3), params=MASS)
    assert any(n.startswith("gravity: standard gravity") for n in default.params.notes)
    none = dynamics(pm, _motion(pm, 3), params=MASS, gravity=[0, 0, 0])
    said = [n for n in none.params.notes if n.startswith("gravity")]
    assert said == ["gravity: (0, 0, 0) model length/s^2 in the base frame, as given"]
    assert np.array_equal(none.params.gravity, [0, 0, 0])


def test_an_interpolated_path_has_the_path_accelerations_at_its_ends(models):
    """``--smoothing 0`` interpolated with a natural spline: its second derivative is 0 at
    the first and last samples, whatever the path (beta = 10 sin(2 t) deg has -40 sin(2) deg/s^2
    at t = 1, by hand). The not-a-knot spline through 41 exact samples has the closed form's
    accelerations at the ends to 1 %."""
    from screwkit.dynamics import motion_from_samples
    t = np.linspace(0.0, 1.0, 41)
    beta = np.radians(10.0 * np.sin(2.0 * t))
    sp = motion_from_samples(t, {"beta": beta}, ["beta"], smoothing=0.0)
    exact = np.radians(-40.0 * np.sin(2.0 * t))
    for i in (0, -1):
        assert sp.accelerations["beta"][i] == pytest.approx(exact[i], rel=1e-2, abs=1e-3)
    smooth = motion_from_samples(t, {"beta": beta}, ["beta"], smoothing=1e-9)
    assert "second derivative is 0 at the first and last samples" in " ".join(smooth.notes)
