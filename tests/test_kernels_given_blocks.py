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
from screwkit.engine._kernels._layout import LEG, L_ACT, LN_V

F, T = np.array([10.0, -20.0, 50.0]), np.array([1.0, 2.0, -3.0])


def _poses(pm, n, seed=0):
    """``n`` random poses around the default one (angles +-0.1 rad, lengths +-5%)."""
    rng = np.random.default_rng(seed)
    pose = {}
    for p, v in dict(pm.default_pose).items():
        amp = 0.1 if p in ("alpha", "beta", "gamma") else 0.05 * max(abs(v), 1.0)
        pose[p] = v + rng.uniform(-amp, amp, n)
    return pose


def _same(a, b, where, skip=()):
    for key in a:
        if key in skip:
            continue
        x, y = np.asarray(a[key]), np.asarray(b[key])
        assert x.shape == y.shape, (where, key)
        assert x.tobytes() == y.tobytes(), (where, key)


@pytest.mark.parametrize("name", ["3RRPRR", "6SPS", "2SPS+2SPR"])
def test_given_unknowns_and_lines_on_blocks_equal_one_pose_at_a_time(name):
    pm = screwkit.load_pm(name)
    ch = chains_of(pm)
    flat, Z = ch.flat, predictor_of(ch)
    n = 150                                   # four blocks of 32 and a part of one
    P6 = ch.full_params(_poses(pm, n), n)
    kw = dict(F=F, T=T, lines=True, twists=True)
    # solved from the predictor: the block solve and the block's lines, against the serial
    # kernel (every pose alone)
    blocks = run_poses(flat, Z, P6, workers=2, per_thread=1, **kw)
    alone = run_poses(flat, Z, P6, workers=1, **kw)
    _same(blocks, alone, "solved")
    assert np.all(alone["residual"] <= 1e-9)
    # the same unknowns given: the block's forward pass against the one-pose pass
    X = np.ascontiguousarray(alone["X"])
    blocks = run_poses(flat, Z, P6, X=X, workers=2, per_thread=1, **kw)
    alone = run_poses(flat, Z, P6, X=X, workers=1, **kw)
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
