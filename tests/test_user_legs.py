"""User-defined leg types: define_leg, load_legs, extend_catalog, and the docs' examples.

Default placement: A = (100, 0, 0), a = (50, 0, 80), O = origin, o = (0, 0, 80),
d = (a - A)/|a - A| = (-50, 0, 80)/sqrt(8900).
"""

import json
import re
from pathlib import Path

import numpy as np
import pytest

import screwkit
from screwkit.cli import main
from screwkit.legs import Placement
from screwkit.pm import Catalog, LegSpec, default_catalog
from screwkit.screws import couple_wrench, force_wrench, same_span, span_contains

X, Y, Z = np.eye(3)
A0, a0 = np.array([100.0, 0, 0]), np.array([50.0, 0, 80])
D0 = (a0 - A0) / np.linalg.norm(a0 - A0)
ROOT = Path(__file__).resolve().parents[1]

RPS_JOINTS = [{"axis": "base.tangent", "at": "A"}, {"axis": "leg"}, {"at": "a"}]

# An RUR of our own: R1 along the base tangent (Y) at A; U2 at M = midpoint of A-a raised
# by 0.3 |a - A| along Z (off the leg line), with U2a parallel to R1 and U2b = R1 x leg;
# R3 parallel to R1 at a.
RUR_YAML = """\
legs:
  - name: RUR/mine
    string: _RUR
    summary: three parallel R axes and a U off the leg line
    joints:
      - {axis: base.tangent, at: A}
      - {at: {offset: {between: [A, a]}, along: base.Z, fraction: 0.3},
         axes: [{parallel: R1}, {perpendicular: [R1, leg]}]}
      - {axis: {parallel: R1}, at: a}
    structure:
      - {parallel: [R1, R3]}
      - {perpendicular: [U2b, R1]}
    expect:
      forces: 1
      couples: 1
      words: forces parallel to R1 meeting U2b; a couple along the leg
      force_lines: [{through: U2, parallel: R1}]
      couples_along: [leg]
"""


def test_define_leg_rps_hand_derived():
    # R1 along Y through A, P along d, S at a.  Rule 2: the force passes through the S
    # centre a and meets or is parallel to R1, so it lies in the plane through a that
    # contains the R1 axis: its direction is in span{Y, d}.  Rule 1: perpendicular to d,
    # so along Y.  5 joints, rank 5 -> exactly one force: along Y through a.
    spec = screwkit.define_leg("RPS/mine", "R_PS", RPS_JOINTS,
                               structure=[{"perpendicular": ["R1", "leg"]}],
                               expect={"forces": 1, "force_lines": [{"through": "a", "parallel": "R1"}]},
                               summary="R tangent to the base, P, S on the platform")
    assert isinstance(spec, LegSpec) and spec.name == "RPS/mine" and spec.string.marked == "R_PS"
    cat = screwkit.extend_catalog([spec])
    leg = screwkit.leg("RPS/mine", catalog=cat)
    assert leg.name == "RPS/mine" and [j.name for j in leg.joints] == ["R1", "P2", "S3a", "S3b", "S3c"]
    res = leg.analyze()
    assert res.connectivity == 5 and (res.n_forces, res.n_couples) == (1, 0)
    c = res.constraints[0]
    assert np.linalg.norm(np.cross(c.direction, Y)) < 1e-12 and c.line.distance_to_point(a0) < 1e-9
    assert c.point_name == "S3"
    assert same_span([force_wrench(Y, a0).vector], res.system.wrenches, res.system.normalisation)
    assert spec.check_expectation(res) == []
    # the actuator force runs along the leg line A-a (meets R1 at A, passes through S3)
    np.testing.assert_allclose(res.actuation.wrench, force_wrench(D0, A0).vector, atol=1e-7)
    # the extended catalog holds it; the packaged catalog is unchanged
    assert cat.find_leg("RPS/mine") is spec and "RRPRR" in cat.legs
    assert default_catalog().find_leg("RPS/mine") is None


def test_check_expectation_catches_a_wrong_claim():
    # a force through A parallel to R1 is not reciprocal to the S at a: it misses a by
    # |(a - A) x y| = |(-50,0,80) x (0,1,0)| = |(-80, 0, -50)| > 0
    spec = screwkit.define_leg("RPS/wrong", "RPS", RPS_JOINTS,
                               expect={"forces": 1, "couples": 1,
                                       "force_lines": [{"through": "A", "parallel": "R1"}]})
    problems = spec.check_expectation(spec.build().analyze())
    assert any("expected 1 couples, found 0" in p for p in problems)
    assert any("is not in the constraint system" in p for p in problems)


def test_define_leg_with_placement():
    pl = Placement(A=[0, 120, 0], a=[0, 40, 90])
    spec = screwkit.define_leg("RPS/p", "RPS", RPS_JOINTS, placement=pl)
    assert spec.placement is pl
    # base tangent at A = (0, 120, 0): z x (A - O) = (-120, 0, 0): force along X through a
    res = spec.build().analyze()
    c = res.constraints[0]
    assert abs(c.direction @ X) == pytest.approx(1) and c.line.distance_to_point([0, 40, 90]) < 1e-9
    spec2 = screwkit.define_leg("RPS/q", "RPS", RPS_JOINTS,
                                placement={"A": [0, 120, 0], "a": [0, 40, 90]})
    np.testing.assert_allclose(spec2.build().A, [0, 120, 0])


def test_load_legs_yaml_rur_hand_derived(tmp_path):
    # R1, U2a, R3 are parallel to Y through A, M, a with M = (75, 0, 40 + 0.3 sqrt(8900))
    # off the line A-a: they span planar motion in XZ (rotation about Y, translations along
    # X and Z); U2b = Y x d ~ (80, 0, 50) adds a rotation: connectivity 4, two wrenches.
    # Rule 3: a couple perpendicular to Y and (80,0,50): Y x (80,0,50) = (50,0,-80) ~ d.
    # Rule 2: a force parallel to Y (parallel to R1, U2a, R3) meeting U2b: along Y through
    # M.  Every force along Y meeting the U2b axis is in the system (M + t (80,0,50)).
    f = tmp_path / "legs.yaml"
    f.write_text(RUR_YAML)
    legs = screwkit.load_legs(f)
    assert [s.name for s in legs] == ["RUR/mine"]
    cat = screwkit.extend_catalog(legs)
    res = screwkit.leg("RUR/mine", catalog=cat).analyze()
    M = np.array([75.0, 0.0, 40.0 + 0.3 * np.sqrt(8900.0)])
    np.testing.assert_allclose(res.leg.joint("U2a").point, M)
    assert res.connectivity == 4 and (res.n_forces, res.n_couples) == (1, 1)
    norm = res.system.normalisation
    assert same_span([force_wrench(Y, M).vector, couple_wrench(D0).vector], res.system.wrenches, norm)
    for t in (-40.0, 25.0):
        assert span_contains(res.system.wrenches, force_wrench(Y, M + t * np.array([80, 0, 50])).vector, norm)
    assert not span_contains(res.system.wrenches, force_wrench(Y, A0).vector, norm)
    assert legs[0].check_expectation(res) == [] and res.agrees()
    couple = next(c for c in res.constraints if c.kind == "couple")
    assert {n.rule for n in couple.rules} == {3}


def test_cli_reads_the_same_yaml(tmp_path, capsys):
    f = tmp_path / "legs.yaml"
    f.write_text(RUR_YAML)
    assert main(["leg", "RUR/mine", "--model", str(f), "--json"]) == 0
    d = json.loads(capsys.readouterr().out)
    assert d["leg"] == "RUR/mine" and d["connectivity"] == 4
    assert sorted(c["kind"] for c in d["constraints"]) == ["couple", "force"]


def test_extend_catalog_rules():
    rps = screwkit.define_leg("RPS/mine", "R_PS", RPS_JOINTS)
    base = screwkit.extend_catalog(rps)                 # a single spec is accepted
    assert isinstance(base, Catalog) and "RPS/mine" in base.legs and "RRPRR" in base.legs
    with pytest.raises(screwkit.CatalogError, match="already exists"):
        screwkit.extend_catalog([rps], base)
    with pytest.raises(screwkit.CatalogError, match="already exists"):
        screwkit.extend_catalog([rps, rps])
    clash = screwkit.define_leg("SPR", "RPS", RPS_JOINTS)   # shadows a catalog leg
    with pytest.raises(screwkit.CatalogError, match="'SPR'"):
        screwkit.extend_catalog([clash])
    assert screwkit.extend_catalog([clash], replace=True).find_leg("SPR") is clash
    with pytest.raises(screwkit.CatalogError, match="expected a LegSpec"):
        screwkit.extend_catalog([{"name": "x"}])
    # extending a Catalog object with another one
    both = screwkit.extend_catalog(Catalog({"RPS/mine": rps}, [], {}), default_catalog())
    assert both.find_leg("RPS/mine") is rps


@pytest.mark.parametrize("kwargs, field, words", [
    (dict(name="b", string="RPS", joints=[{"axis": "leg", "at": "A"}]), "joints", "1 entries for the 3"),
    (dict(name="b", string="RXS", joints=RPS_JOINTS), "string", "unknown joint letter 'X'"),
    (dict(name="b", string="RPS", joints=[{"at": "A"}, {"axis": "leg"}, {"at": "a"}]),
     "joints[0] (R1)", "missing 'axis'"),
    (dict(name="b", string="RPS", joints=RPS_JOINTS, expect={"forces": 9}), "expect.forces", "0 to 6"),
    (dict(name="b", string="RPS", joints=RPS_JOINTS, structure=[{"crosses": ["R1", "leg"]}]),
     "structure[0]", "perpendicular/parallel/meets/through"),
    (dict(name="", string="RPS", joints=RPS_JOINTS), "name", "non-empty"),
])
def test_define_leg_errors_name_entry_and_field(kwargs, field, words):
    with pytest.raises(screwkit.CatalogError, match=re.escape(words)) as exc:
        screwkit.define_leg(**kwargs)
    assert f"field {field!r}" in str(exc.value) and exc.value.field == field


def test_structure_violation_is_a_geometry_error():
    # R1 along the leg cannot be perpendicular to it
    spec = screwkit.define_leg("RPS/bad", "RPS", [{"axis": "leg", "at": "A"}, {"axis": "leg"}, {"at": "a"}],
                               structure=[{"perpendicular": ["R1", "leg"]}])
    with pytest.raises(screwkit.GeometryError, match="structure check"):
        spec.build()


@pytest.mark.parametrize("text, words", [
    ("legs: []\n", "no leg types"),
    ("pms: {}\n", "no leg types"),
    ("legs:\n  - name: X\n    string: RPS\n", "missing required field 'joints'"),
    ("legs:\n  - {name: X, string: RPS, joints: [{axis: leg, at: A}, {axis: leg}, {at: a}], colour: red}\n",
     "unknown field"),
    ("legs: [\n", "invalid YAML"),
])
def test_load_legs_errors(tmp_path, text, words):
    f = tmp_path / "bad.yaml"
    f.write_text(text)
    with pytest.raises(screwkit.CatalogError, match=words) as exc:
        screwkit.load_legs(f)
    assert str(f) in str(exc.value)


def test_load_legs_missing_file(tmp_path):
    with pytest.raises(screwkit.CatalogError, match="cannot read"):
        screwkit.load_legs(tmp_path / "none.yaml")

# docs/api.md's code blocks and the outputs they show: tests/test_docs_run.py
