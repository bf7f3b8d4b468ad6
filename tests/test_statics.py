"""Unified Jacobian and statics: conventions, redundancy, singularity kinds, input errors.

Expected values come from hand-built screws (Pluecker rows of a Stewart platform),
virtual work over an independently written basis of feasible twists, geometric
identities (reciprocity, equilibrium) and counting arguments.
"""

from __future__ import annotations

import numpy as np
import pytest

import screwkit
from screwkit.engine import (COND_THRESHOLD, solve_statics, statics, unified_jacobian,
                             workload_wrench)
from screwkit.errors import InputError, SingularityError
from screwkit.legs import Joint, Leg, Placement, parse_leg
from screwkit.pm import default_catalog, leg_spec_from_mapping

F0 = np.array([10.0, -5.0, -60.0])
T0 = np.array([3.0, 4.0, 5.0])


def ring(n, radius, z=0.0, phase=0.1, centre=(0.0, 0.0, 0.0)):
    ang = 2 * np.pi * np.arange(n) / n + phase
    return np.c_[radius * np.cos(ang), radius * np.sin(ang), np.full(n, z)] + np.asarray(centre)


def upu_legs(name, n, o, base_r=100.0, plat_r=40.0, R=np.eye(3), spec=None, plat_scale=None):
    spec = spec or default_catalog().legs[name]
    A = ring(n, base_r)
    a = ring(n, plat_r)
    if plat_scale is not None:
        a = a * np.asarray(plat_scale)
    a = a @ R.T + o
    return [spec.build(Placement(A[i], a[i], np.zeros(3), o, np.eye(3), R)) for i in range(n)]


# a Schoenflies UPU: first U axis vertical, last U axis along the platform normal, so
# the leg's constraint couple is horizontal (4 legs: 4 couples spanning only 2 directions)
SCHOENFLIES_UPU = leg_spec_from_mapping({
    "name": "UPU/schoenflies", "string": "U_PU",
    "joints": [{"at": "A", "axes": ["base.Z", {"perpendicular": ["U1a", "leg"]}]},
               {"axis": "leg"},
               {"at": "a", "axes": [{"parallel": "U1b"}, "platform.z"]}],
    "structure": [{"parallel": ["U3a", "U1b"]}, {"parallel": ["U3b", "U1a"]}]})


def stewart():
    """A regular 6-6 Stewart platform (joint pairs 20 deg apart on the base)."""
    def pts(r, deg, z=0.0):
        t = np.radians(deg)
        return np.c_[r * np.cos(t), r * np.sin(t), np.full(len(t), z)]
    A = pts(100.0, [-10, 10, 110, 130, 230, 250])
    o = np.array([4.0, -3.0, 85.0])
    a = pts(45.0, [-50, 50, 70, 170, 190, 290]) + o
    return [screwkit.leg("SPS", Placement(A[i], a[i], o=o)) for i in range(6)], A, a, o


# ---------------------------------------------------------------------------
# the Jacobian rows
# ---------------------------------------------------------------------------

def test_stewart_rows_are_the_leg_lines():
    """6SPS: J rows are the Pluecker lines [delta; a x delta]; F_r = -J^-T W."""
    legs, A, a, o = stewart()
    jac = unified_jacobian(legs, o)
    d = (a - A) / np.linalg.norm(a - A, axis=1, keepdims=True)
    J = np.c_[d, np.cross(a, d)]
    np.testing.assert_allclose(jac.J, J, atol=1e-12 * 100)
    assert jac.kinds == ("actuation",) * 6 and jac.n_actuated == 6 and jac.rank == 6
    assert jac.singularity_kind is None and jac.expected_constraint_rank == 0
    res = statics(jac, F0, T0)
    W = np.r_[F0, T0 + np.cross(o, F0)]
    np.testing.assert_allclose(res.values, -np.linalg.solve(J.T, W), rtol=1e-10)
    np.testing.assert_allclose(res.vectors, res.values[:, None] * d, rtol=1e-10)


def test_rows_are_reciprocal_and_unit_actuation():
    """Constraint rows do no work on any joint of their leg; an actuation row does none on
    the passive joints and unit work on the actuated joint's unit twist."""
    o = np.array([3.0, -2.0, 70.0])
    legs = upu_legs("UPU/couple", 3, o)
    jac = unified_jacobian(legs, o)
    assert jac.kinds == ("actuation",) * 3 + ("couple",) * 3
    for r, row in zip(jac.rows, jac.J):
        leg = legs[r.leg]
        p = leg.twists @ row
        if r.kind == "actuation":
            want = np.zeros(len(p))
            want[leg.actuated_index] = 1.0
            np.testing.assert_allclose(p, want, atol=1e-12 * 100)
            assert r.joint == leg.actuated_joint.name and r.member == "force"
            assert abs(np.linalg.norm(r.direction) - 1) < 1e-12
        else:
            assert np.abs(p).max() < 1e-12 * 100
            assert r.point is None and r.joint is None
            np.testing.assert_allclose(row, np.r_[0, 0, 0, r.direction], atol=1e-15)
    np.testing.assert_array_equal(jac.leg_rows(1), [1, 4])


def test_actuator_velocity_of_a_translation():
    """3UPU translational: a pure translation V = [v; 0] is allowed (J_c V = 0) and the
    actuator velocities are d|a_i - A_i|/dt = delta_i . v."""
    o = np.array([3.0, -2.0, 70.0])
    legs = upu_legs("UPU/couple", 3, o)
    jac = unified_jacobian(legs, o)
    v = np.array([0.3, -0.2, 0.5])
    V = np.r_[v, 0, 0, 0]
    assert np.abs(jac.J_c @ V).max() < 1e-14
    d = np.array([(leg.a - leg.A) / leg.length for leg in legs])
    np.testing.assert_allclose(jac.J_a @ V, d @ v, atol=1e-13)


# ---------------------------------------------------------------------------
# statics identities
# ---------------------------------------------------------------------------

def test_workload_wrench_and_application_point():
    o = np.array([1.0, 2.0, 3.0])
    np.testing.assert_allclose(workload_wrench(F0, T0, o), np.r_[F0, T0 + np.cross(o, F0)])
    o = np.array([3.0, -2.0, 70.0])
    jac = unified_jacobian(upu_legs("UPU/couple", 3, o), o)
    p = np.array([10.0, 20.0, 90.0])
    # F at p with torque T equals F at o with torque T + (p - o) x F
    r1 = statics(jac, F0, T0, p)
    r2 = statics(jac, F0, T0 + np.cross(p - o, F0))
    np.testing.assert_allclose(r1.values, r2.values, rtol=1e-10)


def test_batched_workloads_equal_single_ones():
    o = np.array([3.0, -2.0, 70.0])
    jac = unified_jacobian(upu_legs("UPU/couple", 3, o), o)
    rng = np.random.default_rng(3)
    Fs, Ts = rng.normal(size=(5, 3)) * 50, rng.normal(size=(5, 3)) * 500
    batch = statics(jac, Fs, Ts)
    assert batch.values.shape == (5, 6) and batch.leg_wrenches.shape == (5, 3, 6)
    for k in range(5):
        one = statics(jac, Fs[k], Ts[k])
        np.testing.assert_allclose(batch.values[k], one.values, rtol=1e-12, atol=1e-12)
        np.testing.assert_allclose(batch.T_r[k], one.T_r, rtol=1e-12, atol=1e-9)
    assert batch.equilibrium_residual < 1e-12


def test_leg_wrenches_sum_with_load_to_zero_and_T_r_definition():
    o = np.array([3.0, -2.0, 70.0])
    legs = upu_legs("UPU/couple", 3, o)
    res = solve_statics(legs, o, F0, T0)
    W = np.r_[F0, T0 + np.cross(o, F0)]
    tot = res.leg_wrenches.sum(axis=0) + W
    assert np.abs(tot).max() < 1e-10 * np.abs(res.row_wrenches).max()
    # a constraint couple t: T_r = t . delta (the moment of a couple is the same about A)
    for i, leg in enumerate(legs):
        t = res.vectors[3 + i]
        assert res.T_r[i] == pytest.approx(t @ (leg.a - leg.A) / leg.length, rel=1e-12)
    np.testing.assert_allclose(res.constraint_wrenches, res.row_wrenches[3:], atol=1e-12)


# ---------------------------------------------------------------------------
# redundancy: statically indeterminate
# ---------------------------------------------------------------------------

def test_schoenflies_4upu_redundant_constraints():
    """4 horizontal couples span 2 directions: 2 redundant constraints, 4 DOF, 4 actuators.
    The actuator forces are still unique: check them against virtual work over a basis of
    the 4 feasible twists (3 translations, rotation about the vertical through o)."""
    Rz = np.array([[np.cos(0.35), -np.sin(0.35), 0], [np.sin(0.35), np.cos(0.35), 0], [0, 0, 1]])
    o = np.array([5.0, -4.0, 75.0])
    # a platform square similar to the base square would make the 4 leg lines dependent for
    # the Schoenflies motion (rows affine in the vertex, an architecture singularity):
    # stretch the platform into a rectangle (and avoid a rotation of twice the base phase,
    # which for this rectangle is singular too)
    legs = upu_legs(None, 4, o, R=Rz, spec=SCHOENFLIES_UPU, plat_scale=[1.5, 0.7, 1.0])
    jac = unified_jacobian(legs, o)
    assert jac.kinds == ("actuation",) * 4 + ("couple",) * 4
    assert (jac.n_rows, jac.rank, jac.constraint_rank, jac.dof) == (8, 6, 2, 4)
    assert jac.indeterminate and jac.indeterminacy == 2 and not jac.singular
    res = statics(jac, F0, T0)
    assert res.equilibrium_residual < 1e-12
    # feasible twists about O: translations and a rotation about the vertical through o
    Z = np.array([0, 0, 1.0])
    B = np.array([[1, 0, 0, 0, 0, 0], [0, 1, 0, 0, 0, 0], [0, 0, 1, 0, 0, 0],
                  np.r_[np.cross(o, Z), Z]], float).T
    assert np.abs(jac.J_c @ B).max() < 1e-12 * 100
    W = np.r_[F0, T0 + np.cross(o, F0)]
    G = jac.J_a @ B                                       # actuator velocities per basis twist
    Fa = -np.linalg.solve(G.T, B.T @ W)                   # F_a . (G q) + W . (B q) = 0
    np.testing.assert_allclose(res.active, Fa, rtol=1e-9)
    # the self-stresses: pure couples summing to zero, no actuator effort
    S = res.self_stress
    assert S.shape == (2, 8)
    assert np.abs(S @ jac.J).max() < 1e-12 * np.abs(S).max() * 100
    assert np.abs(S[:, :4]).max() < 1e-12 * np.abs(S).max()
    # adding any self-stress keeps the equilibrium
    W_legs = (res.values + 7.0 * S[0] - 3.0 * S[1]) @ jac.J
    np.testing.assert_allclose(W_legs, -W, atol=1e-9 * np.abs(res.row_wrenches).max())


def test_translational_4upu_redundant_actuation_and_constraint():
    """4 UPU/couple legs: 4 couples in 3 dimensions (1 redundant) and 4 actuators for 3
    translations (1 redundant): indeterminacy 8 - 6 = 2."""
    o = np.array([3.0, -2.0, 70.0])
    legs = upu_legs("UPU/couple", 4, o)
    res = solve_statics(legs, o, F0, T0)
    assert (res.jacobian.rank, res.jacobian.constraint_rank) == (6, 3)
    assert res.indeterminate and res.indeterminacy == 2
    assert res.equilibrium_residual < 1e-12 and res.success


# ---------------------------------------------------------------------------
# singularities
# ---------------------------------------------------------------------------

def test_constraint_singularity_of_3upu():
    """3UPU translational with vertical legs (platform as large as the base): every leg's
    couple is vertical, the constraint rows have rank 1 instead of 3."""
    o = np.array([0.0, 0.0, 70.0])
    legs = upu_legs("UPU/couple", 3, o, base_r=60.0, plat_r=60.0)
    jac = unified_jacobian(legs, o)
    assert jac.constraint_rank == 1
    assert jac.singular and jac.singularity_kind == "constraint"
    with pytest.raises(SingularityError) as err:
        statics(jac, F0, T0)
    assert err.value.kind == "constraint" and err.value.condition_number > COND_THRESHOLD
    assert "constraint" in str(err.value)
    soft = statics(jac, F0, T0, raise_on_singular=False)
    assert soft.singular and soft.singularity_kind == "constraint" and not soft.success
    # vertical leg forces and vertical couples cannot resist a horizontal force
    soft = statics(jac, [100.0, 0, 0], [0, 0, 0], raise_on_singular=False)
    assert soft.equilibrium_residual > 0.1


def test_missing_constraints_is_a_constraint_singularity():
    """Three SPS legs leave the platform three freedoms no actuator controls."""
    legs, A, a, o = stewart()
    jac = unified_jacobian(legs[:3], o)
    assert jac.n_rows == 3 and jac.singularity_kind == "constraint"
    assert jac.condition_number == np.inf


def test_dependent_actuator_gives_a_zero_row():
    """A P actuator in series with a parallel passive P moves nothing: its actuation row is
    zero, it is a trivial self-stress (indeterminacy 1) and the least-norm effort is 0."""
    ls = parse_leg("P_PS")
    A, a = np.array([100.0, 0, 0]), np.array([40.0, 0, 80])
    d = (a - A) / np.linalg.norm(a - A)
    joints = [Joint(ls.equivalent[0], d, A), Joint(ls.equivalent[1], d, A)]
    joints += [Joint(s, ax, a) for s, ax in zip(ls.equivalent[2:], np.eye(3))]
    leg = Leg(ls, tuple(joints), A, a)
    legs, _, _, o = stewart()
    jac = unified_jacobian([leg] + legs[2:], o)          # 1 + 4 actuation rows, 2 forces
    assert np.all(jac.J[0] == 0) and jac.rows[0].kind == "actuation" and jac.rows[0].joint == "P2"
    assert jac.kinds[5:] == ("force", "force")
    assert (jac.n_rows, jac.rank, jac.indeterminacy) == (7, 6, 1) and not jac.singular
    res = statics(jac, F0, T0)
    assert abs(res.active[0]) < 1e-9 * np.abs(res.values).max() and res.equilibrium_residual < 1e-12


def test_threshold_is_honoured():
    legs, A, a, o = stewart()
    jac = unified_jacobian(legs, o)
    assert not jac.singular
    tight = unified_jacobian(legs, o, threshold=0.5 * jac.condition_number + 0.5)
    assert tight.singular
    with pytest.raises(SingularityError):
        statics(tight, F0, T0)


# ---------------------------------------------------------------------------
# bad input
# ---------------------------------------------------------------------------

def test_bad_input_raises_input_error():
    legs, A, a, o = stewart()
    with pytest.raises(InputError, match="platform centre"):
        unified_jacobian(legs, [0, np.nan, 80])
    with pytest.raises(InputError, match="at least one leg"):
        unified_jacobian([], o)
    with pytest.raises(InputError, match=r"legs\[1\]"):
        unified_jacobian([legs[0], "SPS"], o)
    with pytest.raises(InputError, match="analyses"):
        unified_jacobian(legs, o, analyses=[legs[0].analyze()])
    with pytest.raises(InputError, match=r"analyses\[0\]"):
        unified_jacobian(legs[:2], o, analyses=[legs[1].analyze(), legs[1].analyze()])
    jac = unified_jacobian(legs, o)
    with pytest.raises(InputError, match="force F"):
        statics(jac, [np.nan, 0, 0], T0)
    with pytest.raises(InputError, match="torque T"):
        statics(jac, F0, [0, 0])
    with pytest.raises(InputError, match="workload point"):
        statics(jac, F0, T0, [0, 0, np.inf])
    with pytest.raises(InputError, match="JacobianResult"):
        statics(jac.J, F0, T0)


def test_precomputed_analyses_are_used():
    legs, A, a, o = stewart()
    an = [leg.analyze() for leg in legs]
    r1 = solve_statics(legs, o, F0, T0, analyses=an)
    r2 = solve_statics(legs, o, F0, T0)
    np.testing.assert_allclose(r1.values, r2.values, rtol=1e-12)
    assert r1.jacobian.analyses[0] is an[0]
    assert "condition number" in r1.describe() and "actuation of P2" in r1.jacobian.describe()


def test_placed_legs_moved_with_their_frame_give_the_same_rows_and_statics():
    """3SPU+SP's legs at a regular pose, placed in Python: its SP leg's two constraint forces
    are picked by reference directions.  Moved by a rigid motion x -> R x + p and given
    ``frame=(R, p)``, every row is the original row moved as a wrench ([R f; R m + p x R f],
    a second derivation of the same rows), and the condition number and the efforts under
    the moved load are the same; without the frame the members change (documented)."""
    from scipy.spatial.transform import Rotation

    from screwkit.engine import solve_statics, unified_jacobian
    pm = screwkit.load_pm("3SPU+SP")
    sol = screwkit.analyze(pm, {k: pm.default_pose[k] for k in pm.independent}).solution
    legs, o = sol.legs, np.asarray(sol.position, float).reshape(3)
    R = Rotation.from_rotvec([0.3, -0.5, 0.7]).as_matrix()
    p = np.array([10.0, -20.0, 5.0])
    moved = [lg.moved(R, p) for lg in legs]
    J0 = np.asarray(unified_jacobian(legs, o).J).reshape(-1, 6)
    J1 = np.asarray(unified_jacobian(moved, R @ o + p, frame=(R, p)).J).reshape(-1, 6)
    f = J0[:, :3] @ R.T
    expect = np.hstack([f, J0[:, 3:] @ R.T + np.cross(p, f)])
    assert np.max(np.abs(J1 - expect)) <= 1e-12 * np.max(np.abs(J0))
    F, T = np.array([1.0, -2.0, -30.0]), np.array([5.0, 0.0, 2.0])
    s0 = solve_statics(legs, o, F, T)
    s1 = solve_statics(moved, R @ o + p, R @ F, R @ T, frame=(R, p))
    assert np.allclose(np.asarray(s1.values), np.asarray(s0.values), rtol=1e-10, atol=1e-12)
    c = [float(np.asarray(j.conditioning.condition_number).ravel()[0]) for j in
         (unified_jacobian(legs, o), unified_jacobian(moved, R @ o + p, frame=(R, p)),
          unified_jacobian(moved, R @ o + p))]
    assert c[1] == pytest.approx(c[0], rel=1e-12) and abs(c[2] / c[0] - 1) > 1e-4
    with pytest.raises(screwkit.InputError, match="rotation"):
        unified_jacobian(legs, o, frame=(2 * R, p))


def test_statics_refuses_leg_points_that_do_not_fit_its_legs():
    """base_points / platform_points of the wrong count reached the compiled leg wrenches
    (a heap corruption, the process killed); they, and workloads of mismatched shapes, are
    input errors now."""
    pm = screwkit.load_pm("3RPS")
    sol = screwkit.analyze(pm).solution
    legs, o = sol.legs, np.asarray(sol.position).reshape(3)
    jac = unified_jacobian(legs, o)
    A = np.array([lg.A for lg in legs])
    a = np.array([lg.a for lg in legs])
    F, T = [0.0, 0.0, -1.0], [0.0, 0.0, 0.0]
    for kw, piece in (({"base_points": [[0, 0, 0]]}, "without platform_points"),
                      ({"base_points": A[:2], "platform_points": a[None, :2]}, r"must be \(3, 3\)"),
                      ({"base_points": A, "platform_points": a[:2]}, "platform_points must be"),
                      ({"platform_points": a}, "without base_points")):
        with pytest.raises(InputError, match=piece):
            statics(jac, F, T, **kw)
    with pytest.raises(InputError, match="as many torques as forces"):
        statics(jac, np.zeros((2, 3)), np.zeros((3, 3)))
    good = statics(jac, F, T, base_points=A, platform_points=a)
    np.testing.assert_array_equal(np.asarray(good.T_r), np.asarray(statics(jac, F, T).T_r))
