"""Issue 20, every listed case at the command line: each quantity bounded and checked
where it enters, one-line errors naming the option (or the file, line and key), no Python
keyword in a CLI message, workloads stated and said, fk's modes marked."""

from __future__ import annotations

import contextlib
import io
import json

import numpy as np
import pytest

import screwkit
from screwkit.cli import main

PAPER = ["--force=-20,-30,-60", "--torque=-30,-30,100"]
#: a pose of the 3RPS 1.6e-6 deg from its actuation singularity (alpha = -43.128847103 deg)
NEAR = ["--pose", "alpha=-43.1288455", "--pose", "beta=0", "--pose", "Zo=60"]


def cli(*argv):
    out, err = io.StringIO(), io.StringIO()
    with contextlib.redirect_stdout(out), contextlib.redirect_stderr(err):
        try:
            code = main([str(a) for a in argv])
        except SystemExit as exc:
            code = exc.code
    return code, out.getvalue(), err.getvalue()


def one_line_error(code, err, *words):
    assert code == 2, err
    lines = err.strip().splitlines()
    assert len(lines) == 1 and ": error: " in lines[0], err
    for w in words:
        assert w in lines[0], (w, lines[0])
    for kw in ("guess=", "params=", "actuator=", "force=", "torque=", "stiffness="):
        assert kw not in lines[0], lines[0]           # CLI messages name CLI options
    return lines[0]


@pytest.mark.parametrize("argv, words", [
    (["map", "3RRPRR", "--grid", "alpha=-5:5:nan", *PAPER], ["--grid alpha COUNT"]),
    (["size", "3RRPRR", "--grid", "alpha=-5:5:nan", *PAPER], ["--grid alpha COUNT"]),
    (["map", "3RRPRR", "--grid", "alpha=-1e308:1e308:3", *PAPER], ["--grid alpha START",
                                                                    "limit"]),
    (["map", "3RRPRR", "--grid", "alpha=-5000:5:3", *PAPER], ["beyond the limit", "deg"]),
    # an angle far beyond any limit is refused with the angle's limit, not the magnitude's
    (["map", "3RRPRR", "--grid", "alpha=-1e13:5:3", *PAPER], ["--grid alpha START",
                                                             "+-3600 deg"]),
    (["view", "3RRPRR", "--grid", "beta=1e20:5:3", "--html", "v.html"],
     ["--grid beta START", "+-3600 deg"]),
    (["map", "3RRPRR", "--grid", "alpha=-5:5:3", "--seed", "-1", *PAPER], ["--seed"]),
    (["map", "3RRPRR", "--grid", "alpha=-5:5:3", "--scheduler", "tcp://nonsense", *PAPER],
     ["--scheduler", "tcp://HOST:PORT"]),
    (["trajectory", "3RRPRR", "--expr", "alpha=t", "--expr", "beta=0", "--expr", "Zo=80",
      "--scheduler", "tcp://nonsense"], ["--scheduler"]),
    (["synthesize", "3T", "--scheduler", "tcp://nonsense"], ["--scheduler"]),
    (["export", "3RRPRR", "--urdf", ""], ["--urdf", "empty"]),
    (["map", "3RRPRR", "--grid", "alpha=-5:5:3", "--out", "", *PAPER], ["--out", "empty"]),
    (["map", "3RRPRR", "--grid", "alpha=-5:5:3", "--plot", "", *PAPER], ["--plot", "empty"]),
    (["trajectory", "3RRPRR", "--expr", "alpha=t", "--expr", "beta=0", "--expr", "Zo=80",
      "--out", ""], ["--out", "empty"]),
    (["synthesize", "3T", "--write", ""], ["--write", "empty"]),
    (["trajectory", "3RRPRR", "--expr", "alpha=t", "--expr", "beta=0", "--expr", "Zo=80",
      "--mass", "m.yaml"], ["--mass", "--dynamics"]),
    (["freedom", "--leg", ""], ["--leg", "empty"]),
    (["stiffness", "3RRPRR", "--k-actuator", "1e-320"], ["--k-actuator", "positive"]),
    (["stiffness", "3RRPRR", "--k-actuator", "1e308"], ["--k-actuator", "1e+20"]),
    (["stiffness", "3RRPRR", "--k-couple", "nan"], ["--k-couple", "finite"]),
    (["stiffness", "3RRPRR", "--k-couple", "-1"], ["--k-couple", "positive"]),
    (["stiffness", "3RRPRR", "--k-couple", "5"], ["--k-couple", "no constraint couple rows"]),
    (["stiffness", "3RRPRR", "--k-couple", "inf"], ["--k-couple"]),
    (["fk", "3RPS", "--actuators", "r1=67,r2=69,r3=64", "--seeds", "5"], ["--seeds", "--all"]),
    (["fk", "3RPS", "--actuators", "r1=67,r2=69,r3=64", "--all", "--seeds", "-3"],
     ["--seeds"]),
    (["size", "3RPS", "--grid", "alpha=-5:5:3"], ["--force FX,FY,FZ", "declares no workload"]),
    (["map", "3RPS", "--grid", "alpha=-5:5:3", "--plot", "m.png", "--quantity", "forces"],
     ["--force FX,FY,FZ", "declares no workload"]),
    (["trajectory", "3RPS", "--expr", "alpha=t", "--expr", "beta=0", "--expr", "Zo=60"],
     ["--force FX,FY,FZ", "declares no workload"]),
])
def test_bad_values_are_one_line_errors_naming_the_option(argv, words):
    code, _, err = cli(*argv)
    one_line_error(code, err, *words)


def test_a_map_without_a_workload_has_no_forces_and_says_so():
    code, out, err = cli("map", "3RPS", "--grid", "alpha=-5:5:3", "--quiet", "--json")
    d = json.loads(out)
    assert code == 0 and d["workload"]["source"].startswith("none")
    assert d["extremes"]["rows"] == [] and d["counts"]["conditioning"]["regular"] == 3
    code, out, err = cli("map", "3RPS", "--grid", "alpha=-5:5:3", "--quiet")
    assert "no forces: no workload" in out and "--force" in out


def test_workloads_csv_with_a_duplicated_column(tmp_path):
    f = tmp_path / "loads.csv"
    f.write_text("Fx,Fy,Fz,Tx,Ty,Tz,Fz\n1,2,3,4,5,6,7\n")
    code, _, err = cli("size", "3RRPRR", "--grid", "alpha=-5:5:2", "--workloads", f, "--quiet")
    one_line_error(code, err, "loads.csv", "line 1", "'Fz'", "twice")


def test_a_platform_of_1e308_kg_is_refused_with_file_line_and_key(tmp_path):
    f = tmp_path / "m.yaml"
    f.write_text("dynamics:\n  platform: {mass: 1.0e308}\n")
    code, _, err = cli("trajectory", "3RRPRR", "--expr", "alpha=t", "--expr", "beta=0",
                       "--expr", "Zo=80", "--dynamics", "--mass", f, *PAPER)
    one_line_error(code, err, "dynamics.platform.mass", "beyond the limit")


@pytest.mark.parametrize("block, key", [
    ("platform: {mass: 2, inertia: [1, 1, 1.0e300]}", "platform.inertia"),
    ("gravity: [0, 0, 1.0e300]\n  platform: {mass: 2}", "gravity"),
    ("stiffness: {actuator: 1.0e-320}", "stiffness.actuator"),
    ("stiffness: {actuator: 1.0e308}", "stiffness.actuator"),
    ("legs: {friction: {P: {viscous: .inf}}}", "friction.P.viscous"),
])
def test_masses_inertias_gravity_friction_stiffness_are_bounded(tmp_path, block, key):
    f = tmp_path / "m.yaml"
    f.write_text(f"dynamics:\n  {block}\n")
    with pytest.raises(screwkit.ScrewkitError, match=key.replace(".", r"\.")):
        screwkit.pm.dynamics_for(screwkit.load_pm("3RPS"), str(f))


def test_model_check_lists_every_problem_of_every_pm(tmp_path):
    f = tmp_path / "two.yaml"
    f.write_text("""\
pms:
  A:
    dimensions: {R: 80, r: 30}
    base: {shape: triangle, circumradius: R, sidez: 3}
    platform: {shape: hexagon, circumradius: r}
    legs: [SPR, SPX, SPR]
    independent: [alpha, beta, Zo]
    pose: {alpha: 5, beta: 9999, Zo: R}
    dof: 3
    colour: red
  B:
    units: {length: cm, force: kN}
    dimensions: {R: 80, r: 30}
    base: {shape: triangle, circumradius: R}
    platform: {shape: triangle, circumradius: r}
    legs: [SPR, SPR, SPR]
    independent: [alpha, beta, Zo]
    pose: {alpha: 5, beta: -3, Zo: R}
    dof: 3
    workload: {force: [0, 0, -1]}
    dynamics:
      platform: {mass: 1.0e308}
      stiffness: {actuator: -5, force: 1.0e-320}
""")
    code, out, err = cli("model", "check", f, "--json")
    assert code == 2 and len(err.strip().splitlines()) == 1
    d = json.loads(out)
    found = {(p["entry"], p["field"]) for p in d["problems"]}
    for key in [("A", "base"), ("A", "platform.shape"), ("A", "legs[1]"), ("A", "pose.beta"),
                ("A", "colour"), ("B", "workload.units"), ("B", "dynamics.platform.mass"),
                ("B", "dynamics.stiffness.actuator"), ("B", "dynamics.stiffness.force")]:
        assert key in found, (key, sorted(found))
    assert all(p["line"] for p in d["problems"])


def test_the_docs_my3spr_model_loads_and_prints_no_placeholder(tmp_path):
    f = tmp_path / "my.yaml"
    f.write_text("""\
pms:
  my3SPR:
    dimensions: {R: 80, r: 30}
    base: {shape: triangle, circumradius: R}
    platform: {shape: triangle, circumradius: r}
    legs: [SPR, SPR, SPR]
    euler: XYZ
    independent: [alpha, beta, Zo]
    pose: {alpha: 5, beta: -3, Zo: R}
    dof: 3
    motion: 1T2R
""")
    assert cli("model", "check", f)[0] == 0
    pm = screwkit.load_pm(str(f))
    assert pm.string == "3SPR" and pm.name == "my3SPR"
    code, out, err = cli("analyze", "--model", f, "--force", "0,0,-1")
    assert code == 0, err
    for placeholder in ("length unit", "force unit", "mass unit"):
        assert placeholder not in out
    assert "[L]" in out and "[F.L]" in out and "declares no units" in out


def test_a_pm_name_that_is_a_pm_string_is_read_as_one():
    assert screwkit.load_pm("3RRPRR").string == "3RRPRR"


def test_analyze_without_a_workload_prints_kinematics_then_one_line_error():
    code, out, err = cli("analyze", "3RPS")
    line = one_line_error(code, err, "--force FX,FY,FZ", "--torque TX,TY,TZ")
    assert "declares no workload" in line
    assert "mobility: 3 DOF" in out and "unified Jacobian" in out and "leg 1 actuation" in out
    assert "statics: not computed" in out and "leg 1 active" not in out
    code, out, err = cli("analyze", "3RPS", "--json")
    d = json.loads(out)
    assert code == 2 and d["statics"] is None and d["jacobian"] and d["error"]["message"]


def test_every_output_says_which_workload_and_where_from():
    code, out, _ = cli("analyze", "3RRPRR")
    assert code == 0 and "(workload: declared default (the paper's workload, section 5.1))" in out
    code, out, _ = cli("analyze", "3RPS", "--force", "0,0,-1")
    assert code == 0 and "T = (0, 0, 0) kN.cm at o (workload: command line)" in out
    code, out, _ = cli("analyze", "3RPS", "--force", "0,0,-1", "--json")
    assert json.loads(out)["workload"]["source"] == "command line"
    code, out, _ = cli("catalog", "3RPS")
    assert "workload: none declared" in out
    code, out, _ = cli("catalog", "2SPS+2SPR")
    assert "workload: F = (-20, -30, -60) kN, T = (-30, -30, 100) kN.cm at o" in out


def test_force_alone_means_zero_torque_and_the_help_says_so():
    a = screwkit.analyze("3RRPRR", force=[1, 2, 3])
    b = screwkit.analyze("3RRPRR", force=[1, 2, 3], torque=[0, 0, 0])
    np.testing.assert_array_equal(a.statics.values, b.statics.values)
    code, out, _ = cli("analyze", "3RRPRR", "--force", "1,2,3", "--json")
    np.testing.assert_allclose(json.loads(out)["statics"]["values"], b.statics.values,
                               rtol=1e-12)
    code, out, _ = cli("analyze", "--help")
    assert "--force alone means zero torque" in " ".join(out.split())


def test_analyze_at_zo_0_warns_that_the_platform_is_in_the_base_plane():
    code, out, err = cli("analyze", "3RRPRR", "--pose", "Zo=0")
    assert code == 0 and "in the base plane" in err
    code, out, err = cli("analyze", "3RRPRR", "--pose", "Zo=-80", "--json")
    assert json.loads(out)["conditioning"]["side_of_base"] == "below"


def test_near_singular_pose_is_said_alike_by_every_command(tmp_path):
    """One classification: analyze, trajectory, map, size, stiffness and dynamics give the
    3RPS pose 1.6e-6 deg from its singularity the class near-singular."""
    code, out, err = cli("analyze", "3RPS", *NEAR, "--force", "0,0,-1", "--json")
    d = json.loads(out)
    assert d["conditioning"]["class"] == "near-singular" and "near-singular" in err
    assert d["conditioning"]["condition_number"] > 1e7
    code, out, err = cli("trajectory", "3RPS", "--expr", "alpha=-43.1288455+0*t", "--expr",
                         "beta=0", "--expr", "Zo=60", "--samples", "2", "--force", "0,0,-1",
                         "--format", "json")
    t = json.loads(out)
    assert t["status"] == ["near-singular"] * 2 and t["conditioning"] == ["near-singular"] * 2
    assert "near-singular" in t["message"][0] and "near-singular" in err
    code, out, err = cli("map", "3RPS", "--grid", "alpha=-43.1288455:-43.1288455:1", "--fix",
                         "beta=0", "--fix", "Zo=60", "--force", "0,0,-1", "--json", "--quiet")
    assert json.loads(out)["counts"]["conditioning"]["near-singular"] == 1
    code, out, err = cli("size", "3RPS", "--grid", "alpha=-43.1288455:-43.1288455:1", "--fix",
                         "beta=0", "--fix", "Zo=60", "--force", "0,0,-1", "--json", "--quiet")
    rows = json.loads(out)["extremes"]                # (a T_r zero by its structure: no pose)
    assert {r["conditioning"] for r in rows if not r["round_off"]} == {"near-singular"}
    assert all(r["max_abs"] == 0.0 for r in rows if r["round_off"])
    code, out, err = cli("stiffness", "3RPS", *NEAR, "--k-actuator", "2000", "--k-force",
                         "5000", "--force", "0,0,-1", "--json")
    s = json.loads(out)
    assert code == 0 and s["conditioning"]["class"] == "near-singular"
    assert all(np.isfinite(s["deflection"]["translation"])) and "near-singular" in err
    pytest.importorskip("pint")
    m = tmp_path / "m.yaml"
    m.write_text("dynamics:\n  platform: {mass: 20}\n")
    code, out, err = cli("trajectory", "3RPS", "--expr", "alpha=-43.1288455+0*t", "--expr",
                         "beta=0", "--expr", "Zo=60", "--samples", "3", "--dynamics", "--mass",
                         m, "--force", "0,0,-1", "--format", "json")
    assert code == 0, err
    assert json.loads(out)["conditioning"] == ["near-singular"] * 3


def test_fk_all_lists_modes_above_the_base_first_and_marks_them():
    code, out, _ = cli("fk", "3RPS", "--actuators", "r1=67.1,r2=69.5,r3=64.8", "--all",
                       "--seeds", "300", "--json")
    sols = json.loads(out)["solutions"]
    sides = [s["side_of_base"] for s in sols]
    assert sides == sorted(sides, key=["above", "in the base plane", "below"].index)
    assert "below" in sides and sides[0] == "above"
    # independent: the side is the sign of Zo (a flat base at z = 0, home above it)
    assert all((s["pose"]["Zo"] > 0) == (s["side_of_base"] == "above") for s in sols)
    assert sols[0]["working_mode"] and all(not s["working_mode"] for s in sols
                                           if s["side_of_base"] == "below")
    assert all(s["mode"] and s["conditioning"] for s in sols)


def test_fk_without_a_solution_is_exit_2_with_the_residual_on_stderr():
    code, out, err = cli("fk", "3RPS", "--actuators", "r1=500,r2=69.5,r3=64.8")
    line = one_line_error(code, err, "no solution", "residual")
    assert float(line.split("residual ")[1].split()[0]) > 1e-6
