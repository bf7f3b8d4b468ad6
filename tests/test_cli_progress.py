"""Progress of the long commands: tqdm bars on a terminal only, ``--quiet``, and the progress
callbacks of the engine, the trajectory, the validation and the catalog check (monotone,
ending at their total)."""

from __future__ import annotations

import io
import types

import numpy as np
import pytest

import screwkit
from screwkit.cli import main
from screwkit.cli import _progress

EXPR = ["--expr", "alpha=8*sin(2*pi*t)", "--expr", "beta=6*sin(2*pi*t+1)", "--expr", "Zo=70+20*t"]


class Terminal(io.StringIO):
    """A stderr that says it is a terminal."""

    def isatty(self) -> bool:
        return True


def _calls():
    calls = []
    return calls, lambda done, total: calls.append((int(done), int(total)))


def _monotone_to_total(calls):
    assert calls, "progress was never called"
    done = [d for d, _ in calls]
    assert done == sorted(done) and len({t for _, t in calls}) == 1
    assert calls[-1][0] == calls[-1][1]


def test_bar_only_on_a_terminal_and_not_with_quiet():
    args = types.SimpleNamespace(quiet=False)
    assert _progress.bar_wanted(args, Terminal())
    assert not _progress.bar_wanted(args, io.StringIO())          # a pipe or a file
    assert not _progress.bar_wanted(types.SimpleNamespace(quiet=True), Terminal())
    with _progress.progress_bar(types.SimpleNamespace(quiet=True), "x", "it") as bar:
        assert bar is None


def test_trajectory_draws_a_tqdm_bar_on_a_terminal(monkeypatch, tmp_path, capsys):
    err = Terminal()
    monkeypatch.setattr("sys.stderr", err)
    monkeypatch.setattr(_progress, "DELAY", 0.0)
    out = tmp_path / "sub" / "path.csv"                # the folder is created
    assert main(["trajectory", "3RRPRR", *EXPR, "--samples", "101", "--out", str(out)]) == 0
    text = err.getvalue()
    assert "trajectory:" in text and "step/s" in text and "/202 [" in text    # 2 N steps
    assert out.is_file() and len(out.read_text().splitlines()) == 102
    quiet = Terminal()
    monkeypatch.setattr("sys.stderr", quiet)
    assert main(["trajectory", "3RRPRR", *EXPR, "--samples", "11", "--out", str(out), "-q"]) == 0
    assert "trajectory:" not in quiet.getvalue() and "wrote" in quiet.getvalue()


def test_no_bar_when_stderr_is_not_a_terminal(capsys, monkeypatch):
    monkeypatch.setattr(_progress, "DELAY", 0.0)
    assert main(["validate", "UPU", "PRRR", "--no-catalog"]) == 0
    err = capsys.readouterr().err
    assert "validate:" not in err and "\r" not in err


def test_engine_path_progress_covers_closures_and_rows():
    calls, cb = _calls()
    t = np.linspace(0, 1, 300)
    pose = {"alpha": 0.1 * np.sin(2 * np.pi * t), "beta": 0.05 + 0.0 * t, "Zo": 70 + 20 * t}
    res = screwkit.analyze("3RRPRR", pose, path=True, chunk=64, progress=cb)
    assert res.ok.all()
    _monotone_to_total(calls)
    assert calls[-1] == (600, 600)
    assert any(d <= 300 for d, _ in calls) and any(300 < d < 600 for d, _ in calls)
    calls, cb = _calls()
    screwkit.analyze("3RRPRR", pose, chunk=64, progress=cb)        # no path: N poses, by chunk
    _monotone_to_total(calls)
    assert calls[-1] == (300, 300) and len(calls) == 5


def test_validation_progress_counts_strings_and_the_catalog():
    from screwkit.synthesis import validate_table1

    calls, cb = _calls()
    rep = validate_table1(draws=1, strings=["UPU", "SPR"], check_catalog=False, progress=cb)
    assert rep.ok and calls == [(1, 2), (2, 2)]


@pytest.mark.parametrize("names", [["3SPR", "3RPS"]])
def test_check_all_reports_each_pose(names):
    from screwkit.interop import check_all

    seen = []
    reports = check_all(1, 0, names, progress=seen.append)
    assert len(seen) == len(reports) == 2 and all(r.passed for r in reports)
