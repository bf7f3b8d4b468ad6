"""Pinocchio cross-check: screwkit legs vs Pinocchio models with native joints.

The screwkit side of every comparison is computed here, independently of the
code under test: the product of exponentials with ``scipy.linalg.expm`` of the
4x4 se(3) matrices, current twists by the adjoint map, and wrenches from the
null spaces of those twists (``scipy.linalg.null_space``).
"""

import zlib

import numpy as np
import pytest
from scipy.linalg import expm, null_space
from scipy.optimize import least_squares

pin = pytest.importorskip("pinocchio")

import screwkit  # noqa: E402
from screwkit.errors import InputError  # noqa: E402
from screwkit.interop import (build_closed_loop_model, build_leg_model,  # noqa: E402
                              check_closed_loop, check_leg, constraint_jacobian, mobility,
                              sphere_angles)
from screwkit.legs import Joint, Leg, Placement  # noqa: E402

TOL = 1e-9
LEGS = ["SPR", "RRPRR", "UPU/couple", "UPU/force", "SPS", "PRRR", "RHC", "US", "CRU", "UPS"]


# ---------------------------------------------------------------- reference POE
def hat(xi):
    v, w = xi[:3], xi[3:]
    X = np.zeros((4, 4))
    X[:3, :3] = [[0, -w[2], w[1]], [w[2], 0, -w[0]], [-w[1], w[0], 0]]
    X[:3, 3] = v
    return X


def home_pose(leg):
    return np.eye(3), np.asarray(leg.a, float)


def poe(leg, q, T_home):
    """End pose T(q) = prod exp(xi_i q_i) T_home and the leg placed at q (independent)."""
    T = np.eye(4)
    joints = []
    for j, qi in zip(leg.joints, q):
        R, p = T[:3, :3], T[:3, 3]
        joints.append(Joint(j.spec, R @ j.direction, R @ j.point + p, j.pitch))
        T = T @ expm(hat(j.twist.vector) * qi)
    a = T[:3, :3] @ leg.a + T[:3, 3]
    return T @ T_home, Leg(leg.string, tuple(joints), leg.A, a, leg.name)


def T_of(R, p):
    T = np.eye(4)
    T[:3, :3], T[:3, 3] = R, p
    return T


def random_q(leg, rng, ang=0.6):
    L = leg.length
    return np.array([rng.uniform(-ang, ang) * (0.3 * L if j.kind == "P" else 1.0) for j in leg.joints])


def wrench_basis(twists, length):
    """Physical wrenches [f; m] reciprocal to the rows of ``twists`` (null space, scaled)."""
    Tn = np.hstack([twists[:, :3] / length, twists[:, 3:]])
    N = null_space(Tn)                                   # columns: [f; m / L]
    return np.vstack([N[:3], N[3:] * length]).T


def leg_wrench(placed, rng, f_act):
    """A wrench on the platform: f_act x (unit actuation wrench) + random constraint wrenches."""
    T = placed.twists
    ia = placed.actuated_index
    L = placed.length
    C = wrench_basis(T, L)
    A = wrench_basis(np.delete(T, ia, axis=0), L)
    g = A @ T[ia]
    act = (g @ A) / (g @ g)                              # act . xi_a = 1, reciprocal to the passive joints
    w = f_act * act + (rng.normal(size=len(C)) * 50.0) @ C if len(C) else f_act * act
    return w, act, C


# ---------------------------------------------------------------- model building
@pytest.mark.parametrize("name", LEGS)
def test_home_frames_are_world_aligned_at_the_joint_points(name):
    leg = screwkit.leg(name)
    lm = build_leg_model(leg)
    model = lm.model
    assert model.check(model.createData())
    for b in lm.chain.blocks:
        jp = model.jointPlacements[b.joint_id]
        assert np.array_equal(jp.rotation, np.eye(3))        # pure translation from the parent
    kinds = [b.kind for b in lm.chain.blocks]
    native = {"S": ["spherical"], "U": ["universal"], "R": ["revolute"], "P": ["prismatic"],
              "H": ["helical"], "C": ["prismatic", "revolute"]}
    assert kinds == [k for c in leg.string.text for k in native[c]]
    assert model.nv == len(leg.joints)
    assert model.nq == len(leg.joints) + kinds.count("spherical")


@pytest.mark.parametrize("name", LEGS)
def test_fk_jacobian_and_q_map_agree_with_poe(name):
    rng = np.random.default_rng(zlib.crc32(name.encode()))   # (the same draws every run)
    leg = screwkit.leg(name)
    lm = build_leg_model(leg)
    L = leg.length
    for _ in range(3):
        q = random_q(leg, rng)
        T, placed = poe(leg, q, T_of(*home_pose(leg)))
        data = lm.model.createData()
        qp = lm.q(q)
        pin.framesForwardKinematics(lm.model, data, qp)
        F = data.oMf[lm.chain.frame_id]
        assert np.linalg.norm(F.translation - T[:3, 3]) / L < TOL
        assert np.abs(F.rotation - T[:3, :3]).max() < TOL
        J = pin.computeFrameJacobian(lm.model, data, qp, lm.chain.frame_id, pin.WORLD)
        Jsk = J @ lm.velocity_map(q)
        scale = np.r_[np.full(3, 1 / L), np.ones(3)][:, None]
        assert np.abs(scale * (Jsk - placed.twists.T)).max() < TOL
        assert np.allclose(lm.joint_values(qp, hint=q), q, atol=1e-12)


def test_velocity_map_by_finite_differences_on_a_sphere():
    leg = screwkit.leg("UPS")                   # generic, non-orthogonal S axes at the platform
    lm = build_leg_model(leg)
    q = random_q(leg, np.random.default_rng(3))
    M = lm.velocity_map(q)
    h = 1e-6
    for i in range(len(q)):
        dq = np.zeros(len(q))
        dq[i] = h
        vfd = pin.difference(lm.model, lm.q(q - dq), lm.q(q + dq)) / (2 * h)
        assert np.allclose(vfd, M[:, i], atol=1e-8)


def test_sphere_angles_inverts_general_axes():
    rng = np.random.default_rng(7)
    axes = np.array([u / np.linalg.norm(u) for u in rng.normal(size=(3, 3))])
    for _ in range(20):
        ang = rng.uniform(-2.5, 2.5, 3)
        R = expm(hat(np.r_[0, 0, 0, axes[0] * ang[0]]))[:3, :3] @ \
            expm(hat(np.r_[0, 0, 0, axes[1] * ang[1]]))[:3, :3] @ expm(hat(np.r_[0, 0, 0, axes[2] * ang[2]]))[:3, :3]
        got = sphere_angles(R, axes, hint=ang + 0.1)
        assert np.allclose(got, ang, atol=1e-9)


# ---------------------------------------------------------------- one-leg checks
@pytest.mark.parametrize("name", LEGS)
def test_leg_checks_pass_on_independent_reference(name):
    rng = np.random.default_rng(11 + len(name))
    leg = screwkit.leg(name)
    q = random_q(leg, rng)
    T, placed = poe(leg, q, T_of(*home_pose(leg)))
    w, _, _ = leg_wrench(placed, rng, f_act=37.5)
    rep = check_leg(leg, q, home_pose(leg), (T[:3, :3], T[:3, 3]), placed, w, 37.5, rtol=TOL)
    assert rep.passed, str(rep)
    names = {r.name for r in rep.rows}
    assert {"closure.position", "twists", "statics.passive", "statics.actuator"} <= names
    assert ("closure.orientation" in names) == (leg.string.text[-1] != "S")
    assert sum(n.startswith("twists.span.S") for n in names) == leg.string.text.count("S")
    assert max(r.deviation for r in rep.rows) < 1e-11


def test_corrupted_inputs_are_caught():
    rng = np.random.default_rng(5)
    leg = screwkit.leg("SPR")
    q = random_q(leg, rng)
    T, placed = poe(leg, q, T_of(*home_pose(leg)))
    pose = (T[:3, :3], T[:3, 3])
    w, act, C = leg_wrench(placed, rng, f_act=20.0)
    assert len(C) == 1
    f = C[0][:3]
    good = 20.0 * act + 3.0 * C[0]
    assert check_leg(leg, q, home_pose(leg), pose, placed, good, 20.0).passed
    # the constraint force moved 1 length unit (1/94 of the leg) off its line
    d = np.cross(f, [0.3, -0.2, 0.9])
    d /= np.linalg.norm(d)
    moved = good + 3.0 * np.r_[np.zeros(3), np.cross(d, f)]
    rep = check_leg(leg, q, home_pose(leg), pose, placed, moved, 20.0)
    assert rep.failed == ("statics.passive",)
    # the force kept through the S centre (reciprocal to S1a-c) but turned about the leg line:
    # only R3 (a non-S passive joint) sees it
    A_c = placed.A
    assert np.allclose(np.cross(A_c, f), C[0][3:], atol=1e-9 * placed.length * np.linalg.norm(f))
    u = (placed.a - placed.A) / placed.length
    th = 1e-3
    f2 = f * np.cos(th) + np.cross(u, f) * np.sin(th) + u * (u @ f) * (1 - np.cos(th))
    turned = 20.0 * act + 3.0 * np.r_[f2, np.cross(A_c, f2)]
    rep = check_leg(leg, q, home_pose(leg), pose, placed, turned, 20.0)
    assert rep.failed == ("statics.passive",)
    # a wrong actuator force
    rep = check_leg(leg, q, home_pose(leg), pose, placed, good, 20.0 * (1 + 1e-6))
    assert rep.failed == ("statics.actuator",)
    # a wrong joint value (the platform pose no longer matches)
    q_bad = q.copy()
    q_bad[-1] += 1e-6
    rep = check_leg(leg, q_bad, home_pose(leg), pose, placed)
    assert "closure.orientation" in rep.failed and "twists" not in rep.failed
    # a wrong twist (an axis turned slightly)
    j = placed.joints[-1]
    bent = Leg(placed.string, placed.joints[:-1] + (Joint(j.spec, j.direction + [0, 0, 1e-6], j.point),),
               placed.A, placed.a, placed.name)
    assert check_leg(leg, q, home_pose(leg), pose, bent).failed == ("twists",)


def test_check_is_scale_invariant():
    rng = np.random.default_rng(2)
    leg = screwkit.leg("RRPRR").moved(np.eye(3), [3.0, -2.0, 1.0], 1000.0)   # metres -> millimetres
    q = random_q(leg, rng)
    T, placed = poe(leg, q, T_of(*home_pose(leg)))
    w, _, _ = leg_wrench(placed, rng, f_act=-4.0)
    rep = check_leg(leg, q, home_pose(leg), (T[:3, :3], T[:3, 3]), placed, w, -4.0)
    assert rep.passed, str(rep)


def test_bad_input_raises():
    leg = screwkit.leg("SPR")
    with pytest.raises(InputError):
        check_leg(leg, np.zeros(4))
    with pytest.raises(InputError):
        build_leg_model(leg, (np.diag([1.0, 1.0, -1.0]), np.zeros(3)))
    with pytest.raises(InputError):
        check_leg(leg, np.zeros(5), wrench=np.zeros(5))


# ---------------------------------------------------------------- closed loops
def circle_legs(name, angles, R_base=100.0, r_plat=50.0, h=80.0):
    o = np.array([0.0, 0.0, h])
    out = []
    for t in angles:
        c, s = np.cos(t), np.sin(t)
        pl = Placement(A=[R_base * c, R_base * s, 0.0], a=[r_plat * c, r_plat * s, h], o=o)
        out.append(screwkit.leg(name, pl))
    return out, (np.eye(3), o)


def three_spr():
    return circle_legs("SPR", np.radians([90.0, 210.0, 330.0]))


def test_3spr_home_mobility():
    legs, home = three_spr()
    for lg in legs:   # R axes tangent to the platform circle
        assert abs(lg.joint("R3").direction @ (lg.a - home[1])) < 1e-12
    qs = [np.zeros(5)] * 3
    rep = check_closed_loop(legs, qs, home, home, legs, expected_dof=3)
    assert rep.passed, str(rep)
    assert rep.value("dof") == 3 and rep.value("locked_dof") == 0
    assert rep.value("constraint_rank") == 12 and rep.value("nv") == 15 and rep.value("idle") == 0
    assert check_closed_loop(legs, qs, home, home, legs, expected_dof=2).failed == ("mobility",)


def test_constraint_jacobian_matches_frame_jacobians():
    legs, home = three_spr()
    clm = build_closed_loop_model(legs, home)
    rng = np.random.default_rng(4)
    qs = [random_q(lg, rng) for lg in legs]          # need not be closed for this identity
    data = clm.model.createData()
    qp = clm.q(qs)
    Jc = constraint_jacobian(clm, data, qp)
    pin.framesForwardKinematics(clm.model, data, qp)
    f0 = clm.chains[0].frame_id
    J0 = pin.getFrameJacobian(clm.model, data, f0, pin.WORLD)
    for k, ch in enumerate(clm.chains[1:]):
        Ji = pin.getFrameJacobian(clm.model, data, ch.frame_id, pin.WORLD)
        Ad = data.oMf[ch.frame_id].inverse().action
        assert np.allclose(Jc[6 * k:6 * k + 6], Ad @ (Ji - J0), atol=1e-9)


def solve_closed(legs, home, q_act, rng):
    """Independent assembly: least squares on the POE loop closures with actuators fixed."""
    T_home = T_of(*home)
    ms = [len(lg.joints) for lg in legs]
    cut = np.cumsum([0] + ms)
    L = legs[0].length

    def ends(x):
        return [poe(lg, x[cut[k]:cut[k + 1]], T_home)[0] for k, lg in enumerate(legs)]

    def res(x):
        E = ends(x)
        r = [np.r_[(E[k][:3, 3] - E[0][:3, 3]) / L, (E[k][:3, :3] - E[0][:3, :3]).ravel()]
             for k in range(1, len(legs))]
        r.append([x[cut[k] + lg.actuated_index] - q_act[k] for k, lg in enumerate(legs)])
        return np.concatenate(r)

    sol = least_squares(res, rng.normal(scale=1e-3, size=cut[-1]), xtol=1e-15, ftol=1e-15, gtol=1e-15)
    assert np.abs(sol.fun).max() < 1e-12
    qs = [sol.x[cut[k]:cut[k + 1]] for k in range(len(legs))]
    placed = [poe(lg, q, T_home)[1] for lg, q in zip(legs, qs)]
    E = ends(sol.x)[0]
    return qs, placed, (E[:3, :3], E[:3, 3])


def test_3spr_moved_pose_mobility_and_statics():
    rng = np.random.default_rng(9)
    legs, home = three_spr()
    qs, placed, pose = solve_closed(legs, home, [6.0, -4.0, 9.0], rng)
    # statics: each leg carries f_a * actuation + c * constraint force; balance a load
    acts, cons = [], []
    for pl in placed:
        _, act, C = leg_wrench(pl, rng, 1.0)
        acts.append(act)
        cons.append(C[0])
    load = np.r_[10.0, -20.0, -300.0, np.cross(pose[1], [10.0, -20.0, -300.0]) + [500.0, 0.0, -200.0]]
    A = np.column_stack(acts + cons)
    x = np.linalg.solve(A, -load)
    wrenches = [x[k] * acts[k] + x[3 + k] * cons[k] for k in range(3)]
    assert np.allclose(sum(wrenches) + load, 0, atol=1e-8)
    rep = check_closed_loop(legs, qs, home, pose, placed, wrenches, x[:3], expected_dof=3)
    assert rep.passed, str(rep)
    assert rep.value("dof") == 3 and rep.value("locked_dof") == 0
    # swapped actuator forces are caught
    bad = check_closed_loop(legs, qs, home, pose, placed, wrenches, x[[1, 0, 2]])
    assert set(bad.failed) == {"leg1.statics.actuator", "leg2.statics.actuator"}


def test_idle_spin_of_an_sps_leg_is_counted():
    spr, home = three_spr()
    sps, _ = circle_legs("SPS", [np.radians(30.0)])
    legs = spr + sps
    clm = build_closed_loop_model(legs, home)
    mob = mobility(clm, [np.zeros(len(lg.joints)) for lg in legs], legs)
    assert (mob.nv, mob.rank, mob.idle, mob.dof) == (22, 18, 1, 3)
    assert (mob.locked_idle, mob.locked_dof) == (1, 0)


def test_unclosed_configuration_fails_loop_closure():
    legs, home = three_spr()
    qs = [np.zeros(5), np.r_[0, 0, 0, 1.0, 0], np.zeros(5)]     # leg 2 lengthened by 1
    rep = check_closed_loop(legs, qs, home, home)
    assert "loop.closure" in rep.failed and "leg2.closure.position" in rep.failed


def test_screwkit_statics_agrees_with_pinocchio_and_check_pm_adapter():
    statics_mod = pytest.importorskip("screwkit.engine")
    from types import SimpleNamespace
    from screwkit.interop import check_pm
    rng = np.random.default_rng(9)
    legs, home = three_spr()
    qs, placed, pose = solve_closed(legs, home, [6.0, -4.0, 9.0], rng)
    res = statics_mod.solve_statics(placed, pose[1], F=[10.0, -20.0, -300.0], T=[50.0, 0.0, -20.0])
    model = SimpleNamespace(home_legs=legs, platform_home=home, dof=3)
    sol = SimpleNamespace(model=model, joint_values=qs, legs=placed, rotation=pose[0], position=pose[1])
    rep = check_pm(sol, res)
    assert rep.passed, str(rep)
    assert sum(r.name.endswith("statics.actuator") for r in rep.rows) == 3
    assert "mobility" in {r.name for r in rep.rows}
