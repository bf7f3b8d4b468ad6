"""A map on two threads overlaps one block's numpy work with the next block's analysis
(``screwkit.maps._compute._pipelined``): the same bits as the map on one thread, errors
raised where the map was called; launches inside ``on_this_thread`` run the serial kernels;
the analysis's threads take pieces of the poses as they are free; and the platform's points
are ``R p + o``."""

from __future__ import annotations

import numpy as np
import pytest

import screwkit
from screwkit.engine import _launch
from screwkit.engine._kernels import kernels
from screwkit.engine._kernels._layout import BLOCK
from screwkit.maps import _compute

pytest.importorskip("xarray")

GRID = {"alpha": (-15.0, 15.0, 31), "beta": (-15.0, 15.0, 21), "Zo": (60.0, 100.0, 15)}
LOADS = [("paper", (-20.0, -30.0, -60.0), (-30.0, -30.0, 100.0)),
         ("other", (10.0, 0.0, -80.0), (0.0, 20.0, 0.0))]


def _same(a, b):
    assert set(a.data_vars) == set(b.data_vars)
    for k in a.data_vars:
        assert np.array_equal(a[k].values, b[k].values, equal_nan=True), k


@pytest.fixture
def pipelined(monkeypatch):
    """Counts the maps that took the pipeline."""
    calls = []
    real = _compute._pipelined

    def spy(*args, **kwargs):
        calls.append(1)
        return real(*args, **kwargs)
    monkeypatch.setattr(_compute, "_pipelined", spy)
    return calls


def test_a_map_on_two_threads_equals_the_map_on_one_bit_for_bit(pipelined):
    # 9,765 cells in blocks of 4,096: three blocks, the last one short
    one = screwkit.map("3RRPRR", GRID, degrees=True, block=4096, workers=1)
    assert not pipelined
    two = screwkit.map("3RRPRR", GRID, degrees=True, block=4096, workers=2)
    assert pipelined
    _same(one, two)
    assert int(two["reachable"].sum()) > 0.9 * two["reachable"].size


def test_a_sizing_over_two_workloads_on_two_threads_equals_one_thread(pipelined):
    grid = dict(GRID, Zo=(60.0, 100.0, 30))      # 19,530 cells: two blocks of the map's size
    one = screwkit.size("3RRPRR", grid, degrees=True, workloads=LOADS, workers=1)
    assert not pipelined
    two = screwkit.size("3RRPRR", grid, degrees=True, workloads=LOADS, workers=2)
    assert pipelined
    assert one.to_dict() == two.to_dict()


def test_an_error_in_a_blocks_arrays_reaches_the_caller(monkeypatch):
    real = _compute.arrays_of
    seen = []

    def failing(model, res):
        seen.append(len(res.ok))
        if len(seen) == 2:
            raise RuntimeError("the second block's arrays")
        return real(model, res)
    monkeypatch.setattr(_compute, "arrays_of", failing)
    with pytest.raises(RuntimeError, match="second block"):
        screwkit.map("3RRPRR", GRID, degrees=True, block=4096, workers=2)
    assert len(seen) >= 2


def test_launches_on_this_thread_run_the_serial_kernels(monkeypatch):
    pm = screwkit.load_pm("3RRPRR")
    n = 3000
    pose = {"alpha": np.linspace(-0.2, 0.2, n), "beta": np.linspace(0.15, -0.15, n),
            "Zo": np.linspace(65.0, 95.0, n)}
    threaded = screwkit.analyze(pm, pose, workers=2)
    k = kernels()

    class Refused:
        """A parallel kernel that may not be launched (its other attributes the real's)."""

        def __init__(self, real):
            self.real = real

        def __getattr__(self, name):
            return getattr(self.real, name)

        def __call__(self, *args):
            raise AssertionError("a parallel launch on this thread")
    monkeypatch.setattr(k, "run_parallel", Refused(k.run_parallel))
    monkeypatch.setattr(k, "indices_parallel", Refused(k.indices_parallel))
    with _launch.on_this_thread():
        alone = screwkit.analyze(pm, pose, workers=2)
        iti = np.asarray(alone.indices.iti)
    for a, b in ((threaded.solution.closures.X, alone.solution.closures.X),
                 (threaded.jacobian.J, alone.jacobian.J), (threaded.statics.F_r,
                                                            alone.statics.F_r)):
        assert np.array_equal(np.asarray(a), np.asarray(b), equal_nan=True)
    monkeypatch.undo()
    assert np.array_equal(iti, np.asarray(threaded.indices.iti), equal_nan=True)
    # outside the block, this thread's launches are on numba's threads again
    assert not getattr(_launch._HERE_ONLY, "on", False)


@pytest.mark.parametrize("N, nw", [(1, 2), (255, 2), (256, 2), (5000, 2), (100_000, 2),
                                   (16384, 2), (77, 1), (100_000, 1), (10_000, 4)])
def test_pieces_are_whole_blocks_about_eight_a_thread(N, nw):
    from screwkit.engine._kernels._layout import MIN_PIECE, PIECES_PER_THREAD
    piece = kernels().piece_of(N, nw)
    if nw == 1:
        assert piece >= N
        return
    assert piece >= MIN_PIECE and piece % BLOCK == 0
    pieces = -(-N // piece)
    assert pieces <= nw * PIECES_PER_THREAD
    if N >= nw * PIECES_PER_THREAD * max(MIN_PIECE, BLOCK):
        # enough poses: every thread has about eight pieces to take
        assert pieces >= nw * (PIECES_PER_THREAD - 1)


@pytest.mark.parametrize("N, nw", [(1, 2), (255, 2), (256, 2), (5000, 2), (100_000, 2),
                                   (50_001, 2), (16384, 2), (77, 1), (100_000, 1),
                                   (10_000, 4)])
def test_the_pieces_cover_the_poses_once_and_shrink_at_the_end(N, nw):
    # claims 0, 1, 2... in turn: consecutive pieces from 0 to N, each once; whole blocks
    # but the last; none larger than piece_of's; never larger than the one before; and the
    # last 2 nw pieces small (guided: at most a quarter of piece_of's size where that is
    # above the floor), so the threads finish a launch or a path level together
    from screwkit.engine._kernels._layout import MIN_PIECE
    k = kernels()
    piece = k.piece_of(N, nw)
    spans, c = [], 0
    while True:
        a, b = k.piece_span(c, N, piece, nw)
        if a >= N:
            assert (a, b) == (N, N)
            break
        spans.append((a, b))
        c += 1
        assert c <= 10_000
    assert spans[0][0] == 0 and spans[-1][1] == N
    assert all(s[1] == t[0] for s, t in zip(spans, spans[1:]))
    sizes = [b - a for a, b in spans]
    assert all(0 < s <= piece for s in sizes)
    assert all(s % BLOCK == 0 for s in sizes[:-1])
    assert all(s >= t for s, t in zip(sizes[:-1], sizes[1:-1]))
    if nw == 1:
        assert sizes == [N]
    elif piece >= 4 * MIN_PIECE:
        assert max(sizes[-2 * nw:]) <= max(MIN_PIECE, piece // 4)
    # asking again for a claim past the end still says none
    assert k.piece_span(c + 5, N, piece, nw) == (N, N)


def test_every_piece_is_solved_once_on_several_threads():
    # 6,001 poses in pieces of 256 (24 pieces, the last of 113): each pose equals its
    # one-thread solution, so no piece was skipped nor run twice into another's rows
    pm = screwkit.load_pm("3RPS")
    rng = np.random.default_rng(5)
    n = 6001
    base = dict(pm.default_pose)
    pose = {p: v + rng.uniform(-0.1, 0.1, n) * (1.0 if p in ("alpha", "beta", "gamma")
                                                   else 10.0) for p, v in base.items()
            if p in pm.independent}
    one = screwkit.analyze(pm, pose, workers=1)
    two = screwkit.analyze(pm, pose, workers=2)
    assert np.array_equal(one.solution.closures.X, two.solution.closures.X, equal_nan=True)
    assert np.array_equal(np.asarray(one.jacobian.condition_number),
                          np.asarray(two.jacobian.condition_number), equal_nan=True)
    assert np.all(np.asarray(two.solution.closures.iterations) >= 0)


def test_the_platform_points_are_the_rotated_points_plus_the_origin():
    pm = screwkit.load_pm("3RRPRR")
    n = 500
    rng = np.random.default_rng(3)
    pose = {"alpha": rng.uniform(-0.2, 0.2, n), "beta": rng.uniform(-0.2, 0.2, n),
            "Zo": rng.uniform(60.0, 100.0, n)}
    sol = screwkit.analyze(pm, pose).solution
    R, o, a = sol.rotation, sol.position, sol.platform_points
    p = np.asarray(pm.platform_points, float)
    # the rotation is orthonormal and the points R p + o (numpy's matmul, another order)
    assert np.allclose(np.einsum("nij,nik->njk", R, R), np.eye(3), atol=1e-12)
    expect = np.matmul(R, p.T).transpose(0, 2, 1) + o[:, None, :]
    assert np.allclose(a, expect, rtol=0, atol=1e-12 * np.abs(expect).max())
    for x in (R, o, a):
        assert not x.flags.writeable



def test_a_stiffness_map_on_two_threads_equals_one_thread(pipelined):
    # the 6-SPS of tests/data declares its legs' stiffness: the second thread also forms the
    # cells' stiffness fields (their launches on that thread)
    from pathlib import Path
    pm = screwkit.load_pm(str(Path(__file__).parent / "data" / "stewart_6sps.yaml"))
    assert pm.dynamics is not None and pm.dynamics.has_stiffness
    z = pm.default_pose["Zo"]
    grid = {"alpha": (-4.0, 4.0, 21), "beta": (-4.0, 4.0, 21), "Zo": (z - 5.0, z + 5.0, 21)}
    load = dict(force=(10.0, -20.0, -300.0), torque=(100.0, 0.0, 50.0))
    one = screwkit.map(pm, grid, degrees=True, block=4096, workers=1, **load)
    two = screwkit.map(pm, grid, degrees=True, block=4096, workers=2, **load)
    assert pipelined
    assert any(k.startswith("k_") or "stiff" in k for k in two.data_vars)
    _same(one, two)
