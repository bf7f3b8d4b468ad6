"""Inverse dynamics of a Delta-type 3-RRPaR: legs with parallelograms, their bars' masses.

The model is ``tests/data/delta_3rrpar.yaml`` (the geometry of tests/test_parallelogram.py,
in mm and N, with arms, cross-pieces, the parallelograms' bars and friction).  What the
dynamics computes is checked against values obtained without it:

* **by hand** (a point-mass platform on massless legs): each leg then pushes the platform
  along its bars with a force ``t_i u_i`` (the two-force members of a parallelogram with
  massless bars; the couples of the legs take every moment), so ``sum t_i u_i = m (a - g) -
  F`` with the platform's acceleration ``a`` differentiated by hand from the path, and the
  arm's torque is the moment of the bar force about its hinge, ``t_i e_i . ((E_i - A_i) x
  u_i)``; the elbow ``E_i`` from the hand solution of tests/test_parallelogram_motion.py;
* **rigid-body equivalences**: a bar whose centre of mass is at its near hinge (com 0, no
  inertia) moves with that hinge point of the near link, so it is a point mass of the elbow's
  link there; at its far hinge (com 1) a point mass of the far link (which only translates)
  there.  The two models go through different code (the bars' own twists and the Pa's own
  twist rate against the links' chain), so they agree only if both are right;
* **energy balance**: the actuators' work minus what the viscous friction dissipates is the
  change of kinetic plus potential energy (the bars', the arms' and the platform's);
* **Pinocchio** (:func:`screwkit.dynamics.check_dynamics`): each parallelogram as its real
  four-bar (the bars at their offsets, closed on the far link by point contacts), the loops
  solved by Pinocchio from the path's own parameters.  The Delta's legs' couples are
  statically indeterminate (9 rows of rank 6): the legs' wrenches are compared up to the 3
  self-stresses, the actuator torques, twists, accelerations and energies exactly.
"""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest
from scipy.integrate import simpson

import screwkit
from screwkit.dynamics import check_dynamics, motion_from_expressions
from screwkit.errors import CatalogError

DELTA = Path(__file__).parent / "data" / "delta_3rrpar.yaml"
RB, RP, Z0 = 100.0, 40.0, -150.0
LA = 0.5 * np.hypot(RB - RP, Z0)                    # arm: half the home leg line
LB = np.linalg.norm([RP - RB - LA, 0.0, Z0])         # bars: elbow at home to a
PHI = np.radians([0.0, 120.0, 240.0])
Z = np.array([0.0, 0.0, 1.0])
G0 = 9806.65                                         # standard gravity, mm/s^2
# o(t) = (20 sin 2 pi t, 15 cos 2 pi t - 15, -160 + 10 sin 4 pi t) mm, t in s
PATH = ["Xo=20*sin(2*pi*t)", "Yo=15*cos(2*pi*t)-15", "Zo=-160+10*sin(4*pi*t)"]


def o_and_a(t):
    """The platform centre and its acceleration, differentiated by hand (mm, mm/s^2)."""
    w = 2 * np.pi
    o = np.array([20 * np.sin(w * t), 15 * np.cos(w * t) - 15, -160 + 10 * np.sin(2 * w * t)])
    a = np.array([-20 * w ** 2 * np.sin(w * t), -15 * w ** 2 * np.cos(w * t),
                  -10 * (2 * w) ** 2 * np.sin(2 * w * t)])
    return o, a


def hand_leg(i, o):
    """Arm angle (elbow out), ``A, E, C`` and the elbow axis ``e`` of leg ``i`` at ``o``."""
    u = np.array([np.cos(PHI[i]), np.sin(PHI[i]), 0.0])
    e = np.cross(Z, u)
    A, C = RB * u, np.asarray(o, float) + RP * u
    D = C - A
    du, dz = D @ u, D @ Z
    K = (LA ** 2 + D @ D - LB ** 2) / (2 * LA)
    t = np.arctan2(-dz, du) - np.arccos(K / np.hypot(du, dz))
    E = A + LA * (np.cos(t) * u - np.sin(t) * Z)
    return t, A, E, C, e


@pytest.fixture(scope="module")
def delta():
    return screwkit.load_pm(str(DELTA))


@pytest.fixture(scope="module")
def motion(delta):
    return motion_from_expressions(PATH, delta.independent, samples=201)


def _block(legs, platform=None):
    return {"units": {"mass": "kg", "length": "mm", "force": "N"},
            "platform": platform or {"mass": 0.3}, "legs": legs}


def test_massless_legs_reduce_to_a_point_mass_platform_by_hand(delta, motion):
    m, F = 0.3, np.array([2.0, -1.0, -5.0])            # kg, N (on the platform, at o)
    res = screwkit.dynamics(delta, motion, params=_block({}), force=F, torque=[0, 0, 0])
    assert res.ok.all()
    kg = 1e-3                                          # kg in N.s^2/mm
    g = np.array([0.0, 0.0, -G0])
    for k in range(0, len(res.t), 20):
        o, a = o_and_a(res.t[k])
        U, lever = [], []
        for i in range(3):
            _, A, E, C, e = hand_leg(i, o)
            u = (C - E) / LB
            U.append(u)
            lever.append(e @ np.cross(E - A, u))
        t = np.linalg.solve(np.array(U).T, m * kg * (a - g) - F)
        tau = t * np.array(lever)
        # (the engine's least-norm actuation rows of these legs are exact to about 1e-8: the
        # Gram solve that forms them has a shift of 1e-13 of its trace)
        np.testing.assert_allclose(res.dynamic_active[k], tau, rtol=1e-7)
        np.testing.assert_allclose(res.platform_wrench[k][:3], m * kg * (a - g), rtol=1e-10)


def _points(delta, slot_offset):
    """Per leg the home points ``p + o d`` (+ ``b``) of the Pa's bars (base = world here)."""
    out = []
    for lg in delta.home_legs:
        j = lg.joints[2]
        out.append([np.asarray(j.point) + o * np.asarray(j.direction) + slot_offset * j.bar
                    for o in (-12.0, 25.0)])
    return out


def _dumbbell(pts, m):
    """A link of two point masses ``m`` at ``pts``: its com and inertia about it."""
    c = np.mean(pts, axis=0)
    I = sum(m * ((p - c) @ (p - c) * np.eye(3) - np.outer(p - c, p - c)) for p in pts)
    return c, I


@pytest.mark.parametrize("end, link", [(0.0, "R2"), (1.0, "Pa3")])
def test_bars_with_their_mass_at_a_hinge_are_point_masses_of_that_link(delta, motion, end,
                                                                       link):
    m = 0.04
    arm = {"R1": {"mass": 0.2, "com": 0.2, "inertia": {"rod": 80}}}
    bars = _block({"links": arm, "bars": {"Pa3": {"mass": m, "offsets": [-12, 25],
                                                  "com": end}}})
    points = []
    for pts in _points(delta, end):
        c, I = _dumbbell(pts, m)
        points.append({"links": {**arm, link: {"mass": 2 * m, "com": c.tolist(),
                                               "inertia": I.tolist()}}})
    kw = dict(force=[1, 2, -3], torque=[0, 0, 0])
    r1 = screwkit.dynamics(delta, motion, params=bars, **kw)
    r2 = screwkit.dynamics(delta, motion, params=_block(points), **kw)
    scale = np.abs(r2.dynamic_active).max()
    assert np.abs(r1.dynamic_active - r2.dynamic_active).max() < 1e-10 * scale
    E1, E2 = r1.kinetic_energy, r2.kinetic_energy
    assert np.abs(E1 - E2).max() < 1e-10 * E2.max()
    assert np.abs(r1.potential_energy - r2.potential_energy).max() < \
        1e-10 * np.abs(r2.potential_energy).max()
    for q1, q2 in zip(r1.joint_efforts, r2.joint_efforts):
        assert np.abs(q1 - q2).max() < 1e-10 * np.abs(q2).max()
    # the bars are not for nothing: without them the torques differ
    r0 = screwkit.dynamics(delta, motion, params=_block({"links": arm}), **kw)
    assert np.abs(r0.dynamic_active - r2.dynamic_active).max() > 1e-3 * scale


def test_energy_balance_with_bars_and_friction(delta):
    motion = motion_from_expressions(PATH, delta.independent, samples=401)
    res = screwkit.dynamics(delta, motion, force=[0, 0, 0], torque=[0, 0, 0])
    assert res.ok.all() and max(res.residuals["balance"]) < 1e-10
    E = res.kinetic_energy + res.potential_energy
    loss = sum(np.sum(ld.viscous * q ** 2, axis=1)
               for ld, q in zip(res.params.legs, res.joint_rates))
    work = simpson(res.actuator_power - loss, x=res.t)
    assert abs(work - (E[-1] - E[0])) < 1e-8 * np.ptp(E)
    assert np.max(loss) > 1e-3 * np.max(np.abs(res.actuator_power))   # friction counts
    # the bars alone (massless platform and links) carry energy and need power
    bars = screwkit.dynamics(delta, motion, params=_block(
        {"bars": {"Pa3": {"mass": 0.04, "width": 40, "inertia": {"rod": 205.7}}}},
        {"mass": 0.0}), force=[0, 0, 0], torque=[0, 0, 0])
    Eb = bars.kinetic_energy + bars.potential_energy
    assert bars.kinetic_energy.max() > 0
    assert abs(simpson(bars.actuator_power, x=bars.t) - (Eb[-1] - Eb[0])) < 1e-8 * np.ptp(Eb)


def test_pinocchio_agrees_on_the_delta(delta):
    motion = motion_from_expressions(PATH, delta.independent, samples=100)
    chk = check_dynamics(delta, motion, force=[1, -2, 3], torque=[10, 20, -5])
    assert len(chk.samples) == 100 and chk.residual < 1e-10
    assert np.all(chk.self_stress == 3)           # the legs' couples: 9 rows of rank 6
    assert chk.errors["active"] < 1e-8, chk.errors
    assert chk.errors["leg_wrenches"] < 1e-8, chk.errors
    for key in ("twist", "acceleration", "actuator_rates", "energy"):
        assert chk.errors[key] < 1e-10, chk.errors


@pytest.mark.parametrize("bars, field", [
    ({"Pa3": {"mass": 1, "width": 10, "offsets": [0, 1]}}, "legs.bars.Pa3"),
    ({"Pa3": {"mass": 1}}, "legs.bars.Pa3"),
    ({"Pa3": {"mass": 1, "width": 0}}, "legs.bars.Pa3.width"),
    ({"Pa3": {"mass": 1, "width": 10, "com": 1.5}}, "legs.bars.Pa3.com"),
    ({"Pa3": {"mass": 1, "offsets": [3, 3]}}, "legs.bars.Pa3.offsets"),
    ({"Pa3": {"mass": -1, "width": 10}}, "legs.bars.Pa3.mass"),
    ({"R2": {"mass": 1, "width": 10}}, "legs.bars"),
    ({"Pa3": {"mass": 1, "width": 10, "length": 3}}, "legs.bars.Pa3"),
])
def test_bad_bars_are_refused_naming_the_field(delta, bars, field):
    with pytest.raises(CatalogError) as exc:
        screwkit.dynamics(delta, motion_from_expressions(PATH, delta.independent, samples=3),
                          params=_block({"bars": bars}))
    assert f"dynamics.{field}" in str(exc.value) and "\n" not in str(exc.value)


def test_bars_on_a_leg_without_a_parallelogram_are_refused():
    from screwkit.pm import dynamics_for
    with pytest.raises(CatalogError, match="no parallelogram") as exc:
        dynamics_for(screwkit.load_pm("3RPS"), {"legs": {"bars": {"P2": {"mass": 1,
                                                                         "width": 2}}}})
    assert "dynamics.legs.bars" in str(exc.value)


def test_mjcf_writes_the_bars_where_they_are(delta, tmp_path):
    """The MJCF export (SI) gives each bar a body on the near link, tied to turn with the
    Pa: at the exported pose MuJoCo puts the bars' centres where the hand solution has them
    (``E_i -+ 20 e_i + (C_i - E_i) / 2``, the Pa's translation direction being ``-e_i``) and
    closes every loop."""
    mujoco = pytest.importorskip("mujoco", reason="MJCF checks need mujoco")
    from screwkit.interop import write_mjcf
    o = (20.0, -10.0, -170.0)
    out = tmp_path / "delta.xml"
    write_mjcf(delta, out, pose=dict(zip(("Xo", "Yo", "Zo"), o)))
    m = mujoco.MjModel.from_xml_path(str(out))
    d = mujoco.MjData(m)
    mujoco.mj_resetDataKeyframe(m, d, 0)
    mujoco.mj_forward(m, d)
    assert np.abs(d.efc_pos).max() < 1e-12          # welds and ties hold at the keyframe
    for i in range(3):
        _, A, E, C, e = hand_leg(i, o)
        for n, off in enumerate((-20.0, 20.0)):
            body = m.body(f"leg{i + 1}_Pa3_bar{n + 1}")
            assert body.mass[0] == pytest.approx(0.04, rel=1e-12)          # kg
            centre = (E - off * e + 0.5 * (C - E)) * 1e-3                  # m
            np.testing.assert_allclose(d.body(body.id).xipos, centre, atol=1e-12)


def test_a_rotary_actuators_columns_are_its_angle_and_the_angles_rates():
    """The Delta's CSV had ``r1 [mm]`` (the leg's extension |a - A|) beside ``rdot1
    [rad/s]`` (the arm joint's rate): not one quantity's value and rate. A rotary actuator
    has its angle ``q1 [deg]`` and its rates ``qdot1``, ``qddot1`` now; ``qdot1`` is the
    time derivative of ``q1`` (checked here by central differences of the column)."""
    import screwkit
    from screwkit.dynamics import motion_from_expressions
    pm = screwkit.load_pm("tests/data/delta_3rrpar.yaml")
    m = motion_from_expressions(["Xo=10*t", "Yo=-5*t", "Zo=-150+20*t"], pm.independent,
                                samples=401)
    cols = {c: (v, u) for c, v, u in screwkit.dynamics(pm, m, force=[0, 0, 0]).columns()}
    assert "rdot1" not in cols and cols["q1"][1] == "deg" and cols["qdot1"][1] == "rad/s"
    t, q = cols["t"][0], np.radians(cols["q1"][0])
    fd = (q[2:] - q[:-2]) / (t[2:] - t[:-2])
    np.testing.assert_allclose(cols["qdot1"][0][1:-1], fd, rtol=1e-4,
                               atol=1e-6 * np.abs(fd).max())


def _delta(scale=1.0, units="mm"):
    """A Delta of R-R-Pa-R legs (base radius 120, platform 30, arm 90, forearm 220 mm, axes
    along the base tangent), built from literal joints, and its arm angle in closed form:
    the elbow E on the circle of radius ``LA`` about A in the leg's vertical plane, at ``LB``
    from the platform point C."""
    RB, RP, LA, LB = 120.0, 30.0, 90.0, 220.0
    z = np.array([0.0, 0.0, 1.0])

    def arm(phi, o):
        u = np.array([np.cos(phi), np.sin(phi), 0.0])
        A, C = RB * u, o + RP * u
        D = C - A
        K = (LA ** 2 + D @ D - LB ** 2) / (2 * LA)
        return np.arccos(K / np.hypot(D @ u, D @ z)) - np.arctan2(D @ z, D @ u), u, A, C

    o0 = np.array([0.0, 0.0, -180.0])
    b = screwkit.PMBuilder("delta", units={"length": units, "force": "N"})
    for phi in np.radians([0, 120, 240]):
        t, u, A, C = arm(phi, o0)
        e = np.array([-np.sin(phi), np.cos(phi), 0.0])
        E = A + LA * (np.cos(t) * u - np.sin(t) * z)
        b.add_leg(screwkit.leg_from_joints(
            [("R", e, A * scale), ("R", e, E * scale), ("Pa", np.cross(e, C - E), E * scale,
                                                         (C - E) * scale), ("R", e, C * scale)],
            A * scale, C * scale))
    b.set_pose(["Xo", "Yo", "Zo"], home={"Xo": 0, "Yo": 0, "Zo": o0[2] * scale}, order="xyz")
    return b.build(), (lambda o: np.array([arm(phi, o)[0] for phi in np.radians([0, 120, 240])]))


def test_a_delta_gives_the_same_torques_in_mm_and_in_m():
    """The least-norm actuation row of a leg with a Pa (a translation among its passive
    joints) depended on the length unit through its Gram matrix (the Pa's twist 1/L^2 below
    the rotations): a Delta's torques in mm and in m differed by 2.7e-6 at a condition number
    of 2265. Now they agree to 1e-11; and at a pose of condition 25 they are the closed form's
    (virtual work: tau = -(dq/dx)^-T F, dq/dx by central differences of the arm angles)."""
    mm, q_of = _delta()
    m, _ = _delta(1e-3, "m")
    F = np.array([5.0, -3.0, -20.0])
    for p in ({"Xo": -40.0, "Yo": 25.0, "Zo": -220.0}, {"Xo": 20.0, "Yo": -10.0, "Zo": -170.0}):
        a = screwkit.analyze(mm, p, force=F)
        b = screwkit.analyze(m, {k: v * 1e-3 for k, v in p.items()}, force=F)
        ta = np.asarray(a.statics.F_r).ravel()[:3]                       # N.mm
        tb = np.asarray(b.statics.F_r).ravel()[:3] * 1e3                 # N.m -> N.mm
        np.testing.assert_allclose(ta, tb, rtol=1e-11, atol=1e-11 * np.abs(ta).max())
    o, h = np.array([20.0, -10.0, -170.0]), 1e-4
    Jq = np.array([(q_of(o + h * e) - q_of(o - h * e)) / (2 * h) for e in np.eye(3)]).T
    tau = -np.linalg.solve(Jq.T, F)
    np.testing.assert_allclose(ta, tau, rtol=1e-8, atol=1e-8 * np.abs(tau).max())
