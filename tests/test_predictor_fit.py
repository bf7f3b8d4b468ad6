"""The home predictor's least-squares fit (``screwkit.engine._solve._least_squares``).

Its coefficients set every pose's start, so the last bits of every solution: they must be
the same in any process on the machine, whatever number of threads OpenBLAS runs (a Dask
worker runs one: ``OPENBLAS_NUM_THREADS=1``).  ``numpy.linalg.solve`` of a 4SPS+SPR's
126 x 126 normal equations gave other bits on one thread than on two, so a distributed map
differed from the serial one in the last bits.  The independent references: LAPACK's
``lstsq`` (the fit's values), and the fit run in fresh processes with one and with two
BLAS threads (its bits)."""

import os
import subprocess
import sys

import numpy as np

from screwkit.engine._solve import _cholesky_solve, _least_squares


def test_the_fit_is_lapacks_least_squares_to_rounding():
    rng = np.random.default_rng(3)
    for m, n in ((125, 35), (373, 126)):
        A, Y = rng.standard_normal((m, n)), rng.standard_normal((m, 4))
        ref = np.linalg.lstsq(A, Y, rcond=None)[0]
        assert np.max(np.abs(_least_squares(A, Y) - ref)) < 1e-12


def test_monomials_it_cannot_tell_apart_are_left_out():
    """A column repeated (a fit whose failed poses leave two monomials equal on the rest):
    the later one's coefficient is 0 and the fit closes as well as the least-norm one."""
    rng = np.random.default_rng(4)
    A = rng.standard_normal((60, 8))
    A[:, 6] = A[:, 2]
    Y = rng.standard_normal((60, 3))
    C = _least_squares(A, Y)
    assert np.all(C[6] == 0.0)
    best = np.linalg.lstsq(A, Y, rcond=None)[0]
    assert np.allclose(A @ C, A @ best, atol=1e-12)
    # a positive definite system: the exact solution
    G = A[:, :6].T @ A[:, :6]
    X = rng.standard_normal((6, 2))
    assert np.allclose(_cholesky_solve(G, G @ X), X, atol=1e-12)


_FIT = ("import hashlib, screwkit\n"
        "from screwkit.engine._chains import chains_of\n"
        "from screwkit.engine._solve import predictor_of\n"
        "Z = predictor_of(chains_of(screwkit.load_pm('4SPS+SPR')))\n"
        "print(hashlib.sha1(Z[7].tobytes()).hexdigest())\n")


def _fit_in_process(threads):
    env = dict(os.environ, OPENBLAS_NUM_THREADS=str(threads), OMP_NUM_THREADS=str(threads))
    run = subprocess.run([sys.executable, "-c", _FIT], capture_output=True, text=True,
                         env=env, timeout=900)
    assert run.returncode == 0, run.stderr
    return run.stdout.strip()


def test_the_predictor_does_not_depend_on_the_blas_threads():
    one, two = _fit_in_process(1), _fit_in_process(2)
    assert len(one) == 40 and one == two
