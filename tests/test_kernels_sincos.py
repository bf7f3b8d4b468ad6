"""The kernels' own sine and cosine (``_kernels._trig.sin_cos``, vectorised across a block's
lanes in the products of exponentials) against independent references: the C library's, and
numpy's in extended precision (``np.longdouble``) as the exact values; identities that hold
exactly in floating point (odd/even symmetry, quadrants)."""

import math

import numpy as np
import pytest


@pytest.fixture(scope="module")
def sin_cos_of():
    from numba import njit

    from screwkit.engine._kernels._trig import SIN_COS_MAX, sin_cos, sin_cos_fix

    @njit(cache=False)
    def both(x):
        s, c = np.empty_like(x), np.empty_like(x)
        for k in range(x.shape[0]):
            s[k], c[k] = sin_cos(x[k])
        for k in range(x.shape[0]):
            s[k], c[k] = sin_cos_fix(x[k], s[k], c[k])
        return s, c

    return both, SIN_COS_MAX


def _ulps(got, x, fn):
    exact = fn(x.astype(np.longdouble))
    if np.finfo(np.longdouble).eps >= np.finfo(float).eps:   # no extended precision here
        pytest.skip("np.longdouble is float64 on this platform")
    return np.abs((got - exact) / np.spacing(np.abs(exact).astype(float))).astype(float)


@pytest.mark.parametrize("half", [1e-8, 1.0, 7.0, 100.0, 1e4, 9.9e4])
def test_within_two_ulps_of_exact(sin_cos_of, half):
    both, _ = sin_cos_of
    x = np.random.default_rng(int(half * 10) % 1000).uniform(-half, half, 200_000)
    s, c = both(x)
    assert _ulps(s, x, np.sin).max() <= 2.5
    assert _ulps(c, x, np.cos).max() <= 2.5
    # and within one ulp of the C library's nearly everywhere: the absolute error stays at
    # rounding level
    assert np.abs(s - np.sin(x)).max() <= 2.3e-16
    assert np.abs(c - np.cos(x)).max() <= 2.3e-16


def test_joint_angles_of_a_mechanism(sin_cos_of):
    """The angles the kernels see (a few turns at most) and the multiples of pi/2 around
    which the reduction cancels."""
    both, _ = sin_cos_of
    k = np.arange(-40, 41)
    x = np.concatenate([k * (math.pi / 2), np.nextafter(k * (math.pi / 2), np.inf),
                        np.linspace(-4 * math.pi, 4 * math.pi, 100_001)])
    s, c = both(x)
    assert np.abs(s - np.sin(x)).max() <= 2.3e-16
    assert np.abs(c - np.cos(x)).max() <= 2.3e-16
    assert np.abs(s * s + c * c - 1.0).max() <= 4.5e-16


def test_symmetries_and_quadrants(sin_cos_of):
    both, _ = sin_cos_of
    x = np.random.default_rng(3).uniform(0.0, 50.0, 50_000)
    s, c = both(x)
    sm, cm = both(-x)
    assert np.array_equal(sm, -s) and np.array_equal(cm, c)
    assert both(np.array([0.0]))[0][0] == 0.0 and both(np.array([0.0]))[1][0] == 1.0


def test_beyond_the_range_and_non_finite_fall_back_to_the_c_library(sin_cos_of):
    both, limit = sin_cos_of
    x = np.array([limit * 1.5, -3e7, 1e300, np.inf, -np.inf, np.nan])
    s, c = both(x)
    with np.errstate(invalid="ignore"):
        ref_s, ref_c = np.sin(x), np.cos(x)
    assert np.array_equal(s, ref_s, equal_nan=True)
    assert np.array_equal(c, ref_c, equal_nan=True)


def test_the_ratio_of_a_small_angle_to_its_sine():
    """``_trig.angle_over_sine`` (the closure errors' rotation vectors below ``SMALL_ANGLE``,
    without atan2) against ``asin(s) / s`` in extended precision and against the C library's
    ``atan2(s, c) / s`` (what the kernels called before): within two ulps over the range."""
    from numba import njit

    from screwkit.engine._kernels._trig import SMALL_ANGLE, angle_over_sine

    @njit(cache=False)
    def ratios(z):
        out = np.empty_like(z)
        for k in range(z.shape[0]):
            out[k] = angle_over_sine(z[k])
        return out

    theta = np.concatenate([np.geomspace(1e-17, SMALL_ANGLE, 20_000), [SMALL_ANGLE]])
    s = np.sin(theta)
    got = ratios(s * s)
    libm = np.array([math.atan2(a, math.sqrt(1.0 - a * a)) / a for a in s])
    assert np.abs(got - libm).max() <= 2 * np.spacing(1.0)
    if np.finfo(np.longdouble).eps < np.finfo(float).eps:
        sl = s.astype(np.longdouble)
        exact = (np.arcsin(sl) / sl).astype(float)
        assert np.abs(got - exact).max() <= 2 * np.spacing(1.0)
    assert ratios(np.array([0.0]))[0] == 1.0
