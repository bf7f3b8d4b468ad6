"""`screwkit leg`: text and JSON output, and one-line errors (exit code != 0)."""

import json
import os
import shutil
import subprocess
import sys
from pathlib import Path

import numpy as np
import pytest

from screwkit.cli import main


def run(capsys, *argv):
    code = main(list(argv))
    out, err = capsys.readouterr()
    return code, out, err


def test_text_output_names_chain_connectivity_force_and_rules(capsys):
    code, out, err = run(capsys, "leg", "RRPRR")
    assert code == 0 and err == ""
    assert "RR_PRR" in out
    for name in ("R1", "R2", "P3", "R4", "R5"):
        assert name in out
    assert "connectivity: 5" in out
    assert "1 force" in out
    # the force is along Y through (50, 0, 0) (hand derivation in test_hand_derived.py)
    assert "force along (0, -1, 0)" in out or "force along (0, 1, 0)" in out
    assert "(50, 0, 0)" in out
    assert "(rule 1)" in out and "(rule 2)" in out
    assert "actuation wrench of P3" in out


def test_json_output(capsys):
    code, out, err = run(capsys, "leg", "RRPRR", "--json")
    assert code == 0
    d = json.loads(out)
    assert [j["name"] for j in d["joints"]] == ["R1", "R2", "P3", "R4", "R5"]
    assert all(j["origin"] in "RPHUSC" for j in d["joints"])
    assert d["connectivity"] == 5
    (c,) = d["constraints"]
    assert c["kind"] == "force"
    assert abs(abs(c["direction"][1]) - 1) < 1e-12
    # the point lies on the line through (50, 0, 0) along Y
    assert np.allclose(np.array(c["point"])[[0, 2]], [50, 0], atol=1e-9)
    assert c["pitch"] == 0
    assert {r["rule"] for r in c["rules"]} == {1, 2} and all(r["holds"] for r in c["rules"])
    act = d["actuation"]
    assert act["joint"] == "P3" and act["kind"] == "force"
    dvec = np.array([-50.0, 0, 80]) / np.sqrt(8900)
    assert np.allclose(act["direction"], dvec)


def test_json_kinds_of_all_members(capsys):
    # origin letters of compound joints, couples without a point, inf pitch as a string
    code, out, _ = run(capsys, "leg", "UPU/couple", "--json")
    d = json.loads(out)
    assert [j["origin"] for j in d["joints"]] == ["U", "U", "P", "U", "U"]
    (c,) = d["constraints"]
    assert c["kind"] == "couple" and "point" not in c and c["pitch"] == "inf"
    assert {r["rule"] for r in c["rules"]} == {3, None}
    code, out, _ = run(capsys, "leg", "SPS", "--json")
    d = json.loads(out)
    assert d["constraints"] == [] and d["dependent_joints"] == ["S3c"]


def test_bare_string_and_seed(capsys):
    code, out, _ = run(capsys, "leg", "PPPP", "--seed", "3")
    assert code == 0 and "generic geometry (seed 3)" in out
    assert "dependent joints: P4" in out and "actuation wrench: none" in out


@pytest.mark.parametrize("arg, words", [
    ("RXP", "unknown joint letter 'X'"),
    ("", "empty leg string"),
    ("3RR+", "a leg count belongs to a PM string"),
    ("R__P", "second actuation marker"),
])
def test_bad_leg_strings(capsys, arg, words):
    code, out, err = run(capsys, "leg", arg)
    assert code != 0 and out == ""
    lines = err.strip().splitlines()
    assert len(lines) == 1 and words in lines[0] and "Traceback" not in err
    assert lines[0].startswith("screwkit leg: error:")


def test_model_file_with_missing_field(capsys, tmp_path):
    bad = tmp_path / "model.yaml"
    bad.write_text("legs:\n  - name: RPS/mine\n    string: R_PS\n")
    code, out, err = run(capsys, "leg", "RPS/mine", "--model", str(bad))
    assert code != 0
    lines = err.strip().splitlines()
    assert len(lines) == 1 and "Traceback" not in err
    assert str(bad) in lines[0] and "RPS/mine" in lines[0] and "'joints'" in lines[0]


def test_model_file_with_bad_yaml_and_missing_file(capsys, tmp_path):
    bad = tmp_path / "broken.yaml"
    bad.write_text("legs:\n  - name: X\n   string: RPS\n")
    code, _, err = run(capsys, "leg", "X", "--model", str(bad))
    assert code != 0 and len(err.strip().splitlines()) == 1 and "line 3" in err
    code, _, err = run(capsys, "leg", "X", "--model", str(tmp_path / "nope.yaml"))
    assert code != 0 and len(err.strip().splitlines()) == 1 and "nope.yaml" in err


def _console_script():
    exe = Path(sys.executable).with_name("screwkit")
    return str(exe) if exe.exists() else shutil.which("screwkit")


def test_console_script(tmp_path):
    exe = _console_script()
    if exe is None:
        pytest.skip("the screwkit console script is not installed")
    ok = subprocess.run([exe, "leg", "SPR", "--json"], capture_output=True, text=True, timeout=120)
    assert ok.returncode == 0, ok.stderr
    d = json.loads(ok.stdout)
    assert d["connectivity"] == 5 and [c["kind"] for c in d["constraints"]] == ["force"]
    # a catalog with a missing field, through the environment variable
    bad = tmp_path / "catalog.yaml"
    bad.write_text("legs:\n  - string: R_PS\n    joints: []\n")
    env = dict(os.environ, SCREWKIT_CATALOG=str(bad))
    fail = subprocess.run([exe, "leg", "RPS"], capture_output=True, text=True, timeout=120, env=env)
    assert fail.returncode == 2 and fail.stdout == ""
    lines = fail.stderr.strip().splitlines()
    assert len(lines) == 1 and "Traceback" not in fail.stderr
    assert str(bad) in lines[0] and "legs[0]" in lines[0] and "'name'" in lines[0]
