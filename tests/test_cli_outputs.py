"""Commands that write files create the folders they write to (a fresh folder, as a new user
runs the tutorial), and say what they wrote."""

from __future__ import annotations

import os
import shlex
import subprocess
import sys
from pathlib import Path

import numpy as np
import pytest

import screwkit

from screwkit.cli import COMMANDS, main

# the paper's workload, stated (only 3RRPRR and 2SPS+2SPR declare it as their default)
PAPER_LOAD = {"force": (-20.0, -30.0, -60.0), "torque": (-30.0, -30.0, 100.0)}
PAPER_ARGS = ["--force=-20,-30,-60", "--torque=-30,-30,100"]

EXPR = ["--expr", "alpha=8*sin(2*pi*t)", "--expr", "beta=6*sin(2*pi*t+1)", "--expr", "Zo=70+20*t"]

CASES = [
    ("validate", ["validate", "UPU", "--no-catalog", "--format", "markdown", "--out", "{d}/t.md"]),
    ("trajectory", ["trajectory", "3RRPRR", *EXPR, "--samples", "5", "--out", "{d}/p.csv",
                    "--plot", "{d}/fig/p.png"]),
    ("draw", ["draw", "3RRPRR", "-o", "{d}/d.png"]),
    ("leg", ["leg", "SPR", "--draw", "{d}/leg.png"]),
    ("map", ["map", "3RRPRR", "--grid", "alpha=-2:2:3", "--out", "{d}/m.csv"]),
]


@pytest.mark.parametrize("cmd,argv", CASES, ids=[c for c, _ in CASES])
def test_missing_output_folders_are_created(cmd, argv, tmp_path, monkeypatch, capsys):
    if cmd not in COMMANDS:
        pytest.skip(f"no {cmd} command")
    if any(a.endswith(".png") for a in argv):
        pytest.importorskip("matplotlib")
    if cmd == "map":
        pytest.importorskip("xarray")
    monkeypatch.chdir(tmp_path)
    d = "new/deeper"
    args = [a.format(d=d) for a in argv]
    rc = main(args)
    captured = capsys.readouterr()
    assert rc == 0, captured.err
    for a in args:
        if a.startswith(d):
            assert (tmp_path / a).is_file() and (tmp_path / a).stat().st_size > 0, a


def test_an_unwritable_output_is_one_line_exit_2(tmp_path, capsys):
    blocker = tmp_path / "file"
    blocker.write_text("x")
    rc = main(["validate", "UPU", "--no-catalog", "--out", str(blocker / "t.md")])
    err = capsys.readouterr().err
    assert rc == 2 and err.count("\n") == 1 and "cannot write" in err


def test_model_option_takes_file_hash_name(tmp_path, capsys):
    """``--model FILE#NAME`` picks one PM of a multi-PM file (the error for such a file
    suggests exactly that); the name is checked, and not given twice."""
    from screwkit.cli import main
    f = tmp_path / "two.yaml"
    body = ("    string: 3RRPRR\n    dimensions: {L: %s, l: 60}\n"
            "    base: {shape: triangle, side: L}\n    platform: {shape: triangle, side: l}\n"
            "    legs: [RRPRR, RRPRR, RRPRR]\n    euler: XYX\n"
            "    independent: [alpha, beta, Zo]\n    home: {alpha: 0, beta: 0, Zo: 80}\n"
            "    pose: {alpha: 5, beta: -3, Zo: 80}\n"
            "    dof: 3\n    motion: 1T2R\n")
    f.write_text("units: {length: cm, force: kN}\npms:\n  A:\n" + body % 120 + "  B:\n" + body % 130)
    assert main(["analyze", "--model", str(f), "--json", *PAPER_ARGS]) == 2
    assert f"{f.name}#NAME" in capsys.readouterr().err
    assert main(["analyze", "--model", f"{f}#B", "--json", *PAPER_ARGS]) == 0
    import json
    assert json.loads(capsys.readouterr().out)["pm"] == "B"
    assert main(["analyze", "--model", f"{f}#C", *PAPER_ARGS]) == 2
    assert "unknown PM 'C'" in capsys.readouterr().err
    assert main(["analyze", "A", "--model", f"{f}#B", *PAPER_ARGS]) == 2
    assert "already names its PM" in capsys.readouterr().err


@pytest.mark.parametrize("argv, what", [([], "screwkit"), (["model"], "screwkit model")])
def test_no_command_lists_them_and_exits_2(argv, what, capsys):
    assert main(argv) == 2
    out, err = capsys.readouterr()
    assert "usage:" in out
    assert err.count("\n") == 1 and err.startswith(f"{what}: error: ")


@pytest.mark.parametrize("argv", [
    ["trajectory", "3RRPRR", "--expr", "alpha=t", "--expr", "beta=1", "--expr", "Zo=80",
     "--samples", "3", "--plot", "FIG.txt"],
    ["draw", "3RRPRR", "-o", "FIG"],
    ["leg", "RRPRR", "--draw", "FIG.csv"],
])
def test_a_figure_name_matplotlib_cannot_write_is_refused_before_any_work(argv, tmp_path,
                                                                           capsys):
    argv = [a.replace("FIG", str(tmp_path / "fig")) for a in argv]
    assert main(argv) == 2
    out, err = capsys.readouterr()
    assert out == "" and err.count("\n") == 1 and "a figure's file name ends in" in err
    assert list(tmp_path.iterdir()) == []


def test_a_view_with_no_reachable_pose_is_refused(tmp_path, capsys):
    page = tmp_path / "v.html"
    assert main(["view", "3RRPRR", "--html", str(page), "--pose", "alpha=90"]) == 2
    err = capsys.readouterr().err
    assert err.count("\n") == 1 and "none of the 729 poses of the view is reachable" in err
    assert not page.exists()


@pytest.mark.skipif(not os.path.exists("/dev/full"), reason="needs /dev/full")
@pytest.mark.parametrize("redirect", ["> /dev/full", ">&-"])
def test_an_output_that_cannot_be_written_is_one_line_exit_2(redirect):
    # a full disk or a closed standard output: the system's error, said in one line (not an
    # internal error, exit 3, nor a traceback)
    cmd = f"{shlex.quote(sys.executable)} -m screwkit catalog {redirect}"
    proc = subprocess.run(["bash", "-c", cmd], capture_output=True, text=True, timeout=120,
                          env={**os.environ, "PYTHONPATH": str(Path(screwkit.__file__).parents[1])})
    assert proc.returncode == 2, proc.stderr
    assert proc.stderr.count("\n") == 1 and proc.stderr.startswith("screwkit")
    assert "Traceback" not in proc.stderr and "internal error" not in proc.stderr

@pytest.mark.parametrize("argv", [["--set", "L=nan"], ["--bogus"]])
def test_a_json_error_into_a_closed_pipe_is_one_line_exit_2(argv):
    """--json prints an error's JSON object on stdout too; where the reader has closed the
    pipe (its read end closed before the command starts: every write fails) the error's
    line on stderr is all, exit 2 (it was a BrokenPipeError traceback, exit 1)."""
    r, w = os.pipe()
    os.close(r)
    try:
        proc = subprocess.run([sys.executable, "-m", "screwkit", "analyze", "3RRPRR", "--json",
                               *argv], stdout=w, stderr=subprocess.PIPE, text=True, timeout=120,
                              env={**os.environ,
                                   "PYTHONPATH": str(Path(screwkit.__file__).parents[1])})
    finally:
        os.close(w)
    assert proc.returncode == 2, proc.stderr
    assert proc.stderr.count("\n") == 1 and proc.stderr.startswith("screwkit analyze: error:")



@pytest.mark.parametrize("argv, piece", [
    (["map", "3RRPRR", "--grid", "alpha=-10:10:1", "--grid", "Zo=70:90:3"],
     "one value cannot span -10 to 10"),
    (["map", "3RRPRR", "--grid", "alpha=-10:10:3", "--grid", "beta=-3:3:3", "--grid",
      "Zo=70:90:3", "--plot", "PNG", "--at", "Zo=1000"], "--at Zo=1000: outside the map's Zo"),
    (["synthesize", "3T", "--passive", "--no-passive"], "not allowed with argument --passive"),
])
def test_contradictory_or_out_of_range_choices_are_refused(argv, piece, tmp_path, capsys):
    argv = [str(tmp_path / "m.png") if a == "PNG" else a for a in argv]
    assert main(argv) == 2
    err = capsys.readouterr().err
    assert err.count("\n") == 1 and piece in err
    assert list(tmp_path.iterdir()) == []


def test_json_keeps_undefined_and_infinite_apart(capsys):
    """docs/conventions.md: NaN is null, an infinity the string "inf"; never a bare NaN or
    Infinity token.  3RPS with only its actuators compliant: its constraint rows are rigid,
    so three principal stiffnesses are infinite (a 3RPS has three constraint forces)."""
    import json

    from screwkit.cli import main
    from screwkit.cli._commands._common import to_jsonable
    assert to_jsonable([float("nan"), float("inf"), -float("inf"), 1.5]) == [None, "inf", "-inf", 1.5]
    assert main(["stiffness", "3RPS", "--k-actuator", "2000", "--force", "0,0,-1", "--json"]) == 0
    text = capsys.readouterr().out

    def refuse(token):
        raise AssertionError(f"bare {token} in the JSON")

    out = json.loads(text, parse_constant=refuse)
    rows = out["rows"]
    assert [r["label"] for r in rows if r["stiffness"] == "inf"] == \
        [r["label"] for r in rows if r["rigid"]] == [r["label"] for r in rows[3:]]
    assert all(r["stiffness"] == 2000 for r in rows[:3])
    # a rigid row system leaves rigid directions: an infinite principal stiffness among them
    p = out["principal"]
    assert "inf" in p["translational"]["stiffness"] + p["rotational"]["stiffness"]


@pytest.mark.parametrize("argv, what, hint", [
    (["analyze", "3RRPRR", "--bogus"], "screwkit analyze", None),
    (["analyze", "3RRPRR", "--forse", "1,2,3"], "screwkit analyze", "--force"),
    (["map", "3RRPRR", "--grid", "alpha=-1:1:3", "--jsn"], "screwkit map", "--json"),
    (["--bogus"], "screwkit", None),
])
def test_unknown_arguments_name_the_commands_help(capsys, argv, what, hint):
    from screwkit.cli import main
    assert main(argv) == 2
    err = capsys.readouterr().err.strip()
    assert len(err.splitlines()) == 1
    assert err.startswith(f"{what}: error: unrecognized arguments: ")
    assert err.endswith(f"(see '{what} --help')")
    assert (f"did you mean {hint}?" in err) if hint else "did you mean" not in err


@pytest.mark.parametrize("argv, piece", [
    (["analyze", "3RRPRR", "--force=-1,-2,-3", "--force=1,2,3"],
     "--force given twice with different values"),
    (["stiffness", "3RRPRR", "--k-actuator", "5", "--k-actuator", "7"],
     "--k-actuator given twice"),
    (["optimize", "3RRPRR", "--grid", "alpha=-10:10:3", "--fix", "beta=0", "--fix", "Zo=80",
      "--vary", "l=30:120", "--set", "l=50"], "--set l and --vary l"),
    (["optimize", "3RRPRR", "--grid", "alpha=-10:10:3", "--vary", "l=30:120", "--objective",
      "stroke", "--objective", "condition", "--no-polish"], "--no-polish"),
    (["synthesize", "1T2R", "--symmetric", "--passive", "--no-generate"],
     "--symmetric --passive"),
    (["synthesize", "3T", "--no-generate", "--wide"], "--no-generate with --wide"),
    (["synthesize", "3T", "--no-generate", "--variants", "3"], "--no-generate with --variants"),
    (["synthesize", "3T", "--legs", "6"], "not in 3 .. 5"),
    (["trajectory", "3RRPRR", "--expr", "alpha=t", "--expr", "beta=0", "--expr", "Zo=80",
      "--samples", "3", "--dynamics", "--smoothing", "1"], "--smoothing smooths"),
])
def test_contradictory_or_repeated_options_are_refused(capsys, argv, piece):
    assert main(argv) == 2
    err = capsys.readouterr().err
    assert piece in err and len(err.strip().splitlines()) == 1, err


def test_a_workloads_csv_with_units_in_its_header_says_so(tmp_path, capsys):
    f = tmp_path / "w.csv"
    f.write_text("Fx [N],Fy [N],Fz [N],Tx [N.m],Ty [N.m],Tz [N.m]\n1,2,3,4,5,6\n",
                 encoding="utf-8")
    assert main(["size", "3RRPRR", "--grid", "alpha=-5:5:3", "--workloads", str(f)]) == 2
    assert "a unit in the header is not read here" in capsys.readouterr().err


def test_optimize_without_a_feasible_design_exits_2(capsys):
    argv = ["optimize", "3RRPRR", "--grid", "alpha=-5:5:3", "--fix", "beta=0", "--fix", "Zo=80",
            "--vary", "l=30:120", "--constraint", "stroke<=-5", "--maxiter", "2", "--popsize",
            "3", "-q"]
    assert main(argv) == 2
    cap = capsys.readouterr()
    assert "no feasible design" in cap.out and "error: no design in the bounds" in cap.err


def test_map_at_is_read_in_the_model_units_whatever_units_shows(tmp_path, capsys):
    png = str(tmp_path / "p.png")
    argv = ["map", "3RRPRR", "--grid", "alpha=0:10:3", "--grid", "beta=-3:3:3", "--grid",
            "Zo=70:90:3", "--units", "SI", "--plot", png, "-q"]
    assert main(argv + ["--at", "Zo=80"]) == 0
    out = capsys.readouterr().out
    assert "Zo = 0.9 m" in out and "alpha = 10 deg" in out
    assert main(argv + ["--at", "Zo=0.8"]) == 2        # 0.8 cm: outside the map


@pytest.mark.parametrize("argv, piece", [
    (["catalog", "--path", "3RRPRR"], "give no PM or --json"),
    (["model", "schema", "--path", "--out", "s.json"], "screwkit model schema: error: --path"),
    (["model", "check", "x.yaml", "--jsn"], "did you mean --json? (see 'screwkit model check --help')"),
])
def test_model_and_catalog_options_that_conflict(tmp_path, monkeypatch, capsys, argv, piece):
    monkeypatch.chdir(tmp_path)
    assert main(argv) == 2
    assert piece in capsys.readouterr().err


def test_validate_out_takes_its_format_from_the_suffix_and_leg_seed_is_said(tmp_path, capsys):
    import json
    out = tmp_path / "v.json"
    assert main(["validate", "UPU", "-q", "--out", str(out)]) == 0
    assert json.loads(out.read_text())["summary"].startswith("1 strings")
    assert main(["leg", "RR_PRR", "--seed", "3"]) == 0
    assert "--seed (generic geometry of a bare string) is not used" in capsys.readouterr().err


def test_leg_and_assembly_modes_refuse_bad_arguments_as_input_errors():
    for call in (lambda: screwkit.leg(None), lambda: screwkit.leg("RPS", {"A": 1}),
                 lambda: screwkit.leg("RR_PRR", seed=-1), lambda: screwkit.leg("RPS", catalog="x"),
                 lambda: screwkit.assembly_modes("3RPS", [0, 0, 0], seed=-1)):
        with pytest.raises(screwkit.InputError):
            call()


def test_api_values_of_the_wrong_kind_are_input_errors(tmp_path):
    """Strings where numbers go, a directory to write a model to, a leg index beyond the
    legs, a passive leg given twice: InputError (they were ValueError, IsADirectoryError, an
    empty array, accepted)."""
    from screwkit.engine import unified_jacobian
    from screwkit.legs import Placement
    pm = screwkit.load_pm("3RPS")
    sol = screwkit.analyze(pm).solution
    o = np.asarray(sol.position).reshape(3)
    for call in (lambda: Placement(A="abc", a=[0, 0, 1]),
                 lambda: unified_jacobian(sol.legs, "0,0,80"),
                 lambda: screwkit.forward(pm, "1,2,3"),
                 lambda: screwkit.analyze(pm).jacobian.leg_rows(3),
                 lambda: unified_jacobian(sol.legs, o, passive=[0, 0]),
                 lambda: pm.to_yaml(str(tmp_path))):
        with pytest.raises(screwkit.InputError):
            call()


def test_validate_counts_one_leg_written_two_ways_once(capsys):
    assert main(["validate", "UPU", "UPU", "U_PU", "-q"]) == 0
    out = capsys.readouterr().out
    assert out.count("\nU_PU ") == 1 and "\n1 strings:" in out


def test_json_usage_errors_and_leg_expectations(tmp_path, capsys):
    import json
    assert main(["analyze", "3RRPRR", "--json", "--bogus"]) == 2
    out = json.loads(capsys.readouterr().out)
    assert out["error"]["type"] == "UsageError" and "--bogus" in out["error"]["message"]
    f = tmp_path / "legs.yaml"
    f.write_text("legs:\n  - name: PRS/wrong\n    string: _PRS\n    joints:\n"
                 "      - {axis: base.Z}\n"
                 "      - {axis: base.tangent, at: {offset: A, along: base.Z, fraction: 0.4}}\n"
                 "      - {at: a}\n"
                 "    expect: {forces: 2, couples: 0}\n", encoding="utf-8")
    assert main(["leg", "PRS/wrong", "--model", str(f), "--json"]) == 1
    d = json.loads(capsys.readouterr().out)
    assert d["expectation"] == {"holds": False, "problems": ["expected 2 forces, found 1"]}
    assert main(["model", "check", str(f)]) == 2
    assert "contradicts its 'expect'" in capsys.readouterr().out
    assert main(["leg", "RPS", "--json"]) == 0
    assert json.loads(capsys.readouterr().out)["expectation"]["holds"] is True


def test_size_workloads_are_named_triples(capsys):
    for w, piece in (([("a", None, None)], "its force and torque"),
                     ([("a", [0, 0, 1], [0, 0, 0]), ("a", [0, 0, 2], [0, 0, 0])],
                      "names must differ"),
                     ([("a", [0, 0, 1])], "name, force")):
        with pytest.raises(screwkit.InputError, match=piece):
            screwkit.size("3RRPRR", {"alpha": (-2, 2, 3)}, workloads=w, degrees=True)


def test_a_model_file_whose_name_holds_a_hash(tmp_path, monkeypatch, capsys):
    """`h#x.yaml` is a file, not the PM `x.yaml` of a file `h` (model check rejected it,
    `--model` read it as a catalog name); `file.yaml#NAME` still picks a PM."""
    monkeypatch.chdir(tmp_path)
    text = screwkit.load_pm("3RPS").to_yaml()
    (tmp_path / "h#x.yaml").write_text(text, encoding="utf-8")
    assert main(["model", "check", "h#x.yaml"]) == 0
    assert main(["analyze", "--model", "h#x.yaml", "--force", "0,0,-1"]) == 0
    assert capsys.readouterr().out.count("PM 3RPS") == 1
    assert main(["analyze", "--model", "h#x.yaml#3RPS", "--force", "0,0,-1"]) == 0


def test_synthesize_write_folder_is_made_before_the_search(tmp_path, capsys):
    """``synthesize --write DIR`` under a file ran the whole search, then failed to write;
    the folder is made first now (one line, exit 2, before any verification)."""
    blocker = tmp_path / "afile"
    blocker.write_text("x", encoding="utf-8")
    assert main(["synthesize", "3T", "--write", str(blocker / "models")]) == 2
    err = capsys.readouterr().err.strip().splitlines()
    assert len(err) == 1 and "cannot make the folder" in err[0]
