"""A path's level loop compiled into the analysis kernel.

The levels run one after the other inside one launch (``_kernels._path_loop``), Python
coming back only for a level's retries and, with progress told, every so many samples.
Independent references: the same path solved with a launch per level (each launch
returning after one level: the route without the compiled loop's bookkeeping between
levels), and the rows and statics formed again from the path's solved unknowns by the
launch from given unknowns (``chunk_after_path``), per-sample stiffnesses included.
"""

from __future__ import annotations

import numpy as np
import pytest

import screwkit
from screwkit.engine import _path, _path_launch
from screwkit.engine._run import chunk_after_path
from path_samples import PAPER_PATH_LOAD, smooth_path

LOAD = PAPER_PATH_LOAD


def _walk(n):
    rng = np.random.default_rng(1)
    return {"alpha": np.radians(np.cumsum(rng.normal(0, 1.5, n))),
            "beta": np.radians(np.cumsum(rng.normal(0, 1.5, n))),
            "Zo": 80 + np.cumsum(rng.normal(0, 0.5, n))}


def _one_level_a_launch(monkeypatch):
    """Every launch of a path's levels returns after one level; returns the launches'
    log (the samples solved in each)."""
    run = _path_launch.LevelLaunches.run
    log = []

    def one(self, budget, workers=None):
        before = int(self.solved.sum())
        got = run(self, 1, workers)
        log.append(int(self.solved.sum()) - before)
        return got
    monkeypatch.setattr(_path_launch.LevelLaunches, "run", one)
    return log


@pytest.mark.parametrize("kind", ["smooth", "walk"])
def test_all_levels_in_one_launch_equal_a_launch_a_level(kind, monkeypatch):
    pm = screwkit.load_pm("3RRPRR")
    pose = (smooth_path if kind == "smooth" else _walk)(3000)
    whole = screwkit.analyze(pm, pose, path=True, raise_on_singular=False, **LOAD)
    log = _one_level_a_launch(monkeypatch)
    apart = screwkit.analyze(pm, pose, path=True, raise_on_singular=False, **LOAD)
    # 32 anchors, then levels halving gaps of about 94 samples: seven levels at least
    assert len(log) >= 7
    if kind == "walk":
        assert whole.diagnostics["retried"] > 0 and \
            whole.diagnostics["retried"] == apart.diagnostics["retried"]
    a, b = whole.solution.closures, apart.solution.closures
    for x, y in ((a.X, b.X), (a.residual, b.residual), (a.iterations, b.iterations),
                 (a.how, b.how), (whole.jacobian.J, apart.jacobian.J),
                 (whole.statics.values, apart.statics.values)):
        np.testing.assert_array_equal(np.asarray(x), np.asarray(y))


def test_each_sample_solved_once_and_its_rows_those_of_its_unknowns():
    """Every sample of a path is solved (no sample left with the state's initial values)
    and its rows, conditioning and statics are those formed again from its unknowns."""
    pm = screwkit.load_pm("3RRPRR")
    pose = smooth_path(5001)
    res = screwkit.analyze(pm, pose, path=True, **LOAD)
    c = res.solution.closures
    assert np.all(c.residual <= 1e-10) and np.all(c.how == 0)
    again, out = chunk_after_path(pm, pose, c.X, c.residual, rows=True,
                                  F=np.array(LOAD["force"]), T=np.array(LOAD["torque"]))
    np.testing.assert_array_equal(c.residual, again)
    np.testing.assert_array_equal(res.jacobian.J, out["J"])
    np.testing.assert_array_equal(res.statics.values, out["values"])


def test_per_sample_stiffness_along_a_path_equals_the_given_unknowns_route():
    """A path of an indeterminate PM with a stiffness per sample: each level's samples take
    their own compliances (gathered in the launch); the compliance-weighted statics equal
    those formed from the solved unknowns with the same compliances."""
    from screwkit.engine._chains import chains_of
    from screwkit.engine._statics import compliance_of
    from screwkit.engine._templates import labels_of, templates_of
    pm = screwkit.load_pm("4UPU")
    ch = chains_of(pm)
    n = 1500
    s = np.linspace(0, 1, n)
    home = {k: float(pm.default_pose[k]) for k in ch.fixed}
    pose = {k: v + (0.05 * np.sin(2 * np.pi * s) if k not in ("Xo", "Yo", "Zo")
                    else 2.0 * np.sin(2 * np.pi * s)) for k, v in home.items()}
    m = len(labels_of(templates_of(pm)))
    k = 1e3 * (1.0 + 0.5 * np.sin(np.arange(n)[:, None] * 0.37 + np.arange(m)[None, :]))
    F, T = np.array([1.0, -2.0, -30.0]), np.array([0.5, 0.2, 3.0])
    res = screwkit.analyze(pm, pose, path=True, force=F, torque=T, stiffness=k,
                           raise_on_singular=False)
    c = res.solution.closures
    assert np.all(c.residual <= 1e-6)
    _, out = chunk_after_path(pm, pose, c.X, c.residual, rows=True, F=F, T=T,
                              compliance=np.ascontiguousarray(compliance_of(k, m, n)))
    np.testing.assert_array_equal(np.asarray(res.statics.values), out["values"])
    # and the stiffnesses matter: one stiffness for all gives other forces
    one = screwkit.analyze(pm, pose, path=True, force=F, torque=T, stiffness=k[0],
                           raise_on_singular=False)
    assert not np.allclose(np.asarray(one.statics.values), out["values"], rtol=1e-6)


def test_progress_is_told_between_launches_up_to_the_total(monkeypatch):
    monkeypatch.setattr(_path, "PROGRESS_SAMPLES", 500)
    pm = screwkit.load_pm("3RRPRR")
    seen = []
    res = screwkit.analyze(pm, smooth_path(8000), path=True, progress=lambda d, t: seen.append((d, t)),
                           **LOAD)
    done = [d for d, _ in seen]
    assert {t for _, t in seen} == {16000}            # the closures, then the rows
    assert done == sorted(done) and done[-1] == 16000 and len(seen) >= 4
    quiet = screwkit.analyze(pm, smooth_path(8000), path=True, **LOAD)
    np.testing.assert_array_equal(res.solution.closures.X, quiet.solution.closures.X)


@pytest.mark.parametrize("kind", ["smooth", "walk"])
def test_a_team_of_threads_equals_a_launch_of_threads_a_level(kind, monkeypatch):
    """The levels on a team of threads that wait for each other between levels (numba's
    workqueue layer) and on threads started for each level (any other layer): the same
    bits, retries included; and the team does run here (two threads, workqueue)."""
    from screwkit.engine._kernels import kernels
    from screwkit.engine._kernels._layout import LH_TEAM
    pm = screwkit.load_pm("3RRPRR")
    pose = (smooth_path if kind == "smooth" else _walk)(6000)
    init = _path_launch.LevelLaunches.__init__
    teams = []

    def spy(self, *a, **k):
        init(self, *a, **k)
        teams.append(int(self.Li[LH_TEAM]))
    monkeypatch.setattr(_path_launch.LevelLaunches, "__init__", spy)
    team = screwkit.analyze(pm, pose, path=True, raise_on_singular=False, workers=2, **LOAD)
    assert teams == [kernels().numba.config.THREADING_LAYER == "workqueue"]

    def no_team(self, *a, **k):
        init(self, *a, **k)
        self.Li[LH_TEAM] = 0
    monkeypatch.setattr(_path_launch.LevelLaunches, "__init__", no_team)
    apart = screwkit.analyze(pm, pose, path=True, raise_on_singular=False, workers=2, **LOAD)
    a, b = team.solution.closures, apart.solution.closures
    for x, y in ((a.X, b.X), (a.residual, b.residual), (a.iterations, b.iterations),
                 (team.jacobian.J, apart.jacobian.J),
                 (team.statics.values, apart.statics.values)):
        np.testing.assert_array_equal(np.asarray(x), np.asarray(y))


def test_the_serial_kernels_level_loop_equals_the_threads():
    """On this thread alone (the serial kernel's loop over the levels, each pose alone) and
    on the threads in blocks: the same bits."""
    from screwkit.engine import _launch
    pm = screwkit.load_pm("3RRPRR")
    pose = _walk(3000)
    threaded = screwkit.analyze(pm, pose, path=True, raise_on_singular=False, **LOAD)
    with _launch.on_this_thread():
        alone = screwkit.analyze(pm, pose, path=True, raise_on_singular=False, **LOAD)
    assert threaded.diagnostics["retried"] > 0
    for x, y in ((threaded.solution.closures.X, alone.solution.closures.X),
                 (threaded.solution.closures.residual, alone.solution.closures.residual),
                 (threaded.jacobian.J, alone.jacobian.J),
                 (threaded.statics.values, alone.statics.values)):
        np.testing.assert_array_equal(np.asarray(x), np.asarray(y))
