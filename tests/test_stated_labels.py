"""Issue 20 follow-ups: a rotary actuator's effort is labelled as the torque it is in every
output (analyze, trajectory, map, size), an absurd path is flagged without numpy's warnings
on stderr, and the view's empty output paths are refused."""

from __future__ import annotations

import json
import warnings

import numpy as np
import pytest

import screwkit
from screwkit.cli import main

LOAD = {"force": (0.0, 0.0, -10.0), "torque": (0.0, 0.0, 0.0)}


def test_rotary_actuators_are_labelled_T_in_analyze_and_linear_ones_F(capsys):
    for pm, letter in (("3RSR", "T"), ("3RPS", "F")):
        assert main(["analyze", pm, "--force=0,0,-10", "--json"]) == 0
        st = json.loads(capsys.readouterr().out)["statics"]
        for lab, unit in zip(st["labels"][:3], st["units"][:3]):
            # the label's letter and the unit say the same: a torque is in force x length
            assert lab[0] == letter and (unit == "kN.cm") == (letter == "T"), (pm, lab, unit)


def test_rotary_labels_in_map_and_size(capsys):
    res = screwkit.analyze("3RSR", {"Zo": np.array([40.0, 45.0])}, **LOAD)
    assert res.jacobian.labels[:3] == ("T_a1", "T_a2", "T_a3")
    ds = screwkit.map("3RSR", {"Zo": (38.0, 42.0, 3)}, **LOAD)
    assert "T_a1" in ds and "F_a1" not in ds and ds["T_a1"].attrs["units"] == "kN.cm"
    assert main(["size", "3RSR", "--grid", "Zo=38:42:3", "--force=0,0,-10", "--json",
                 "--quiet"]) == 0
    rows = {r["name"]: r["unit"] for r in json.loads(capsys.readouterr().out)["extremes"]}
    assert rows["T_a1"] == "kN.cm" and "F_a1" not in rows and rows["F_c1"] == "kN"


def test_rotary_labels_in_the_trajectory_csv(tmp_path, capsys):
    out = tmp_path / "t.csv"
    assert main(["trajectory", "3RSR", "--expr", "alpha=2*t", "--expr", "beta=0", "--expr",
                 "Zo=40", "--samples", "3", "--force=0,0,-10", "--out", str(out)]) == 0
    head = out.read_text().splitlines()[0]
    assert "T_a1 [kN.cm]" in head and "F_a1" not in head


@pytest.mark.parametrize("z", ["1e6+t", "-1e6*t"])
def test_an_absurd_path_is_flagged_without_numpy_warnings(capsys, z):
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        code = main(["trajectory", "3RRPRR", "--expr", f"Zo={z}", "--expr", "beta=0",
                     "--expr", "alpha=0", "--samples", "5", "--format", "json"])
    err = capsys.readouterr()
    assert code == 0 and not caught, [str(w.message) for w in caught]
    assert "Warning" not in err.err
    status = json.loads(err.out)["status"]
    assert sum(s == "unreachable" for s in status) >= 4        # flagged, not garbage


@pytest.mark.parametrize("opt", ["--html", "--png"])
def test_the_view_refuses_an_empty_output_path(capsys, opt):
    assert main(["view", "3RPS", opt, ""]) == 2
    err = capsys.readouterr().err.strip().splitlines()
    assert len(err) == 1 and f"argument {opt}: an empty file name" in err[0]


MODEL = """units: {length: mm, force: N}
pms:
  H3SPR:
    dimensions: {R: 80, r: 30}
    base: {shape: triangle, circumradius: R}
    platform: {shape: triangle, circumradius: r}
    legs: [SPR, SPR, SPR]
    euler: XYZ
    independent: [alpha, beta, Zo]
    pose: {alpha: 5, beta: -3, Zo: R}
    dof: 3
    workload: {torque: [1, 2, 3], force: [0, 0, 1], units: {force: N, length: LENGTH}}
"""


@pytest.mark.parametrize("length", ["{}", "'{}'", "'()'", "'m**'", "3"])
def test_a_workload_unit_pint_cannot_read_is_one_line_naming_the_field(tmp_path, capsys,
                                                                       length):
    """pint's parser fails on '{}' with a bare AssertionError: it was an internal error."""
    path = tmp_path / "m.yaml"
    path.write_text(MODEL.replace("LENGTH", length))
    assert main(["analyze", "--model", str(path), "--force", "1,2,3"]) == 2
    err = capsys.readouterr().err.strip().splitlines()
    assert len(err) == 1 and "line 12" in err[0] and "workload.units" in err[0], err
