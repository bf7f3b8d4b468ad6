"""The fill of a path: once the levels are smooth and the gaps narrow, every sample left
starts from the cubic through the solved samples around its gap, in the path's order.

Independent references: the paper's closed forms of the 3RRPRR (gamma = alpha, eq. 11c;
X_o and Y_o of eq. 11e with the Z_o sign corrected, docs NOTES.md; the extensions
|a_i - A_i|), ``np.polyfit`` for the starts, the rows formed again from the solved unknowns
by the launch from given unknowns, and the same path solved with a launch for each level
(each of the fill's portions in a launch of its own).
"""

from __future__ import annotations

import numpy as np
import pytest
from scipy.spatial.transform import Rotation

import screwkit
from screwkit.engine import _path_launch
from screwkit.engine._run import chunk_after_path
from path_samples import PAPER_PATH_LOAD, check_starts, smooth_path

LOAD = PAPER_PATH_LOAD


def _levels_logged(monkeypatch):
    """Every launch of a path's levels returns after one level; returns the log of each
    launch's ``(samples solved, filling)``."""
    run = _path_launch.LevelLaunches.run
    log = []

    def one(self, budget, workers=None):
        before = int(np.count_nonzero(self.solved))
        got = run(self, 1, workers)
        log.append((int(np.count_nonzero(self.solved)) - before, self.filling))
        return got
    monkeypatch.setattr(_path_launch.LevelLaunches, "run", one)
    return log


def test_a_smooth_path_is_filled_every_sample_on_the_closed_forms():
    """(beta kept away from 0, the XYX representation singularity, where the closed forms'
    split of alpha + gamma is not the engine's limit.)"""
    pm = screwkit.load_pm("3RRPRR")
    n = 20_000
    pose = smooth_path(n)
    pose["beta"] = np.radians(10 + 5 * np.cos(2 * np.pi * np.linspace(0, 1, n)))
    res = screwkit.analyze(pm, pose, path=True, **LOAD)
    # 32 anchors and the levels down to a smooth one; the rest (most of the path) filled
    assert res.diagnostics["filled"] > 0.7 * n
    c = res.solution.closures
    assert np.all(c.residual <= 1e-10) and np.all(c.how == 0)
    e, E = 60 / np.sqrt(3), 120 / np.sqrt(3)
    al, be, Z = pose["alpha"], pose["beta"], pose["Zo"]
    sa, ca, sb, cb = np.sin(al), np.cos(al), np.sin(be), np.cos(be)
    den = -sa ** 2 + ca ** 2 * cb
    Xo = (Z * ca + e * sa) * sb / den
    Yo = (-Z * sa * ca * (1 + cb) + e * (cb - ca ** 2 + sa ** 2 * cb) / 2) / den
    p = res.solution.params
    np.testing.assert_allclose(p["gamma"], al, rtol=0, atol=1e-10)
    np.testing.assert_allclose(p["Xo"], Xo, rtol=0, atol=1e-9)
    np.testing.assert_allclose(p["Yo"], Yo, rtol=0, atol=1e-9)
    ang = np.radians([-30.0, 90.0, 210.0])
    A = E * np.column_stack([np.cos(ang), np.sin(ang), np.zeros(3)])
    ma = e * np.column_stack([np.cos(ang), np.sin(ang), np.zeros(3)])
    R = Rotation.from_euler("XYX", np.column_stack([al, be, al])).as_matrix()
    a = np.einsum("nij,kj->nki", R, ma) + np.column_stack([Xo, Yo, Z])[:, None, :]
    np.testing.assert_allclose(res.solution.extensions, np.linalg.norm(a - A, axis=2),
                               rtol=0, atol=1e-9)
    # the rows, conditioning and statics each fill launch formed are those of the unknowns
    again, out = chunk_after_path(pm, pose, c.X, c.residual, rows=True,
                                  F=np.array(LOAD["force"]), T=np.array(LOAD["torque"]))
    np.testing.assert_array_equal(res.jacobian.J, out["J"])
    np.testing.assert_array_equal(res.jacobian.condition_number, out["condition_number"])
    np.testing.assert_array_equal(res.statics.values, out["values"])


def test_the_fill_in_portions_gives_the_same_bits_retries_included(monkeypatch):
    """A 3RSR path whose platform rises out of reach for a moment (0.5 % of its samples):
    the levels are smooth all the same, the fill runs into the unreachable samples and
    retries them from their neighbours; in one launch, or with every level (every portion
    of the fill) in a launch of its own, the same bits."""
    pm = screwkit.load_pm("3RSR")
    n = 20_000
    s = np.linspace(0, 1, n)
    z0 = pm.default_pose["Zo"]
    pose = {"alpha": np.radians(6 * np.sin(2 * np.pi * s)),
            "beta": np.radians(5 * np.cos(2 * np.pi * s)),
            "Zo": z0 * (1 + 1.0 * np.exp(-((s - 0.4) / 0.002) ** 2))}
    whole = screwkit.analyze(pm, pose, path=True, raise_on_singular=False, **LOAD)
    log = _levels_logged(monkeypatch)
    apart = screwkit.analyze(pm, pose, path=True, raise_on_singular=False, **LOAD)
    lost = int(np.count_nonzero(~whole.ok))
    assert 0 < lost < 0.01 * n
    assert whole.diagnostics["filled"] > 0.5 * n and whole.diagnostics["retried"] > 0
    assert sum(1 for _, filling in log if filling) >= 3          # the fill in portions
    for key in ("filled", "retried"):
        assert whole.diagnostics[key] == apart.diagnostics[key]
    a, b = whole.solution.closures, apart.solution.closures
    for x, y in ((a.X, b.X), (a.residual, b.residual), (a.iterations, b.iterations),
                 (a.how, b.how), (whole.jacobian.J, apart.jacobian.J),
                 (whole.statics.values, apart.statics.values)):
        np.testing.assert_array_equal(np.asarray(x), np.asarray(y))
    # each sample the path gave up is out of reach: solved alone, from home with
    # continuation, none closes either
    bad = np.flatnonzero(~whole.ok)
    alone = screwkit.solve(pm, {k: v[bad] for k, v in pose.items()})
    assert not np.any(alone.success)


def test_a_rough_path_is_not_filled():
    """A random walk (steps of about 1.5 deg and 0.5 cm): no level is smooth, every sample
    is solved by the bisection, as before the fill."""
    rng = np.random.default_rng(1)
    n = 4000
    pose = {"alpha": np.radians(np.cumsum(rng.normal(0, 1.5, n))),
            "beta": np.radians(np.cumsum(rng.normal(0, 1.5, n))),
            "Zo": 80 + np.cumsum(rng.normal(0, 0.5, n))}
    res = screwkit.analyze(screwkit.load_pm("3RRPRR"), pose, path=True,
                           raise_on_singular=False, **LOAD)
    assert res.diagnostics["filled"] == 0 and res.diagnostics["retried"] > 0


@pytest.mark.parametrize("seed", [3, 4])
def test_fill_starts_are_the_cubic_through_the_grid_at_each_sample(seed):
    """A fill's starts (``gap_stencils`` then ``level_starts``) at every sample of its gaps,
    not only the middle ones, against ``np.polyfit`` of degree 3 through the four solved
    samples around the gap (where all four converged; the linear interpolation or the one
    that converged otherwise)."""
    from screwkit.engine._kernels import kernels
    from screwkit.engine._kernels._layout import STENCIL_WIDTH
    K = kernels()
    rng = np.random.default_rng(seed)
    N, nx = 400, 5
    XT = rng.normal(size=(N, nx))
    idx = np.unique(np.concatenate([[0, N - 1], rng.choice(N, 30, replace=False)]))
    good = rng.uniform(size=N) > 0.15
    k, mid = [], []
    for j in range(len(idx) - 1):
        for q in range(idx[j] + 1, idx[j + 1]):
            k.append(j)
            mid.append(q)
    k, mid = np.array(k, np.int64), np.array(mid, np.int64)
    S = np.empty((len(k), STENCIL_WIDTH))
    K.gap_stencils(idx, k, good, mid, S)
    Xs = np.empty((len(k), nx))
    K.level_starts(S, XT, Xs)
    kinds = check_starts(idx, k, mid, good, XT, Xs)
    assert kinds == {"cubic", "linear", "one"}
