"""Finite motion of the parallelogram Pa in the engine: a Delta-type 3-RRPaR (issue 14, item 2).

The PM is the revolute-hinged form of Clavel's Delta (R. Clavel, US patent 4,976,582, 1990):
each leg an actuated arm hinge R1 about the tangent ``e_i`` at ``A_i``, an elbow R2 about
``e_i``, a parallelogram Pa of two bars and four hinges normal to the plane of ``e_i`` and
the bars, and R3 about ``e_i`` at the platform.  The model is the rule-language YAML of
``tests/test_parallelogram.py`` (arm half the home leg line, horizontal and radial at home;
Euler order ``xyz`` so that the solved angles are regular at the identity).

The engine's inverse displacement is checked against a solution by hand, independent of the
engine: the platform point ``C_i = o + r u_i`` is at the bar length ``LB`` from the elbow
``E_i = A_i + LA (cos t u_i - sin t z)``, which lies on the circle of the arm; ``t`` from the
sphere-circle intersection ``du cos t - dz sin t = K`` (``D = C - A``, ``K = (LA^2 + |D|^2 -
LB^2) / (2 LA)``).  A translational Delta's platform never rotates.  At the solved poses, the
leg's twists are written by hand too: three rotations about ``e_i`` through ``A``, ``E``,
``C`` and the Pa's translation, normal to the bar ``b = C - E`` and to the hinges (which stay
normal to ``e_i`` and ``b``); the statics' wrenches must be reciprocal to them.
"""

import numpy as np
import pytest

import screwkit
from screwkit.engine import analyze_pm
from test_parallelogram import DELTA_YAML

# the paper's workload, stated (only 3RRPRR and 2SPS+2SPR declare it as their default)
PAPER_LOAD = {"force": (-20.0, -30.0, -60.0), "torque": (-30.0, -30.0, 100.0)}
PAPER_ARGS = ["--force=-20,-30,-60", "--torque=-30,-30,100"]

RB, RP, Z0 = 100.0, 40.0, -150.0
LA = 0.5 * np.hypot(RB - RP, Z0)                          # arm: half the home leg line
LB = np.linalg.norm([RP - RB - LA, 0.0, Z0])               # bars: elbow at home to a
PHI = np.radians([0.0, 120.0, 240.0])
POSES = [(20.0, -10.0, -170.0), (-30.0, 25.0, -140.0), (10.0, 30.0, -190.0),
         (-15.0, -35.0, -160.0), (35.0, 5.0, -130.0)]
Z = np.array([0.0, 0.0, 1.0])


@pytest.fixture(scope="module")
def model(tmp_path_factory):
    path = tmp_path_factory.mktemp("delta") / "delta.yaml"
    path.write_text(DELTA_YAML.replace("    motion: 3T\n", "    motion: 3T\n    euler: xyz\n"))
    return screwkit.load_pm(path)


def hand_leg(i, o):
    """Arm angle ``t`` (elbow out: the root that is 0 at home), ``A, E, C`` and ``e``."""
    u = np.array([np.cos(PHI[i]), np.sin(PHI[i]), 0.0])
    e = np.cross(Z, u)
    A, C = RB * u, np.asarray(o, float) + RP * u
    D = C - A
    du, dz = D @ u, D @ Z
    K = (LA ** 2 + D @ D - LB ** 2) / (2 * LA)
    rho, psi = np.hypot(du, dz), np.arctan2(-dz, du)     # du cos t - dz sin t = rho cos(t - psi)
    t = psi - np.arccos(K / rho)
    E = A + LA * (np.cos(t) * u - np.sin(t) * Z)
    return t, A, E, C, e


def test_the_hand_solution_is_home_at_home():
    for i in range(3):
        t, A, E, C, e = hand_leg(i, (0.0, 0.0, Z0))
        assert abs(t) < 1e-12
        assert np.linalg.norm(C - E) == pytest.approx(LB, rel=1e-12)


def test_inverse_displacement_matches_the_hand_solution_and_never_rotates(model):
    X, Y, Zs = (np.array(c) for c in zip(*POSES))
    sol = screwkit.solve(model, {"Xo": X, "Yo": Y, "Zo": Zs})
    assert np.all(sol.residual < 1e-12)
    np.testing.assert_allclose(sol.rotation, np.broadcast_to(np.eye(3), (len(POSES), 3, 3)),
                               atol=1e-12)
    for k, o in enumerate(POSES):
        for i in range(3):
            t, A, E, C, e = hand_leg(i, o)
            q = np.asarray(sol.joint_values[i])[k]
            assert q[0] == pytest.approx(t, abs=1e-10), (k, i)
            assert q[0] + q[1] + q[3] == pytest.approx(0.0, abs=1e-10)   # the platform keeps e
            placed = sol[k].legs[i]
            np.testing.assert_allclose(placed.joints[1].point, E, atol=1e-9)
            np.testing.assert_allclose(placed.joints[2].bar, C - E, atol=1e-9)
            np.testing.assert_allclose(placed.joints[3].point, C, atol=1e-9)


def test_the_pa_value_is_the_arc_of_its_bars(model):
    """The Pa's value is the arc of the bars' ends: ``|s| = LB * angle(b_home, b)`` about the
    hinges, which the arm and elbow have turned about ``e``."""
    sol = screwkit.solve(model, {"Xo": 25.0, "Yo": -20.0, "Zo": -165.0})
    home = model.home_legs
    for i in range(3):
        t, A, E, C, e = hand_leg(i, (25.0, -20.0, -165.0))
        q = np.asarray(sol.joint_values[i]).reshape(-1)
        b0 = np.asarray(home[i].joints[2].bar)
        c, s = np.cos(q[0] + q[1]), np.sin(q[0] + q[1])
        b0r = b0 * c + np.cross(e, b0) * s + e * (e @ b0) * (1 - c)   # Rodrigues about e
        ang = np.arccos(np.clip(b0r @ (C - E) / LB ** 2, -1, 1))
        assert abs(q[2]) == pytest.approx(LB * ang, rel=1e-9, abs=1e-9)


def _hand_twists(i, o):
    t, A, E, C, e = hand_leg(i, o)
    b = C - E
    d = np.cross(np.cross(e, b), b)
    d /= np.linalg.norm(d)
    return np.array([np.r_[np.cross(p, e), e] for p in (A, E)] + [np.r_[d, 0, 0, 0]] +
                    [np.r_[np.cross(C, e), e]])


@pytest.mark.parametrize("o", POSES[:3])
def test_statics_reciprocity_virtual_work_and_leg_equilibrium(model, o):
    res = analyze_pm(model, dict(zip(("Xo", "Yo", "Zo"), o)), **PAPER_LOAD)
    assert (res.mobility.dof, res.mobility.motion_type) == (3, "3T")
    st = res.statics
    W = np.asarray(st.workload, float)
    scale = np.linalg.norm(W[:3]) + np.linalg.norm(W[3:]) / LB
    assert np.linalg.norm(np.sum(st.leg_wrenches, axis=0) + W) < 1e-9 * scale * LB
    tau = []
    for i in range(3):
        T = _hand_twists(i, o)
        w = np.asarray(st.leg_wrenches[i], float)
        work = T[:, :3] @ w[:3] + T[:, 3:] @ w[3:]                  # f . v + m . w
        assert np.all(np.abs(work[1:]) < 1e-9 * scale * LB), work    # passive joints: no work
        act = [k for k, r in enumerate(st.jacobian.rows) if r.leg == i and r.kind == "actuation"]
        assert work[0] == pytest.approx(st.values[act[0]], rel=1e-9, abs=1e-9 * scale * LB)
        for k, r in enumerate(st.jacobian.rows):                       # reciprocity
            if r.leg == i and r.kind != "actuation":
                c = np.asarray(st.row_wrenches[k], float)
                assert np.all(np.abs(T[:, :3] @ c[:3] + T[:, 3:] @ c[3:]) < 1e-9 * (
                    np.linalg.norm(c[:3]) * LB + np.linalg.norm(c[3:])))
        tau.append(work[0])
    # zero virtual work: a platform translation dv with the hand solution's arm rates
    h = 1e-5
    for dv in np.eye(3):
        rates = [(hand_leg(i, np.add(o, h * dv))[0] - hand_leg(i, np.subtract(o, h * dv))[0])
                 / (2 * h) for i in range(3)]
        assert np.dot(tau, rates) + W[:3] @ dv == pytest.approx(0.0, abs=1e-6 * scale)


def test_forward_kinematics_from_the_hand_arm_angles(model):
    """The engine's forward kinematics (actuated arms frozen, the platform and the passive
    joints, the Pa's arc among them, solved) lands on the poses the hand solution came from."""
    from screwkit.engine import forward_kinematics
    arms = np.array([[hand_leg(i, o)[0] for i in range(3)] for o in POSES])
    fk = forward_kinematics(model, arms)
    assert np.all(fk.success)
    np.testing.assert_allclose(fk.position, POSES, atol=1e-9)
    np.testing.assert_allclose(fk.rotation, np.broadcast_to(np.eye(3), (len(POSES), 3, 3)),
                               atol=1e-12)


def test_joint_values_do_not_change_with_the_base_frame_or_the_units(model, tmp_path):
    """The base frame moved (pose parameters stay relative to it): the same joint values and a
    platform rotated with the frame; every length times 10: the same angles, arcs times 10."""
    from scipy.spatial.transform import Rotation
    pose = {"Xo": 20.0, "Yo": -10.0, "Zo": -170.0}
    q = np.array([np.asarray(v).ravel() for v in screwkit.solve(model, pose).joint_values])
    R = Rotation.from_euler("zyx", [30, -20, 10], degrees=True).as_matrix()
    moved = screwkit.solve(model.moved(R, [5.0, -7.0, 300.0]), pose)
    np.testing.assert_allclose([np.asarray(v).ravel() for v in moved.joint_values], q,
                               atol=1e-9)
    np.testing.assert_allclose(moved.rotation, R, atol=1e-12)
    path = tmp_path / "delta10.yaml"
    path.write_text(DELTA_YAML.replace("    motion: 3T\n", "    motion: 3T\n    euler: xyz\n")
                    .replace("{R: 100, r: 40}", "{R: 1000, r: 400}").replace("Zo: -150", "Zo: -1500"))
    big = screwkit.solve(screwkit.load_pm(path), {k: 10 * v for k, v in pose.items()})
    qb = np.array([np.asarray(v).ravel() for v in big.joint_values])
    np.testing.assert_allclose(qb[:, [0, 1, 3]], q[:, [0, 1, 3]], atol=1e-10)
    np.testing.assert_allclose(qb[:, 2], 10 * q[:, 2], rtol=1e-10)


def test_pinocchio_leg_with_a_four_bar_side_reaches_the_solved_platform(model):
    """Pinocchio, independently of the engine's product of exponentials: each leg as R1, R2,
    one side of the four-bar (two hinges along the Pa's hinge, a bar apart, at ``theta`` and
    ``-theta`` with ``theta = s / |b|``) and R3; at the engine's joint values the platform
    frame lands on the solved pose, unrotated."""
    pin = pytest.importorskip("pinocchio")
    o = POSES[3]
    sol = screwkit.solve(model, dict(zip(("Xo", "Yo", "Zo"), o)))
    o_home = np.array([0.0, 0.0, Z0])
    for i, lg in enumerate(model.home_legs):
        R1, R2, pa, R3 = lg.joints
        b = np.asarray(pa.bar)
        pts = [R1.point, R2.point, pa.point, pa.point + b, R3.point]
        axes = [R1.direction, R2.direction, pa.hinge, pa.hinge, R3.direction]
        pm, parent, prev = pin.Model(), 0, np.zeros(3)
        for k, (p, a) in enumerate(zip(pts, axes)):
            parent = pm.addJoint(parent, pin.JointModelRevoluteUnaligned(np.asarray(a)),
                                 pin.SE3(np.eye(3), np.asarray(p) - prev), f"j{k}")
            prev = np.asarray(p)
        fid = pm.addFrame(pin.Frame("platform", parent, pin.SE3(np.eye(3), o_home - prev),
                                    pin.FrameType.OP_FRAME))
        data = pm.createData()
        q1, q2, s, q3 = np.asarray(sol.joint_values[i]).ravel()
        th = s / np.linalg.norm(b)
        pin.framesForwardKinematics(pm, data, np.array([q1, q2, th, -th, q3]))
        np.testing.assert_allclose(data.oMf[fid].translation, o, atol=1e-9)
        np.testing.assert_allclose(data.oMf[fid].rotation, np.eye(3), atol=1e-12)


def test_a_large_batch_of_poses_matches_the_hand_solution(model):
    """180 poses (3 x 180 legs x poses: the product of exponentials' slot-by-slot branch)."""
    rng = np.random.default_rng(7)
    o = np.column_stack([rng.uniform(-35, 35, 180), rng.uniform(-35, 35, 180),
                         rng.uniform(-190, -130, 180)])
    sol = screwkit.solve(model, {"Xo": o[:, 0], "Yo": o[:, 1], "Zo": o[:, 2]})
    assert np.all(sol.residual < 1e-12)
    hand = np.array([[hand_leg(i, p)[0] for i in range(3)] for p in o])
    got = np.column_stack([np.asarray(sol.joint_values[i])[:, 0] for i in range(3)])
    np.testing.assert_allclose(got, hand, atol=1e-10)
    np.testing.assert_allclose(sol.rotation, np.broadcast_to(np.eye(3), (180, 3, 3)), atol=1e-12)


def test_leg_forward_moves_a_pa_along_its_circle_and_the_link_frames_carry_it(model):
    """A lone Pa: the far link translates by Rot(h, s / |b|) b - b (Rodrigues by hand) and its
    twist is the translation normal to the turned bar; the link frames of the dynamics (which
    refused Pa legs before their dynamics was written) give the same: the Pa's twist the
    translation normal to the placed bar and to the hinges, its far link not turned."""
    from screwkit.engine import leg_forward, link_frames
    h, b = np.array([0.0, 0.0, 1.0]), np.array([3.0, 4.0, 0.0])
    leg = screwkit.leg_from_joints([("Pa", h, [1.0, 2.0, 3.0], b)])
    s = 2.0
    tw, (R, t) = leg_forward(leg, [s])
    th = s / 5.0
    bt = np.array([3 * np.cos(th) - 4 * np.sin(th), 3 * np.sin(th) + 4 * np.cos(th), 0.0])
    np.testing.assert_allclose(R, np.eye(3), atol=1e-15)
    np.testing.assert_allclose(t, bt - b, atol=1e-12)
    np.testing.assert_allclose(tw[0], np.r_[np.cross(h, bt) / 5.0, 0, 0, 0], atol=1e-12)
    sol = screwkit.solve(model, {"Xo": 5.0, "Yo": 0.0, "Zo": -150.0})
    lf = link_frames(sol)
    for i, placed in enumerate(sol.legs):
        pa = placed.joints[2]
        np.testing.assert_allclose(lf.twists[2, :, i, 0], np.r_[pa.direction, 0, 0, 0],
                                   atol=1e-12)
        assert abs(lf.twists[2, :3, i, 0] @ pa.bar) < 1e-9 * np.linalg.norm(pa.bar)
        np.testing.assert_allclose(lf.R[2, :, :, i, 0], lf.R[1, :, :, i, 0], atol=1e-15)
