"""``screwkit check``: pass/fail table, JSON, --all, exit statuses."""

import json
from pathlib import Path

import pytest

pytest.importorskip("pinocchio")

from screwkit.cli import COMMANDS, main  # noqa: E402
from screwkit.interop import SUMMARY_CHECKS  # noqa: E402
from screwkit.pm import pm_names  # noqa: E402

USER_PM = str(Path(__file__).parent / "data" / "user_pm.yaml")
CHECKS = [k for k, _ in SUMMARY_CHECKS]


def test_registered_after_analyze():
    assert COMMANDS[:4] == ["leg", "catalog", "analyze", "check"]


def test_text_table(capsys):
    assert main(["check", "3SPR", "--pose", "alpha=4", "--pose", "beta=-2", "--pose", "Zo=63"]) == 0
    out = capsys.readouterr().out.splitlines()
    assert out[0].split() == ["PM", "pose", "check", "deviation", "tolerance", "pass"]
    rows = [ln.split() for ln in out[1:-1]]
    assert [r[2] for r in rows] == CHECKS
    for r in rows:
        assert r[0] == "3SPR" and r[1] == "alpha=4,beta=-2,Zo=63" and r[5] == "ok"
        assert float(r[3]) <= float(r[4])
    assert out[-1].startswith("1 pose(s) of 1 PM(s), 8 checks: all passed")


def test_json_and_drawn_poses(capsys):
    assert main(["check", "2SPS+2SPR", "--poses", "2", "--seed", "5", "--json"]) == 0
    reps = json.loads(capsys.readouterr().out)
    assert len(reps) == 2 and all(r["pm"] == "2SPS+2SPR" and r["passed"] for r in reps)
    assert reps[0]["pose"] != reps[1]["pose"]
    assert set(reps[0]["pose"]) == {"alpha", "beta", "gamma", "Zo"}
    assert [r["check"] for r in reps[0]["rows"]] == CHECKS
    assert reps[0]["detail"]["values"]["dof"] == 4


def test_user_model_file(capsys):
    assert main(["check", "--model", USER_PM, "--json"]) == 0
    (rep,) = json.loads(capsys.readouterr().out)
    assert rep["pm"] == "3RHS/user" and rep["passed"]


def test_failed_check_exits_1(capsys):
    # a tolerance below the rounding error of the comparisons: the relative checks fail
    assert main(["check", "3SPR", "--rtol", "1e-30"]) == 1
    out = capsys.readouterr().out
    assert "FAIL" in out and "FAILED" in out.splitlines()[-1]


def test_all(capsys):
    assert main(["check", "--all", "--poses", "1", "--json"]) == 0
    reps = json.loads(capsys.readouterr().out)
    assert sorted(r["pm"] for r in reps) == sorted(pm_names())
    assert all(r["passed"] for r in reps)


@pytest.mark.parametrize("argv,words", [
    (["check", "NOPE"], "unknown PM"),
    (["check"], "name a PM"),
    (["check", "--all", "3SPR"], "--all"),
    (["check", "3SPR", "--poses", "0"], "--poses"),
    (["check", "3SPR", "--pose", "alpha"], "NAME=VALUE"),
    (["check", "3SPR", "--pose", "Xo=1"], "dependent"),
    (["check", "3SPR", "--rtol", "-1"], "--rtol"),
    (["check", "--model", "/nonexistent/x.yaml"], "x.yaml"),
])
def test_bad_input_is_one_line_exit_2(capsys, argv, words):
    assert main(argv) == 2
    err = capsys.readouterr().err
    assert err.count("\n") == 1 and err.startswith("screwkit check: error:") and words in err
