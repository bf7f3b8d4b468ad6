"""Launches on given unknowns and the lines of the transmission indices' joints, formed on
blocks of poses (``_block.frames_block``, ``_block.block_lines``: the parallel kernel's loop)
against the serial kernel, which forms them one pose at a time (``_kin.forward``,
``_indices.pose_lines``): the engine's promise that a batch equals a loop of one-pose calls,
bit for bit; and the lines' actuated twists against the frames kernel's joint twists
(``_extra``, another kernel) at the same unknowns."""

import numpy as np
import pytest

import screwkit
from screwkit.engine._chains import chains_of
from screwkit.engine._launch import frames, run_poses
from screwkit.engine._run import predictor_of
from screwkit.engine._kernels._layout import BLOCK, LEG, L_ACT, LN_V

from random_poses import around_default, assert_same_bits

F, T = np.array([10.0, -20.0, 50.0]), np.array([1.0, 2.0, -3.0])


def _poses(pm, n, seed=0):
    """``n`` random poses around the default one (angles +-0.1 rad, lengths +-5%)."""
    return around_default(pm, n, seed, 0.1, 0.05)


_same = assert_same_bits


@pytest.mark.parametrize("name", ["3RRPRR", "6SPS", "2SPS+2SPR"])
def test_given_unknowns_and_lines_on_blocks_equal_one_pose_at_a_time(name):
    pm = screwkit.load_pm(name)
    ch = chains_of(pm)
    flat, Z = ch.flat, predictor_of(ch)
    n = 2 * BLOCK + 22                        # blocks and a part of one
    P6 = ch.full_params(_poses(pm, n), n)
    kw = dict(F=F, T=T, lines=True, twists=True)
    # solved from the predictor: the block solve and the block's lines, against the serial
    # kernel (every pose alone)
    blocks = run_poses(flat, Z, P6, workers=2, per_thread=1, **kw)
    alone = run_poses(flat, Z, P6, workers=1, blocks=False, **kw)
    _same(blocks, alone, "solved")
    assert np.all(alone["residual"] <= 1e-9)
    # the same unknowns given: the block's forward pass against the one-pose pass
    X = np.ascontiguousarray(alone["X"])
    blocks = run_poses(flat, Z, P6, X=X, workers=2, per_thread=1, **kw)
    alone = run_poses(flat, Z, P6, X=X, workers=1, blocks=False, **kw)
    # (a launch on given unknowns solves nothing: its iterations, how and singular_beta are
    # not outputs)
    _same(blocks, alone, "given", skip=("iterations", "how", "singular_beta"))
    # the lines' actuated twists are the frames kernel's twists of the actuated joints (at
    # X itself, the lines at X's joint values as the solution hands them back: a rounding)
    tw = frames(flat, Z, P6, X, twists=True)["twists"]
    leg = flat.M[LEG]
    for i in range(flat.n):
        act = max(int(leg[i, L_ACT]), 0)
        d = np.abs(tw[:, i, act] - blocks["lines"][:, i, LN_V:LN_V + 6]).max()
        assert d <= 1e-9 * max(1.0, np.abs(tw[:, i, act]).max()), (name, i, d)


def test_a_block_with_poses_solved_alone_or_rescued_equals_one_pose_at_a_time():
    """A block whose lanes the block solves, beside lanes solved alone (``beta = 0``, the
    XYX representation singularity of the 3RRPRR: its limit taken) and lanes Newton does
    not close from the predictor (far from home: the continuation from home): the block puts
    its lanes' template rows into their poses' rows of the outputs at once
    (``_block.block_rows_into``), and a pose whose frames are its own forms its rows again
    over them.  Every output equals the serial kernel's (every pose alone, no block), bit
    for bit."""
    pm = screwkit.load_pm("3RRPRR")
    ch = chains_of(pm)
    flat, Z = ch.flat, predictor_of(ch)
    rng = np.random.default_rng(7)
    n = BLOCK + 6
    a, b = np.radians(rng.uniform(-10, 10, n)), np.radians(rng.uniform(-10, 10, n))
    z = rng.uniform(60, 100, n)
    b[5::9] = 0.0
    a[7::11], b[7::11], z[7::11] = np.radians(38.0), np.radians(-36.0), 115.0
    P6 = ch.full_params({"alpha": a, "beta": b, "Zo": z}, n)
    kw = dict(F=F, T=T, twists=True)
    alone = run_poses(flat, Z, P6, workers=1, blocks=False, **kw)
    # (the kinds of lanes asked for are there: alone at the singularity, rescued)
    assert alone["singular_beta"].sum() >= 5 and (alone["how"] == 1).sum() >= 5
    assert np.all(alone["residual"] <= 1e-9)
    for workers in (2, 1):          # (two first: the parallel kernel then runs on one too)
        blocks = run_poses(flat, Z, P6, workers=workers, per_thread=1, **kw)
        _same(blocks, alone, f"mixed block, {workers} thread(s)")


class _Counted:
    """A kernel dispatcher that counts its calls and the threads each was given."""

    def __init__(self, fn):
        self.fn, self.calls = fn, []

    @property
    def overloads(self):
        return self.fn.overloads

    def __call__(self, *args):
        self.calls.append(args[-3])         # (the threads, then a path's state: none here)
        assert args[-2].size == 0 and args[-1].size == 0
        return self.fn(*args)


def test_a_batch_on_one_thread_runs_in_blocks_with_the_serial_kernels_bits(monkeypatch):
    """A launch of the analysis kernel on one thread (``workers=1``, or too few poses for
    two threads) runs the parallel kernel on that one thread, its closures solved in blocks,
    from :data:`BLOCKS_ALONE` poses (once that kernel is loaded; from
    :data:`BLOCKS_LOADING` in any case); the serial kernel below, and where asked
    (``blocks=False``).  The outputs are the serial kernel's, bit for bit."""
    from screwkit.engine import _launch
    from screwkit.engine._kernels import kernels
    pm = screwkit.load_pm("3RRPRR")
    ch = chains_of(pm)
    flat, Z = ch.flat, predictor_of(ch)
    k = kernels()
    spy = _Counted(k.run_parallel)
    monkeypatch.setattr(k, "run_parallel", spy)
    n = _launch.BLOCKS_LOADING + 37
    P6 = ch.full_params(_poses(pm, n, seed=3), n)
    kw = dict(F=F, T=T, lines=True)
    blocks = run_poses(flat, Z, P6, workers=1, **kw)
    assert spy.calls == [1]                          # the parallel kernel, one thread
    for many in (None, 2):                           # too few poses for two threads
        run_poses(flat, Z, P6[:_launch.BLOCKS_ALONE], workers=many, **kw)
    assert spy.calls == [1, 1, 1]
    run_poses(flat, Z, P6[:_launch.BLOCKS_ALONE - 1], workers=1, **kw)
    alone = run_poses(flat, Z, P6, workers=1, blocks=False, **kw)
    assert spy.calls == [1, 1, 1]                    # the serial kernel for these two
    _same(blocks, alone, "one thread")
    assert np.all(alone["residual"] <= 1e-9)


def test_loading_the_block_kernel_before_a_dask_map_loads_it():
    """What a Dask map's client does before it sends the blocks (the workers run them in
    blocks on one thread): the parallel kernel loaded in a fresh process, which had not."""
    assert _printed_in_a_fresh_process(
        "from screwkit.engine._kernels import kernels\n"
        "from screwkit.engine._run import load_block_kernel\n"
        "k = kernels()\n"
        "before = bool(k.run_parallel.overloads)\n"
        "load_block_kernel(screwkit.load_pm('3RRPRR'))\n"
        "print(before, bool(k.run_parallel.overloads))\n") == ["False", "True"]


def test_a_one_pose_analysis_of_a_six_parameter_pm_never_loads_the_parallel_kernel():
    """The home predictor's fit of a 6-SPS (741 poses, more than a launch on one thread
    takes in blocks unasked) runs in blocks only where the parallel kernel is loaded
    already: a one-pose command in a fresh process neither loads nor compiles it."""
    assert _printed_in_a_fresh_process(
        "from screwkit.engine._kernels import _driver\n"
        "m = screwkit.load_pm('6SPS')\n"
        "res = screwkit.analyze(m, dict(m.default_pose))\n"
        "print(bool(res.ok), len(_driver.run_parallel.overloads))\n") == ["True", "0"]


def _printed_in_a_fresh_process(code):
    """The words ``code`` (after ``import screwkit``) prints in a new Python process."""
    import subprocess
    import sys
    run = subprocess.run([sys.executable, "-c", "import screwkit\n" + code],
                         capture_output=True, text=True, timeout=900)
    assert run.returncode == 0, run.stderr
    return run.stdout.split()


def test_the_predictor_fit_runs_in_blocks_once_the_parallel_kernel_is_loaded(monkeypatch):
    """A fit of the home predictor (a new model's: an optimiser's candidate) in a process
    that has loaded the parallel kernel runs in blocks on one thread, and gives the
    predictor of the serial kernel's fit bit for bit."""
    from screwkit.engine import _launch, _solve
    from screwkit.engine._kernels import kernels
    from screwkit.engine._run import load_block_kernel
    pm = screwkit.load_pm("3RRPRR")
    load_block_kernel(pm)
    k = kernels()
    spy = _Counted(k.run_parallel)
    monkeypatch.setattr(k, "run_parallel", spy)
    ch = chains_of(pm.with_dimensions({"l": 61.5}))
    in_blocks = _solve.predictor_of(ch)
    assert spy.calls == [1]
    _solve._PREDICTORS.pop(ch)
    real = _launch.run_poses
    monkeypatch.setattr(_launch, "run_poses",
                        lambda *a, **kw: real(*a, **dict(kw, blocks=False)))
    alone = _solve.predictor_of(ch)
    assert spy.calls == [1]                          # the serial kernel's fit
    assert len(in_blocks) == len(alone)
    for a, b in zip(in_blocks, alone):
        assert np.asarray(a).tobytes() == np.asarray(b).tobytes()
