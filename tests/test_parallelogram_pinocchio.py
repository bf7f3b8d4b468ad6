"""The Delta-type 3-RRPaR through Pinocchio: the parallelogram as its real four-bar.

Pinocchio's model (:func:`screwkit.interop.build_closed_loop_model`) has, per Pa, the first
bar, the far link turning back with it and the second bar, whose end is tied to the far
link by a point contact; it is built from screwkit's home geometry only.  At regular poses
screwkit solved, Pinocchio's forward kinematics closes every loop (the legs on the platform
and the parallelograms), its frame Jacobians give screwkit's joint twists (the Pa's a
translation), the mobility from its constraint Jacobian is screwkit's (3 translations, no
internal motion, none left with the actuators locked), and each leg's wrench does no work
on its passive joints (virtual work on the closed loop).  The URDF export writes the same
four-bars, which Pinocchio's URDF parser reads back and closes at a solved pose.
"""

import json

import numpy as np
import pytest

import screwkit

pin = pytest.importorskip("pinocchio")

from screwkit.interop import (CHECK_RTOL, PMChecker, SUMMARY_CHECKS,  # noqa: E402
                              check_analysis, regular_analyses)

DELTA = """\
units: {length: mm, force: N}
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
    euler: xyz
    dof: 3
    motion: 3T
"""


@pytest.fixture(scope="module")
def delta(tmp_path_factory):
    p = tmp_path_factory.mktemp("delta") / "delta.yaml"
    p.write_text(DELTA)
    return screwkit.load_pm(str(p))


def test_the_delta_passes_the_pinocchio_check(delta):
    checker = PMChecker.for_model(delta)
    clm = checker.closed
    # 3 legs x (R1, R2, the Pa's bar, far link and second bar, R3) = 18 columns; 2 legs on
    # the platform (6-D) and 3 parallelogram loops (3-D)
    assert clm.model.nv == 18
    kinds = sorted(c.residualSize() for c in clm.constraints)
    assert kinds == [3, 3, 3, 6, 6]
    for a in regular_analyses(delta, 6, seed=1):
        rep = check_analysis(a, checker)
        assert rep.passed, str(rep)
        assert tuple(r.name for r in rep.rows) == tuple(k for k, _ in SUMMARY_CHECKS)
        assert max(r.deviation for r in rep.detail.rows) < CHECK_RTOL
        assert rep.detail.value("dof") == 3 == a.mobility.dof
        assert rep.detail.value("locked_dof") == 0 and rep.detail.value("internal") == 0


def test_the_point_contacts_close_the_second_bars(delta):
    """Without the parallelograms' point contacts each second bar turns freely (three more
    motions of the loop); with them the closed loop has the platform's 3 DOF only."""
    checker = PMChecker.for_model(delta)
    clm = checker.closed
    model, data = clm.model, clm.model.createData()
    a = regular_analyses(delta, 1, seed=2)[0]
    q = clm.q([np.asarray(v) for v in a.solution.joint_values])
    from screwkit.interop import constraint_jacobian
    Jc = constraint_jacobian(clm, data, q)
    rows = [k for k, c in enumerate(clm.constraints) for _ in range(c.residualSize())]
    keep = [i for i, k in enumerate(rows) if clm.constraints[k].residualSize() == 6]
    full = np.linalg.matrix_rank(Jc, tol=1e-9 * np.abs(Jc).max())
    welds = np.linalg.matrix_rank(Jc[keep], tol=1e-9 * np.abs(Jc).max())
    assert model.nv - full == 3 + 0           # the platform's 3 translations
    assert model.nv - welds == 3 + 3          # + the three second bars, free without loops
    assert full - welds == 3                  # each contact fixes its second bar


def test_the_urdf_writes_the_four_bars(delta, tmp_path):
    from screwkit.interop import write_urdf
    urdf, side = write_urdf(delta, tmp_path / "delta.urdf")
    model = pin.buildModelFromUrdf(urdf)
    loops = json.loads(open(side).read())
    assert model.nq == 18
    pa = [c for c in loops["constraints"] if c.get("contact_type") == "CONTACT_3D"]
    assert [c["joint1"] for c in pa] == ["leg1_Pa3_twin", "leg2_Pa3_twin", "leg3_Pa3_twin"]
    assert loops["actuated_joints"] == ["leg1_R1", "leg2_R1", "leg3_R1"]
    text = open(urdf).read()
    assert text.count("<mimic") == 6 and 'multiplier="-1"' in text

    def se3(p):
        return pin.SE3(np.array(p["rotation"]), np.array(p["translation"]))
    cons = [pin.RigidConstraintModel(getattr(pin.ContactType, c.get("contact_type",
                                                                    loops["contact_type"])),
                                     model, model.getJointId(c["joint1"]), se3(c["placement1"]),
                                     model.getJointId(c["joint2"]), se3(c["placement2"]),
                                     pin.ReferenceFrame.LOCAL) for c in loops["constraints"]]
    sol = screwkit.solve(delta, {"Xo": 20.0, "Yo": -10.0, "Zo": -170.0})
    q = pin.neutral(model)
    for k, (leg, jv) in enumerate(zip(delta.home_legs, sol.joint_values)):
        for j, v in zip(leg.joints, np.asarray(jv)):
            if j.spec.parallelogram:         # the arc length: the bars turn by s / |b|
                th = v / np.linalg.norm(j.bar)
                for suffix, f in (("_bar", 1.0), ("_far", -1.0), ("_twin", 1.0)):
                    q[model.joints[model.getJointId(f"leg{k + 1}_{j.name}{suffix}")].idx_q] = f * th
            else:
                q[model.joints[model.getJointId(f"leg{k + 1}_{j.name}")].idx_q] = v
    data = model.createData()
    pin.framesForwardKinematics(model, data, q)
    m = {"mm": 1e-3, "cm": 1e-2, "m": 1.0}[delta.units.length]     # URDF is in metres
    for c in cons:
        M1 = data.oMi[c.joint1_id] * c.joint1_placement
        M2 = data.oMi[c.joint2_id] * c.joint2_placement
        assert np.linalg.norm(M1.translation - M2.translation) < 1e-9 * 100 * m
        if c.type == pin.ContactType.CONTACT_6D:
            assert np.linalg.norm(pin.log3(M1.rotation.T @ M2.rotation)) < 1e-10
    F = data.oMf[model.getFrameId("platform")]
    assert np.allclose(F.rotation, np.eye(3), atol=1e-10)
    assert np.allclose(F.translation, sol.position * m, atol=1e-8 * m)
