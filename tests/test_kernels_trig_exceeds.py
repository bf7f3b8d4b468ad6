"""The test that spares the representation-singularity checks their call of the C library
(``_kernels._trig.trig_exceeds``): wherever it says ``|sin b|`` (or ``|cos b|``) exceeds a
tolerance, the C library's value, and numpy's in extended precision, exceed it; and it says
so for nearly every angle a pose has, so that the call is spared.  The checks that use it
(``near_singular``, ``tolerance``) then give what the C library's value alone gives, for
angles around every zero of the sine and cosine within a few turns."""

import math

import numpy as np
import pytest


@pytest.fixture(scope="module")
def kernels():
    from numba import njit

    from screwkit.engine._kernels._closures import near_singular
    from screwkit.engine._kernels._newton import tolerance
    from screwkit.engine._kernels._trig import trig_exceeds

    @njit(cache=False)
    def exceeds(b, sine, tol):
        out = np.empty(b.shape[0], np.bool_)
        for k in range(b.shape[0]):
            out[k] = trig_exceeds(b[k], sine, tol)
        return out

    @njit(cache=False)
    def checks(b, order4, tol):
        # beta given (unknowns alpha and gamma: 3, 5), as a 3RRPRR's closures
        order = np.array([0, 0, 0, 0, order4, 0], np.int64)
        unk = np.array([3, 5], np.int64)
        xs = np.ones(2)
        near = np.empty(b.shape[0], np.bool_)
        tols = np.empty(b.shape[0])
        p6 = np.zeros(6)
        x0 = np.zeros(2)
        for k in range(b.shape[0]):
            p6[4] = b[k]
            near[k] = near_singular(order, unk, p6, tol)
            tols[k] = tolerance(order, unk, xs, p6, x0)
        return near, tols

    return exceeds, checks


def _angles():
    rng = np.random.default_rng(7)
    zeros = np.arange(-80, 81) * (math.pi / 2)
    around = (zeros[:, None] + np.linspace(-0.03, 0.03, 601)[None, :]).ravel()
    return np.concatenate([
        around, np.nextafter(zeros, np.inf), np.nextafter(zeros, -np.inf),
        rng.uniform(-4 * math.pi, 4 * math.pi, 200_000), rng.uniform(-0.2, 0.2, 50_000),
        [0.0, -0.0, 1e5, -1e5, 2e6, np.inf, -np.inf, np.nan]])


@pytest.mark.parametrize("sine", [True, False])
@pytest.mark.parametrize("tol", [1e-2, 1e-5, 1e-7])
def test_never_says_exceeds_where_it_does_not(kernels, sine, tol):
    exceeds, _ = kernels
    b = _angles()
    said = exceeds(b, sine, tol)
    with np.errstate(invalid="ignore"):                  # (inf)
        exact = np.abs((np.sin if sine else np.cos)(b.astype(np.longdouble)))
    libm = np.abs(np.array([(math.sin if sine else math.cos)(x) if np.isfinite(x) else np.nan
                            for x in b]))
    assert not (said & ~(libm > tol)).any()
    assert not (said & ~(exact > tol)).any()
    # it spares the call for nearly every angle: all but those within about 1.6 tol (plus
    # rounding) of a zero, and the non-finite and huge ones
    finite = np.isfinite(b) & (np.abs(b) < 1e6)
    assert (said | ~finite | (libm <= 1.6 * tol + 1e-8)).all()
    assert said[finite].mean() > 0.8


@pytest.mark.parametrize("order4", [1, 0])
def test_checks_equal_the_libm_formula(kernels, order4):
    _, checks = kernels
    b = _angles()
    b = b[np.isfinite(b)]
    from screwkit.engine._kernels._layout import STOP
    s = np.abs([math.sin(x) if order4 == 1 else math.cos(x) for x in b])    # (the C library)
    for tol in (1e-5, 1e-7):
        near, tols = checks(b, order4, tol)
        np.testing.assert_array_equal(near, s <= tol)
        np.testing.assert_array_equal(tols, np.maximum(STOP * np.minimum(1.0, s / 1e-2),
                                                       1e-16))
