"""The paper's two examples (section 5.1): 3RRPRR and 2SPS+2SPR statics.

Every expected value here is built independently of screwkit.engine (Jacobian, statics):
the paper's own Jacobian rows (eqs. 13d, 14a-e, 18, 19 with the corrections of
NOTES.md) assembled by hand, the legs' own joint twists, finite differences of
the closed-form inverse displacement, and invariance under a change of frame
and of units.
"""

from __future__ import annotations

import numpy as np
import pytest
from scipy.optimize import brentq
from scipy.spatial.transform import Rotation

import screwkit
from screwkit.engine import solve_statics, statics, unified_jacobian
from screwkit.errors import GeometryError, SingularityError
from screwkit.legs import Placement, structure_residuals
from screwkit.pm import default_catalog, leg_spec_from_mapping
from screwkit.screws import transform_wrenches

F_LOAD = np.array([-20.0, -30.0, -60.0])      # kN
T_LOAD = np.array([-30.0, -30.0, 100.0])      # kN.cm
B3 = np.sqrt(3.0)


# ---------------------------------------------------------------------------
# 3RRPRR: L = 120, l = 60 cm; E = L/sqrt(3) = 2e
# ---------------------------------------------------------------------------
L3, l3 = 120.0, 60.0
E3, e3 = L3 / B3, l3 / B3
A3 = np.array([E3 / 2 * np.array([B3, -1, 0]), [0, E3, 0], E3 / 2 * np.array([-B3, -1, 0])])
MA3 = np.array([e3 / 2 * np.array([B3, -1, 0]), [0, e3, 0], e3 / 2 * np.array([-B3, -1, 0])])
R1_3 = A3 / np.linalg.norm(A3, axis=1, keepdims=True)          # eq. 14b: unit O -> A_i


def rrprr_pose(alpha, beta, Zo, paper_sign=False):
    """Closed forms: gamma = alpha (11c), X_o (11e), Y_o (11e with the Z_o sign fixed)."""
    sa, ca, sb, cb = np.sin(alpha), np.cos(alpha), np.sin(beta), np.cos(beta)
    den = -sa ** 2 + ca ** 2 * cb
    Xo = (Zo * ca + e3 * sa) * sb / den
    sgn = 1.0 if paper_sign else -1.0
    Yo = (sgn * Zo * sa * ca * (1 + cb) + e3 * (cb - ca ** 2 + sa ** 2 * cb) / 2) / den
    R = Rotation.from_euler("XYX", [alpha, beta, alpha]).as_matrix()
    o = np.array([Xo, Yo, Zo])
    return R, o, MA3 @ R.T + o


def rrprr_legs(alpha, beta, Zo, paper_sign=False):
    spec = default_catalog().legs["RRPRR"]
    R, o, a = rrprr_pose(alpha, beta, Zo, paper_sign)
    legs = [spec.build(Placement(A3[i], a[i], np.zeros(3), o, np.eye(3), R)) for i in range(3)]
    return legs, R, o, a


REGULAR_3RRPRR = [(5.0, -3.0, 80.0), (-8.0, 6.0, 95.0), (12.0, 10.0, 70.0), (0.5, -7.0, 110.0)]


def paper_3rrprr(alpha, beta, Zo):
    """The paper's F_r and T_r (eqs. 13d, 13e, 14a-e), built by hand."""
    R, o, a = rrprr_pose(alpha, beta, Zo)
    z = R[:, 2]
    rows, lines = [], []
    for i in range(3):
        d = (a[i] - A3[i]) / np.linalg.norm(a[i] - A3[i])
        rows.append(np.r_[d, np.cross(a[i] - o, d)])
    Q = []
    for i in range(3):
        d = (a[i] - A3[i]) / np.linalg.norm(a[i] - A3[i])
        c = np.cross(R1_3[i], d)
        c /= np.linalg.norm(c)
        q = a[i] - a[i][2] / z[2] * z                    # eq. 14d: R_4i meets z = 0
        Q.append(q)
        rows.append(np.r_[c, np.cross(q - o, c)])
        lines.append((q, c))
    J = np.array(rows)
    Fr = -np.linalg.solve(J.T, np.r_[F_LOAD, T_LOAD])   # eq. 9 with V = [v_o; w]
    T_r = []
    for i in range(3):
        d = (a[i] - A3[i]) / np.linalg.norm(a[i] - A3[i])
        q, c = lines[i]
        T_r.append(np.cross(Fr[3 + i] * c, A3[i] - q) @ d)   # eq. 13e
    return Fr, lines, np.array(T_r), J


def _dist_to_line(p, q, d):
    return np.linalg.norm(np.cross(p - q, d)) / np.linalg.norm(d)


def test_3rrprr_printed_Yo_sign_is_wrong_and_corrected_one_closes():
    """The corrected Y_o (NOTES.md) satisfies the RRPRR structure; the printed one does not."""
    spec = default_catalog().legs["RRPRR"]
    al, be, Z = np.radians(5), np.radians(-3), 80.0
    legs, R, o, a = rrprr_legs(al, be, Z)
    for i, leg in enumerate(legs):
        pl = Placement(A3[i], a[i], np.zeros(3), o, np.eye(3), R)
        res = [abs(v) for _, v in structure_residuals(spec.rules, pl, leg)]
        assert max(res) < 1e-12
    with pytest.raises(GeometryError):
        rrprr_legs(al, be, Z, paper_sign=True)
    # eq. 14e prints the same o with the right sign: its Y_o agrees with the fix
    sa, ca, sb, cb = np.sin(al), np.cos(al), np.sin(be), np.cos(be)
    y14e = (-Z * ca * sa * (1 + cb) + e3 * (cb - ca ** 2 + sa ** 2 * cb) / 2) / (-sa ** 2 + ca ** 2 * cb)
    assert o[1] == pytest.approx(y14e, rel=1e-14)


@pytest.mark.parametrize("pose", REGULAR_3RRPRR)
def test_3rrprr_statics_matches_paper_rows(pose):
    al, be, Z = np.radians(pose[0]), np.radians(pose[1]), pose[2]
    legs, R, o, a = rrprr_legs(al, be, Z)
    res = solve_statics(legs, o, F_LOAD, T_LOAD)
    jac = res.jacobian
    assert jac.J.shape == (6, 6) and jac.kinds == ("actuation",) * 3 + ("force",) * 3
    assert not res.singular and not res.indeterminate

    Fr, lines, T_r, Jp = paper_3rrprr(al, be, Z)
    scale = np.abs(Fr).max()
    # active forces: same values (F_ai > 0 pushes the platform away from A_i)
    np.testing.assert_allclose(res.active, Fr[:3], rtol=1e-9, atol=1e-9 * scale)
    # actuation rows about o are the paper's [delta; e x delta]
    np.testing.assert_allclose(jac.rows_about(o)[:3], Jp[:3], atol=1e-12 * L3)
    # constraint forces as vectors, on the paper's lines (through Q_i, along c_i)
    for i in range(3):
        r = 3 + i
        np.testing.assert_allclose(res.vectors[r], Fr[r] * lines[i][1], atol=1e-9 * scale)
        assert _dist_to_line(lines[i][0], jac.rows[r].point, jac.rows[r].direction) < 1e-9 * L3
    # the constraint torque about each leg axis (eq. 13e)
    np.testing.assert_allclose(res.T_r, T_r, rtol=1e-9, atol=1e-9 * scale * L3)


@pytest.mark.parametrize("pose", REGULAR_3RRPRR[:2])
def test_3rrprr_leg_wrenches_act_only_on_the_actuator(pose):
    """(a) Each leg's total wrench does no work on its passive joints and F_ai on its P."""
    legs, R, o, a = rrprr_legs(np.radians(pose[0]), np.radians(pose[1]), pose[2])
    res = solve_statics(legs, o, F_LOAD, T_LOAD)
    fscale = np.abs(res.values).max()
    for i, leg in enumerate(legs):
        p = leg.twists @ res.leg_wrenches[i]            # power per unit joint rate
        want = np.zeros(len(leg.joints))
        want[leg.actuated_index] = res.active[i]
        # R twists carry moments: compare with force x length
        np.testing.assert_allclose(p, want, atol=1e-10 * fscale * L3)
    # (b) platform equilibrium, rebuilt here from the leg wrenches
    W = np.r_[F_LOAD, T_LOAD + np.cross(o, F_LOAD)]
    tot = res.leg_wrenches.sum(axis=0) + W
    assert np.abs(tot[:3]).max() < 1e-10 * fscale
    assert np.abs(tot[3:]).max() < 1e-10 * fscale * L3
    assert res.equilibrium_residual < 1e-12


def test_3rrprr_rows_about_O_and_about_o_give_the_same_Fr():
    """The paper's convention (rows and workload about o, V = [v_o; w]) and screwkit's
    (about O) give the same F_r: eq. 9 solved both ways."""
    legs, R, o, a = rrprr_legs(np.radians(5), np.radians(-3), 80.0)
    jac = unified_jacobian(legs, o)
    F_about_O = -np.linalg.solve(jac.J.T, np.r_[F_LOAD, T_LOAD + np.cross(o, F_LOAD)])
    F_about_o = -np.linalg.solve(jac.rows_about(o).T, np.r_[F_LOAD, T_LOAD])
    np.testing.assert_allclose(F_about_O, F_about_o, rtol=1e-10)
    np.testing.assert_allclose(statics(jac, F_LOAD, T_LOAD).values, F_about_o, rtol=1e-10)


def _twist_fd(pose_fn, x, dx, h):
    """Central-difference platform twist [v_O; w] along x + t dx, and d(leg lengths)/dt."""
    Rp, op, ap = pose_fn(x + h * dx)
    Rm, om, am = pose_fn(x - h * dx)
    R0, o0, a0 = pose_fn(x)
    Om = (Rp - Rm) / (2 * h) @ R0.T
    w = 0.5 * np.array([Om[2, 1] - Om[1, 2], Om[0, 2] - Om[2, 0], Om[1, 0] - Om[0, 1]])
    v_O = (op - om) / (2 * h) - np.cross(w, o0)
    return np.r_[v_O, w], (ap, am)


def test_3rrprr_virtual_work_finite_differences():
    """(d) Moving along the constrained motion (alpha, beta, Zo free; gamma, Xo, Yo from the
    closed forms): the twist is reciprocal to every constraint row and J_a V = dr/dt."""
    x0 = np.array([np.radians(5), np.radians(-3), 80.0])
    legs, R, o, a = rrprr_legs(*x0)
    jac = unified_jacobian(legs, o)
    h = 1e-5
    for dx in (np.array([1.0, 0, 0]), np.array([0, 1.0, 0]), np.array([0, 0, 30.0]),
               np.array([0.3, -0.5, 10.0])):
        V, (ap, am) = _twist_fd(lambda x: rrprr_pose(*x), x0, dx, h)
        rdot = (np.linalg.norm(ap - A3, axis=1) - np.linalg.norm(am - A3, axis=1)) / (2 * h)
        Vn = np.linalg.norm(V[:3]) + L3 * np.linalg.norm(V[3:])
        assert np.abs(jac.J_c @ V).max() < 1e-8 * Vn
        np.testing.assert_allclose(jac.J_a @ V, rdot, atol=1e-8 * Vn)


# ---------------------------------------------------------------------------
# 2SPS+2SPR: square base side L = 100, platform 60 x 50 cm
# ---------------------------------------------------------------------------
L4, l1, l2 = 100.0, 60.0, 50.0
A4 = L4 / 2 * np.array([[1, -1, 0], [1, 1, 0], [-1, 1, 0], [-1, -1, 0]], float)
MA4 = 0.5 * np.array([[l1, -l2, 0], [l1, l2, 0], [-l1, l2, 0], [-l1, -l2, 0]])


def _spr(name, axis):
    # the catalog SPR has its R along platform.tangent; here R2 is along a1 - a3 and R3
    # along a2 - a4 (section 4.1), which for a 60 x 50 rectangle is not the tangent
    return leg_spec_from_mapping({
        "name": name, "string": "S_PR",
        "joints": [{"at": "A"}, {"axis": "leg"}, {"axis": {"platform": list(axis)}, "at": "a"}],
        "structure": [{"perpendicular": ["R3", "leg"]}]})


SPR2 = _spr("SPR/a1a3", MA4[0] - MA4[2])
SPR3 = _spr("SPR/a2a4", MA4[1] - MA4[3])


def sps_spr_pose(alpha, beta, gamma, Zo):
    """X_o, Y_o from the SPR structure r2 . (a1 - a3) = r3 . (a2 - a4) = 0 (linear in o)."""
    R = Rotation.from_euler("XYX", [alpha, beta, gamma]).as_matrix()
    u2, u3 = R @ (MA4[0] - MA4[2]), R @ (MA4[1] - MA4[3])
    z = np.array([0, 0, Zo])
    M = np.array([u2[:2], u3[:2]])
    rhs = -np.array([(R @ MA4[1] + z - A4[1]) @ u2, (R @ MA4[2] + z - A4[2]) @ u3])
    xy = np.linalg.solve(M, rhs)
    o = np.array([xy[0], xy[1], Zo])
    return R, o, MA4 @ R.T + o


def sps_spr_legs(alpha, beta, gamma, Zo):
    R, o, a = sps_spr_pose(alpha, beta, gamma, Zo)
    sps = default_catalog().legs["SPS"]
    specs = [sps, SPR2, SPR3, sps]
    legs = [specs[i].build(Placement(A4[i], a[i], np.zeros(3), o, np.eye(3), R)) for i in range(4)]
    return legs, R, o, a


def paper_16d(alpha, beta, gamma, Zo):
    """Eq. 16d with E = L/2 and s_gamma^2 in the last Y_o term (NOTES.md)."""
    sa, ca, sb, cb, sg, cg = (np.sin(alpha), np.cos(alpha), np.sin(beta), np.cos(beta),
                              np.sin(gamma), np.cos(gamma))
    den = 2 * (ca * cb * cg - sa * sg)
    X = sb * (l2 * sa + 2 * Zo * cg - L4 * sg * (ca * cg - sa * cb * sg) * l2 / l1
              - sa * (l1 - L4 * cb) * l1 / l2) / den
    Y = (-2 * Zo * (ca * sg + sa * cb * cg) - l2 * cb + cb * (l1 - L4 * cb) * l1 / l2
         + L4 * sb ** 2 * sg ** 2 * l2 / l1) / den + L4 / 2
    return np.array([X, Y, Zo])


REGULAR_2SPS2SPR = [(3.0, 4.0, -2.0, 80.0), (-5.0, -6.0, 4.0, 90.0), (2.0, 0.0, 2.0, 80.0)]


def paper_2sps2spr_rows(R, o, a):
    """Eqs. 18-19 (rows about o) with rho_j = A_j - o (NOTES.md)."""
    rows = []
    for i in range(4):
        d = (a[i] - A4[i]) / np.linalg.norm(a[i] - A4[i])
        rows.append(np.r_[d, np.cross(a[i] - o, d)])
    for j, (p, q) in ((1, (0, 2)), (2, (1, 3))):
        c = (a[p] - a[q]) / np.linalg.norm(a[p] - a[q])
        rows.append(np.r_[c, np.cross(A4[j] - o, c)])
    return np.array(rows)


@pytest.mark.parametrize("pose", REGULAR_2SPS2SPR)
def test_2sps2spr_pose_and_corrected_16d(pose):
    al, be, ga = np.radians(pose[:3])
    R, o, a = sps_spr_pose(al, be, ga, pose[3])
    np.testing.assert_allclose(paper_16d(al, be, ga, pose[3]), o, atol=1e-10 * L4)


@pytest.mark.parametrize("pose", REGULAR_2SPS2SPR)
def test_2sps2spr_statics(pose):
    al, be, ga = np.radians(pose[:3])
    legs, R, o, a = sps_spr_legs(al, be, ga, pose[3])
    res = solve_statics(legs, o, F_LOAD, T_LOAD)
    jac = res.jacobian
    assert jac.kinds == ("actuation",) * 4 + ("force",) * 2
    assert [r.leg for r in jac.rows[4:]] == [1, 2]
    fscale = np.abs(res.values).max()
    for i, leg in enumerate(legs):
        want = np.zeros(len(leg.joints))
        want[leg.actuated_index] = res.active[i]
        np.testing.assert_allclose(leg.twists @ res.leg_wrenches[i], want, atol=1e-10 * fscale * L4)
    assert res.equilibrium_residual < 1e-12
    # the SPS legs carry only their actuator force, along the leg
    for i in (0, 3):
        d = (a[i] - A4[i]) / np.linalg.norm(a[i] - A4[i])
        np.testing.assert_allclose(res.leg_wrenches[i][:3], res.active[i] * d, atol=1e-10 * fscale)
    # the paper's rows (eq. 18 with the corrected arm) give the same forces, as vectors
    Jp = paper_2sps2spr_rows(R, o, a)
    Fr = -np.linalg.solve(Jp.T, np.r_[F_LOAD, T_LOAD])
    np.testing.assert_allclose(res.active, Fr[:4], rtol=1e-9, atol=1e-9 * fscale)
    for k, r in enumerate((4, 5)):
        np.testing.assert_allclose(res.vectors[r], Fr[r] * Jp[r, :3], atol=1e-9 * fscale)
        assert _dist_to_line(A4[1 + k], jac.rows[r].point, jac.rows[r].direction) < 1e-9 * L4


def test_2sps2spr_printed_arm_through_a_is_not_a_constraint():
    """Eq. 19 as printed puts F_c2 through a_2: that line is not reciprocal to the S at A_2."""
    legs, R, o, a = sps_spr_legs(np.radians(3), np.radians(4), np.radians(-2), 80.0)
    c = (a[0] - a[2]) / np.linalg.norm(a[0] - a[2])
    through_a = np.r_[c, np.cross(a[1], c)]
    through_A = np.r_[c, np.cross(A4[1], c)]
    T = legs[1].twists
    assert np.abs(T @ through_A).max() < 1e-9 * L4
    assert np.abs(T @ through_a).max() > 1e-2 * L4


def _paper_det(s_deg, Zo):
    al = ga = np.radians(s_deg) / 2
    R, o, a = sps_spr_pose(al, 0.0, ga, Zo)
    return np.linalg.det(paper_2sps2spr_rows(R, o, a))


@pytest.mark.parametrize("Zo", [60.0, 80.0, 100.0])
def test_2sps2spr_actuation_singularity_is_reported(Zo):
    """beta = 0, alpha = gamma: the paper's det(J) changes sign for alpha + gamma in
    13..20 deg; there screwkit reports an actuation singularity instead of a number."""
    grid = np.arange(10.0, 22.01, 1.0)
    dets = [_paper_det(s, Zo) for s in grid]
    k = next(i for i in range(len(grid) - 1) if dets[i] * dets[i + 1] < 0)
    s_star = brentq(_paper_det, grid[k], grid[k + 1], args=(Zo,), xtol=1e-15, rtol=1e-15)
    assert 13.0 < s_star < 20.0
    legs, R, o, a = sps_spr_legs(np.radians(s_star) / 2, 0.0, np.radians(s_star) / 2, Zo)
    jac = unified_jacobian(legs, o)
    assert jac.singular and jac.singularity_kind == "actuation"
    with pytest.raises(SingularityError) as err:
        statics(jac, F_LOAD, T_LOAD)
    assert err.value.kind == "actuation" and err.value.condition_number > 1e8
    assert "actuation" in str(err.value)
    soft = statics(jac, F_LOAD, T_LOAD, raise_on_singular=False)
    assert soft.singular and soft.singularity_kind == "actuation" and not soft.success
    # half a degree away: regular, but the actuators carry many times the load
    legs, R, o, a = sps_spr_legs(np.radians(s_star - 0.5) / 2, 0.0, np.radians(s_star - 0.5) / 2, Zo)
    near = solve_statics(legs, o, F_LOAD, T_LOAD)
    assert near.condition_number > 100
    assert np.abs(near.active).max() > 10 * np.linalg.norm(F_LOAD)
    assert near.equilibrium_residual < 1e-9


# ---------------------------------------------------------------------------
# invariance: base frame and units
# ---------------------------------------------------------------------------

def _moved_problem(legs, o, Rm, p, k):
    legs2 = [leg.moved(Rm, p, k) for leg in legs]
    return legs2, Rm @ (k * o) + p, Rm @ F_LOAD, k * (Rm @ T_LOAD)


@pytest.mark.parametrize("example", ["3RRPRR", "2SPS+2SPR"])
def test_invariance_under_frame_and_units(example):
    if example == "3RRPRR":
        legs, R, o, a = rrprr_legs(np.radians(5), np.radians(-3), 80.0)
    else:
        legs, R, o, a = sps_spr_legs(np.radians(3), np.radians(4), np.radians(-2), 80.0)
    ref = solve_statics(legs, o, F_LOAD, T_LOAD)
    Rm = Rotation.from_euler("zyx", [40, -25, 70], degrees=True).as_matrix()
    p = np.array([250.0, -130.0, 42.0])
    for (Rk, pk, k) in ((Rm, p, 1.0), (np.eye(3), np.zeros(3), 1000.0), (Rm, 1000 * p, 1000.0)):
        legs2, o2, F2, T2 = _moved_problem(legs, o, Rk, pk, k)
        res = solve_statics(legs2, o2, F2, T2)
        fs = np.abs(ref.values).max()
        np.testing.assert_allclose(res.active, ref.active, rtol=1e-8, atol=1e-9 * fs)
        assert res.condition_number == pytest.approx(ref.condition_number, rel=1e-8)
        # each leg's wrench moves with the frame: forces rotate, moments scale with k
        moved = transform_wrenches(Rk, pk, ref.leg_wrenches * np.r_[np.ones(3), k * np.ones(3)])
        np.testing.assert_allclose(res.leg_wrenches[:, :3], moved[:, :3], atol=1e-9 * fs)
        np.testing.assert_allclose(res.leg_wrenches[:, 3:], moved[:, 3:],
                                   atol=1e-9 * fs * k * (L4 + np.linalg.norm(pk)))
        np.testing.assert_allclose(res.T_r, k * ref.T_r, atol=1e-9 * fs * k * L4)
        # constraint forces as vectors (sign of the direction is a convention)
        nc = ref.jacobian.n_actuated
        np.testing.assert_allclose(res.vectors[nc:], ref.vectors[nc:] @ Rk.T, atol=1e-9 * fs)


# ---------------------------------------------------------------------------
# integration with screwkit.pm (skipped while the catalog has no 3RRPRR PM)
# ---------------------------------------------------------------------------

def test_3rrprr_from_load_pm_matches_the_paper():
    from screwkit.errors import CatalogError
    pm_mod = pytest.importorskip("screwkit.pm")
    try:
        pm = pm_mod.load_pm("3RRPRR")
    except CatalogError as exc:
        pytest.skip(f"no 3RRPRR PM in the catalog yet: {exc}")
    sol = screwkit.solve(pm, {"alpha": 5, "beta": -3, "Zo": 80}, degrees=True)
    assert sol.success
    res = solve_statics(sol.legs, sol.position, F_LOAD, T_LOAD)
    Fr, lines, T_r, _ = paper_3rrprr(np.radians(5), np.radians(-3), 80.0)
    # the PM's own vertex numbering may differ: compare the sets
    np.testing.assert_allclose(np.sort(res.active), np.sort(Fr[:3]), rtol=1e-7)
    np.testing.assert_allclose(np.sort(res.T_r), np.sort(T_r), rtol=1e-6, atol=1e-6)
