"""Interop: ``screwkit export PM --urdf``, :func:`screwkit.to_pinocchio`, ``res.to_frame()``
and ``_repr_html_``.

The URDF is read back by Pinocchio's own URDF parser (independent of screwkit's writer);
the loop closures of the sidecar, built into ``RigidConstraintModel`` objects by the
documented lines, must hold at a pose screwkit solved, and the platform frame must sit at
the solved platform pose.  The paper's actuator forces (F_a1 = 19.3572 kN, ...) are the
reference values of the tables.
"""

from __future__ import annotations

import json

import numpy as np
import pytest

import screwkit
from screwkit.cli import main

pin = pytest.importorskip("pinocchio")


def _constraints(model, loops):
    # the lines of docs/pinocchio.md
    def se3(p):
        return pin.SE3(np.array(p["rotation"]), np.array(p["translation"]))
    def kind(c):
        return getattr(pin.ContactType, c.get("contact_type", loops["contact_type"]))
    return [pin.RigidConstraintModel(kind(c), model,
                                     model.getJointId(c["joint1"]), se3(c["placement1"]),
                                     model.getJointId(c["joint2"]), se3(c["placement2"]),
                                     pin.ReferenceFrame.LOCAL) for c in loops["constraints"]]


def _closure_gaps(model, cons, q):
    data = model.createData()
    pin.framesForwardKinematics(model, data, q)
    gaps = [np.linalg.norm(pin.log6((data.oMi[c.joint1_id] * c.joint1_placement).inverse()
                                    * (data.oMi[c.joint2_id] * c.joint2_placement)).vector)
            for c in cons]
    return gaps, data


@pytest.mark.parametrize("name, pose", [("3RRPRR", {"alpha": 5, "beta": -3, "Zo": 80}),
                                        ("2SPS+2SPR", {"alpha": 4, "beta": 3, "gamma": 2,
                                                       "Zo": 80})])
def test_urdf_loads_in_pinocchio_and_closes_at_a_solved_pose(name, pose, tmp_path, capsys):
    out = tmp_path / "new" / "pm.urdf"                     # the folder is created
    assert main(["export", name, "--urdf", str(out)]) == 0
    assert "wrote" in capsys.readouterr().out
    side = out.with_name("pm.closures.json")
    model = pin.buildModelFromUrdf(str(out))
    loops = json.loads(side.read_text(encoding="utf-8"))
    pm = screwkit.load_pm(name)
    m = 0.01                                             # URDF is in metres: the model's cm
    assert loops["units"]["length"] == "m"
    assert model.nq == model.nv == sum(len(lg.joints) for lg in pm.home_legs)
    assert len(loops["constraints"]) == pm.n_legs - 1
    cons = _constraints(model, loops)
    # home (q = 0): every loop closed
    gaps, _ = _closure_gaps(model, cons, pin.neutral(model))
    assert max(gaps) < 1e-9 * pm.normalisation.length * m
    # a pose solved by screwkit: joint values by name -> closed loops, platform at the pose
    sol = screwkit.solve(pm, pose, degrees=True)
    q = pin.neutral(model)
    for k, (leg, jv) in enumerate(zip(pm.home_legs, sol.joint_values)):
        for j, v in zip(leg.joints, np.asarray(jv).reshape(-1)):
            q[model.joints[model.getJointId(f"leg{k + 1}_{j.name}")].idx_q] = \
                v * (m if j.kind == "P" else 1.0)
    gaps, data = _closure_gaps(model, cons, q)
    assert max(gaps) < 1e-8 * pm.normalisation.length * m, gaps
    F = data.oMf[model.getFrameId("platform")]
    assert np.allclose(F.rotation, sol.rotation, atol=1e-10)
    assert np.allclose(F.translation, np.asarray(sol.position).reshape(3) * m,
                       atol=1e-9 * pm.normalisation.length * m)
    # moving one actuated joint alone opens a loop (the closures really constrain)
    q2 = q.copy()
    q2[model.joints[model.getJointId(loops["actuated_joints"][1])].idx_q] += 1.0
    assert max(_closure_gaps(model, cons, q2)[0]) > 0.1


def test_urdf_has_visual_geometry_and_named_joints(tmp_path):
    import xml.etree.ElementTree as ET
    pm = screwkit.load_pm("3RPS")
    from screwkit.interop import urdf_text
    root = ET.fromstring(urdf_text(pm))
    links = {ln.get("name"): ln for ln in root.iter("link")}
    assert {"base", "platform"} <= set(links)
    assert len(root.findall(".//visual/geometry/cylinder")) >= 2 * pm.n_legs
    assert root.findall(".//visual/geometry/sphere")                     # S centres
    kinds = {j.get("type") for j in root.iter("joint")}
    assert kinds == {"revolute", "prismatic", "fixed"}


def test_to_pinocchio_returns_model_and_constraint_models():
    pm = screwkit.load_pm("3RRPRR")
    clm = screwkit.to_pinocchio(pm)
    assert isinstance(clm.model, pin.Model)
    assert len(clm.constraints) == 2
    assert all(isinstance(c, pin.RigidConstraintModel) for c in clm.constraints)
    sol = screwkit.solve(pm, {"alpha": 5, "beta": -3, "Zo": 80}, degrees=True)
    q = clm.q([np.asarray(v).reshape(-1) for v in sol.joint_values])
    data = clm.model.createData()
    pin.framesForwardKinematics(clm.model, data, q)
    for c in clm.constraints:
        M1 = data.oMi[c.joint1_id] * c.joint1_placement
        M2 = data.oMi[c.joint2_id] * c.joint2_placement
        assert np.linalg.norm(pin.log6(M1.inverse() * M2).vector) < 1e-9 * pm.normalisation.length


def test_to_frame_long_format_and_html():
    pd = pytest.importorskip("pandas")
    res = screwkit.analyze("3RRPRR", pose={"alpha": [5, 0], "beta": [-3, 0], "Zo": [80, 80]},
                           degrees=True)
    df = res.to_frame()
    assert list(df.columns) == ["pose", "quantity", "leg", "kind", "value", "unit", "ok", "level"]
    one = df[(df.pose == 0) & (df.kind == "actuation")].set_index("quantity")
    # the paper's values at alpha = 5, beta = -3 deg, Zo = 80 cm (section 5.1)
    assert one.loc["F_a1", "value"] == pytest.approx(19.3572, abs=5e-4)
    assert one.loc["F_a3", "value"] == pytest.approx(52.8076, abs=5e-4)
    assert set(one["unit"]) == {"kN"} and list(one["leg"]) == [1, 2, 3]
    assert df[(df.pose == 0) & (df.quantity == "alpha")]["value"].item() == pytest.approx(5)
    assert df[df.quantity == "Zo"]["unit"].unique().tolist() == ["cm"]
    wide = df.pivot(index="pose", columns="quantity", values="value")
    assert wide.shape[0] == 2 and "condition_number" in wide
    assert isinstance(df["leg"].dtype, pd.Int64Dtype)
    html = res._repr_html_()
    assert "<table>" in html and "19.3572" in html and "2 poses" in html
    html1 = res[0]._repr_html_()
    assert "F_a1" in html1 and "kN" in html1 and "19.3572" in html1


def test_urdf_joints_allow_effort_and_motion(tmp_path):
    """Every URDF joint had ``effort="0" velocity="0"``: Pinocchio read effort and velocity
    limits of 0, no actuation allowed by any tool that applies them. The model has no such
    limits: the URDF says so and writes 1e12."""
    pin = pytest.importorskip("pinocchio")
    from screwkit.interop import urdf_text
    path = tmp_path / "m.urdf"
    path.write_text(urdf_text(screwkit.load_pm("3RRPRR")), encoding="utf-8")
    model = pin.buildModelFromUrdf(str(path))
    assert model.nv > 0
    assert np.all(np.asarray(model.effortLimit) >= 1e12)
    assert np.all(np.asarray(model.velocityLimit) >= 1e12)
    assert "effort and velocity limits are not part of the model" in path.read_text()
