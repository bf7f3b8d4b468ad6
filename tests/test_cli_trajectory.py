"""Issue 6: `screwkit trajectory` (CSV/JSON output, --plot, progress bar, errors).

The CLI's rows are compared with `screwkit analyze --json` at the same poses (the per-pose
pipeline, run through the CLI too)."""

import csv
import io
import json

import numpy as np
import pytest

from screwkit.cli import main

EXPR = ["--expr", "alpha=8*sin(2*pi*t)", "--expr", "beta=6*sin(2*pi*t+1)", "--expr", "Zo=70+20*t"]


def _rows(out):
    """The CSV's rows keyed by column name without its unit (``F_a1 [kN]`` -> ``F_a1``)."""
    return [{k.split(" [")[0]: v for k, v in r.items()}
            for r in csv.DictReader(io.StringIO(out))]


def _cli(capsys, *argv):
    rc = main(list(argv))
    out, err = capsys.readouterr()
    return rc, out, err


def test_csv_rows_equal_screwkit_analyze(capsys):
    rc, out, err = _cli(capsys, "trajectory", "3RRPRR", *EXPR, "--samples", "9")
    assert rc == 0 and err == ""                    # stderr is not a terminal: no progress bar
    rows = _rows(out)
    assert len(rows) == 9 and all(r["status"] == "ok" for r in rows)
    for k in (0, 4, 7):
        r = rows[k]
        pose = [f"--pose=alpha={r['alpha']}", f"--pose=beta={r['beta']}", f"--pose=Zo={r['Zo']}"]
        rc, js, _ = _cli(capsys, "analyze", "3RRPRR", *pose, "--json")
        a = json.loads(js)
        st = a["statics"]
        scale = max(abs(v) for v in st["values"])
        for i in range(3):
            assert float(r[f"F_a{i + 1}"]) == pytest.approx(st["active"][i], abs=1e-8 * scale)
            assert float(r[f"F_c{i + 1}"]) == pytest.approx(st["constraint"][i], abs=1e-8 * scale)
            assert float(r[f"T_r{i + 1}"]) == pytest.approx(st["T_r"][i], abs=1e-7 * scale)
            assert float(r[f"r{i + 1}"]) == pytest.approx(a["extensions"][i], rel=1e-10)
        assert float(r["condition_number"]) == pytest.approx(a["condition_number"], rel=1e-8)
        for p in ("Xo", "Yo", "gamma"):
            assert float(r[p]) == pytest.approx(a["pose"][p], abs=1e-8)


def test_json_out_file_and_plot(tmp_path, capsys):
    out, png = tmp_path / "t.json", tmp_path / "fig.png"
    rc, stdout, err = _cli(capsys, "trajectory", "2SPS+2SPR", "--expr", "alpha=4*sin(2*pi*t)",
                           "--expr", "beta=3", "--expr", "gamma=-2", "--expr", "Zo=70+20*t",
                           "--samples", "7", "--out", str(out), "--plot", str(png),
                           "--title", "my title")
    assert rc == 0 and stdout == ""
    assert f"wrote {out}" in err and f"wrote {png}" in err
    d = json.loads(out.read_text())
    assert d["pm"] == "2SPS+2SPR" and d["n_samples"] == 7 and d["counts"]["ok"] == 7
    assert d["constraint"]["labels"] == ["F_c2", "F_c3"]
    assert d["pose"]["Zo"][0] == pytest.approx(70.0) and d["pose"]["beta"] == [pytest.approx(3.0)] * 7
    import matplotlib.image as mpimg
    img = mpimg.imread(png)[..., :3]
    assert img.shape[0] > 800 and img.shape[1] > 1200
    assert np.mean(np.any(img < 0.9, axis=2)) > 0.05


def test_csv_path_file_with_flagged_samples(tmp_path, capsys):
    f = tmp_path / "p.csv"
    f.write_text("t,alpha,beta,Zo\n0,5,-3,80\n1,70,-3,80\n2,5,-3,80\n")
    rc, out, err = _cli(capsys, "trajectory", "3RRPRR", "--path", str(f))
    assert rc == 0
    rows = _rows(out)
    assert [r["status"] for r in rows] == ["ok", "unreachable", "ok"]
    assert rows[1]["F_a1"] == "nan" and rows[1]["message"].startswith("unreachable")
    assert rows[0]["F_a1"] == rows[2]["F_a1"]
    assert "1 unreachable of 3 samples" in err


@pytest.mark.parametrize("argv, piece", [
    (["3RRPRR", "--expr", "alpha=t"], "missing beta, Zo"),
    (["3RRPRR", *EXPR, "--path", "x.csv"], "not both"),
    (["3RRPRR"], "no path given"),
    (["3RRPRR", "--expr", "alpha=__import__('os')", "--expr", "beta=0", "--expr", "Zo=80"],
     "alpha"),
    (["NOPE", *EXPR], "unknown PM"),
    (["3RRPRR", *EXPR, "--force", "1,2"], "--force"),
])
def test_errors_are_one_line_exit_2(capsys, argv, piece):
    rc, out, err = _cli(capsys, "trajectory", *argv)
    assert rc == 2 and out == ""
    assert err.count("\n") == 1 and piece in err and err.startswith("screwkit trajectory: error:")


def test_user_model_file(capsys):
    """--model FILE with a PM name (a user YAML with its own leg type)."""
    from pathlib import Path
    data = Path(__file__).with_name("data") / "user_3prs.yaml"
    rc, out, err = _cli(capsys, "trajectory", "3PRS", "--model", str(data), "--expr", "alpha=2*t",
                        "--expr", "beta=-1", "--expr", "Zo=60", "--samples", "3",
                        "--force=-20,-30,-60", "--torque=-30,-30,100")
    assert rc == 0, err
    rows = _rows(out)
    assert [r["status"] for r in rows] == ["ok"] * 3 and float(rows[2]["alpha"]) == 2.0
