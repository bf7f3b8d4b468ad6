"""A path's rows formed in the launches that solve it, and the indices' shortcuts, equal the
plain routes bit for bit.

Independent references: the rows, conditioning and statics formed again from the path's
solved unknowns by :func:`screwkit.engine._run.chunk_after_path` (the launch from given
unknowns that the Dask route runs, and that a path ran before its levels kept their rows);
``np.nanmin`` and ``np.isfinite(...).all()`` for the indices' minima and finite test.
"""

from __future__ import annotations

import numpy as np
import pytest

import screwkit
from screwkit.engine._run import chunk_after_path
from path_samples import check_starts

LOAD = {"force": (-20.0, -30.0, -60.0), "torque": (-30.0, -30.0, 100.0)}


def _path(kind, n=600):
    s = np.linspace(0, 1, n)
    if kind == "smooth":
        return {"alpha": np.radians(10 * np.sin(2 * np.pi * s)),
                "beta": np.radians(8 * np.cos(2 * np.pi * s)), "Zo": 70 + 20 * s}
    # a random walk of steps of about 1.5 deg and 0.5 cm: it leaves the workspace and comes
    # back, with retries and unreachable samples
    rng = np.random.default_rng(1)
    return {"alpha": np.radians(np.cumsum(rng.normal(0, 1.5, n))),
            "beta": np.radians(np.cumsum(rng.normal(0, 1.5, n))),
            "Zo": 80 + np.cumsum(rng.normal(0, 0.5, n))}


@pytest.mark.parametrize("kind", ["smooth", "walk"])
def test_path_rows_equal_those_formed_again_from_its_unknowns(kind, monkeypatch):
    import screwkit.engine._run as run
    if kind == "walk":
        monkeypatch.setattr(run, "CHUNK", 700)          # the levels in several launches
    pm = screwkit.load_pm("3RRPRR")
    pose = _path(kind, 4000)
    res = screwkit.analyze(pm, pose, path=True, raise_on_singular=False, **LOAD)
    c = res.solution.closures
    if kind == "walk":
        assert res.diagnostics["retried"] > 0 and not res.ok.all()
    again, out = chunk_after_path(pm, pose, c.X, c.residual, rows=True,
                                  F=np.array(LOAD["force"]), T=np.array(LOAD["torque"]))
    np.testing.assert_array_equal(c.residual, again)
    np.testing.assert_array_equal(res.jacobian.J, out["J"])
    reach = res.solution.reachable_mask                 # (the analysis masks the others)
    for got, key in ((res.jacobian.condition_number, "condition_number"),
                     (res.statics.values, "values"),
                     (res.statics.equilibrium_residual, "equilibrium")):
        np.testing.assert_array_equal(np.asarray(got)[reach], out[key][reach])


def test_index_minima_and_finite_test_equal_numpy():
    import warnings

    from screwkit.engine._indices import TransmissionIndices
    from screwkit.engine._transmission import _all_finite
    rng = np.random.default_rng(2)
    a = rng.uniform(0, 1, (50, 3))
    a[3] = np.nan                                       # a pose with no index
    a[5, 1] = np.nan
    data = {k: np.zeros((50, 0)) for k in ("cti_rows", "input_arm", "output_arm",
                                          "constraint_arm")}
    data.update(iti_legs=a, oti_legs=a[:, ::-1].copy(), condition_number=np.ones(50),
                sigma_min=np.ones(50), amplification=np.ones(50))
    ix = TransmissionIndices(data, (0, 1, 2), ())
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", RuntimeWarning)
        np.testing.assert_array_equal(ix.iti, np.nanmin(a, axis=1))
        np.testing.assert_array_equal(ix.oti, np.nanmin(a[:, ::-1], axis=1))
    assert np.isnan(ix.cti).all() and np.isnan(ix.lti[3])
    for bad in (np.nan, np.inf, -np.inf):
        b = rng.normal(size=(20, 6, 6))
        assert _all_finite(b) == bool(np.isfinite(b).all())
        b[7, 2, 3] = bad
        assert _all_finite(b) == bool(np.isfinite(b).all()) is False
    big = np.full((4, 6, 6), 1e308)                    # the sum overflows: checked one by one
    assert _all_finite(big) is True


def test_levels_solved_in_the_launches_equal_the_plain_route():
    """The starts and branch-jump test formed in the levels' launches (the analysis with
    rows) solve the path as the route without rows does (``solve``: starts and test in the
    levels' own passes), retries and unreachable samples included, bit for bit."""
    pm = screwkit.load_pm("3RRPRR")
    pose = _path("walk", 4000)
    fused = screwkit.analyze(pm, pose, path=True, raise_on_singular=False, **LOAD)
    plain = screwkit.solve(pm, pose, path=True)
    assert fused.diagnostics["retried"] > 0
    a, b = fused.solution.closures, plain.closures
    np.testing.assert_array_equal(a.X, b.X)
    np.testing.assert_array_equal(a.iterations, b.iterations)
    np.testing.assert_array_equal(a.how, b.how)
    np.testing.assert_array_equal(np.isfinite(a.residual), np.isfinite(b.residual))


def test_level_stencils_are_the_interpolations_of_the_neighbours():
    """A level's starts (``level_stencil`` then ``level_starts``) against numpy: the cubic
    through the four solved samples around a gap (``np.polyfit`` of degree 3 through
    them) where all four converged, the linear interpolation of the two neighbours, or
    the one that converged; the excess against its formula in numpy."""
    from screwkit.engine._kernels import kernels
    from screwkit.engine._kernels._layout import STENCIL_WIDTH
    K = kernels()
    rng = np.random.default_rng(5)
    N, nx = 200, 7
    XT = rng.normal(size=(N, nx))
    idx = np.unique(np.concatenate([[0, N - 1], rng.choice(N, 40, replace=False)]))
    good = rng.uniform(size=N) > 0.2
    k = np.flatnonzero(np.diff(idx) > 1)
    G = len(k)
    mid, S = np.empty(G, np.int64), np.empty((G, STENCIL_WIDTH))
    K.level_stencil(idx, k, good, mid, S)
    Xs = np.empty((G, nx))
    K.level_starts(S, XT, Xs)
    np.testing.assert_array_equal(mid, (idx[k] + idx[k + 1]) // 2)
    kinds = check_starts(idx, k, mid, good, XT, Xs)
    assert kinds == {"cubic", "linear", "one"}
    XT[mid] = Xs + rng.normal(scale=0.3, size=Xs.shape)        # the level's "solutions"
    XT[mid[3], 2] = np.nan
    XT[mid[5]] += 10.0                                          # a jump
    excess = np.empty(G)
    K.level_check(S, XT, mid, Xs, excess)
    left, right = idx[k], idx[k + 1]
    want = np.abs(XT[mid] - Xs).max(axis=1) - (
        0.5 * np.abs(XT[right] - XT[left]).max(axis=1) + 1e-9)
    np.testing.assert_allclose(excess, want, rtol=1e-15, atol=0)
    assert np.isnan(excess[3]) and (excess > 0).any() and (excess <= 0).any()
    # a stencil naming a row the unknowns do not have: NaN, never a read outside them
    for bad in (-1.0, float(N), 1e30):
        S2 = S.copy()
        S2[4, 5 + 3] = bad
        K.level_starts(S2, XT, Xs)
        K.level_check(S2, XT, mid, Xs, excess)
        assert np.isnan(Xs[4]).all() and np.isnan(excess[4])
        assert np.isfinite(np.delete(Xs, 4, axis=0)).all()


def test_level_launches_take_only_a_paths_buffers():
    """A path's levels write their samples' rows of the path's output buffers, with their
    excess, made for as many samples and the same outputs: any other buffers are refused
    with an error naming them."""
    from screwkit.engine._chains import chains_of
    from screwkit.engine._launch import output_buffers
    from screwkit.engine._path_launch import LevelLaunches
    from screwkit.engine._solve import predictor_of
    ch = chains_of(screwkit.load_pm("3RRPRR"))
    Z = predictor_of(ch)
    for buffers, kw in ((output_buffers(ch.flat, 10), {}),                 # no excess
                        (output_buffers(ch.flat, 12, excess=True), {}),    # other samples
                        (output_buffers(ch.flat, 10, excess=True), {"rows": False}),
                        (output_buffers(ch.flat, 10, rows=False, excess=True), {})):
        with pytest.raises(ValueError, match="path of 10 samples"):
            LevelLaunches(ch.flat, Z, buffers, 10, **kw)
    ok = LevelLaunches(ch.flat, Z, output_buffers(ch.flat, 10, statics=False, excess=True), 10)
    assert ok.P6.shape == (10, 6) and ok.solved.shape == (10,) and not ok.solved.any()