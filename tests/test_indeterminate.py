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


def _pivoted_basis(N, rtol=1e-9):
    """The canonical basis of the span of the columns of ``N (m, k)`` computed apart from the
    engine: the pivots are the first coordinates, in order, that raise the rank of the rows
    taken so far (numpy's rank), then ``inv(N[piv].T) N.T`` is 1 on its own pivot, 0 on the
    others'."""
    piv = []
    for c in range(N.shape[0]):
        if np.linalg.matrix_rank(N[piv + [c]], tol=rtol * np.abs(N).max()) > len(piv):
            piv.append(c)
    return np.linalg.solve(N[piv].T, N.T), piv


def test_the_self_stress_basis_is_canonical(upu):
    """The self-stresses are one basis of their space whatever the last bits of J (an SVD's
    basis is not): in reduced row echelon form over the rows, as an independent null space
    (scipy's) gives it by another route, and the same values when the model's lengths are
    a thousand times larger (the couples' ratios have no unit)."""
    from scipy.linalg import null_space
    res = screwkit.analyze(upu, **PAPER_LOAD)
    S = res.statics.self_stress
    J = np.asarray(res.jacobian.J)
    d = np.linalg.norm(J[:, :3], axis=1) * res.jacobian.conditioning.length + \
        np.linalg.norm(J[:, 3:], axis=1)                  # rows' sizes: coordinates of a kind
    ref, piv = _pivoted_basis(null_space(J.T) * d[:, None])
    ref = ref / d[None, :]
    ref = ref / ref[np.arange(len(piv)), piv][:, None]
    assert S.shape == ref.shape == (2, 8) and piv == [4, 5]
    np.testing.assert_allclose(S, ref, rtol=1e-9, atol=1e-12)
    np.testing.assert_array_equal(S[:, piv], np.eye(2))
    assert np.all(S[:, :4] == 0.0)                        # no actuator takes part: exact 0
    k = 1000.0
    big = screwkit.load_pm("4UPU", {n: v * k for n, v in upu.dimensions.items()
                                    if isinstance(v, (int, float)) and n != "order"})
    pose = {n: (v * k if n in ("Xo", "Yo", "Zo") else v)
            for n, v in res.solution.params.items() if n in upu.independent}
    res_big = screwkit.analyze(big, pose, force=PAPER_LOAD["force"],
                               torque=np.array(PAPER_LOAD["torque"]) * k)
    np.testing.assert_allclose(res_big.statics.self_stress, S, rtol=1e-9, atol=1e-12)


def test_stiffnesses_of_the_self_stressed_rows_are_all_or_none_and_unit_free():
    """4UPU: its self-stresses load the four couples.  A stiffness for only some of them is
    refused (beside the others' least-norm weights the answer took the units' choice: 9
    times apart between cm and mm); stiffnesses for all four give, for the same PM in mm
    (lengths, torques and couple stiffnesses x10), couples exactly 10 times the cm ones."""
    pm = screwkit.load_pm("4UPU")
    load = {"force": [0.0, 0.0, -1.0], "torque": [1.0, 2.0, 3.0]}
    with pytest.raises(InputError, match="T_c2, T_c3, T_c4 carry self-stress"):
        screwkit.analyze(pm, stiffness={"T_c1": 1e3}, **load)
    k = {"T_c1": 1e3, "T_c2": 4e3, "T_c3": 2e3, "T_c4": 9e3}
    cm = screwkit.analyze(pm, stiffness=k, **load)
    import yaml
    d = yaml.safe_load(pm.to_yaml())["pms"]["4UPU"]
    d["units"] = {"length": "mm", "force": "kN"}
    d["dimensions"] = {k: 10 * v for k, v in d["dimensions"].items()}
    d["pose"] = dict(d["pose"], Xo=10 * d["pose"]["Xo"], Yo=10 * d["pose"]["Yo"])
    mm_pm = screwkit.load_pm(d, name="4UPU")
    mm = screwkit.analyze(mm_pm, stiffness={r: 10 * v for r, v in k.items()},
                          force=[0.0, 0.0, -1.0], torque=[10.0, 20.0, 30.0])
    assert mm.model.units.length == "mm"
    np.testing.assert_allclose(np.asarray(mm.statics.constraint),
                               10 * np.asarray(cm.statics.constraint), rtol=1e-9)
    np.testing.assert_allclose(np.asarray(mm.statics.active), np.asarray(cm.statics.active),
                               rtol=1e-9)
