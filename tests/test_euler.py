"""Euler angles: the paper's XYX direction cosines, the 24 scipy orders, singularities."""

import numpy as np
import pytest

from screwkit.errors import InputError
from screwkit.screws import ORDERS, angular_jacobian, euler_angles, is_singular, rotation_matrix


def _elem(axis, t):
    """Elementary rotation written out by hand."""
    c, s = np.cos(t), np.sin(t)
    return {"x": np.array([[1, 0, 0], [0, c, -s], [0, s, c]]),
            "y": np.array([[c, 0, s], [0, 1, 0], [-s, 0, c]]),
            "z": np.array([[c, -s, 0], [s, c, 0], [0, 0, 1]])}[axis]


@pytest.mark.parametrize("a,b,g", [(0.3, -0.2, 0.5), (1.1, 0.7, -2.0), (-0.4, 2.5, 0.1)])
def test_xyx_is_the_papers_eq_10c(a, b, g):
    # eq. (10c) typed from the paper, lambda = gamma; R = [[xl yl zl], [xm ym zm], [xn yn zn]]
    ca, sa, cb, sb, cg, sg = np.cos(a), np.sin(a), np.cos(b), np.sin(b), np.cos(g), np.sin(g)
    xl, xm, xn = cb, sa * sb, -ca * sb
    yl, ym, yn = sg * sb, ca * cg - sa * cb * sg, sa * cg + ca * cb * sg
    zl, zm, zn = cg * sb, -ca * sg - sa * cb * cg, -sa * sg + ca * cb * cg
    R10c = np.array([[xl, yl, zl], [xm, ym, zm], [xn, yn, zn]])
    assert np.allclose(rotation_matrix("XYX", a, b, g), R10c, atol=1e-14)


@pytest.mark.parametrize("order", ORDERS + tuple(o.lower() for o in ORDERS))
def test_orders_match_hand_products_and_invert(order):
    rng = np.random.default_rng(sum(map(ord, order)) + 100 * order.isupper())
    a, b, g = rng.uniform(-1.2, 1.2, 3)
    b = abs(b) + 0.2 if order[0].lower() == order[2].lower() else b  # inside scipy's canonical range
    ax = order.lower()
    if order.isupper():
        ref = _elem(ax[0], a) @ _elem(ax[1], b) @ _elem(ax[2], g)
    else:
        ref = _elem(ax[2], g) @ _elem(ax[1], b) @ _elem(ax[0], a)
    R = rotation_matrix(order, a, b, g)
    assert np.allclose(R, ref, atol=1e-14)
    ea = euler_angles(R, order)
    assert not ea.singular
    assert np.allclose(ea.angles, [a, b, g], atol=1e-10)
    assert np.allclose(rotation_matrix(order, *np.degrees([a, b, g]), degrees=True), R)
    assert np.allclose(euler_angles(R, order, degrees=True).angles, np.degrees([a, b, g]), atol=1e-8)


@pytest.mark.parametrize("order", ["XYX", "ZYZ", "XYZ", "zyx"])
def test_angular_jacobian_by_finite_differences(order):
    x = np.array([0.3, 0.6, -0.4])
    E = angular_jacobian(order, *x)
    R = rotation_matrix(order, *x)
    h = 1e-6
    for k in range(3):
        d = np.zeros(3)
        d[k] = h
        W = (rotation_matrix(order, *(x + d)) - rotation_matrix(order, *(x - d))) / (2 * h) @ R.T
        assert np.allclose([W[2, 1], W[0, 2], W[1, 0]], E[:, k], atol=1e-8)


def test_singularities():
    assert is_singular("XYX", 0.0) and is_singular("XYX", np.pi) and is_singular("ZYZ", 180, degrees=True)
    assert not is_singular("XYX", 0.1)
    assert is_singular("XYZ", np.pi / 2) and is_singular("XYZ", -90, degrees=True)
    assert not is_singular("XYZ", 0.0)
    # at the singularity only alpha + gamma is defined (XYX, beta = 0): R = Rx(alpha + gamma)
    R = rotation_matrix("XYX", 0.5, 0.0, 0.2)
    assert np.allclose(R, _elem("x", 0.7))
    ea = euler_angles(R, "XYX", reference=[0.0, 0.0, 0.3])
    assert ea.singular and ea.combination == "alpha+gamma"
    assert np.isclose(ea.angles[2], 0.3) and np.isclose(ea.angles[0], 0.4)
    assert np.allclose(rotation_matrix("XYX", *ea.angles), R)
    # the Jacobian loses rank exactly there
    assert abs(np.linalg.det(angular_jacobian("XYX", 0.5, 0.0, 0.2))) < 1e-14
    # Tait-Bryan XZY at beta = pi/2: alpha - gamma is what is defined
    R = rotation_matrix("XZY", 0.5, np.pi / 2, 0.2)
    ea = euler_angles(R, "XZY", reference=[0, 0, 0.1])
    assert ea.singular and np.allclose(rotation_matrix("XZY", *ea.angles), R)
    assert np.allclose(R, rotation_matrix("XZY", 0.5 + 0.3, np.pi / 2, 0.2 + 0.3)) == \
        (ea.combination == "alpha-gamma")


def test_bad_input():
    with pytest.raises(InputError, match="Euler order"):
        rotation_matrix("XXY", 0, 0, 0)
    with pytest.raises(InputError):
        rotation_matrix("XyX", 0, 0, 0)
    with pytest.raises(InputError, match="finite"):
        rotation_matrix("XYX", float("nan"), 0, 0)
