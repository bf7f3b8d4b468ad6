"""The rows of a block of poses (the legs' context, named points and directions formed for
the block's lanes at once, ``_geometry.legs_frames_block``, each pose's rows from its lane)
against the serial kernel's, which forms them one pose at a time (``_rows.leg_frames``):
bit for bit, for row templates with groups of forces and of couples (of dimensions 1 to
3), the line and least-norm actuations, passive legs, and the generic rule (forced on every
leg of a model whose templates have groups)."""

import numpy as np
import pytest

import screwkit
from screwkit.engine._chains import chains_of
from screwkit.engine._launch import run_poses
from screwkit.engine._run import predictor_of
from screwkit.engine._kernels._layout import BLOCK, TPL, T_GENERIC

from random_poses import around_default, assert_same_bits

F, T = np.array([10.0, -20.0, 50.0]), np.array([1.0, 2.0, -3.0])


def _poses(pm, n, seed=1):
    """``n`` random poses around the default one (angles +-0.15 rad, lengths +-8%)."""
    return around_default(pm, n, seed, 0.15, 0.08)


_same = assert_same_bits


@pytest.mark.parametrize("name, generic", [
    ("3RRPRR", False),            # forces through the meeting point of two axes, a line
    ("3UPU", False),              # couples (dimension 1), a line
    ("3RPUR", False),             # least-norm actuation
    ("2UPR+SPR", False),          # couples and forces of dimension 2
    ("3SPU+PRRR", False),         # no group on three legs; couples and least-norm on one
    ("3UPS+UP/passive", False),   # a passive leg (no actuation row), a group of dimension 3
    ("3RRPRR", True),             # the generic rule on every leg
])
def test_block_rows_equal_one_pose_at_a_time(name, generic):
    pm = screwkit.load_pm(name)         # (a model object of its own: its arrays changed)
    ch = chains_of(pm)
    flat, Z = ch.flat, predictor_of(ch)
    if generic:
        flat.M[TPL][:, T_GENERIC] = 1
    n = 2 * BLOCK + 36                  # blocks and a part of one
    P6 = ch.full_params(_poses(pm, n), n)
    kw = dict(F=F, T=T, twists=True)
    blocks = run_poses(flat, Z, P6, workers=2, per_thread=1, **kw)
    alone = run_poses(flat, Z, P6, workers=1, **kw)
    _same(blocks, alone, (name, "solved"))
    X = np.ascontiguousarray(alone["X"])
    blocks = run_poses(flat, Z, P6, X=X, workers=2, per_thread=1, **kw)
    alone = run_poses(flat, Z, P6, X=X, workers=1, **kw)
    _same(blocks, alone, (name, "given"), skip=("iterations", "how", "singular_beta"))
    assert np.isfinite(alone["J"]).mean() > 0.9, name
