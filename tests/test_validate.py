"""Batch validation over Table I and the catalog, and the ``screwkit validate`` command.

The partition of Table I is derived by hand from the rules:

* a string with an S cannot exert a couple (rule 3 against three non-coplanar axes);
* a string with three or more P-type joints (P, or the P of a C) cannot exert a force
  (rule 1 puts them in the plane perpendicular to it: dependent, rank too low);
* a string with four or more P-type joints always has dependent joints (translations
  span at most 3 directions);
* every other string of Table I can exert both (R axes meeting L / perpendicular to t).
"""

import csv
import io
import json

import numpy as np
import pytest

import screwkit.synthesis._validation as validation
from screwkit.cli import main
from screwkit.legs import Joint, Leg
from screwkit.pm import Catalog, default_catalog, leg_spec_from_mapping
from screwkit.synthesis import validate_catalog, validate_string, validate_table1


def _n_ptype(s):
    return sum(c in "PC" for c in s)


@pytest.fixture(scope="module")
def report():
    return validate_table1(draws=1, seed=0)


def test_table1_no_disagreement(report):
    assert len(report.legs) == 101
    assert report.ok, [p for v in report.legs for p in v.problems] + \
        [p for c in report.catalog for p in c.problems]
    assert report.counts["disagreements"] == 0


def test_table1_partition_by_hand(report):
    strings = {v.string.text: v for v in report.legs}
    force_only = {s for s, v in strings.items() if v.can_force and not v.can_couple}
    couple_only = {s for s, v in strings.items() if v.can_couple and not v.can_force}
    both = {s for s, v in strings.items() if v.can_force and v.can_couple}
    neither = {s for s, v in strings.items() if not v.can_force and not v.can_couple}
    assert force_only == {s for s in strings if "S" in s}
    assert {"SRR", "SRP", "SPP", "SPR", "US", "CS", "SU", "SC", "PS", "SP"} == force_only
    assert couple_only == {s for s in strings if _n_ptype(s) >= 3}
    assert neither == set()
    assert len(both) == 101 - 10 - 25
    dependent = {s for s, v in strings.items() if v.dependent}
    assert dependent == {"PPPPP", "RPPPP", "CPPP", "PPPC", "PPCP", "PRPPP", "PPRPP"}
    assert strings["PPPPP"].k == 3 and strings["PPPPP"].connectivity == 3


def test_four_joint_legs_by_hand(report):
    strings = {v.string.text: v for v in report.legs}
    ok = lambda s: {t.label for t in strings[s].targets if t.realizable}  # noqa: E731
    # S: forces through the centre only
    assert ok("SP") == ok("PS") == {"2F"}
    # U: two couples would need both U axes parallel to n
    assert ok("RPU") == ok("PRU") == ok("UPR") == {"2F", "1F+1C"}
    # only R and one P: every mix (2C: all R parallel to n, P free)
    assert ok("PRRR") == ok("RPRR") == {"2F", "1F+1C", "2C"}
    # four P-type: only couples, dependent
    assert ok("RPPPP") == {"2C"}


def test_every_realizable_draw_verified(report):
    n = 0
    for v in report.legs:
        for t in v.targets:
            for d in t.draws:
                if d.realizable:
                    n += 1
                    assert d.verification.ok
                    assert d.verification.dimension == sum(t.composition)
    assert n == report.counts["synthesized_legs"] > 150


def test_catalog_legs_validated(report):
    cat = default_catalog()
    assert {c.name for c in report.catalog} == set(cat.legs)
    assert all(c.ok for c in report.catalog), [c.problems for c in report.catalog if not c.ok]


def test_wrong_catalog_expectation_is_flagged():
    good = default_catalog().legs["SPR"]
    raw = {"name": "SPR/wrong", "string": "S_PR",
           "joints": [{"at": "A"}, {"axis": "leg"}, {"axis": "platform.tangent", "at": "a"}],
           "expect": {"forces": 0, "couples": 1, "words": "deliberately wrong"}}
    bad = leg_spec_from_mapping(raw)
    cat = Catalog({"SPR": good, "SPR/wrong": bad}, [], {}, "test")
    checks = {c.name: c for c in validate_catalog(cat, draws=1)}
    assert checks["SPR"].ok
    assert not checks["SPR/wrong"].ok
    assert any("expected 1 couples" in p for p in checks["SPR/wrong"].problems)


def test_draws_agree_over_seeds():
    for s in ("UPU", "RPU", "CPPP"):
        a = validate_string(s, draws=4, seed=1)
        b = validate_string(s, draws=2, seed=99)
        assert a.ok and b.ok
        assert [(t.label, t.realizable, t.layout) for t in a.targets] == \
            [(t.label, t.realizable, t.layout) for t in b.targets]


def test_outside_table_notes():
    v = validate_string("SS", draws=1)
    # generic rank 5 < counting bound 6: the idle rotation about the line of the centres
    assert v.connectivity == 5 and v.counting == 6 and v.notes
    assert validate_string("RRRRRR", draws=1).k == 0


# ----------------------------------------------------------------- the command
def test_cli_formats(capsys, tmp_path):
    assert main(["validate", "UPU", "PPPPP", "--draws", "1", "--no-catalog"]) == 0
    out = capsys.readouterr().out
    assert "U_PU" in out and "2 strings" in out
    assert main(["validate", "UPU", "SPR", "--draws", "1", "--format", "csv"]) == 0
    rows = list(csv.DictReader(io.StringIO(capsys.readouterr().out)))
    t1 = [r for r in rows if r["section"] == "table1"]
    assert [r["leg"] for r in t1] == ["U_PU", "S_PR"]
    assert t1[1]["couple"].startswith("no:") and t1[1]["force"].startswith("yes")
    assert any(r["section"] == "catalog" for r in rows)
    assert main(["validate", "SP", "--draws", "2", "--seed", "5", "--format", "json",
                 "--no-catalog"]) == 0
    d = json.loads(capsys.readouterr().out)
    assert d["ok"] and d["draws"] == 2 and d["seed"] == 5
    (leg,) = d["legs"]
    assert [t["label"] for t in leg["targets"] if t["realizable"]] == ["2F"]
    out_file = tmp_path / "t.md"
    assert main(["validate", "RRPRR", "--draws", "1", "--format", "markdown",
                 "--out", str(out_file), "--no-catalog"]) == 0
    text = out_file.read_text()
    assert text.startswith("| Leg |") and "RR_PRR" in text
    assert "1 strings" in capsys.readouterr().out


def test_cli_errors(capsys):
    assert main(["validate", "RXR"]) == 2
    assert "position 1" in capsys.readouterr().err
    assert main(["validate", "UPU", "--draws", "0"]) == 2


def test_cli_exit_1_when_a_synthesis_is_wrong(monkeypatch, capsys):
    """A synthesizer that moves an R axis off the force line is caught by the verifier."""
    real = validation.synthesize

    def broken(ls, comp, rng, placement=None):
        s = real(ls, comp, rng, placement)
        if not s.realizable or comp != (1, 0):
            return s
        (p, c), = s.layout.force_lines
        joints = list(s.leg.joints)
        i = next(i for i, j in enumerate(joints) if j.kind == "R" and j.spec.origin == "R")
        j = joints[i]
        off = np.cross(j.direction, c)
        joints[i] = Joint(j.spec, j.direction, j.point + 0.2 * s.leg.length * off / np.linalg.norm(off))
        import dataclasses
        return dataclasses.replace(s, leg=Leg(s.leg.string, tuple(joints), s.leg.A, s.leg.a))

    monkeypatch.setattr(validation, "synthesize", broken)
    assert main(["validate", "RRPRR", "--draws", "1", "--no-catalog"]) == 1
    out = capsys.readouterr().out
    assert "not in the constraint system" in out and "1 disagreement" in out


def test_cli_local_processes_equal_serial(capsys):
    """``--jobs 2`` (forked worker processes) gives the serial report, string by string."""
    argv = ["validate", "UPU", "SPR", "RRPRR", "SP", "PRRR", "--draws", "1", "--no-catalog",
            "--format", "json", "--quiet"]
    reports = []
    for jobs in ("1", "2"):
        assert main(argv + ["--jobs", jobs]) == 0
        rep = json.loads(capsys.readouterr().out)
        rep.pop("seconds")
        reports.append(rep)
    assert reports[0] == reports[1]
    assert len(reports[1]["legs"]) == 5 and reports[1]["legs"][0]["leg"] == "U_PU"
    assert main(["validate", "UPU", "--jobs", "2", "--workers", "2"]) == 2
    assert "either --jobs" in capsys.readouterr().err
