"""Statically indeterminate statics: least norm, compliance-weighted solutions, self-stress.

The 4UPU (Schoenflies) has 2 redundant constraint couples: its actuator forces are
determined, its couples only up to the 2-dimensional self-stress space.  Independent
checks: the weighted least-squares solution computed here by Lagrange multipliers on the
raw rows of J (x = K J (J^T K J)^-1 (-W), K = diag(stiffness)); the optimality condition
(x / k is orthogonal to every self-stress); equilibrium.
"""

import numpy as np
import pytest

import screwkit
from screwkit.engine import PAPER_FORCE, PAPER_TORQUE
from screwkit.errors import InputError

# the paper's workload, stated (only 3RRPRR and 2SPS+2SPR declare it as their default)
PAPER_LOAD = {"force": (-20.0, -30.0, -60.0), "torque": (-30.0, -30.0, 100.0)}
PAPER_ARGS = ["--force=-20,-30,-60", "--torque=-30,-30,100"]


@pytest.fixture(scope="module")
def upu():
    return screwkit.load_pm("4UPU")


def _weighted(J, W, k):
    K = np.diag(k)
    return K @ J @ np.linalg.solve(J.T @ K @ J, -W)


def test_equal_stiffness_is_the_least_norm_solution(upu):
    res = screwkit.analyze(upu, **PAPER_LOAD)
    assert res.jacobian.indeterminacy == 2
    labels = res.jacobian.labels
    L = upu.normalisation.length
    stiff = {lab: (7.0 if lab.startswith("F") else 3.0 * L ** 2) for lab in labels}
    w = screwkit.analyze(upu, stiffness=stiff, **PAPER_LOAD)
    np.testing.assert_allclose(w.statics.values, res.statics.values, rtol=1e-10,
                               atol=1e-10 * np.abs(res.statics.values).max())
    W = res.statics.workload
    k = np.array([stiff[lab] for lab in labels])
    np.testing.assert_allclose(res.statics.values, _weighted(res.jacobian.J, W, k), rtol=1e-9,
                               atol=1e-9 * np.abs(res.statics.values).max())


def test_unequal_stiffness_differs_balances_and_is_optimal(upu):
    res = screwkit.analyze(upu, **PAPER_LOAD)
    labels = res.jacobian.labels
    k = np.array([1e3, 1e3, 1e3, 1e3, 1e6, 4e6, 2e6, 9e6])
    w = screwkit.analyze(upu, stiffness=k, **PAPER_LOAD)
    x = w.statics.values
    assert np.abs(x - res.statics.values).max() > 1e-3 * np.abs(x).max()
    np.testing.assert_allclose(w.statics.active, res.statics.active, rtol=1e-10)  # determined
    assert w.statics.equilibrium_residual < 1e-12
    S = w.statics.self_stress
    assert S.shape == (2, 8)
    opt = S @ (x / k)
    assert np.abs(opt).max() <= 1e-9 * np.abs(S).max() * np.abs(x / k).max()
    np.testing.assert_allclose(x, _weighted(w.jacobian.J, w.statics.workload, k), rtol=1e-9,
                               atol=1e-9 * np.abs(x).max())
    det = w.statics.determined
    assert det.tolist() == [True] * 4 + [False] * 4
    assert "not determined by statics" in w.statics.describe()
    assert labels[4].startswith("T_c")


def test_stiffness_input_errors(upu):
    with pytest.raises(InputError, match="no row 'X'"):
        screwkit.analyze(upu, stiffness={"X": 1.0}, **PAPER_LOAD)
    with pytest.raises(InputError, match="positive"):
        screwkit.analyze(upu, stiffness=[1, 1, 1, 1, 1, 1, 1, -1], **PAPER_LOAD)
    with pytest.raises(InputError, match="one value per row"):
        screwkit.analyze(upu, stiffness=[1, 2], **PAPER_LOAD)
