"""PM definitions and the unified inverse displacement (screwkit.pm, screwkit.engine).

Expected values come from the paper's closed forms (typed here, with the errata of
docs NOTES.md), from hand derivations, from the leg rules rebuilt independently of
the product of exponentials, and from invariances (frame, units).
"""

import numpy as np
import pytest

import screwkit
from screwkit.engine import leg_forward
from screwkit.errors import CatalogError, InputError, UnreachablePoseError
from screwkit.legs import structure_residuals
from screwkit.pm import load_pm
from screwkit.screws import reciprocal_system, same_span, transform_twists

b3 = np.sqrt(3.0)


@pytest.fixture(scope="module")
def rrprr():
    return load_pm("3RRPRR")


@pytest.fixture(scope="module")
def sps_spr():
    return load_pm("2SPS+2SPR")


def _dc(a, b, g):
    """Direction cosines of eq. (10c) (lambda = gamma)."""
    ca, sa, cb, sb, cg, sg = np.cos(a), np.sin(a), np.cos(b), np.sin(b), np.cos(g), np.sin(g)
    return dict(xl=cb, xm=sa * sb, xn=-ca * sb, yl=sg * sb, ym=ca * cg - sa * cb * sg,
                yn=sa * cg + ca * cb * sg, zl=cg * sb, zm=-ca * sg - sa * cb * cg,
                zn=-sa * sg + ca * cb * cg)


# --------------------------------------------------------------------------- 3RRPRR

@pytest.mark.parametrize("a,b,Zo", [(5, -3, 80), (-8, 6, 70), (12, 10, 95), (0.5, -15, 85)])
def test_3rrprr_closed_forms(rrprr, a, b, Zo):
    E, e = 120 / b3, 60 / b3                       # sides 120 and 60: E = 2e
    sol = screwkit.solve(rrprr, {"alpha": a, "beta": b, "Zo": Zo}, degrees=True)
    assert sol.success and sol.residual < 1e-10
    a, b = np.radians(a), np.radians(b)
    ca, sa, cb, sb = np.cos(a), np.sin(a), np.cos(b), np.sin(b)
    den = -sa ** 2 + ca ** 2 * cb
    Xo = (Zo * ca + e * sa) * sb / den                                    # eq. 11e (correct)
    Yo = (-Zo * sa * ca * (1 + cb) + e * (cb - ca ** 2 + sa ** 2 * cb) / 2) / den  # 11e, Zo sign fixed
    Yo_printed = (Zo * sa * ca * (1 + cb) + e * (cb - ca ** 2 + sa ** 2 * cb) / 2) / den
    assert sol.params["gamma"] == pytest.approx(a, abs=1e-9)              # gamma = alpha (11c)
    assert sol.params["Xo"] == pytest.approx(Xo, abs=1e-8)
    assert sol.params["Yo"] == pytest.approx(Yo, abs=1e-8)
    assert abs(sol.params["Yo"] - Yo_printed) > 1.0                       # the printed sign is wrong
    c = _dc(a, b, a)
    xl, xm, xn, yl, ym, yn = (c[k] for k in ("xl", "xm", "xn", "yl", "ym", "yn"))
    D = Xo ** 2 + Yo ** 2 + Zo ** 2 + E ** 2 + e ** 2
    px, py = xl * Xo + xm * Yo + xn * Zo, yl * Xo + ym * Yo + yn * Zo
    r2 = D + 2 * e * py - 2 * E * (e * ym + Yo)                           # eq. 12
    r1 = D + E * Yo - b3 * E * Xo + b3 * e * px - e * py + e * E * (b3 * yl + b3 * xm - 3 * xl - ym) / 2
    r3 = D + E * Yo + b3 * E * Xo - b3 * e * px - e * py - e * E * (b3 * yl + b3 * xm + 3 * xl + ym) / 2
    assert np.allclose(sol.extensions, np.sqrt([r1, r2, r3]), rtol=1e-10)
    # the actuated P joint moves by the change of leg length from home
    home_r = np.array([lg.length for lg in rrprr.home_legs])
    assert np.allclose(sol.actuator_values, sol.extensions - home_r, atol=1e-9)


def test_3rrprr_vertices_are_eq_10a(rrprr):
    E, e = 120 / b3, 60 / b3
    assert np.allclose(rrprr.base_points, [[E * b3 / 2, -E / 2, 0], [0, E, 0], [-E * b3 / 2, -E / 2, 0]])
    assert np.allclose(rrprr.platform_points, [[e * b3 / 2, -e / 2, 0], [0, e, 0], [-e * b3 / 2, -e / 2, 0]])
    assert rrprr.independent == ("alpha", "beta", "Zo") and rrprr.order == "XYX"


def test_beta_zero_is_resolved_by_continuity(rrprr):
    sol = screwkit.solve(rrprr, {"alpha": 0.1, "beta": 0.0, "Zo": 80})
    assert sol.success
    assert sol.params["gamma"] == pytest.approx(0.1, abs=1e-7)           # the limit gamma = alpha
    assert any("representation singularity" in n for n in sol.notes)
    near = screwkit.solve(rrprr, {"alpha": 0.1, "beta": 1e-6, "Zo": 80})
    assert not any("representation" in n for n in near.notes)
    for k in ("Xo", "Yo", "gamma"):
        assert sol.params[k] == pytest.approx(near.params[k], abs=1e-4)
    # warm start from one side: same limit
    side = screwkit.solve(rrprr, {"alpha": 0.1, "beta": 0.0, "Zo": 80},
                          guess=screwkit.solve(rrprr, {"alpha": 0.1, "beta": -0.05, "Zo": 80}))
    assert side.params["gamma"] == pytest.approx(0.1, abs=1e-7)
    assert any("one-sided" in n for n in side.notes)


def test_path_continuity_and_warm_start(rrprr):
    t = np.linspace(0, 1, 41)
    path = [{"alpha": 0.15 * np.sin(3 * s), "beta": 0.1 * np.cos(2 * s) - 0.05, "Zo": 75 + 10 * s}
            for s in t]   # crosses beta = 0 (not exactly)
    sols = screwkit.solve_path(rrprr, path)
    assert all(s.success for s in sols)
    q = np.array([np.concatenate(s.joint_values) for s in sols])
    prismatic = np.array([j.kind == "P" for h in rrprr.home_legs for j in h.joints])
    step = np.max(np.abs(np.diff(q, axis=0)), axis=0)
    assert np.all(step[~prismatic] < 0.05) and np.all(step[prismatic] < 2.0)  # no jump (cm, rad)
    g = np.array([s.params["gamma"] - s.params["alpha"] for s in sols])
    assert np.max(np.abs(g)) < 1e-8
    cold = screwkit.solve(rrprr, path[-1])
    assert np.allclose(np.concatenate(cold.joint_values), q[-1], atol=1e-7)
    assert sols[-1].iterations <= cold.iterations


# --------------------------------------------------------------------------- 2SPS+2SPR

def test_2sps2spr_home_is_not_centred(sps_spr):
    L, l1, l2 = 100, 60, 50
    assert sps_spr.home_pose["Xo"] == pytest.approx(0, abs=1e-9)
    # from eq. 16a at alpha = beta = gamma = 0 (hand): Yo = (l1^2 - l2^2 - L (l1 - l2)) / (2 l2) = 1
    assert sps_spr.home_pose["Yo"] == pytest.approx((l1 ** 2 - l2 ** 2 - L * (l1 - l2)) / (2 * l2), abs=1e-9)
    assert np.allclose(sps_spr.base_points, 50 * np.array([[1, -1, 0], [1, 1, 0], [-1, 1, 0], [-1, -1, 0]]))
    assert np.allclose(sps_spr.platform_points, 0.5 * np.array([[60, -50, 0], [60, 50, 0], [-60, 50, 0], [-60, -50, 0]]))


@pytest.mark.parametrize("a,b,g,Zo", [(4, 3, 2, 80), (-6, 10, 8, 90), (15, -12, -14, 70)])
def test_2sps2spr_eq16_and_eq17(sps_spr, a, b, g, Zo):
    L, l1, l2 = 100.0, 60.0, 50.0
    sol = screwkit.solve(sps_spr, {"alpha": a, "beta": b, "gamma": g, "Zo": Zo}, degrees=True)
    assert sol.success
    a, b, g = np.radians([a, b, g])
    c = _dc(a, b, g)
    R = np.array([[c["xl"], c["yl"], c["zl"]], [c["xm"], c["ym"], c["zm"]], [c["xn"], c["yn"], c["zn"]]])
    m = 0.5 * np.array([[l1, -l2, 0], [l1, l2, 0], [-l1, l2, 0], [-l1, -l2, 0]])
    A = L / 2 * np.array([[1, -1, 0], [1, 1, 0], [-1, 1, 0], [-1, -1, 0]])
    # eq. 16a, (a2 - A2).(a1 - a3) = 0 and (a3 - A3).(a2 - a4) = 0, are linear in (Xo, Yo)
    d13, d24 = R @ (m[0] - m[2]), R @ (m[1] - m[3])
    M = np.array([d13[:2], d24[:2]])
    rhs = [(A[1] - R @ m[1] - [0, 0, Zo]) @ d13, (A[2] - R @ m[2] - [0, 0, Zo]) @ d24]
    Xo, Yo = np.linalg.solve(M, rhs)
    assert sol.params["Xo"] == pytest.approx(Xo, abs=1e-9)
    assert sol.params["Yo"] == pytest.approx(Yo, abs=1e-9)
    # eq. 16d with E -> L/2 and s_gamma^2 in the last Yo term
    ca, sa, cb, sb, cg, sg = np.cos(a), np.sin(a), np.cos(b), np.sin(b), np.cos(g), np.sin(g)
    den = 2 * (ca * cb * cg - sa * sg)
    X16 = sb * (l2 * sa + 2 * Zo * cg - L * sg * (ca * cg - sa * cb * sg) * l2 / l1
                - sa * (l1 - L * cb) * l1 / l2) / den
    Y16 = (-2 * Zo * (ca * sg + sa * cb * cg) - l2 * cb + cb * (l1 - L * cb) * l1 / l2
           + L * sb ** 2 * sg ** 2 * l2 / l1) / den + L / 2
    assert (X16, Y16) == pytest.approx((Xo, Yo), abs=1e-9)
    # eq. 17
    xl, xm, yl, ym = c["xl"], c["xm"], c["yl"], c["ym"]
    K = L ** 2 / 2 + Xo ** 2 + Yo ** 2 + Zo ** 2
    r2 = [K + L * (l1 * xm - l2 * ym - Xo + Yo) + (3 * l2 ** 2 - l1 ** 2) / 4,
          K - L * (l1 * xl + l2 * yl + Xo + Yo) + (3 * l1 ** 2 - l2 ** 2) / 4,
          K + L * (l2 * yl - l1 * xl + Xo - Yo) + (3 * l1 ** 2 - l2 ** 2) / 4,
          K - L * (l2 * ym + l1 * xm - Xo - Yo) + (3 * l2 ** 2 - l1 ** 2) / 4]
    assert np.allclose(sol.extensions, np.sqrt(r2), rtol=1e-10)
    # the SPR R axes are the platform diagonals (eq. 19)
    for k, d in ((1, d13), (2, d24)):
        assert abs(abs(sol.legs[k].joint("R3").direction @ d) - np.linalg.norm(d)) < 1e-9


# --------------------------------------------------------------------------- legs at the pose

def _same_line(j1, j2, tol=1e-7):
    if abs(abs(j1.direction @ j2.direction) - 1) > tol:
        return False
    if j1.kind == "P":
        return True
    r = j2.point - j1.point
    return np.linalg.norm(r - (r @ j1.direction) * j1.direction) < tol * 100


ALL = ["3RRPRR", "2SPS+2SPR", "3SPR", "3RPS", "3UPU", "3UPU/spherical", "2UPU+SPR", "3UPRR",
       "3RPRU", "3RSR", "2UPS+2SPR", "2UPS+2UPU", "4UPU", "3SPU+UPR", "3SPU+SP", "3SPU+PRRR",
       "3SPU+RPRR", "4SPS+SPR", "4SPS+UPU", "4SPS+URPR"]     # every catalog PM but 3RPUR
# legs whose rules place every joint from the end points and frames alone: rebuilt at any pose
# they give the same joints.  The others place an elbow (a joint after the actuator, an S
# between two R, the U1a-U3b meeting point) by a home construction: rebuilt, they must still
# exert the same constraint wrenches, except where the constraint goes through the elbow
# (RSR) or the moving meeting point (UPU/force outside a spherical motion).
SAME_JOINTS = {"3RRPRR", "2SPS+2SPR", "3SPR", "3RPS", "3UPU", "3UPU/spherical", "2UPS+2SPR",
               "2UPS+2UPU", "4UPU", "3SPU+UPR", "3SPU+SP", "4SPS+SPR"}
SAME_WRENCHES = {"3UPRR", "3RPRU", "3SPU+PRRR", "3SPU+RPRR", "4SPS+URPR"}


@pytest.mark.parametrize("name", ALL)
def test_placed_legs_keep_their_structure_and_close_the_loops(name):
    pm = load_pm(name)
    rng = np.random.default_rng(7)
    ind = {p: pm.default_pose[p] + (rng.uniform(-0.08, 0.08) if p in ("alpha", "beta", "gamma")
                                    else rng.uniform(-4, 4)) for p in pm.independent}
    sol = screwkit.solve(pm, ind)
    assert sol.success and not sol.notes
    rebuilt = pm.rebuild_legs(sol.params)
    Rp, op = sol.rotation, sol.position
    for i, (lg, rb, rules) in enumerate(zip(sol.legs, rebuilt, pm.leg_rules)):
        pl = pm.placement(i, sol.params)
        assert max([abs(r) for _, r in structure_residuals(rules, pl, lg)] + [0]) < 1e-8
        assert np.allclose(lg.A, rb.A) and np.allclose(lg.a, rb.a)
        if name in SAME_JOINTS:
            for j1, j2 in zip(lg.joints, rb.joints):
                if j1.spec.origin == "S":          # an S is its centre: its axes are a basis
                    assert np.allclose(j1.point, j2.point, atol=1e-7)
                else:
                    assert _same_line(j1, j2), (name, i, j1.name)
        if name in SAME_WRENCHES | SAME_JOINTS:
            s1 = reciprocal_system(lg.twists, lg.points)
            s2 = reciprocal_system(rb.twists, rb.points)
            assert s1.dimension == s2.dimension
            assert same_span(s1.wrenches, s2.wrenches, pm.normalisation)
        # the product of exponentials carries the home platform pose onto the platform pose
        _, (Re, pe) = leg_forward(pm.home_legs[i], sol.joint_values[i], pm.platform_home)
        assert np.allclose(Re, Rp, atol=1e-9) and np.allclose(pe, op, atol=1e-7)


def test_structure_notes_when_a_leg_loses_its_structure():
    pm = load_pm("3RPUR")        # R4 parallel to R1 only while the platform does not rotate
    assert not screwkit.solve(pm, {"alpha": 0, "beta": 0, "Zo": 65}).notes
    sol = screwkit.solve(pm, {"alpha": 0.05, "beta": 0.02, "Zo": 60})
    assert sol.success and any("structure checks do not hold" in n for n in sol.notes)


def test_translational_and_spherical_3upu():
    tr = load_pm("3UPU")
    s = screwkit.solve(tr, {"Xo": 7, "Yo": -4, "Zo": 55})
    assert np.allclose(s.rotation, np.eye(3), atol=1e-10)
    sp = load_pm("3UPU/spherical")
    C = sp.centre
    d0 = np.linalg.norm(sp.platform_home[1] - C)
    for ang in ([0.1, -0.05, 0.08], [-0.12, 0.1, 0.0]):
        s = screwkit.solve(sp, dict(zip(("alpha", "beta", "gamma"), ang)))
        assert np.linalg.norm(s.position - C) == pytest.approx(d0, abs=1e-8)
        # the platform point at C stays at C (rotation about C)
        assert np.allclose(s.rotation @ (C - sp.platform_home[1]) + s.position, C, atol=1e-8)


# --------------------------------------------------------------------------- invariances

def test_units_scaling(rrprr):
    big = load_pm("3RRPRR", {"L": 120000, "l": 60000})
    s1 = screwkit.solve(rrprr, {"alpha": 7, "beta": -4, "Zo": 85}, degrees=True)
    s2 = screwkit.solve(big, {"alpha": 7, "beta": -4, "Zo": 85000}, degrees=True)
    assert s2.success
    assert np.allclose(s2.extensions, 1000 * s1.extensions, rtol=1e-10)
    for k in ("alpha", "beta", "gamma"):
        assert s2.params[k] == pytest.approx(s1.params[k], abs=1e-10)
    for h, q1, q2 in zip(rrprr.home_legs, s1.joint_values, s2.joint_values):
        scale = np.array([1000.0 if j.kind == "P" else 1.0 for j in h.joints])
        assert np.allclose(q2, scale * q1, rtol=1e-8, atol=1e-10)


@pytest.mark.parametrize("name", ["3RRPRR", "2SPS+2SPR"])
def test_change_of_base_frame(name):
    pm = load_pm(name)
    c, s = np.cos(0.7), np.sin(0.7)
    R = np.array([[c, -s, 0], [s, c, 0], [0, 0, 1]]) @ np.array([[1, 0, 0], [0, 0.8, -0.6], [0, 0.6, 0.8]])
    p = np.array([300.0, -120.0, 45.0])
    moved = pm.moved(R, p)
    ind = {k: pm.default_pose[k] * 1.3 for k in pm.independent}
    s1, s2 = screwkit.solve(pm, ind), screwkit.solve(moved, ind)
    assert s2.success
    assert np.allclose(s2.position, R @ s1.position + p)
    assert np.allclose(s2.rotation, R @ s1.rotation)
    assert np.allclose(s2.extensions, s1.extensions, rtol=1e-10)
    for q1, q2 in zip(s1.joint_values, s2.joint_values):
        assert np.allclose(q1, q2, atol=1e-8)
    for l1, l2 in zip(s1.legs, s2.legs):
        assert np.allclose(transform_twists(R, p, l1.twists), l2.twists, atol=1e-7)


# --------------------------------------------------------------------------- errors

def test_unreachable_and_bad_input(rrprr):
    rsr = load_pm("3RSR")      # fixed-length links: the platform cannot rise far
    with pytest.raises(UnreachablePoseError) as ei:
        screwkit.solve(rsr, {"alpha": 0, "beta": 0, "Zo": 400})
    assert ei.value.residual > 1e-6 and "unreachable" in str(ei.value)
    with pytest.raises(InputError, match="finite"):
        screwkit.solve(rrprr, {"alpha": float("nan"), "beta": 0, "Zo": 80})
    with pytest.raises(InputError, match="dependent"):
        screwkit.solve(rrprr, {"alpha": 0, "beta": 0, "Zo": 80, "gamma": 0.1})
    with pytest.raises(InputError, match="unknown pose parameter"):
        screwkit.solve(rrprr, {"theta": 1})
    s = screwkit.solve(rrprr, {"alpha": 0.05})
    assert any("default pose" in n for n in s.notes)
    with pytest.raises(InputError, match="unknown dimension"):
        load_pm("3RRPRR", {"H": 3})
    with pytest.raises(InputError, match="positive"):
        load_pm("3RRPRR", {"L": -1})
    with pytest.raises(CatalogError, match="unknown PM"):
        load_pm("7XYZ")


_GOOD = """
legs:
  - name: MYSPR
    string: S_PR
    joints:
      - {at: A}
      - {axis: leg}
      - {axis: platform.tangent, at: a}
    structure:
      - {perpendicular: [R3, leg]}
pms:
  3MYSPR:
    string: 3SPR
    dimensions: {R: 50, r: 20}
    base: {shape: circle, radius: R, count: 3, start: 90}
    platform: {shape: circle, radius: r, count: 3, start: 90}
    legs: [MYSPR, MYSPR, MYSPR]
    euler: XYZ
    independent: [alpha, beta, Zo]
    pose: {alpha: 0, beta: 0, Zo: R}
    dof: 3
"""


def test_user_file(tmp_path):
    f = tmp_path / "my.yaml"
    f.write_text(_GOOD)
    pm = load_pm(str(f))
    assert pm.legs == ("MYSPR",) * 3 and pm.dimensions == {"R": 50.0, "r": 20.0}
    s = screwkit.solve(pm, {"alpha": 4, "beta": 2, "Zo": 45}, degrees=True)
    assert s.success and np.allclose(pm.base_points[0], [0, 50, 0], atol=1e-12)


@pytest.mark.parametrize("change,field", [
    (("dof: 3", "dof: 4"), "independent"),
    (("legs: [MYSPR, MYSPR, MYSPR]", "legs: [MYSPR, NOPE, MYSPR]"), "legs[1]"),
    (("platform: {shape: circle", "platform: {shape: hexagon"), "platform.shape"),
    (("Zo: R}", "Zo: R*}"), "pose.Zo"),
    (("euler: XYZ", "euler: XYQ"), "euler"),
    (("    dof: 3\n", ""), "dof"),
])
def test_schema_errors_name_pm_and_field(tmp_path, change, field):
    f = tmp_path / "bad.yaml"
    assert change[0] in _GOOD
    f.write_text(_GOOD.replace(change[0], change[1]))
    with pytest.raises(CatalogError) as ei:
        load_pm(str(f))
    assert "'3MYSPR'" in str(ei.value) and f"'{field}'" in str(ei.value)
