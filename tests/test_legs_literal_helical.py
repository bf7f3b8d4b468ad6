"""Explicit legs in YAML (literal points and vectors), rules referring to earlier joints,
and helical joints with their pitch in leg strings (issue 14, items 1 and 2)."""

import numpy as np
import pytest
import yaml

import screwkit
from screwkit.errors import ParseError
from screwkit.legs import default_placement, parse_leg
from screwkit.pm import default_catalog, mobility_of_legs
from screwkit.screws import same_span

CATALOG = default_catalog()


def _literal_entry(name, lg):
    """The YAML rules of a placed leg with every axis and point written as a literal."""
    joints = []
    for pos, letter in enumerate(lg.string.letters, start=1):
        js = [j for j in lg.joints if j.spec.position == pos]
        if letter in ("U", "S"):
            joints.append({"axes": [{"world": j.direction.tolist()} for j in js],
                           "at": {"world": js[0].point.tolist()}})
        else:
            joints.append({"axis": {"world": js[0].direction.tolist()},
                           "at": {"world": js[0].point.tolist()}})
    # the string, with the pitch of each H written in it (model lengths per radian)
    shown = [f"H({js[0].pitch!r})" if letter == "H" else letter
             for letter, js in ((t, [j for j in lg.joints if j.spec.position == k])
                                for k, t in enumerate(lg.string.letters, start=1))]
    act = lg.string.actuated_position
    marked = "".join(shown[:act - 1]) + "_" + "".join(shown[act - 1:])
    return {"name": f"{name}/literal", "string": marked, "joints": joints,
            "placement": {"A": lg.A.tolist(), "a": lg.a.tolist()}}


def test_every_catalog_leg_rebuilt_from_a_yaml_file_of_literals(tmp_path):
    """Each catalog leg written as a YAML leg type whose rules are only literal world points
    and vectors: loaded with screwkit.load_legs, it has the same constraint system."""
    entries, built = [], {}
    for name in sorted(CATALOG.legs):
        lg = CATALOG.legs[name].build()
        built[name] = lg
        entries.append(_literal_entry(name, lg))
    path = tmp_path / "literal_legs.yaml"
    path.write_text(yaml.safe_dump({"legs": entries}))
    specs = {s.name: s for s in screwkit.load_legs(path)}
    assert len(specs) == len(built)
    for name, lg in built.items():
        ex = specs[f"{name}/literal"].build()
        a1, a2 = lg.analyze(), ex.analyze()
        np.testing.assert_allclose(ex.twists, lg.twists, atol=1e-9 * max(1.0, lg.length))
        W1, W2 = a1.system.wrenches, a2.system.wrenches
        assert W1.shape == W2.shape, name
        assert (same_span(W1, W2, a1.system.normalisation) if len(W1) else True), name
        assert a1.summary() == a2.summary(), name


def test_a_rule_refers_to_earlier_joints_and_literal_points():
    """R3's axis points from R2's point toward the centre C; R1 sits at a literal world point
    and R2 at a literal point of the base frame; R3 at a literal point of the platform frame.
    Expected values by hand from the default placement."""
    pl = default_placement()
    spec = screwkit.define_leg("RRR/refs", "_RRR", [
        {"axis": "base.Z", "at": {"world": [1.0, 2.0, 3.0]}},
        {"axis": "base.Z", "at": {"base": [5.0, 0.0, 0.0]}},
        {"axis": {"toward": ["R2", "C"]}, "at": {"platform": [0.0, 1.0, 0.0]}}])
    lg = spec.build(pl)
    R2 = pl.O + pl.base_rotation @ [5.0, 0.0, 0.0]
    np.testing.assert_allclose(lg.joints[0].point, [1, 2, 3])
    np.testing.assert_allclose(lg.joints[1].point, R2)
    np.testing.assert_allclose(lg.joints[2].point, pl.o + pl.platform_rotation @ [0, 1.0, 0])
    d = pl.centre - R2
    np.testing.assert_allclose(lg.joints[2].direction, d / np.linalg.norm(d))


def test_a_literal_point_is_checked():
    with pytest.raises(screwkit.CatalogError):
        screwkit.define_leg("R/bad", "R", [{"axis": "base.Z", "at": {"world": [1, 2]}}]).build()
    with pytest.raises(screwkit.CatalogError, match="unknown key"):
        screwkit.define_leg("R/bad2", "R", [{"axis": "base.Z",
                                             "at": {"world": [1, 2, 3], "t": 1}}])


def test_helical_pitch_in_strings():
    ls = parse_leg("RH(2.5)_PR")
    assert ls.text == "RHPR" and ls.marked == "RH(2.5)_PR"
    assert [j.pitch for j in ls.equivalent] == [None, 2.5, None, None]
    assert parse_leg(ls.marked) == ls                      # the marked string round-trips
    lg = screwkit.leg("RH(2.5)_PR")                         # a generic geometry keeps it
    assert lg.joints[1].pitch == 2.5
    # the rule language takes the string's pitch (model lengths per radian) ...
    spec = screwkit.define_leg("H/mine", "_H(-1.5)", [{"axis": "base.Z", "at": "A"}])
    h = spec.build().joints[0]
    assert h.pitch == -1.5
    np.testing.assert_allclose(h.twist.vector, np.r_[np.cross(h.point, h.direction)
                                                     - 1.5 * h.direction, h.direction])
    # ... and scales it with the lengths
    assert spec.build().moved(np.eye(3), np.zeros(3), 10.0).joints[0].pitch == -15.0
    with pytest.raises(screwkit.CatalogError, match="twice"):
        screwkit.define_leg("H/twice", "_H(2)", [{"axis": "base.Z", "at": "A", "pitch": 0.1}])
    for bad in ("RH(x)R", "RH(2R", "R(2)", "RH(1)(2)", "RH(nan)R"):
        with pytest.raises(ParseError):
            parse_leg(bad)


def test_helical_motion_is_labelled_with_its_pitch():
    """A platform on an H leg (pitch 2.5 about Z through (1, 0, 0)) and a coaxial C leg:
    the H twist [p x z + 2.5 z; z] lies in the C's span {[z; 0], [p x z; z]}, so the only
    motion is that helical one (by hand)."""
    p = [1.0, 0.0, 0.0]
    h = screwkit.leg_from_joints([("H", [0, 0, 1], p, 2.5)])
    c = screwkit.leg_from_joints([("P", [0, 0, 1], p), ("R", [0, 0, 1], p)])
    m = mobility_of_legs([h, c])
    assert (m.dof, m.motion_type) == (1, "1H(p=2.5)")
    np.testing.assert_allclose(np.cross(m.twists[0][3:], [0, 0, 1]), 0, atol=1e-12)
    w, v = m.twists[0][3:], m.twists[0][:3]
    assert v @ w / (w @ w) == pytest.approx(2.5, rel=1e-9)


def test_a_helical_columns_rows_are_the_members_their_labels_say_at_any_pose():
    """Three UPS legs and a passive column P(x), P(y), H(z, pitch h) (the generic rule: its
    system holds a screw). Its constraint rows, by hand: two couples normal to z and one
    screw along z of pitch -h (a force along z with the moment -h z does no work on the H
    twist [p x z + h z; z]); each row is reciprocal to the column's joint twists formed here,
    and each is labelled as what it is (they were the analysis' members in its order, a
    screw labelled a couple and a couple a screw, and off home the couples took a force).
    The H couples the platform's height to its turn, Zo = h gamma (the builder dropped the
    column's pitch: an R joint, Zo = 0)."""
    h = 20.0
    col = screwkit.leg_from_joints([("P", [1, 0, 0], [0, 0, 0]), ("P", [0, 1, 0], [0, 0, 0]),
                                    ("H", [0, 0, 1], [0, 0, 500.0], h)], [0, 0, 0], [0, 0, 500.0])
    b = screwkit.PMBuilder("hel", units={"length": "mm", "force": "N"})
    for t in np.radians([0, 120, 240]):
        u = np.array([np.cos(t), np.sin(t), 0.0])
        b.add_leg("UPS", base=300 * u, platform=100 * u + [0, 0, 500])
    b.add_leg(col, passive=True)
    b.set_pose(["Xo", "Yo", "gamma"], home={"Xo": 0, "Yo": 0, "gamma": 0}, order="XYZ")
    pm = b.build()
    assert col.string.marked == "_PPH(20)" and pm.home_legs[3].joints[2].pitch == h
    for pose in ({"Xo": 0.0, "Yo": 0.0, "gamma": 0.0}, {"Xo": 18.0, "Yo": -8.0, "gamma": 0.3}):
        res = screwkit.analyze(pm, pose, force=[10, -5, -200], torque=[500, -300, 1000])
        assert float(res.solution.params["Zo"]) == pytest.approx(h * pose["gamma"], abs=1e-9)
        p = np.array([pose["Xo"], pose["Yo"], 0.0])          # the H axis: z through p
        twists = [np.r_[1.0, 0, 0, 0, 0, 0], np.r_[0, 1.0, 0, 0, 0, 0],
                  np.r_[np.cross(p, [0, 0, 1]) + h * np.array([0, 0, 1]), 0, 0, 1]]
        rows = [(r, w) for r, w in zip(res.jacobian.info, res.jacobian.J) if r.leg == 3]
        assert sorted(r.kind for r, _ in rows) == ["couple", "couple", "screw"]
        for r, w in rows:
            assert max(abs(w @ t) for t in twists) <= 1e-12 * np.abs(w).max()
            if r.kind == "couple":
                assert r.label.startswith("T_c") and np.abs(w[:3]).max() <= 1e-12
                assert abs(w[5]) <= 1e-12                   # normal to z
            else:
                assert r.label.startswith("W_c")
                np.testing.assert_allclose(w[:3] / np.linalg.norm(w[:3]), [0, 0, 1], atol=1e-12)
                assert w[:3] @ w[3:] / (w[:3] @ w[:3]) == pytest.approx(-h, rel=1e-9)
