"""Pinocchio cross-check of assembled PMs (issue 4): every catalog PM at 10 regular poses,
a user-defined YAML model, and deliberately corrupted screwkit results.

Pinocchio is the independent second method: its native joints (spherical with quaternions,
universal, unaligned revolute / prismatic / helical) placed from screwkit's home geometry,
its forward kinematics and frame Jacobians, and its loop-closure constraint Jacobian.
"""

import dataclasses
from pathlib import Path

import numpy as np
import pytest

# the paper's workload, stated (only 3RRPRR and 2SPS+2SPR declare it as their default)
PAPER_LOAD = {"force": (-20.0, -30.0, -60.0), "torque": (-30.0, -30.0, 100.0)}
PAPER_ARGS = ["--force=-20,-30,-60", "--torque=-30,-30,100"]

pin = pytest.importorskip("pinocchio")

from screwkit.engine import analyze_pm  # noqa: E402
from screwkit.errors import GeometryError, InputError  # noqa: E402
from screwkit.interop import (CHECK_RTOL, PMChecker, SUMMARY_CHECKS,  # noqa: E402
                              build_closed_loop_model, check_all, check_analysis, check_pm,
                              constraint_jacobian, mobility, regular_analyses)
from screwkit.pm import load_pm, pm_names  # noqa: E402

USER_PM = str(Path(__file__).parent / "data" / "user_pm.yaml")
ALL_CHECKS = tuple(k for k, _ in SUMMARY_CHECKS)
N_POSES = 10


def _assert_clean(rep):
    assert rep.passed, str(rep)
    assert tuple(r.name for r in rep.rows) == ALL_CHECKS        # every check ran
    for r in rep.rows:
        assert r.deviation < CHECK_RTOL, str(rep)
    assert max(r.deviation for r in rep.detail.rows) < CHECK_RTOL


def _check_regular_poses(model):
    checker = PMChecker.for_model(model)                       # built once, reused at every pose
    analyses = regular_analyses(model, N_POSES, seed=0)
    assert len(analyses) == N_POSES
    for a in analyses:
        rep = check_analysis(a, checker)
        _assert_clean(rep)
        # Pinocchio's closed loop has the DOF the PM definition states, and it is screwkit's
        assert rep.detail.value("dof") == model.stated_dof == a.mobility.dof
        assert rep.detail.value("locked_dof") == 0
        assert rep.detail.value("internal") == a.mobility.idle


@pytest.mark.parametrize("name", pm_names())
def test_catalog_pm_at_regular_poses(name):
    _check_regular_poses(load_pm(name))


def test_user_defined_yaml_model():
    model = load_pm(USER_PM)
    assert model.name == "3RHS/user" and model.legs == ("RHS/user",) * 3
    # the user's leg brings a helical joint (unaligned, pitch 0.02 leg lengths per radian)
    checker = PMChecker.for_model(model)
    kinds = [b.kind for b in checker.leg_models[0].chain.blocks]
    assert kinds == ["revolute", "helical", "spherical"]
    h = model.home_legs[0].joint("H2")
    assert h.pitch == pytest.approx(0.02 * model.home_legs[0].length)
    _check_regular_poses(model)


def test_regular_poses_are_drawn_as_specified():
    model = load_pm("3UPU")                          # lengths only: Xo, Yo, Zo
    a1 = regular_analyses(model, 4, seed=3)
    a2 = regular_analyses(model, 4, seed=3)
    a3 = regular_analyses(model, 4, seed=4)
    p1 = [a.solution.params for a in a1]
    assert p1 == [a.solution.params for a in a2]
    assert p1 != [a.solution.params for a in a3]
    c = model.default_pose
    for p in p1:
        for k in model.independent:
            assert abs(p[k] - c[k]) <= 0.08 * abs(c["Zo"])
    model = load_pm("3SPR")                          # angles within +-8 deg
    for a in regular_analyses(model, 4, seed=1):
        p = a.solution.params
        assert abs(p["alpha"] - model.default_pose["alpha"]) <= np.radians(8)
        assert abs(p["beta"] - model.default_pose["beta"]) <= np.radians(8)
    with pytest.raises(GeometryError):
        regular_analyses(model, 3, max_draws=2)
    with pytest.raises(InputError):
        regular_analyses(model, 0)


# ---------------------------------------------------------------- model variants
def test_point_contacts_and_6d_closures_give_the_same_mobility():
    """S-ended legs: a 3-D point contact at the S centre (S dropped) or the S kept with a
    6-D closure; the two Pinocchio models must agree on the platform motion."""
    for name in ("4SPS+SPR", "3RPS", "2SPS+2SPR"):
        model = load_pm(name)
        a = analyze_pm(model, **PAPER_LOAD)
        sol = a.solution
        m3 = mobility(build_closed_loop_model(model.home_legs, model.platform_home, point_contacts=True),
                      sol.joint_values, sol.legs)
        m6 = mobility(build_closed_loop_model(model.home_legs, model.platform_home), sol.joint_values,
                      sol.legs)
        n_s_ended = sum(lg.string.text.endswith("S") for lg in model.home_legs)
        carrier_keeps_s = all(lg.string.text.endswith("S") for lg in model.home_legs)
        dropped = n_s_ended - carrier_keeps_s
        assert m6.nv - m3.nv == 3 * dropped and m6.rank - m3.rank == 3 * dropped
        assert m3.dof == m6.dof == a.mobility.dof == model.stated_dof
        assert m3.internal == m6.internal == a.mobility.idle
        assert m3.locked_dof == m6.locked_dof == 0
        L = model.normalisation
        from screwkit.screws import same_span
        assert same_span(m3.twists, m6.twists, L) and same_span(m3.twists, a.mobility.twists, L)


def test_point_contact_jacobian_is_the_relative_point_velocity():
    model = load_pm("3RPS")
    clm = build_closed_loop_model(model.home_legs, model.platform_home, point_contacts=True)
    assert [cm.type for cm in clm.constraints] == [pin.ContactType.CONTACT_3D] * 2
    assert clm.carrier == 0 and clm.constraint_legs == (1, 2)
    rng = np.random.default_rng(1)
    qs = [rng.uniform(-0.3, 0.3, len(lg.joints)) for lg in model.home_legs]   # need not be closed
    data = clm.model.createData()
    qp = clm.q(qs)
    Jc = constraint_jacobian(clm, data, qp)
    pin.framesForwardKinematics(clm.model, data, qp)
    for k, (cm, leg) in enumerate(zip(clm.constraints, clm.constraint_legs)):
        ch = clm.chains[leg]
        # the S centre on the leg (frame 'contact') and the same platform point on the carrier
        J1 = pin.getFrameJacobian(clm.model, data, ch.frame_id, pin.LOCAL_WORLD_ALIGNED)[:3]
        fid = clm.model.addFrame(pin.Frame(f"probe{k}", cm.joint2_id, cm.joint2_placement,
                                           pin.FrameType.OP_FRAME))
        d2 = clm.model.createData()
        pin.computeJointJacobians(clm.model, d2, qp)
        pin.updateFramePlacements(clm.model, d2)
        J2 = pin.getFrameJacobian(clm.model, d2, fid, pin.LOCAL_WORLD_ALIGNED)[:3]
        R1 = d2.oMf[ch.frame_id].rotation
        assert np.allclose(Jc[3 * k:3 * k + 3], R1.T @ (J1 - J2), atol=1e-9)


# ---------------------------------------------------------------- corrupted screwkit results
@pytest.fixture(scope="module")
def spr():
    model = load_pm("3SPR")
    a = analyze_pm(model, {"alpha": 4.0, "beta": -2.0, "Zo": 63.0}, degrees=True, **PAPER_LOAD)
    return a, PMChecker.for_model(model)


class _Patched:
    """``obj`` with some attributes replaced (results are immutable; the checks read
    attributes only)."""

    def __init__(self, obj, **changes):
        self._obj, self._changes = obj, changes

    def __getattr__(self, name):
        if name in self._changes:
            return self._changes[name]
        return getattr(self._obj, name)


def _with_statics(a, **changes):
    if "values" in changes:          # the active forces are the first n values
        n = a.jacobian.n_actuated
        changes.update(active=changes["values"][:n], constraint=changes["values"][n:])
    return _Patched(a, statics=_Patched(a.statics, **changes))


def test_uncorrupted_result_passes(spr):
    a, checker = spr
    _assert_clean(check_analysis(a, checker))


@pytest.mark.parametrize("name", ["3SPR", "3RRPRR", "2SPS+2SPR", "3RPS"])
def test_constraint_force_moved_off_its_line_is_caught(name):
    a = analyze_pm(name, **PAPER_LOAD)
    st, jac = a.statics, a.jacobian
    k = next(r for r, row in enumerate(jac.rows) if row.kind == "force")
    leg = jac.rows[k].leg
    f = st.row_wrenches[k][:3]
    L = a.model.normalisation.length
    d = np.cross(f, [0.3, -0.2, 0.9])
    d *= 0.01 * L / np.linalg.norm(d)                 # the line moved by 1 % of the PM's size
    W = np.array(st.leg_wrenches)
    W[leg, 3:] += np.cross(d, f)
    rep = check_analysis(_with_statics(a, leg_wrenches=W))
    assert rep.failed == ("statics.passive",)
    assert rep.detail.failed == (f"leg{leg + 1}.statics.passive",)
    assert rep.row("statics.passive").deviation > 1e-4


def test_wrong_actuator_force_is_caught(spr):
    a, checker = spr
    vals = np.array(a.statics.values)
    vals[1] *= 1.01                                   # leg 2's active force, leg wrench unchanged
    rep = check_analysis(_with_statics(a, values=vals), checker)
    assert rep.failed == ("statics.actuator", "statics.work")
    assert rep.detail.failed == ("leg2.statics.actuator", "statics.work")


def test_consistent_but_unbalanced_actuator_force_is_caught_by_virtual_work(spr):
    """Scale leg 2's active force and its actuation wrench together: every leg still
    looks right on its own, but the platform is no longer in equilibrium."""
    a, checker = spr
    st = a.statics
    vals = np.array(st.values)
    W = np.array(st.leg_wrenches)
    W[1] += 0.01 * st.row_wrenches[1]                 # row 1 = leg 2's actuation row
    vals[1] *= 1.01
    rep = check_analysis(_with_statics(a, values=vals, leg_wrenches=W), checker)
    assert rep.failed == ("statics.work",)


def test_wrong_mobility_and_twist_space_are_caught(spr):
    a, checker = spr
    m = a.mobility
    rep = check_analysis(_Patched(a, mobility=dataclasses.replace(m, dof=m.dof + 1)), checker)
    assert rep.failed == ("mobility",)
    T = np.array(m.twists)
    T[0] = T[0] + 1e-6 * np.linalg.norm(T[0]) * np.r_[0, 0, 0, 1.0, 0, 0]
    rep = check_analysis(_Patched(a, mobility=dataclasses.replace(m, twists=T)), checker)
    assert rep.failed == ("mobility.twists",)


def test_wrong_joint_value_and_wrong_pose_are_caught(spr):
    a, checker = spr
    sol = a.solution
    qs = [np.array(q) for q in sol.joint_values]
    qs[2][3] += 1e-6                                  # leg 3's P: the loop no longer closes
    bad = _Patched(a, solution=_Patched(sol, joint_values=tuple(qs)))
    rep = check_analysis(bad, checker)
    assert "closure" in rep.failed
    assert {"leg3.closure.position", "loop.closure"} <= set(rep.detail.failed)
    moved = _Patched(sol, position=sol.position + [0, 0, 1e-5])
    rep = check_analysis(_Patched(a, solution=moved), checker)
    assert rep.failed == ("closure",)


def test_check_pm_accepts_a_solution_and_its_statics(spr):
    a, checker = spr
    rep = check_pm(a.solution, a.statics, checker=checker)
    assert rep.passed, str(rep)
    names = {r.name for r in rep.rows}
    assert {"mobility", "mobility.locked", "statics.work", "loop.closure"} <= names
    assert "mobility.twists" not in names             # no screwkit mobility given
    with pytest.raises(InputError):
        check_analysis(a.solution)


def test_check_all_reports_every_pm_and_errors():
    reps = check_all(1, names=["3SPR", "NOPE", load_pm(USER_PM)])
    assert [r.pm for r in reps] == ["3SPR", "NOPE", "3RHS/user"]
    assert reps[0].passed and reps[2].passed
    assert not reps[1].passed and "unknown PM" in reps[1].error and reps[1].rows == ()
    d = reps[0].as_dict()
    assert d["pm"] == "3SPR" and [r["check"] for r in d["rows"]] == list(ALL_CHECKS)


def test_singular_and_unreachable_draws_are_skipped(monkeypatch):
    import screwkit.engine as pa
    from screwkit.errors import SingularityError, UnreachablePoseError

    real, calls = pa.analyze_pm, []

    def flaky(model, pose, **kw):
        calls.append(dict(pose))
        k = len(calls)
        if k % 3 == 1:
            raise SingularityError("test: singular", kind="actuation")
        if k % 3 == 2:
            raise UnreachablePoseError("test: unreachable", residual=1.0)
        return real(model, pose, **kw)

    monkeypatch.setattr(pa, "analyze_pm", flaky)
    got = regular_analyses("3SPR", 3, seed=2)
    assert len(got) == 3 and len(calls) == 9
    # the kept ones are the 3rd, 6th and 9th draws
    for a, pose in zip(got, calls[2::3]):
        assert all(a.solution.params[k] == pytest.approx(v) for k, v in pose.items())
