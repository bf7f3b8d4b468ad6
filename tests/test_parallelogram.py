"""The parallelogram joint Pa and a Delta-type translational PM (issue 14, item 2).

The Delta-type PM here is 3-RRPaR: each leg an actuated R at the base (the arm hinge), an R
along the arm hinge at the elbow, a parallelogram Pa of two bars and four R hinges, and an R
along the arm hinge at the platform (the revolute-hinged formulation of Clavel's Delta,
R. Clavel, US patent 4,976,582, 1990, whose original parallelograms carry four ball joints,
3-R(SS)2; that one is checked too, with the freedoms of its bars' constraint forces).

Counts by hand (not by the code under test):

3-RRPaR with revolute hinges: links base, platform and per leg arm, upper link, two bars and
lower link: 2 + 3 * 5 = 17; joints per leg R1, R2, four hinges, R3: 3 * 7 = 21, all f = 1.
Grübler-Kutzbach M = 6 (17 - 21 - 1) + 21 = -9.  Loops 21 - 17 + 1 = 5.  Each Pa is a planar
4R loop (6 closure equations of rank 3): 3 redundant each, 9; each leg's twists (three
rotations about parallel axes e_i and a translation) leave two couples normal to e_i, six
couples of rank 3: 3 more redundant.  Idle motions 0.  DOF = M + redundant - idle =
-9 + 12 - 0 = 3, pure translations.

3-R(SS)2 (ball-joint parallelograms): links base, platform, per leg arm and two bars:
2 + 3 * 3 = 11; joints 3 R (f = 1) and 12 S (f = 3): M = 6 (11 - 15 - 1) + 3 + 36 = 9; each
bar spins idly about its own line: 6 idle motions; DOF = 9 - 6 = 3.
"""

import numpy as np
import pytest
from scipy.spatial.transform import Rotation

import screwkit
from screwkit.errors import InputError
from screwkit.pm import linkage_graph, mobility_of_legs
from screwkit.screws import force_wrench, freedoms

# the paper's workload, stated (only 3RRPRR and 2SPS+2SPR declare it as their default)
PAPER_LOAD = {"force": (-20.0, -30.0, -60.0), "torque": (-30.0, -30.0, 100.0)}
PAPER_ARGS = ["--force=-20,-30,-60", "--torque=-30,-30,100"]

RB, RP, LA, LB = 100.0, 40.0, 80.0, 180.0        # base and platform radii, arm, bars
PHI = np.radians([0.0, 120.0, 240.0])
POSES = [(0.0, 0.0, -150.0), (20.0, -10.0, -170.0), (-30.0, 25.0, -140.0), (10.0, 30.0, -190.0)]


def _leg_frames(i):
    u = np.array([np.cos(PHI[i]), np.sin(PHI[i]), 0.0])
    e = np.array([-np.sin(PHI[i]), np.cos(PHI[i]), 0.0])
    return u, e


def _elbow(i, o):
    """Inverse kinematics by hand: the arm angle with |E - C| = LB (elbow out)."""
    u, e = _leg_frames(i)
    A, C = RB * u, np.asarray(o) + RP * u
    D = C - A
    du, dz = D @ u, D[2]
    K = (LA ** 2 + D @ D - LB ** 2) / (2 * LA)    # du cos t - dz sin t = K
    rho, psi = np.hypot(du, dz), np.arctan2(dz, du)
    t = np.arccos(K / rho) - psi
    E = A + LA * (np.cos(t) * u - np.sin(t) * np.array([0, 0, 1.0]))
    assert np.linalg.norm(C - E) == pytest.approx(LB, rel=1e-12)
    return A, E, C, e


def delta_legs(o):
    legs = []
    for i in range(3):
        A, E, C, e = _elbow(i, o)
        b = C - E
        hinge = np.cross(e, b)                      # normal to the parallelogram's plane
        legs.append(screwkit.leg_from_joints(
            [("R", e, A), ("R", e, E), ("Pa", hinge, E, b), ("R", e, C)], A, C, actuated=0))
    return legs


@pytest.mark.parametrize("o", POSES)
def test_delta_3rrpar_is_3t_with_the_hand_counts(o):
    legs = delta_legs(o)
    assert [lg.string.marked for lg in legs] == ["_RRPaR"] * 3
    m = mobility_of_legs(legs)
    assert (m.dof, m.motion_type) == (3, "3T")
    assert (m.gruebler, m.n_links, m.n_joints, m.loops) == (-9, 17, 21, 5)
    assert (m.redundant, m.idle) == (12, 0)
    assert m.dof == m.gruebler + m.redundant - m.idle
    g = linkage_graph(legs)
    assert (g.number_of_nodes(), g.number_of_edges()) == (17, 21)


def test_the_pa_twist_is_the_far_link_velocity_of_the_four_bar():
    """Turning the bars by t about the hinge moves the far link by R(t) b - b, a circular
    translation: its derivative at t = 0 (finite difference) is the Pa's twist [d; 0]."""
    leg = delta_legs(POSES[1])[0]
    pa = leg.joints[2]
    h, b, t = np.array(pa.hinge), np.array(pa.bar), 1e-6
    move = (Rotation.from_rotvec(t * h).apply(b) - Rotation.from_rotvec(-t * h).apply(b)) / (2 * t)
    np.testing.assert_allclose(leg.twists[2], np.r_[move / np.linalg.norm(move), 0, 0, 0],
                               atol=1e-8)
    assert abs(h @ b) < 1e-9 * np.linalg.norm(b)


def test_clavel_ball_joint_parallelograms_give_3t_too():
    """3-R(SS)2: each bar (S-S) exerts a force along itself; the arm's R leaves the wrenches
    of span{F1, F2} reciprocal to its twist.  Freedoms of the union: 3T."""
    o = POSES[2]
    rows, width = [], 25.0                           # half the spacing of the balls along e
    for i in range(3):
        A, E, C, e = _elbow(i, o)
        b = C - E
        F = np.array([force_wrench(b, E + s * width * e).vector for s in (-1, 1)])
        arm = screwkit.leg_from_joints([("R", e, A)]).twists[0]
        c = F @ arm                                     # W = x1 F1 + x2 F2 with W . arm = 0
        rows.append(c[1] * F[0] - c[0] * F[1])
    res = freedoms(np.array(rows))
    assert (res.dof, res.label) == (3, "3T")
    # hand counts of the real mechanism (module docstring)
    links, joints_f = 2 + 3 * 3, [1] * 3 + [3] * 12
    M = 6 * (links - len(joints_f) - 1) + sum(joints_f)
    idle = 6
    assert (M, M - idle) == (9, res.dof)


def test_pa_in_strings_and_bad_pa():
    ls = screwkit.parse_leg("RRPaR")
    assert ls.letters == ("R", "R", "Pa", "R") and ls.equivalent[2].name == "Pa3"
    assert ls.equivalent[2].kind == "P" and ls.equivalent[2].parallelogram
    assert [t.leg.letters for t in screwkit.parse_pm("3-RRPaR").terms] == [("R", "R", "Pa", "R")]
    for bad, hint in (("rpar", "did you mean 'RPaR'"), ("RPAR", "did you mean 'RPaR'")):
        with pytest.raises(screwkit.ParseError, match=hint):
            screwkit.parse_leg(bad)
    generic = screwkit.leg("RPaR")                   # a bare string: a generic geometry
    assert generic.joints[1].bar is not None and abs(generic.joints[1].bar @
                                                     generic.joints[1].direction) < 1e-9
    with pytest.raises(InputError, match="normal to its hinges"):
        screwkit.leg_from_joints([("Pa", [0, 0, 1], [0, 0, 0], [0, 1, 1])])
    with pytest.raises(InputError, match="bar vector"):
        screwkit.leg_from_joints([("Pa", [0, 0, 1], [0, 0, 0])])
    with pytest.raises(screwkit.CatalogError, match="a Pa takes 'axis'"):
        screwkit.define_leg("RPaR/mine", "RPaR", [{"axis": "base.Z", "at": "A"}, {},
                                                  {"axis": "base.Z", "at": "a"}])
    with pytest.raises(screwkit.CatalogError, match="only a parallelogram"):
        screwkit.define_leg("R/to", "R", [{"axis": "base.Z", "at": "A", "to": "a"}])
    bent = screwkit.define_leg("RPaR/bent", "RPaR", [{"axis": "base.Z", "at": "A"},
                                                     {"axis": "base.Z", "at": "A", "to": "a"},
                                                     {"axis": "base.Z", "at": "a"}])
    with pytest.raises(screwkit.GeometryError, match="normal to its hinges"):
        bent.build()            # the default leg line A -> a is not normal to base.Z


DELTA_YAML = """
legs:
  - name: RRPaR/delta
    string: _RRPaR
    joints:
      - {axis: base.tangent, at: A}
      - {axis: base.tangent, at: {offset: A, along: base.OA, fraction: 0.5}}
      - {axis: {perpendicular: [R1, {toward: [R2, a]}]}, at: R2, to: a}
      - {axis: R1, at: a}
pms:
  3RRPaR:
    string: 3RRPaR
    dimensions: {R: 100, r: 40}
    base: {shape: circle, radius: R, count: 3}
    platform: {shape: circle, radius: r, count: 3}
    legs: [RRPaR/delta, RRPaR/delta, RRPaR/delta]
    independent: [Xo, Yo, Zo]
    pose: {Xo: 0, Yo: 0, Zo: -150}
    dof: 3
    motion: 3T
"""


def test_a_pa_leg_type_in_yaml_and_a_pm_of_them_in_the_engine(tmp_path, capsys):
    """The rule language places a Pa (hinges along 'axis', bar from 'at' to 'to'); the leg
    equals the one built from explicit joints by hand.  A PM model with Pa legs is analysed
    by the engine (its finite motion: tests/test_parallelogram_motion.py)."""
    from screwkit.cli import main
    from screwkit.legs import default_placement

    path = tmp_path / "delta.yaml"
    path.write_text(DELTA_YAML)
    spec, = screwkit.load_legs(path)
    pl = default_placement()
    lg = spec.build(pl)
    e = np.cross([0, 0, 1.0], pl.A - pl.O)
    e /= np.linalg.norm(e)
    E = pl.A + 0.5 * np.linalg.norm(pl.a - pl.A) * (pl.A - pl.O) / np.linalg.norm(pl.A - pl.O)  # base.OA: O -> A
    b = pl.a - E
    ex = screwkit.leg_from_joints([("R", e, pl.A), ("R", e, E), ("Pa", np.cross(e, b), E, b),
                                   ("R", e, pl.a)], pl.A, pl.a)
    np.testing.assert_allclose(lg.twists, ex.twists, atol=1e-9)
    np.testing.assert_allclose(lg.joints[2].bar, b, atol=1e-9)
    assert lg.analyze().summary() == "2 couples"
    assert main(["analyze", str(path), *PAPER_ARGS]) == 0
    assert "mobility: 3 DOF (3T)" in capsys.readouterr().out


def test_pa_legs_move_with_the_frame_and_units():
    legs = delta_legs(POSES[3])
    R = Rotation.from_euler("zyx", [30, -20, 10], degrees=True).as_matrix()
    moved = [lg.moved(R, [5.0, -7.0, 300.0], 10.0) for lg in legs]
    m = mobility_of_legs(moved)
    assert (m.dof, m.motion_type, m.gruebler, m.redundant) == (3, "3T", -9, 12)
    np.testing.assert_allclose(moved[0].joints[2].bar, 10.0 * R @ legs[0].joints[2].bar)


def test_pinocchio_four_bar_side_moves_as_the_pa():
    """Pinocchio, independently: one side of the four-bar as two hinges about the hinge
    direction (first hinge at the Pa's point, second a bar further), driven with opposite
    joint values (the parallelogram's closure).  The far link's spatial velocity (world
    frame, [v; w] as screwkit's) is the Pa's twist times |bar|, and a finite turn moves it
    by R(t) b - b without rotating it."""
    pin = pytest.importorskip("pinocchio")
    leg = delta_legs(POSES[2])[1]
    pa = leg.joints[2]
    h, b, p0 = np.array(pa.hinge), np.array(pa.bar), np.array(pa.point)
    model = pin.Model()
    j1 = model.addJoint(0, pin.JointModelRevoluteUnaligned(h), pin.SE3(np.eye(3), p0), "h1")
    j2 = model.addJoint(j1, pin.JointModelRevoluteUnaligned(h), pin.SE3(np.eye(3), b), "h2")
    data = model.createData()
    q = np.zeros(2)
    pin.computeJointJacobians(model, data, q)
    J = pin.getJointJacobian(model, data, j2, pin.ReferenceFrame.WORLD)
    np.testing.assert_allclose(J @ [1.0, -1.0] / np.linalg.norm(b), leg.twists[2], atol=1e-9)
    t = 0.4
    pin.forwardKinematics(model, data, np.array([t, -t]))
    M = data.oMi[j2]
    np.testing.assert_allclose(M.rotation, np.eye(3), atol=1e-12)
    np.testing.assert_allclose(M.translation, p0 + Rotation.from_rotvec(t * h).apply(b), atol=1e-9)


def test_a_pa_is_drawn_as_its_four_bar(tmp_path, capsys):
    import matplotlib
    matplotlib.use("Agg")
    from screwkit.cli import main
    from screwkit.viz import draw_leg

    leg = delta_legs(POSES[0])[0]
    fig = draw_leg(leg, leg.analyze(), out=tmp_path / "pa.png")
    ax = fig.axes[0] if hasattr(fig, "axes") else fig
    loops = [ln for ln in ax.get_lines() if ln.get_gid() == "joint:Pa3"]
    assert len(loops) == 1 and len(loops[0].get_data_3d()[0]) == 5     # a closed 4-gon
    assert (tmp_path / "pa.png").stat().st_size > 0
    assert main(["leg", "RPaR"]) == 0
    assert "parallelogram: translation normal to its bar" in capsys.readouterr().out
