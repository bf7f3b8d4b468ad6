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
