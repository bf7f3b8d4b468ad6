"""Passive legs: a leg without an actuator adds its constraint rows to J and no actuation row.

The Tricept-type 3UPS+UP/passive (K.-E. Neumann, US patent 4,732,525; the kinematics of
B. Siciliano, "The Tricept robot: inverse kinematics, manipulability analysis and closed-loop
direct kinematics algorithm", Robotica 17, 1999) is written here as a model file of its own,
with the passive central column a UP leg: a U at the base centre O (first axis the base X
axis, second axis normal to it and to the column) and a P along the column, rigidly fixed to
the platform at its centre o.  Everything the engine prints is compared with a derivation
by hand:

* the platform orientation is that of the column, R = Rx(alpha) Ry(beta) (so with the
  intrinsic XYZ order gamma = 0), and o = s R z with s = Zo / (R z)_z;
* the column exerts the wrenches reciprocal to its twists [0; X], [0; Rx(alpha) Y] (the
  U's rotations about lines through O) and [R z; 0] (the P): forces through O normal to
  the column and a couple along X x Rx(alpha) Y;
* the platform's freedoms are those three twists; virtual work on each of them gives the
  three actuator forces of the UPS legs, whose actuation rows are unit forces along the
  legs: sum_i F_ai (u_i . v + (B_i x u_i) . w) = -(W . T) for each freedom T = [v; w],
  with W = [F; T + o x F] about O.
"""

import numpy as np
import pytest

import screwkit
from screwkit.errors import CatalogError, InputError, ParseError
from screwkit.legs import parse_pm

X, Y, Z = np.eye(3)

TRICEPT = """\
units: {length: mm, force: N}
legs:
  - name: UP/column
    string: U_P
    summary: the Tricept's passive column
    joints:
      - {at: A, axes: [base.X, {perpendicular: [U1a, leg]}]}
      - {axis: leg}
    structure:
      - {perpendicular: [U1b, leg]}
pms:
  tricept:
    string: 3UPS+UP/passive
    dimensions: {R: 300, r: 110, H: 650}
    base: {points: [[R, 0, 0], [-R/2, R*sqrt(3)/2, 0], [-R/2, -R*sqrt(3)/2, 0], [0, 0, 0]]}
    platform: {points: [[r, 0, 0], [-r/2, r*sqrt(3)/2, 0], [-r/2, -r*sqrt(3)/2, 0], [0, 0, 0]]}
    legs: [UPS, UPS, UPS, {leg: UP/column, passive: true}]
    euler: XYZ
    independent: [alpha, beta, Zo]
    home: {alpha: 0, beta: 0, Zo: H}
    pose: {alpha: 5, beta: -3, Zo: H}
    dof: 3
    motion: 1T2R
"""


def _rx(t):
    c, s = np.cos(t), np.sin(t)
    return np.array([[1, 0, 0], [0, c, -s], [0, s, c]])


def _ry(t):
    c, s = np.cos(t), np.sin(t)
    return np.array([[c, 0, s], [0, 1, 0], [-s, 0, c]])


@pytest.fixture(scope="module")
def tricept_file(tmp_path_factory):
    p = tmp_path_factory.mktemp("passive") / "tricept.yaml"
    p.write_text(TRICEPT)
    return screwkit.load_pm(str(p))


@pytest.fixture(scope="module")
def tricept():
    """The catalog's Tricept (the same dimensions as the file above)."""
    return screwkit.load_pm("3UPS+UP/passive")


def _hand(alpha, beta, Zo, R=300.0, r=110.0):
    """Pose, actuation rows, freedoms and constraint wrenches of the Tricept, by hand."""
    Rp = _rx(alpha) @ _ry(beta)
    d = Rp @ Z
    o = (Zo / d[2]) * d
    ang = np.radians([0.0, 120.0, 240.0])
    B = np.column_stack([R * np.cos(ang), R * np.sin(ang), np.zeros(3)])
    P = o + (Rp @ np.column_stack([r * np.cos(ang), r * np.sin(ang), np.zeros(3)]).T).T
    u = (P - B) / np.linalg.norm(P - B, axis=1)[:, None]
    Ja = np.hstack([u, np.cross(B, u)])
    e2 = _rx(alpha) @ Y
    freedoms = np.array([np.r_[0, 0, 0, X], np.r_[0, 0, 0, e2], np.r_[d, 0, 0, 0]])
    n = np.cross(X, e2)
    f1 = np.cross(d, X)
    f1 /= np.linalg.norm(f1)
    constraints = np.array([np.r_[f1, 0, 0, 0], np.r_[np.cross(d, f1), 0, 0, 0],
                            np.r_[0, 0, 0, n / np.linalg.norm(n)]])
    return Rp, o, np.linalg.norm(P - B, axis=1), Ja, freedoms, constraints


def _actuator_forces(Ja, freedoms, F, T, o):
    W = np.r_[F, np.asarray(T) + np.cross(o, F)]
    # virtual work on each freedom: sum_i F_ai (Ja_i . T_k) = -(W . T_k)
    return np.linalg.solve(freedoms @ Ja.T, -(freedoms @ W))


POSES = [(0.0, 0.0, 650.0), (5.0, -3.0, 650.0), (-12.0, 8.0, 590.0), (9.0, 14.0, 720.0)]


@pytest.mark.parametrize("alpha,beta,Zo", POSES)
def test_tricept_against_the_hand_derivation(tricept, alpha, beta, Zo):
    F, T = np.array([30.0, -20.0, -500.0]), np.array([4000.0, -2500.0, 1500.0])
    res = screwkit.analyze(tricept, {"alpha": alpha, "beta": beta, "Zo": Zo}, degrees=True,
                           force=F, torque=T)
    Rp, o, lengths, Ja, freedoms, constraints = _hand(np.radians(alpha), np.radians(beta), Zo)
    sol = res.solution
    # inverse displacement: the column's orientation and the platform centre on it
    np.testing.assert_allclose(sol.rotation, Rp, atol=1e-10)
    np.testing.assert_allclose(sol.position, o, atol=1e-8)
    assert abs(sol.params["gamma"]) < 1e-10
    np.testing.assert_allclose(sol.extensions[:3], lengths, rtol=1e-10)
    # J: 3 actuation rows (the UPS legs), 3 constraint rows of the passive column
    jac = res.jacobian
    assert jac.n_actuated == 3 and jac.J.shape == (6, 6)
    assert jac.labels[:3] == ("F_a1", "F_a2", "F_a3")
    assert [r.leg for r in jac.info] == [0, 1, 2, 3, 3, 3]
    assert all(r.kind != "actuation" for r in jac.info if r.leg == 3)
    np.testing.assert_allclose(jac.J_a, Ja, atol=1e-10)
    # the column's rows span the hand constraint system (and are reciprocal to its twists)
    s = np.linalg.svd(np.vstack([constraints, jac.J_c]), compute_uv=False)
    assert s[3] < 1e-9 * s[0]
    # statics: actuator forces from virtual work; the column takes the rest
    Fa = _actuator_forces(Ja, freedoms, F, T, o)
    np.testing.assert_allclose(res.statics.active, Fa, rtol=1e-9, atol=1e-9 * np.abs(Fa).max())
    W = np.r_[F, T + np.cross(o, F)]
    column = res.statics.leg_wrenches[3]
    np.testing.assert_allclose(column, -(W + Fa @ Ja), atol=1e-8 * np.abs(W).max())
    assert abs(column[:3] @ (Rp @ Z)) < 1e-8 * np.abs(W).max()          # no force along it
    # mobility: 3 DOF, the three actuated legs; the twist space is the hand freedoms
    m = res.mobility
    assert (m.dof, m.constraint_rank, m.n_constraints, m.actuators) == (3, 3, 3, 3)
    assert m.passive == (3,) and m.motion_type == "1T2R"
    per_length = np.r_[np.ones(3), np.full(3, Zo)]          # v / L and w on one scale
    s = np.linalg.svd(np.vstack([freedoms, m.twists]) * per_length, compute_uv=False)
    assert s[3] < 1e-8 * s[0]


def test_the_file_and_the_catalog_tricept_agree(tricept, tricept_file):
    pose = {"alpha": 0.07, "beta": -0.04, "Zo": 610.0}
    a = screwkit.analyze(tricept, pose, force=[1.0, 2.0, -300.0], torque=[0, 0, 0])
    b = screwkit.analyze(tricept_file, pose, force=[1.0, 2.0, -300.0], torque=[0, 0, 0])
    assert tricept.string == tricept_file.string == "3UPS+UP/passive"
    np.testing.assert_allclose(a.jacobian.J, b.jacobian.J, atol=1e-12)
    np.testing.assert_allclose(a.statics.values, b.statics.values, rtol=1e-12, atol=1e-12)


def test_tricept_report_names_the_passive_leg(tricept):
    res = screwkit.analyze(tricept, force=[0, 0, -100.0], torque=[0, 0, 0])
    d = res.to_dict()
    legs = d["legs"]
    assert [lg["passive"] for lg in legs] == [False, False, False, True]
    assert "actuation" not in legs[3] and "actuator_value" not in legs[3]
    assert all("actuator_value" in lg for lg in legs[:3])
    assert d["statics"]["labels"][:3] == ["F_a1", "F_a2", "F_a3"]
    assert len(d["statics"]["active"]) == 3
    assert d["mobility"]["actuators"] == 3 and d["mobility"]["passive_legs"] == [4]
    assert res.solution.actuator_values.shape == (3,)


def test_passive_in_pm_strings():
    p = parse_pm("3UPS+UP/passive")
    assert p.passive == (3,) and p.canonical == "3UPS+UP/passive"
    assert [ls.text for ls in p.legs] == ["UPS", "UPS", "UPS", "UP"]
    p = parse_pm("2UP/passive + 3-UPS")
    assert p.passive == (0, 1) and p.canonical == "2UP/passive+3UPS"
    assert parse_pm("3RPS").passive == ()
    for bad, where in (("3UPS+UP/pasive", 7), ("3UPS+/passive", 5), ("UPS/", 3)):
        with pytest.raises(ParseError) as e:
            parse_pm(bad)
        assert f"position {where}" in str(e.value)


def _variant(tmp_path, legs_line, string="3UPS+UP/passive"):
    text = TRICEPT.replace("    legs: [UPS, UPS, UPS, {leg: UP/column, passive: true}]",
                           f"    legs: {legs_line}").replace(
        "string: 3UPS+UP/passive", f"string: {string}")
    p = tmp_path / "m.yaml"
    p.write_text(text)
    return str(p)


def test_passive_declarations_must_agree(tmp_path):
    # the string says passive, the legs do not
    with pytest.raises(CatalogError, match=r"do not make 3UPS\+UP/passive.*LEG/passive"):
        screwkit.load_pm(_variant(tmp_path, "[UPS, UPS, UPS, UP/column]"))
    # the legs say passive, the string does not
    with pytest.raises(CatalogError, match="do not make 3UPS"):
        screwkit.load_pm(_variant(tmp_path, "[UPS, UPS, UPS, {leg: UP/column, passive: true}]",
                                  "3UPS+UP"))
    # a boolean only as true / false, only for 'passive'
    with pytest.raises(CatalogError, match="write true or false"):
        screwkit.load_pm(_variant(tmp_path, "[UPS, UPS, UPS, {leg: UP/column, passive: yes}]"))
    with pytest.raises(CatalogError, match=r"passive.*did you mean"):
        screwkit.load_pm(_variant(tmp_path, "[UPS, UPS, UPS, {leg: UP/column, pasive: 1}]"))
    with pytest.raises(CatalogError, match="at least one actuated leg"):
        screwkit.load_pm(_variant(
            tmp_path, "[{leg: UPS, passive: true}, {leg: UPS, passive: true}, "
                      "{leg: UPS, passive: true}, {leg: UP/column, passive: true}]",
            "3UPS/passive+UP/passive"))


def test_passive_leg_is_not_an_actuator_in_the_engine(tricept):
    sol = screwkit.solve(tricept, {"alpha": np.radians([2.0, -4.0]), "beta": 0.05,
                                   "Zo": [640.0, 660.0]})
    assert sol.actuator_values.shape == (2, 3)
    with pytest.raises(InputError, match="q1, q2, q3.*leg 4 passive"):
        screwkit.forward(tricept, {"q1": 0.0, "q2": 0.0, "q3": 0.0, "q4": 1.0})


def test_placed_legs_take_passive_indices(tricept):
    F, T = [10.0, 0.0, -300.0], [500.0, 0.0, 0.0]
    res = screwkit.analyze(tricept, {"alpha": 0.1, "beta": -0.05, "Zo": 630.0}, force=F,
                           torque=T)
    from screwkit.engine import solve_statics
    st = solve_statics(res.solution.legs, res.solution.position, F, T, passive=(3,))
    assert st.jacobian.n_actuated == 3
    np.testing.assert_allclose(st.active, res.statics.active, rtol=1e-9)
    with pytest.raises(InputError, match="passive"):
        solve_statics(res.solution.legs, res.solution.position, F, T, passive=(0, 1, 2, 3))


def test_forward_kinematics_takes_the_actuated_legs_only(tricept):
    pose = {"alpha": np.radians(4.0), "beta": np.radians(-2.5), "Zo": 640.0}
    sol = screwkit.solve(tricept, pose)
    fk = screwkit.forward(tricept, sol.actuator_values)          # 3 values, legs 1-3
    assert bool(fk.success[0])
    got = fk.pose(0, degrees=True)
    for p, v in pose.items():
        want = np.degrees(v) if p in ("alpha", "beta") else v
        assert abs(got[p] - want) < 1e-8 * (1 if p in ("alpha", "beta") else 650)
    # leg extensions name the actuated legs: r1..r3 (r4 is the passive column)
    r = {f"r{i + 1}": float(sol.extensions[i]) for i in range(3)}
    assert bool(screwkit.forward(tricept, r).success[0])
    with pytest.raises(InputError, match="give 3 finite actuated joint values"):
        screwkit.forward(tricept, np.zeros(4))


def test_maps_trajectories_and_export_name_the_actuated_legs(tricept, tmp_path):
    ds = screwkit.map(tricept, {"alpha": (-4, 4, 3)}, fix={"beta": 0.0, "Zo": 650.0},
                      degrees=True, force=[0, 0, -100.0], torque=[0, 0, 0])
    assert {"q_a1", "q_a2", "q_a3", "F_a1", "F_a3", "T_c4"} <= set(ds.data_vars)
    assert "q_a4" not in ds.data_vars and "F_a4" not in ds.data_vars
    from screwkit.paths import path_from_expressions, run_trajectory
    path = path_from_expressions(["alpha=3*sin(2*pi*t)", "beta=0", "Zo=650"],
                                 tricept.independent, samples=5)
    tr = run_trajectory(tricept, path, force=[0, 0, -100.0], torque=[0, 0, 0])
    assert tr.active.shape == (5, 3) and tr.actuated == (0, 1, 2)
    cols = [c for c, _ in tr.columns()]
    assert "F_a3" in cols and "F_a4" not in cols and "T_c4" in cols
    from screwkit.interop import closures
    assert closures(tricept)["actuated_joints"] == ["leg1_P2", "leg2_P2", "leg3_P2"]
    assert closures(tricept)["passive_legs"] == [4]


def test_dynamics_of_the_tricept_against_pinocchio(tricept):
    pytest.importorskip("pinocchio")
    from screwkit.dynamics import check_dynamics, motion_from_expressions
    ups = {"cylinder": {"mass": 6, "length": 350, "radius": 30, "inner_radius": 25},
           "piston": {"mass": 3, "length": 350, "radius": 20}}
    params = {"units": {"mass": "kg", "length": "mm", "force": "N"},
              "platform": {"mass": 30, "inertia": {"disc": {"radius": 120, "thickness": 20}}},
              "legs": [ups, ups, ups,
                       {"cylinder": {"mass": 12, "length": 450, "radius": 50,
                                     "inner_radius": 40}}]}
    m = motion_from_expressions(["alpha=6*sin(2*pi*t)", "beta=4*cos(2*pi*t)", "Zo=650+40*t"],
                                tricept.independent, samples=9, t_range=(0, 0.5))
    res = screwkit.dynamics(tricept, m, params=params, force=[0, 0, -200.0], torque=[0, 0, 0])
    assert res.dynamic_active.shape == (9, 3) and res.actuator_rates.shape == (9, 3)
    chk = check_dynamics(tricept, result=res)
    assert chk.passed(1e-9), chk.errors
    assert chk.residual < 1e-9


def _stretched_column_pm(scale=1.0, units="mm"):
    """Three UPS legs and a passive planar R-R-R column (axes along z) whose reach is 200 mm:
    the column is singular where its three joints line up (stretched)."""
    b = screwkit.PMBuilder("rrr-column", units={"length": units, "force": "N"})
    zb = np.array([0.0, 0.0, -200.0])
    for t in np.radians([90, 210, 330]):
        u = np.array([np.cos(t), np.sin(t), 0.0])
        A = 180 * np.array([np.cos(t + 0.7), np.sin(t + 0.7), 0.0]) + zb
        b.add_leg("UPS", base=A * scale, platform=60 * u * scale)
    P1, P2 = np.array([0, 0, -50.0]), np.array([100, 0, -50.0])
    P3 = np.array([150, 86.60254037844386, 0.0])
    col = screwkit.leg_from_joints([("R", [0, 0, 1], P1 * scale), ("R", [0, 0, 1], P2 * scale),
                                    ("R", [0, 0, 1], P3 * scale)], P1 * scale, P3 * scale)
    b.add_leg(col, base=P1 * scale, platform=P3 * scale, passive=True)
    b.set_pose(["Xo", "Yo", "gamma"], home={"Xo": 0, "Yo": 0, "gamma": 0}, order="XYZ")
    return b.build(), P3[:2]


def test_a_passive_leg_near_its_own_singularity_is_said():
    """A passive leg has no transmission index: where its twists lose rank (the R-R-R column
    stretched, its joints on a line) the platform loses a freedom and the statics become
    indeterminate, and nothing said so (condition of J 10.4, no warning). By hand: at a
    distance eps short of the stretch the elbow stands off the line by about sqrt(2 a eps)
    (a, b the links), so the twists' condition number grows as eps^-1/2: ten times for eps
    a hundred times smaller. It is said beyond 1e3, the same in m as in mm."""
    from screwkit.engine._passive import passive_leg_conditioning
    F, T = [10.0, 5.0, -30.0], [100.0, -50.0, 20.0]
    conds = {}
    for units, scale in (("mm", 1.0), ("m", 1e-3)):
        pm, p3 = _stretched_column_pm(scale, units)
        d = p3 / np.linalg.norm(p3)
        for eps in (5.0, 0.1, 1e-3):
            s = (200 - np.linalg.norm(p3) - eps) * scale
            res = screwkit.analyze(pm, {"Xo": s * d[0], "Yo": s * d[1], "gamma": 0.0},
                                   force=F, torque=[t * scale for t in T])
            conds[units, eps] = passive_leg_conditioning(res)[3]
            said = [w for w in res.warnings if w.startswith("passive leg 4")]
            assert bool(said) == (eps == 1e-3), (units, eps, res.warnings)
    assert conds["mm", 1e-3] / conds["mm", 0.1] == pytest.approx(10.0, rel=0.05)
    for eps in (5.0, 0.1, 1e-3):
        assert conds["m", eps] == pytest.approx(conds["mm", eps], rel=1e-6)
    # the catalog's passive columns are never said: a U-P column keeps its rank, and an S is
    # a ball (its three R axes align where they lock, a representation, not the joint)
    rng = np.random.default_rng(3)
    for name in ("3UPS+UP/passive", "3UPS+S/passive"):
        pm = screwkit.load_pm(name)
        for _ in range(10):
            pose = {k: v + rng.uniform(-0.5, 0.5) if k in ("alpha", "beta", "gamma") else v
                    for k, v in pm.default_pose.items()}
            res = screwkit.analyze(pm, pose, force=[0, 0, -1], raise_on_singular=False)
            assert max(passive_leg_conditioning(res).values()) < 10.0
