"""What an independent review of the command line found (session 70), each fixed.

Each test states what the command did and what it does now; references are other spellings
of the same request (``--force=-20,...``, ``--format json``), the model's declared load and
factors written here.
"""

from __future__ import annotations

import json

import numpy as np
import pytest

import screwkit
from screwkit.cli import main


def _run(capsys, *argv):
    rc = main(list(argv))
    out, err = capsys.readouterr()
    return rc, out, err


def test_a_negative_vector_needs_no_equals_sign(capsys):
    """``--force -20,-30,-60`` was read as an option name (exit 2, no hint)."""
    rc, spaced, _ = _run(capsys, "analyze", "3RRPRR", "--force", "-20,-30,-60", "--torque",
                         "-30,-30,100", "--json")
    assert rc == 0
    rc, joined, _ = _run(capsys, "analyze", "3RRPRR", "--force=-20,-30,-60",
                         "--torque=-30,-30,100", "--json")
    assert rc == 0 and json.loads(spaced) == json.loads(joined)
    assert _run(capsys, "freedom", "--couple", "-1,0,0")[0] == 0


@pytest.mark.parametrize("argv, words", [
    (["trajectory", "3RRPRR", "-q", "--path", "{csv}", "--samples", "5"], "--samples"),
    (["trajectory", "3RRPRR", "-q", "--path", "{csv}", "--t-range", "0", "2"], "--t-range"),
    (["trajectory", "3RRPRR", "-q", "--path", "{csv}", "--title", "T"], "add --plot"),
    (["trajectory", "3RRPRR", "-q", "--path", "{csv}", "--plot", "{csv}/x.png"],
     "is a file, not a folder"),
    (["optimize", "3RRPRR", "-q", "--grid", "alpha=-5:5:3", "--vary", "l=30:120",
      "--lti-threshold", "0.2"], "gtw-volume"),
    (["optimize", "3RRPRR", "-q", "--grid", "alpha=-5:5:3", "--vary", "l=30:120",
      "--constraint", "stroke<=nan"], "finite number"),
    (["check", "3RRPRR", "--seed", "3"], "--poses"),
    (["analyze", "3RRPRR", "--pose", "alpha=-5000"], "alpha = -5000 deg"),
    (["analyze", "3RRPRR", "--set", "L=1e-300"], "with the overrides L=1e-300"),
    (["leg", "UPU/bogus"], "catalog variant"),
])
def test_an_option_that_would_be_ignored_or_misread_is_one_line_and_exit_2(tmp_path, capsys,
                                                                           argv, words):
    csv = tmp_path / "p.csv"
    csv.write_text("t,alpha,beta,Zo\n0,0,0,80\n0.5,2,1,80\n1,4,2,80\n")
    rc, out, err = _run(capsys, *[a.replace("{csv}", str(csv)) for a in argv])
    assert rc == 2 and out == ""                  # (refused before any work or output)
    lines = err.strip().splitlines()
    assert len(lines) == 1 and words in lines[0], err


def test_json_is_spelled_json_everywhere(tmp_path, capsys):
    csv = tmp_path / "p.csv"
    csv.write_text("t,alpha,beta,Zo\n0,0,0,80\n0.5,2,1,80\n1,4,2,80\n")
    a = _run(capsys, "trajectory", "3RRPRR", "-q", "--path", str(csv), "--json")
    b = _run(capsys, "trajectory", "3RRPRR", "-q", "--path", str(csv), "--format", "json")
    assert a[0] == b[0] == 0 and json.loads(a[1]) == json.loads(b[1])
    rc, out, _ = _run(capsys, "validate", "UPU", "--json")
    assert rc == 0 and "summary" in json.loads(out)


def test_check_json_says_its_workload(capsys):
    rc, out, _ = _run(capsys, "check", "3RRPRR", "--json")
    w = json.loads(out)[0]["workload"]
    pm = screwkit.load_pm("3RRPRR")
    assert rc == 0 and w["force"] == list(pm.workload.force) and w["applied_at"] == "o"
    assert w["torque"] == list(pm.workload.torque) and "declared" in w["source"]
    rc, out, _ = _run(capsys, "check", "6SPS", "--json")
    w = json.loads(out)[0]["workload"]
    assert np.allclose(w["force"], np.array([1.0, 2.0, 3.0]) / np.sqrt(14.0))
    assert "check load" in w["source"]


def test_a_title_of_ones_own_keeps_the_workload_on_the_figure():
    from screwkit.cli._commands.draw import _title
    res = screwkit.analyze("3RRPRR")
    t = _title(res, "kN", "cm", False, "My title")
    assert t.startswith("My title\n") and "F = [-20, -30, -60] kN" in t and "at o" in t


def test_the_assembly_modes_search_says_its_progress():
    calls = []
    res = screwkit.assembly_modes("3RPS", {"r1": 67.1, "r2": 69.5, "r3": 64.8}, seeds=9000,
                                  progress=lambda d, t: calls.append((d, t)))
    assert calls == [(4096, 9000), (8192, 9000), (9000, 9000)]
    alone = screwkit.assembly_modes("3RPS", {"r1": 67.1, "r2": 69.5, "r3": 64.8}, seeds=9000)
    assert len(res) == len(alone) and alone.converged == res.converged
