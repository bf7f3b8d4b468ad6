"""PMs built in Python: PMBuilder, one PM's mapping, models written back and read again.

The reference is a 3-RPS of non-catalog dimensions (base radius 70, platform radius 25 mm,
home height 60 mm, N): built in memory, written as a YAML file by hand, and derived by hand.

Hand derivation (RPS: R at A_i along the tangent t_i of the base circle, P along the leg,
S at a_i).  The leg stays in the plane through A_i normal to t_i, so at a pose
(alpha, beta, Zo) the dependent Xo, Yo, gamma solve (a_i - A_i) . t_i = 0, i = 1..3
(solved here by Newton's method on these three equations).  Its rows: the actuation row
is the unit force along the leg through A_i (the R and the S are anchored at the leg's
two ends), [u_i; A_i x u_i] with u_i = (a_i - A_i) / |a_i - A_i|; the constraint row is
the unit force through the S centre along the R axis, [t_i; a_i x t_i] (up to its sign).
Statics: J^T F = -W with W = [F; T + o x F], J the 6 x 6 of these rows.
"""

import numpy as np
import pytest
import yaml

import screwkit
from screwkit import PMBuilder
from screwkit.errors import CatalogError, InputError

R_BASE, R_PLAT, H = 70.0, 25.0, 60.0
ANGLES = np.radians([90.0, 210.0, 330.0])

YAML_3RPS = f"""\
pms:
  my3RPS:
    string: 3RPS
    units: {{length: mm, force: N}}
    dimensions: {{R: {R_BASE}, r: {R_PLAT}}}
    base: {{shape: circle, radius: R, angles: [90, 210, 330]}}
    platform: {{shape: circle, radius: r, angles: [90, 210, 330]}}
    legs: [RPS, RPS, RPS]
    euler: XYZ
    independent: [alpha, beta, Zo]
    home: {{alpha: 0, beta: 0, Zo: {H}}}
    pose: {{alpha: 0, beta: 0, Zo: {H}}}
    dof: 3
"""


def _radial(r):
    return [r * np.array([np.cos(t), np.sin(t), 0.0]) for t in ANGLES]


def _builder():
    b = PMBuilder("my3RPS", units={"length": "mm", "force": "N"})
    for A, a in zip(_radial(R_BASE), _radial(R_PLAT)):
        b.add_leg("RPS", base=A, platform=a)
    return b.set_pose(["alpha", "beta", "Zo"], home={"alpha": 0, "beta": 0, "Zo": H})


@pytest.fixture(scope="module")
def built():
    return screwkit.load_pm(_builder())


@pytest.fixture(scope="module")
def from_yaml(tmp_path_factory):
    p = tmp_path_factory.mktemp("build") / "my3rps.yaml"
    p.write_text(YAML_3RPS)
    return screwkit.load_pm(str(p))


def _rot(a, b, g):
    ca, sa, cb, sb, cg, sg = np.cos(a), np.sin(a), np.cos(b), np.sin(b), np.cos(g), np.sin(g)
    return (np.array([[1, 0, 0], [0, ca, -sa], [0, sa, ca]])
            @ np.array([[cb, 0, sb], [0, 1, 0], [-sb, 0, cb]])
            @ np.array([[cg, -sg, 0], [sg, cg, 0], [0, 0, 1]]))


def _hand(alpha, beta, Zo):
    A = np.array(_radial(R_BASE))
    ap = np.array(_radial(R_PLAT))
    t = np.array([np.cross([0, 0, 1.0], x) / np.linalg.norm(x) for x in A])   # base.tangent

    def eqs(x):
        Xo, Yo, g = x
        a = np.array([Xo, Yo, Zo]) + ap @ _rot(alpha, beta, g).T
        return [(a[i] - A[i]) @ t[i] for i in range(3)]

    x = np.array([0.1, -0.1, 0.01])            # Newton, central-difference Jacobian
    for _ in range(30):
        f = np.array(eqs(x))
        Jx = np.column_stack([(np.array(eqs(x + h)) - np.array(eqs(x - h))) / 2e-7
                              for h in 1e-7 * np.eye(3)])
        x = x - np.linalg.solve(Jx, f)
    assert np.max(np.abs(eqs(x))) < 1e-11
    Xo, Yo, g = x
    o = np.array([Xo, Yo, Zo])
    a = o + ap @ _rot(alpha, beta, g).T
    u = (a - A) / np.linalg.norm(a - A, axis=1)[:, None]
    J = np.vstack([np.hstack([u, np.cross(A, u)]), np.hstack([t, np.cross(a, t)])])
    return (Xo, Yo, g), o, J


POSES = [(4.0, -3.0, 62.0), (-9.0, 6.0, 55.0), (0.0, 0.0, 60.0)]


def test_the_built_model_is_the_yaml_model(built, from_yaml):
    # the file's entry as a mapping in memory: the same model, bit for bit
    entry = yaml.safe_load(YAML_3RPS)["pms"]["my3RPS"]
    assert screwkit.load_pm(entry, name="my3RPS").same_as(from_yaml)
    # built leg by leg (vertices from numpy's cos and sin): the same to rounding
    np.testing.assert_allclose(built.base_points, from_yaml.base_points, atol=1e-12)
    np.testing.assert_allclose(built.platform_points, from_yaml.platform_points, atol=1e-12)
    assert (built.string, built.legs, built.independent, built.order, built.units) == \
        (from_yaml.string, from_yaml.legs, from_yaml.independent, from_yaml.order,
         from_yaml.units)
    for lb, ly in zip(built.home_legs, from_yaml.home_legs):
        for jb, jy in zip(lb.joints, ly.joints):
            np.testing.assert_allclose(jb.direction, jy.direction, atol=1e-14)
            np.testing.assert_allclose(jb.point, jy.point, atol=1e-12)


@pytest.mark.parametrize("alpha,beta,Zo", POSES)
def test_the_built_3rps_against_the_hand_derivation(built, from_yaml, alpha, beta, Zo):
    F, T = np.array([3.0, -2.0, -40.0]), np.array([50.0, 20.0, -30.0])
    pose = {"alpha": alpha, "beta": beta, "Zo": Zo}
    res = screwkit.analyze(built, pose, degrees=True, force=F, torque=T)
    ref = screwkit.analyze(from_yaml, pose, degrees=True, force=F, torque=T)
    (Xo, Yo, g), o, J = _hand(np.radians(alpha), np.radians(beta), Zo)
    p = res.solution.params
    assert abs(p["Xo"] - Xo) < 1e-9 and abs(p["Yo"] - Yo) < 1e-9 and abs(p["gamma"] - g) < 1e-11
    Jm = res.jacobian.J
    np.testing.assert_allclose(Jm[:3], J[:3], atol=1e-10)            # actuation rows
    sign = np.sign(np.sum(Jm[3:, :3] * J[3:, :3], axis=1))           # constraint rows: +-1
    assert np.all(np.abs(sign) == 1)
    np.testing.assert_allclose(Jm[3:], sign[:, None] * J[3:], atol=1e-10)
    W = np.r_[F, T + np.cross(o, F)]
    Fr = np.linalg.solve(J.T, -W)
    np.testing.assert_allclose(res.statics.active, Fr[:3], rtol=1e-9, atol=1e-9)
    np.testing.assert_allclose(res.statics.constraint, sign * Fr[3:], rtol=1e-9, atol=1e-9)
    # the same model read from YAML gives the same numbers
    np.testing.assert_allclose(ref.jacobian.J, Jm, atol=1e-12)
    np.testing.assert_allclose(ref.statics.values, res.statics.values, rtol=1e-11, atol=1e-11)


def test_written_back_and_read_again_is_identical(built, tmp_path):
    text = built.to_yaml()
    assert yaml.safe_load(text) == {"pms": {"my3RPS": built.to_mapping()}}
    path = tmp_path / "back.yaml"
    built.to_yaml(path)
    again = screwkit.load_pm(str(path))
    assert again.same_as(built)
    assert screwkit.load_pm(built.to_mapping(), name=built.name).same_as(built)
    # a catalog model, a user file with its own leg type, a dimension override
    for pm in (screwkit.load_pm("3UPS+UP/passive"), screwkit.load_pm("3RRPRR", {"L": 150})):
        assert screwkit.load_pm(pm.to_mapping(), name=pm.name).same_as(pm)


def test_a_model_written_with_other_dimensions_says_so_in_its_source():
    """The catalog's source text describes its own dimensions (``L = 120``): written with
    ``L = 150`` the file's source says which dimension changed and from what; with the same
    dimensions the source is the catalog's word for word."""
    base = screwkit.load_pm("3RRPRR").to_mapping()["source"]
    assert "L = 120" in base
    moved = screwkit.load_pm("3RRPRR", {"L": 150})
    src = moved.to_mapping()["source"]
    assert src.startswith(base) and "L = 150 (the source's 120)" in src
    assert "l =" not in src[len(base):]                        # l unchanged: not named
    assert screwkit.load_pm("3RRPRR", {"L": 120}).to_mapping()["source"] == base
    assert screwkit.load_pm(moved.to_mapping(), name=moved.name).same_as(moved)


def test_a_user_leg_type_is_written_inline(tmp_path):
    from pathlib import Path
    src = Path(__file__).parent / "data" / "user_pm.yaml"
    pm = screwkit.load_pm(str(src))
    legs = pm.to_mapping()["legs"]
    assert all(isinstance(e, dict) for e in legs)                  # the file's own leg type
    again = screwkit.load_pm(pm.to_mapping(), name=pm.name)
    assert again.same_as(pm)
    pm.to_yaml(tmp_path / "u.yaml")
    assert screwkit.load_pm(str(tmp_path / "u.yaml")).same_as(pm)


def test_a_mapping_gets_the_errors_of_a_file(tmp_path):
    bad = yaml.safe_load(YAML_3RPS)["pms"]["my3RPS"]
    bad["dof"] = 4
    p = tmp_path / "bad.yaml"
    p.write_text(yaml.safe_dump({"pms": {"my3RPS": bad}}))
    with pytest.raises(CatalogError) as from_file:
        screwkit.load_pm(str(p))
    with pytest.raises(CatalogError) as from_memory:
        screwkit.load_pm(bad, name="my3RPS")
    assert from_memory.value.detail == from_file.value.detail
    assert (from_memory.value.entry, from_memory.value.field) == ("my3RPS", "independent")
    bad["legs"] = ["RPS", {"leg": "RPS", "pasive": True}, "RPS"]
    bad["dof"] = 3
    with pytest.raises(CatalogError, match=r"legs\[1\].*did you mean 'passive'"):
        screwkit.load_pm(bad)
    inline = dict(yaml.safe_load(YAML_3RPS)["pms"]["my3RPS"])
    inline["legs"] = [{"leg": {"name": "RPS/mine", "string": "R_PS",
                               "joints": [{"axis": "base.tangent", "at": "A"},
                                          {"axis": "leg"}, {"at": "b"}]}}] * 3
    with pytest.raises(CatalogError, match=r"legs\[0\]\.leg.*RPS/mine"):
        screwkit.load_pm(inline, name="x")
    with pytest.raises(InputError, match="PMBuilder"):
        screwkit.analyze([screwkit.leg("RPS")] * 3)


def test_every_entry_point_takes_a_mapping_or_a_builder(built):
    mapping = built.to_mapping()
    F, T = [0.0, 0.0, -10.0], [0.0, 0.0, 0.0]
    a = screwkit.analyze(mapping, {"alpha": 0.05, "beta": 0.0, "Zo": 60.0}, force=F, torque=T)
    b = screwkit.analyze(_builder(), {"alpha": 0.05, "beta": 0.0, "Zo": 60.0}, force=F,
                         torque=T)
    np.testing.assert_array_equal(a.statics.values, b.statics.values)
    sol = screwkit.solve(mapping, {"alpha": 0.05, "beta": 0.0, "Zo": 60.0})
    assert bool(screwkit.forward(_builder(), sol.actuator_values).success[0])
    ds = screwkit.map(mapping, {"alpha": (-2, 2, 2)}, fix={"beta": 0, "Zo": 60}, degrees=True,
                      force=F, torque=T)
    assert bool(ds["ok"].all())


def test_placed_legs_with_their_attachments():
    """The same 3-RPS from legs written joint by joint (leg_from_joints), one of them given
    in a frame of its own and placed by frame=: the same rows as the rule-built model."""
    A, ap = _radial(R_BASE), _radial(R_PLAT)
    o = np.array([0.0, 0.0, H])
    b = PMBuilder("my3RPS/joints", units={"length": "mm", "force": "N"})
    for i in range(3):
        t = np.cross([0, 0, 1.0], A[i]) / R_BASE
        a = o + ap[i]
        joints = [("R", t, A[i]), ("P", a - A[i], A[i]),
                  ("R", [1, 0, 0], a), ("R", [0, 1, 0], a), ("R", [0, 0, 1], a)]
        leg = screwkit.leg_from_joints(joints, A[i], a, actuated=1)
        if i == 2:        # given about its own base point, rotated: placed back by frame=
            Rl = _rot(0.3, -0.2, 0.7)
            local = leg.moved(Rl.T, -Rl.T @ A[i])
            b.add_leg(local, frame=(Rl, A[i]))
        else:
            b.add_leg(leg)
    b.set_pose(["alpha", "beta", "Zo"], home={"alpha": 0, "beta": 0, "Zo": H})
    pm = b.build()
    assert pm.string == "3RPRRR"
    np.testing.assert_allclose(pm.platform_points, np.array(ap), atol=1e-12)
    ref = screwkit.load_pm(_builder())
    pose = {"alpha": 0.06, "beta": -0.04, "Zo": 62.0}
    F, T = [1.0, 2.0, -30.0], [10.0, 0.0, 5.0]
    x = screwkit.analyze(pm, pose, force=F, torque=T)
    y = screwkit.analyze(ref, pose, force=F, torque=T)
    np.testing.assert_allclose(x.jacobian.J_a, y.jacobian.J_a, atol=1e-9)
    np.testing.assert_allclose(x.statics.active, y.statics.active, rtol=1e-8)
    assert screwkit.load_pm(pm.to_mapping(), name=pm.name).same_as(pm)


def test_an_override_of_a_dimension_nothing_uses_is_refused(tmp_path):
    """A dimension declared but named by no expression (``H`` here): ``--set H=...`` would
    change nothing, so it is refused naming it; the dimensions the expressions use take
    their overrides (the base's radius follows ``R``)."""
    d = yaml.safe_load(YAML_3RPS)["pms"]["my3RPS"]
    d["dimensions"]["H"] = 5.0
    p = tmp_path / "h.yaml"
    p.write_text(yaml.safe_dump({"pms": {"my3RPS": d}}))
    assert screwkit.load_pm(str(p)).dimensions["H"] == 5.0     # declared: loads as it is
    with pytest.raises(InputError, match="override H: no expression .* uses the dimension H"):
        screwkit.load_pm(str(p), {"H": 6.0})
    with pytest.raises(InputError, match="override H"):
        screwkit.load_pm(d, {"H": 6.0}, name="my3RPS")
    moved = screwkit.load_pm(str(p), {"R": 2 * R_BASE})
    np.testing.assert_allclose(np.linalg.norm(moved.base_points, axis=1), 2 * R_BASE)


def test_model_check_reports_a_dimension_nothing_uses(tmp_path):
    """``model check`` reports a declared dimension no expression names (it loads, and
    changes nothing) as a problem of the PM at its line; without it the file is valid."""
    from screwkit.pm import check_model_file
    d = yaml.safe_load(YAML_3RPS)["pms"]["my3RPS"]
    d["dimensions"]["H"] = 5.0
    p = tmp_path / "h.yaml"
    p.write_text(yaml.safe_dump({"pms": {"my3RPS": d}}))
    problems = check_model_file(p)
    assert [(x.entry, x.field, x.check) for x in problems] == \
        [("my3RPS", "dimensions.H", "pm")], [str(x) for x in problems]
    assert "dimension H is declared but no expression of the PM uses it" in problems[0].message
    assert problems[0].line == p.read_text().splitlines().index(
        next(t for t in p.read_text().splitlines() if t.strip().startswith("H:"))) + 1
    del d["dimensions"]["H"]
    p.write_text(yaml.safe_dump({"pms": {"my3RPS": d}}))
    assert check_model_file(p) == []
