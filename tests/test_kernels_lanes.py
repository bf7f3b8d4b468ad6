"""Kernels that run on a block's lanes at once, against independent references, and a block
against its lanes one at a time (the engine's promise: a batch equals a loop of one-pose
calls bit for bit):

* the eigenvalues of small symmetric matrices (``_eigen.symmetric_eigenvalues_lanes``: the
  QL iteration with the lanes in step, each taking a step where its own test says) against LAPACK's
  (``numpy.linalg.eigvalsh``), on well-conditioned, graded and rank-deficient Gram matrices,
  with a non-finite lane among finite ones (``singular_values_lanes``);
* the home predictor's polynomial (``_closures.predict``) against the same polynomial
  evaluated here with numpy from its monomials, and a lane far outside the fit starting at
  home;
* LU with partial pivoting on lanes (``_small.lu_lanes``, ``lu_apply_lanes``: the statics of
  a block) against LAPACK (``scipy.linalg.lu_factor``, ``numpy.linalg.solve``) on random,
  graded, nearly singular and exactly singular matrices, against the one-pose
  ``lu_factor`` / ``lu_apply`` (the same kernel on one lane), with a NaN lane; the block's
  compiled functions (``lu_block``, ``lu_apply_block``) and ``_extra.det_sign_batch`` on
  them, each matrix as alone.
"""

import itertools

import numpy as np
import pytest

from screwkit.engine._kernels._layout import BLOCK

#: The lane stride of these tests' blocks: the engine's (its block kernels are compiled for it).
B = BLOCK


@pytest.fixture(scope="module")
def eig():
    from numba import njit

    from screwkit.engine._kernels._eigen import symmetric_eigenvalues_lanes

    @njit(cache=False)
    def run(G, n, nb):
        """The eigenvalues of ``G (N, n, n)``, ``nb`` matrices a block (lanes ``ls = B``)."""
        N = G.shape[0]
        A = np.zeros((6, 6, B))
        d, e, S = np.zeros((6, B)), np.zeros((6, B)), np.zeros((6, B))
        out = np.zeros((N, n))
        for p0 in range(0, N, nb):
            m = min(nb, N - p0)
            for a in range(n):
                for b in range(a + 1):
                    for k in range(m):
                        A[a, b, k] = G[p0 + k, a, b]
            symmetric_eigenvalues_lanes(A, n, d, e, S, m, B)
            for k in range(m):
                for a in range(n):
                    out[p0 + k, a] = d[a, k]
        return out

    return run


@pytest.fixture(scope="module")
def svd():
    from numba import njit

    from screwkit.engine._kernels._eigen import singular_values_lanes

    @njit(cache=False)
    def run(J):
        """The singular values of the rows ``J (nb, m, 6)`` as one block (``nb <= B``)."""
        nb, m = J.shape[0], J.shape[1]
        JL = np.zeros((m, 6, B))
        for k in range(nb):
            for r in range(m):
                for c in range(6):
                    JL[r, c, k] = J[k, r, c]
        s = np.zeros((6, B))
        singular_values_lanes(JL, 0, m, np.zeros((6, 6, B)), s, min(m, 6), np.zeros((6, B)),
                              np.zeros((6, B)), np.zeros((5, B), np.int64),
                              np.zeros((max(m, 6), 6)), nb, B)
        return s[:, :nb].T.copy()

    return run


def _grams(rng, N, n, kind):
    """Gram matrices ``J J^T`` of unit rows (as the conditioning forms them)."""
    J = rng.normal(size=(N, n, 6))
    if kind == "graded":
        J *= np.logspace(0, -3, 6)
    if kind == "deficient":
        J[:, -1] = J[:, 0] * (1 + 1e-13 * rng.normal(size=(N, 1)))
        J[::3, min(2, n - 1)] = 0.0
    J /= np.maximum(np.linalg.norm(J, axis=2, keepdims=True), 1e-300)
    return np.einsum("pik,pjk->pij", J, J)


@pytest.mark.parametrize("n", [2, 3, 4, 5, 6])
@pytest.mark.parametrize("kind", ["random", "graded", "deficient"])
def test_eigenvalues_on_lanes_match_lapack_and_the_lanes_alone(eig, n, kind):
    G = _grams(np.random.default_rng(10 * n + len(kind)), 3000, n, kind)
    block = eig(G, n, B)
    alone = eig(G, n, 1)
    assert np.array_equal(block, alone)           # every lane as the matrix alone, bit for bit
    ref = np.linalg.eigvalsh(G)
    got = np.sort(block, axis=1)
    scale = np.abs(ref).max(axis=1, keepdims=True)
    assert np.max(np.abs(got - ref) / scale) < 20 * np.finfo(float).eps * n


def test_singular_values_on_lanes_with_a_non_finite_lane(svd):
    rng = np.random.default_rng(7)
    J = rng.normal(size=(B, 6, 6))
    J /= np.linalg.norm(J, axis=2, keepdims=True)
    J = 0.7 * np.eye(6) + 0.3 * J                  # moderate condition: the Gram matrices' route
    J /= np.linalg.norm(J, axis=2, keepdims=True)
    bad = J.copy()
    bad[5, 2, 3] = np.nan
    s_good, s_bad = svd(J), svd(bad)
    assert np.all(np.isnan(s_bad[5]))
    keep = np.arange(B) != 5
    assert np.array_equal(s_good[keep], s_bad[keep])   # the other lanes do not notice it
    ref = np.linalg.svd(J, compute_uv=False)
    assert np.max(np.abs(s_good - ref) / ref[:, :1]) < 1e-13



@pytest.mark.parametrize("value", [np.inf, -np.inf])
def test_singular_values_on_lanes_with_an_infinite_lane(svd, value):
    # an infinite entry (its Gram matrix infinite or NaN) gives the lane NaN singular
    # values, as a NaN does; the finite lanes equal numpy's SVD
    rng = np.random.default_rng(8)
    J = 0.7 * np.eye(6) + 0.3 * rng.normal(size=(B, 6, 6))
    J /= np.linalg.norm(J, axis=2, keepdims=True)
    bad = J.copy()
    bad[9, 0, 0] = value
    s_bad = svd(bad)
    assert np.all(np.isnan(s_bad[9]))
    keep = np.arange(B) != 9
    ref = np.linalg.svd(J[keep], compute_uv=False)
    assert np.max(np.abs(s_bad[keep] - ref) / ref[:, :1]) < 1e-13

@pytest.fixture(scope="module")
def predictor():
    from numba import njit

    from screwkit.engine._kernels._closures import predict

    @njit(cache=False)
    def run(C, fix, home, span, degree, P6, Xhome, nb):
        """The starts of the poses ``P6 (N, 6)``, ``nb`` a block."""
        N, nx = P6.shape[0], C.shape[1]
        P, X, z = np.zeros((6, B)), np.zeros((nx, B)), np.zeros((12, B))
        out = np.zeros((N, nx))
        for p0 in range(0, N, nb):
            m = min(nb, N - p0)
            for k in range(m):
                for q in range(6):
                    P[q, k] = P6[p0 + k, q]
            predict(C, fix, home, span, degree, P, Xhome, X, z, m, B)
            for k in range(m):
                for x in range(nx):
                    out[p0 + k, x] = X[x, k]
        return out

    return run


@pytest.mark.parametrize("nf,degree", [(3, 3), (3, 4), (5, 4), (6, 3)])
def test_predictor_on_lanes_is_its_polynomial(predictor, nf, degree):
    rng = np.random.default_rng(nf * 10 + degree)
    mono = [c for d in range(degree + 1)
            for c in itertools.combinations_with_replacement(range(nf), d)]
    nx = 7
    C = rng.normal(size=(len(mono), nx))
    fix = np.sort(rng.choice(6, nf, replace=False)).astype(np.int64)
    home, span = rng.normal(size=nf), rng.uniform(0.5, 2.0, nf)
    Xhome = rng.normal(size=nx)
    N = 200
    P6 = rng.normal(size=(N, 6))
    P6[:, fix] = home + span * rng.uniform(-1.5, 1.5, (N, nf))
    P6[17, fix[0]] = home[0] + 5.0 * span[0]       # more than four half-widths out: home
    got = predictor(C, fix, home, span, degree, P6, Xhome, B)
    assert np.array_equal(got, predictor(C, fix, home, span, degree, P6, Xhome, 1))
    z = (P6[:, fix] - home) / span
    feats = np.stack([np.prod(z[:, list(c)], axis=1) if c else np.ones(N) for c in mono], 1)
    ref = feats @ C
    ref[17] = Xhome
    assert np.array_equal(got[17], Xhome)
    assert np.max(np.abs(got - ref)) < 1e-12 * np.max(np.abs(ref))


@pytest.fixture(scope="module")
def lu():
    from numba import njit

    from screwkit.engine._kernels._small import (lu_apply, lu_apply_block, lu_apply_lanes,
                                                 lu_block, lu_factor, lu_lanes, lu_sign)

    @njit(cache=False, error_model="numpy")          # as the kernels: no exceptions
    def run(A, b, nb, once=False):
        """LU factors, interchanges, solutions of ``A x = b`` and signs of ``det A`` of
        ``A (N, 6, 6)``, ``nb`` matrices a block on lanes (stride ``B``; ``nb = 0``: each
        alone through the one-pose ``lu_factor`` and ``lu_apply``; ``once``: the block's LU
        compiled once for the stride ``B``, ``lu_block`` and ``lu_apply_block``)."""
        N = A.shape[0]
        F, x = np.zeros((N, 6, 6)), np.zeros((N, 6))
        P, sg = np.zeros((N, 6), np.int64), np.zeros(N)
        if nb == 0:
            a, piv, y = np.zeros((6, 6)), np.zeros(6, np.int64), np.zeros(6)
            for p in range(N):
                a[:, :] = A[p]
                y[:] = b[p]
                sg[p] = lu_factor(a, 6, piv)
                if sg[p] != 0.0:
                    lu_apply(a, 6, piv, y)
                F[p], P[p], x[p] = a, piv, y
            return F, P, x, sg
        L, piv, y = np.zeros((6, 6, B)), np.zeros((6, B), np.int64), np.zeros((6, B))
        for p0 in range(0, N, nb):
            m = min(nb, N - p0)
            for k in range(m):
                for r in range(6):
                    y[r, k] = b[p0 + k, r]
                    for c in range(6):
                        L[r, c, k] = A[p0 + k, r, c]
            if once:
                lu_block(L, 6, piv, m)
                lu_apply_block(L, 6, piv, y, m)
            else:
                lu_lanes(L, 6, piv, m, B)
                lu_apply_lanes(L, 6, piv, y, m, B)
            for k in range(m):
                sg[p0 + k] = lu_sign(L, 6, piv, k)
                for r in range(6):
                    P[p0 + k, r] = piv[r, k]
                    x[p0 + k, r] = y[r, k]
                    for c in range(6):
                        F[p0 + k, r, c] = L[r, c, k]
        return F, P, x, sg

    return run


def _matrices(rng, N, kind):
    A = rng.normal(size=(N, 6, 6))
    if kind == "graded":                           # rows and columns over 1e-6 .. 1e6
        A *= np.logspace(-3, 3, 6)[:, None] * np.logspace(3, -3, 6)
    elif kind == "nearly singular":                # condition numbers 1e8 .. 1e14
        U, _, Vt = np.linalg.svd(A)
        s = np.logspace(0, -1, 6) * np.ones((N, 1))
        s[:, 5] = 10.0 ** -rng.uniform(8, 14, N)
        A = np.einsum("pij,pj,pjk->pik", U, s, Vt)
    return A


@pytest.mark.parametrize("kind", ["random", "graded", "nearly singular"])
def test_lu_on_lanes_matches_lapack_and_the_matrices_alone(lu, kind):
    import scipy.linalg

    rng = np.random.default_rng(len(kind))
    N = 1000
    A = _matrices(rng, N, kind)
    b = rng.normal(size=(N, 6))
    F, P, x, sg = lu(A, b, B)
    for got, alone in zip((F, P, x, sg), lu(A, b, 0)):
        assert np.array_equal(got, alone)          # every lane as the matrix alone
    for got, alone in zip((F, P, x, sg), lu(A, b, 7)):
        assert np.array_equal(got, alone)          # whatever the block's width
    assert np.array_equal(sg, np.sign(np.linalg.det(A)))
    cond = np.linalg.cond(A)
    ref = np.linalg.solve(A, b[..., None])[..., 0]
    err = np.linalg.norm(x - ref, axis=1) / np.linalg.norm(ref, axis=1)
    assert np.all(err < 1e-14 * cond)
    res = np.linalg.norm(np.einsum("pij,pj->pi", A, x) - b, axis=1)
    assert np.all(res < 1e-14 * np.linalg.norm(A, axis=(1, 2)) * np.linalg.norm(x, axis=1))
    for p in range(0, N, 50):                      # LAPACK's getrf: its pivots, its factors
        lf, lp = scipy.linalg.lu_factor(A[p])
        assert np.array_equal(P[p], lp)
        assert np.max(np.abs(F[p] - lf)) <= 1e-12 * np.max(np.abs(lf)) * min(cond[p], 1e4)


def test_lu_on_lanes_with_a_nan_and_a_singular_lane(lu):
    rng = np.random.default_rng(3)
    A = rng.normal(size=(B, 6, 6))
    b = rng.normal(size=(B, 6))
    bad = A.copy()
    bad[4, 2, 3] = np.nan
    bad[9, :, 1] = 0.0                             # exactly singular: det sign 0
    bad[9, 3, 1] = 0.0
    good, worse = lu(A, b, B), lu(bad, b, B)
    keep = ~np.isin(np.arange(B), [4, 9])
    for g, w in zip(good, worse):
        assert np.array_equal(g[keep], w[keep])    # the other lanes do not notice them
    assert worse[3][9] == 0.0 and np.isnan(worse[2][4]).any()
    alone = lu(bad, b, 0)
    assert np.array_equal(worse[3], alone[3])
    for g, w in zip(worse[:2], alone[:2]):         # the NaN lane's factors as alone
        assert np.array_equal(g[4], w[4], equal_nan=True)
    assert np.array_equal(worse[0][9], alone[0][9])   # stopped at the zero pivot, as alone


def test_lu_block_and_det_sign_batch_are_the_matrices_alone(lu):
    """``_small.lu_block`` / ``lu_apply_block`` (the lane LU compiled once for the stride
    ``BLOCK``, the order a run-time value) and ``_extra.det_sign_batch`` (on blocks of
    them) give every matrix's factors, solution and sign as the one-pose LU alone: random
    matrices, an exactly singular and a NaN one, a last block of 13 lanes."""
    from screwkit.engine._kernels._extra import det_sign_batch

    rng = np.random.default_rng(5)
    N = 3 * B + 13
    A = rng.normal(size=(N, 6, 6))
    b = rng.normal(size=(N, 6))
    A[40, :, 2] = 0.0                              # exactly singular: det sign 0
    A[77, 1, 4] = np.nan
    alone = lu(A, b, 0)
    got = lu(A, b, B, True)
    solved = alone[3] != 0.0                       # (alone, a singular system is not solved)
    for g, r in zip(got, alone):
        assert np.array_equal(g[solved], r[solved], equal_nan=True)
    assert np.array_equal(got[0], alone[0], equal_nan=True) and np.array_equal(got[1], alone[1])
    assert np.array_equal(got[3], alone[3], equal_nan=True)
    sign = np.full(N, 7.0)
    det_sign_batch(A, sign)
    assert np.array_equal(sign, alone[3], equal_nan=True)
    assert sign[40] == 0.0
    fin = np.isfinite(A).all(axis=(1, 2))
    assert np.array_equal(sign[fin], np.sign(np.linalg.det(A[fin])))


def test_lu_of_one_lane_is_the_lanes_with_ties_and_zero_pivots(lu):
    """The one-lane LU (``_small._lu_lane``, its own loop form: the pivot and its row held in
    registers) makes each comparison, interchange and update of the lanes' form: on small
    integer matrices (ties between candidate pivots, exact zero pivots mid-way, zero
    columns, zero matrices, a NaN entry) its factors, pivots and signs are the lanes' bit
    for bit (signed zeros included; a NaN's sign is LLVM's choice), and its signs those of
    the exact determinants (integers, which numpy's rounds to)."""
    rng = np.random.default_rng(11)
    N = 2 * B + 29
    A = rng.integers(-2, 3, size=(N, 6, 6)).astype(float)
    A[:20, :, 3] = 0.0                             # a zero column: det 0 at pivot 3 or later
    A[20:40, 4] = A[20:40, 1]                      # two equal rows
    A[40:50] = 0.0
    A[50:60] = np.eye(6)[rng.permutation(6)]       # permutations: every pivot a tie of ones
    A[61, 2, 5] = np.nan
    b = rng.normal(size=(N, 6))
    alone, lanes = lu(A, b, 0), lu(A, b, B)

    def bits(x):                                   # (every NaN one NaN: its sign is LLVM's)
        return np.where(np.isnan(x), np.nan, x).view(np.int64)

    assert np.array_equal(bits(alone[0]), bits(lanes[0]))
    assert np.array_equal(alone[1], lanes[1]) and np.array_equal(bits(alone[3]), bits(lanes[3]))
    solved = alone[3] != 0.0
    assert np.array_equal(alone[2][solved], lanes[2][solved], equal_nan=True)
    fin = np.isfinite(A).all(axis=(1, 2))
    exact = np.round(np.linalg.det(A[fin]))
    assert np.array_equal(alone[3][fin], np.sign(exact))
    assert (alone[3][fin] == 0.0).sum() >= 50      # (the singular ones are there)
