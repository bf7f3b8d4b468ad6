"""Issue 22: the MJCF export, loaded by MuJoCo.

MuJoCo's own forward kinematics at keyframe 0 (the exported pose, solved by screwkit) and at
qpos0 (home) must close every loop (the weld sites coincide to 1e-9 m and in orientation) and
put the platform where screwkit solved it; the masses and inertias are compared with the
numbers of the model file converted by hand; every joint placement agrees with the URDF's."""

import json
import xml.etree.ElementTree as ET

import numpy as np
import pytest

import screwkit
from screwkit.cli import main
from screwkit.interop import urdf_text, write_mjcf

from delta import DELTA

mujoco = pytest.importorskip("mujoco", reason="MJCF checks need mujoco (screwkit[mujoco])")

STEWART = "tests/data/stewart_6sps.yaml"
CM = 0.01                 # the catalog's cm in m (written here, not read from screwkit)


def load(path):
    m = mujoco.MjModel.from_xml_path(str(path))
    return m, mujoco.MjData(m)


def loop_gaps(m, d, n_legs):
    """Largest position (m) and orientation gaps of the weld sites of legs 2..n."""
    dp = dr = 0.0
    for k in range(2, n_legs + 1):
        e, p = d.site(f"leg{k}_end"), d.site(f"platform_a{k}")
        dp = max(dp, float(np.abs(e.xpos - p.xpos).max()))
        dr = max(dr, float(np.abs(e.xmat - p.xmat).max()))
    return dp, dr


CASES = [("3RRPRR", {"alpha": 5, "beta": -3, "Zo": 80}),
         ("2SPS+2SPR", {"alpha": 4, "beta": 3, "gamma": 2, "Zo": 80}),
         ("3SPU+PRRR", {"Xo": 3, "Yo": -2, "Zo": 78, "gamma": 6}),
         ("4SPS+UPU", None)]


@pytest.mark.parametrize("name, pose", CASES)
def test_loops_close_in_mujoco(tmp_path, name, pose):
    pm = screwkit.load_pm(name)
    out = tmp_path / "pm.xml"
    info = write_mjcf(pm, out, pose=pose, degrees=True, massless=True)
    m, d = load(out)
    assert m.nkey == 1 and m.neq >= pm.n_legs - 1 and m.nu == pm.n_legs
    sol = screwkit.solve(pm, pose or {}, degrees=True)
    for key in (None, 0):                      # qpos0 (home), then keyframe 0 (the pose)
        if key is None:
            mujoco.mj_resetData(m, d)
        else:
            mujoco.mj_resetDataKeyframe(m, d, key)
        mujoco.mj_forward(m, d)
        dp, dr = loop_gaps(m, d, pm.n_legs)
        assert dp < 1e-9 and dr < 1e-9, (key, dp, dr)
    # MuJoCo's forward kinematics puts the platform where screwkit solved it
    np.testing.assert_allclose(d.body("platform").xpos, sol.position * CM, atol=1e-9)
    np.testing.assert_allclose(d.body("platform").xmat.reshape(3, 3), sol.rotation, atol=1e-9)
    # and the equality constraints are satisfied: MuJoCo's own residuals
    eq = d.efc_type == mujoco.mjtConstraint.mjCNSTR_EQUALITY
    assert np.abs(d.efc_pos[eq]).max() < 1e-9
    assert info["loops"] == pm.n_legs - 1


def test_parallelogram_legs_close(tmp_path):
    yaml = tmp_path / "delta.yaml"
    yaml.write_text(DELTA)
    pm = screwkit.load_pm(str(yaml))
    out = tmp_path / "delta.xml"
    write_mjcf(pm, out, pose={"Xo": 20.0, "Yo": -10.0, "Zo": -170.0}, massless=True)
    m, d = load(out)
    mujoco.mj_resetDataKeyframe(m, d, 0)
    mujoco.mj_forward(m, d)
    dp, dr = loop_gaps(m, d, 3)
    assert dp < 1e-9 and dr < 1e-9
    np.testing.assert_allclose(d.body("platform").xpos, [0.020, -0.010, -0.170], atol=1e-9)
    np.testing.assert_allclose(d.body("platform").xmat.reshape(3, 3), np.eye(3), atol=1e-9)


def test_masses_and_inertias_in_si(tmp_path):
    pm = screwkit.load_pm(STEWART)
    out = tmp_path / "s.xml"
    write_mjcf(pm, out)
    m, d = load(out)
    # the model file: platform 30 kg, a disc of radius 30 cm and thickness 4 cm about its com
    # at (0, 0, 2) cm of {o}; standard gravity
    b = m.body("platform")
    assert b.mass[0] == pytest.approx(30.0, rel=1e-12)
    r, h = 0.30, 0.04
    expect = sorted([30 * (3 * r ** 2 + h ** 2) / 12] * 2 + [30 * r ** 2 / 2])
    assert sorted(b.inertia) == pytest.approx(expect, rel=1e-9)
    assert b.ipos == pytest.approx([0, 0, 0.02], abs=1e-12)
    np.testing.assert_allclose(m.opt.gravity, [0, 0, -9.80665], rtol=1e-12)
    params = pm.dynamics
    kg = 1e5                                # the catalog's kN.s^2/cm in kg
    total = params.total_mass() * kg
    assert float(np.sum(m.body_mass)) == pytest.approx(total, abs=1e-4)   # + bound masses
    mujoco.mj_resetDataKeyframe(m, d, 0)
    mujoco.mj_forward(m, d)
    assert loop_gaps(m, d, pm.n_legs)[0] < 1e-9


def _urdf_joints(text):
    """World position and axis of every URDF joint at home (rpy 0: pure translations)."""
    root = ET.fromstring(text)
    parent_of, origin, axis = {}, {}, {}
    for j in root.iter("joint"):
        parent_of[j.find("child").get("link")] = (j.find("parent").get("link"), j.get("name"))
        origin[j.get("name")] = np.array(j.find("origin").get("xyz").split(), float)
        ax = j.find("axis")
        axis[j.get("name")] = None if ax is None else np.array(ax.get("xyz").split(), float)
    link_of = {name: child for child, (_, name) in parent_of.items()}
    out = {}
    for name in origin:
        p, link = np.zeros(3), link_of[name]
        while link in parent_of:
            parent, jn = parent_of[link]
            p = p + origin[jn]
            link = parent
        out[name] = (p, axis[name])
    return out


@pytest.mark.parametrize("name", ["3RRPRR", "2SPS+2SPR", "3SPU+PRRR"])
def test_urdf_and_mjcf_agree_on_every_joint(tmp_path, name):
    pm = screwkit.load_pm(name)
    urdf = _urdf_joints(urdf_text(pm))
    out = tmp_path / "pm.xml"
    write_mjcf(pm, out, massless=True)
    m, d = load(out)
    mujoco.mj_resetData(m, d)
    mujoco.mj_forward(m, d)
    mj = {m.joint(k).name: k for k in range(m.njnt)}
    # the URDF is in the model's length unit or in metres: one factor for every joint
    first = next(n for n in urdf if n in mj and urdf[n][1] is not None and
                 np.linalg.norm(urdf[n][0]) > 0)
    factor = np.linalg.norm(d.xanchor[mj[first]]) / np.linalg.norm(urdf[first][0])
    assert factor == pytest.approx(CM) or factor == pytest.approx(1.0)
    checked = 0
    for jn, (p, a) in urdf.items():
        if a is None:                          # the fixed platform joint
            continue
        ball = jn[:-1] if jn[:-1] in mj and m.joint(jn[:-1]).type == mujoco.mjtJoint.mjJNT_BALL \
            else None
        k = mj[ball or jn]
        np.testing.assert_allclose(d.xanchor[k], p * factor, atol=1e-12, err_msg=jn)
        if ball is None:
            np.testing.assert_allclose(d.xaxis[k], a, atol=1e-12, err_msg=jn)
        checked += 1
    assert checked == sum(len(lg.joints) for lg in pm.home_legs)


def test_cli_export_mjcf(tmp_path, capsys):
    out = tmp_path / "pm.xml"
    rc = main(["export", "3RRPRR", "--mjcf", str(out), "--pose", "alpha=5", "--massless",
               "--json"])
    assert rc == 0
    info = json.loads(capsys.readouterr().out)["mjcf"]
    assert info["loops"] == 2 and info["actuators"] == 3 and info["pose"]["alpha"] == 5.0
    m, _ = load(out)
    assert [m.actuator(k).name for k in range(m.nu)] == ["F_a1", "F_a2", "F_a3"]


def test_cli_export_mjcf_needs_masses(tmp_path, capsys):
    rc = main(["export", "3RRPRR", "--mjcf", str(tmp_path / "pm.xml")])
    err = capsys.readouterr().err
    assert rc == 2 and len(err.strip().splitlines()) == 1
    assert "--mass FILE" in err and "--massless" in err
    rc = main(["export", "3RRPRR", "--pose", "alpha=5", "--urdf", str(tmp_path / "pm.urdf")])
    assert rc == 2 and "options of --mjcf" in capsys.readouterr().err
    # both asked for, the MJCF failing: nothing written (not a URDF without its MJCF)
    rc = main(["export", "3RRPRR", "--urdf", str(tmp_path / "both.urdf"), "--mjcf",
               str(tmp_path / "both.xml")])
    assert rc == 2 and "--massless" in capsys.readouterr().err
    assert sorted(p.name for p in tmp_path.iterdir()) == []


from tricept import TRICEPT  # noqa: E402


def test_passive_leg_has_no_motor(tmp_path):
    """A passive leg (the Tricept's column) closes its loop and drives nothing."""
    (tmp_path / "tricept.yaml").write_text(TRICEPT)
    pm = screwkit.load_pm(str(tmp_path / "tricept.yaml"))
    out = tmp_path / "t.xml"
    write_mjcf(pm, out, pose={"alpha": 3, "beta": 2, "Zo": 640}, degrees=True, massless=True)
    m, d = load(out)
    assert [m.actuator(k).name for k in range(m.nu)] == ["F_a1", "F_a2", "F_a3"]
    mujoco.mj_resetDataKeyframe(m, d, 0)
    mujoco.mj_forward(m, d)
    assert loop_gaps(m, d, 4)[0] < 1e-9
    sol = screwkit.solve(pm, {"alpha": 3, "beta": 2, "Zo": 640}, degrees=True)
    np.testing.assert_allclose(d.body("platform").xpos, sol.position * 1e-3, atol=1e-9)
