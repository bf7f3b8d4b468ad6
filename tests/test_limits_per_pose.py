"""A model's declared ``limits:`` at one pose: every per-pose command says when a pose is
beyond them (as a map counts its cells outside them), never reporting it as fine.

The extensions ``|a_i - A_i|`` are checked here from the base and platform points the
analysis reports, against the bounds written into the model file."""

from __future__ import annotations

import json

import numpy as np
import pytest

import screwkit
from screwkit.cli import main


def _model(tmp_path, bounds):
    text = screwkit.load_pm("3RRPRR").to_yaml()
    path = tmp_path / "lim.yaml"
    path.write_text(text.rstrip("\n") + f"\n    limits:\n      extensions: {list(bounds)}\n",
                    encoding="utf-8")
    return str(path)


@pytest.mark.parametrize("bounds, inside", [((100, 120), False), ((0, 1000), True)])
def test_analyze_fk_trajectory_say_when_a_pose_is_outside_the_limits(tmp_path, capsys,
                                                                     bounds, inside):
    path = _model(tmp_path, bounds)
    an = screwkit.analyze(path)
    ext = np.linalg.norm(np.asarray(an.solution._platform[2]).reshape(-1, 3)
                         - np.asarray(an.solution.base_points), axis=1)
    assert np.all((ext >= bounds[0]) & (ext <= bounds[1])) == inside
    said = [w for w in an.warnings if "declared limits" in w]
    assert bool(said) != inside
    assert main(["analyze", "--model", path, "--json"]) == 0
    out = json.loads(capsys.readouterr().out)
    assert out["within_limits"] is inside
    assert main(["fk", "--model", path, "--actuators", "q1=0,q2=0,q3=0", "--json"]) == 0
    fk = json.loads(capsys.readouterr().out)
    home_ext = screwkit.analyze(path, {"alpha": 0, "beta": 0, "Zo": 80}).solution.extensions
    assert fk["solutions"][0]["within_limits"] is bool(
        np.all((home_ext >= bounds[0]) & (home_ext <= bounds[1])))
    assert main(["trajectory", "--model", path, "--expr", "alpha=t", "--expr", "beta=0",
                 "--expr", "Zo=80", "--samples", "2", "--format", "json"]) == 0
    cap = capsys.readouterr()
    tr = json.loads(cap.out)
    assert all(("outside the model's declared limits" in m) != inside for m in tr["message"])
    assert ("outside the model's declared limits" in cap.err) != inside


def test_export_warns_of_its_keyframe_as_analyze_does(tmp_path, capsys):
    out = str(tmp_path / "m.xml")
    assert main(["export", "3RRPRR", "--mjcf", out, "--massless", "--pose", "Zo=-80"]) == 0
    assert "keyframe 0: the platform centre o is below the base" in capsys.readouterr().err
    assert main(["export", "3RRPRR", "--mjcf", out, "--massless"]) == 0
    assert "warning" not in capsys.readouterr().err
    assert main(["export", "3RRPRR", "--urdf", str(tmp_path / "a.urdf"), "--massless"]) == 2
    err = capsys.readouterr().err
    assert "error: --massless given: --pose and --massless are options of --mjcf" in err
