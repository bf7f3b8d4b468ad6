"""``_kernels._jit.choose``: ``a if c else b`` as one select, value for value the conditional
expression (signed zeros, NaN, infinities, an integer and a float unified), in a lane loop as
in one call."""

import numpy as np
import pytest


@pytest.fixture(scope="module")
def kernels():
    from numba import njit

    from screwkit.engine._kernels._jit import choose

    @njit(cache=False)
    def with_choose(c, a, b, out):
        for k in range(a.shape[0]):
            out[k] = choose(c[k], a[k], b[k])

    @njit(cache=False)
    def with_branch(c, a, b, out):
        for k in range(a.shape[0]):
            out[k] = a[k] if c[k] else b[k]

    @njit(cache=False)
    def mixed(c, i, x):
        return choose(c, i, x)

    return with_choose, with_branch, mixed


def test_choose_is_the_conditional_expression_bit_for_bit(kernels):
    with_choose, with_branch, _ = kernels
    rng = np.random.default_rng(3)
    special = np.array([0.0, -0.0, np.nan, np.inf, -np.inf, 1e-310, -1.5])
    a = np.concatenate([special, rng.normal(size=93)])
    b = np.concatenate([special[::-1], rng.normal(size=93)])
    c = rng.random(a.shape[0]) < 0.5
    got, want = np.empty_like(a), np.empty_like(a)
    with_choose(c, a, b, got)
    with_branch(c, a, b, want)
    assert np.array_equal(got.view(np.int64), want.view(np.int64))
    # and against numpy's own select, independently of the kernels
    assert np.array_equal(got.view(np.int64), np.where(c, a, b).view(np.int64))


def test_choose_unifies_an_integer_and_a_float(kernels):
    _, _, mixed = kernels
    assert mixed(True, 3, 2.5) == 3.0 and isinstance(mixed(True, 3, 2.5), float)
    assert mixed(False, 3, 2.5) == 2.5
