"""Screw primitives: constructors, pitch/axis round trips, frame changes.

Expected values come from the definitions (v = p x w + h w for a screw of
pitch h through p; m = p x f + h f for a wrench) written out by hand here, or
from identities (reciprocal products are frame-invariant).
"""

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st
from scipy.spatial.transform import Rotation

from screwkit.errors import GeometryError, InputError
from screwkit.screws import (Line, Twist, Wrench, couple_wrench, force_wrench, helical_twist,
                             prismatic_twist, reciprocal_product, revolute_twist, screw_axis_point,
                             screw_pitch, transform_twists, transform_wrenches)

SETTINGS = settings(max_examples=50, deadline=None)

finite = st.floats(-100, 100, allow_nan=False, allow_infinity=False)
vec3 = st.tuples(finite, finite, finite).map(np.array)
direction = st.tuples(finite, finite, finite).map(np.array).filter(
    lambda v: np.linalg.norm(v) > 1e-2)
pitch = st.floats(-50, 50, allow_nan=False, allow_infinity=False)
rotation = st.integers(0, 2**31 - 1).map(lambda s: Rotation.random(random_state=s).as_matrix())


def _same_line(line: Line, point, d, atol):
    """The line passes through ``point`` and is parallel to ``d``."""
    u = np.asarray(d, float) / np.linalg.norm(d)
    assert np.linalg.norm(np.cross(line.direction, u)) < 1e-9
    assert line.distance_to_point(point) < atol


# ---------------------------------------------------------------- round trips

@SETTINGS
@given(d=direction, p=vec3, h=pitch)
def test_twist_pitch_and_axis_round_trip(d, p, h):
    V = helical_twist(d, p, h)
    u = d / np.linalg.norm(d)
    # by definition V = [p x u + h u; u]
    np.testing.assert_allclose(V.vector, np.r_[np.cross(p, u) + h * u, u], atol=1e-12)
    assert V.pitch == pytest.approx(h, abs=1e-9 * (1 + abs(h)))
    _same_line(V.axis, p, d, atol=1e-9 * (1 + np.linalg.norm(p)))
    # an R is the zero-pitch case
    R = revolute_twist(d, p)
    assert R.pitch == pytest.approx(0.0, abs=1e-9 * (1 + np.linalg.norm(p)))
    _same_line(R.axis, p, d, atol=1e-9 * (1 + np.linalg.norm(p)))


@SETTINGS
@given(d=direction, p=vec3, h=pitch, mag=st.floats(0.1, 10))
def test_wrench_pitch_and_axis_round_trip(d, p, h, mag):
    u = d / np.linalg.norm(d)
    f = mag * u
    W = Wrench(np.r_[f, np.cross(p, f) + h * f])   # a wrench of pitch h on the line (p, u)
    assert W.pitch == pytest.approx(h, abs=1e-9 * (1 + abs(h)))
    _same_line(W.axis, p, d, atol=1e-9 * (1 + np.linalg.norm(p)))
    F = force_wrench(d, p, mag)
    np.testing.assert_allclose(F.vector, np.r_[f, np.cross(p, f)], atol=1e-9 * (1 + np.linalg.norm(p)))
    assert F.pitch == pytest.approx(0.0, abs=1e-9 * (1 + np.linalg.norm(p)))
    # the moment about a point of the line vanishes
    np.testing.assert_allclose(F.moment_about(p), 0.0, atol=1e-9 * mag * (1 + np.linalg.norm(p)))


def test_infinite_pitch_screws():
    P = prismatic_twist([0, 0, 2])
    np.testing.assert_array_equal(P.vector, [0, 0, 1, 0, 0, 0])
    assert P.pitch == np.inf and P.axis is None
    C = couple_wrench([3, 0, 0], 2.0)
    np.testing.assert_array_equal(C.vector, [0, 0, 0, 2, 0, 0])
    assert C.pitch == np.inf and C.axis is None
    assert np.all(np.isnan(screw_axis_point(P.vector)))


def test_batched_pitch_and_axis_point():
    # two twists by hand: R about Z through (1, 2, 0); H about X through (0, 0, 3) of pitch 0.5
    V = np.array([[2.0, -1.0, 0, 0, 0, 1],       # p x u = (1,2,0) x (0,0,1) = (2, -1, 0)
                  [0.5, 3.0, 0, 1, 0, 0]])       # (0,0,3) x (1,0,0) = (0, 3, 0), + 0.5 x
    np.testing.assert_allclose(screw_pitch(V), [0.0, 0.5])
    np.testing.assert_allclose(screw_axis_point(V), [[1, 2, 0], [0, 0, 3]])


# ---------------------------------------------------------------- products

def test_reciprocal_product_hand_values():
    # unit force along Y through O, R axis along X at height d: moment of the force about
    # the axis = ((O - (0,0,d)) x y) . x = d
    d = 7.0
    V = revolute_twist([1, 0, 0], [0, 0, d])
    W = force_wrench([0, 1, 0], [0, 0, 0])
    assert W.reciprocal(V) == pytest.approx(d)
    assert V.reciprocal(W) == pytest.approx(d)
    # a force meeting the axis, a force parallel to it, a couple perpendicular to it: no work
    assert force_wrench([0, 1, 0], [5, 0, d]).reciprocal(V) == pytest.approx(0, abs=1e-12)
    assert force_wrench([1, 0, 0], [1, 2, 3]).reciprocal(V) == pytest.approx(0, abs=1e-12)
    assert couple_wrench([0, 1, 1]).reciprocal(V) == pytest.approx(0, abs=1e-12)
    # a force along a prismatic joint does work |f|
    assert force_wrench([0, 0, 1], [4, 4, 4], 3.0).reciprocal(prismatic_twist([0, 0, 1])) == pytest.approx(3.0)
    # helical of pitch h and a force along its axis: f.(h u) = h
    assert force_wrench([0, 0, 1], [1, 1, 0]).reciprocal(helical_twist([0, 0, 1], [1, 1, 0], 0.25)) \
        == pytest.approx(0.25)


def test_reciprocal_product_broadcasts():
    W = np.arange(12.0).reshape(2, 6)
    V = np.ones(6)
    np.testing.assert_allclose(reciprocal_product(W, V), [15.0, 51.0])


# ---------------------------------------------------------------- frame changes

@SETTINGS
@given(R=rotation, p=vec3, W=st.lists(finite, min_size=6, max_size=6),
       V=st.lists(finite, min_size=6, max_size=6))
def test_transforms_preserve_reciprocal_product(R, p, W, V):
    W, V = np.array(W), np.array(V)
    before = reciprocal_product(W, V)
    after = reciprocal_product(transform_wrenches(R, p, W), transform_twists(R, p, V))
    scale = (1 + np.linalg.norm(p)) * (1 + np.linalg.norm(W)) * (1 + np.linalg.norm(V))
    assert after == pytest.approx(before, abs=1e-10 * scale)


@SETTINGS
@given(R=rotation, p=vec3, d=direction, q=vec3, h=pitch)
def test_transforms_match_construction_in_the_new_frame(R, p, d, q, h):
    """Moving a joint axis / force line and building the screw there gives the same screw."""
    tol = 1e-9 * (1 + np.linalg.norm(p) + np.linalg.norm(q)) * (1 + abs(h))
    np.testing.assert_allclose(transform_twists(R, p, helical_twist(d, q, h).vector),
                               helical_twist(R @ d, R @ q + p, h).vector, atol=tol)
    np.testing.assert_allclose(transform_twists(R, p, prismatic_twist(d).vector),
                               prismatic_twist(R @ d).vector, atol=1e-12)
    np.testing.assert_allclose(transform_wrenches(R, p, force_wrench(d, q).vector),
                               force_wrench(R @ d, R @ q + p).vector, atol=tol)
    np.testing.assert_allclose(transform_wrenches(R, p, couple_wrench(d).vector),
                               couple_wrench(R @ d).vector, atol=1e-12)
    # the value types do the same, and lines move with the points
    T = revolute_twist(d, q).transformed(R, p)
    _same_line(T.axis, R @ q + p, R @ d, atol=tol)
    L = Line.through(q, d).transformed(R, p)
    _same_line(L, R @ q + p, R @ d, atol=tol)


def test_transforms_broadcast_over_batches():
    Rs = Rotation.random(3, random_state=4).as_matrix()
    ps = np.random.default_rng(4).normal(size=(3, 3))
    V = np.random.default_rng(5).normal(size=(3, 6))
    out = transform_twists(Rs, ps, V)
    for i in range(3):
        np.testing.assert_allclose(out[i], transform_twists(Rs[i], ps[i], V[i]))


# ---------------------------------------------------------------- lines

def test_line_geometry_by_hand():
    x_axis = Line.through([5, 0, 0], [2, 0, 0])
    np.testing.assert_allclose(x_axis.point, [0, 0, 0], atol=1e-15)
    y_at_5 = Line.through([3, 7, 5], [0, -1, 0])
    assert x_axis.distance_to_line(y_at_5) == pytest.approx(5.0)      # skew: common normal Z
    p1, p2 = x_axis.closest_points(y_at_5)
    np.testing.assert_allclose(p1, [3, 0, 0], atol=1e-12)
    np.testing.assert_allclose(p2, [3, 0, 5], atol=1e-12)
    par = Line.through([0, 2, 0], [1, 0, 0])
    assert x_axis.is_parallel(par) and x_axis.distance_to_line(par) == pytest.approx(2.0)
    j = Line.joining([1, 1, 1], [1, 1, 4])
    np.testing.assert_allclose(j.direction, [0, 0, 1])
    assert j.contains([1, 1, -10], atol=1e-12) and not j.contains([1, 1.1, 0], atol=1e-3)
    # the Plücker condition is enforced: d . m = 0
    L = Line([1, 0, 0], [1, 2, 3])
    assert float(L.direction @ L.moment) == pytest.approx(0.0)


# ---------------------------------------------------------------- values and errors

def test_values_are_immutable_and_comparable():
    V = revolute_twist([0, 0, 1], [1, 0, 0])
    with pytest.raises(ValueError):
        V.vector[0] = 3.0
    assert V == Twist(V.vector.copy()) and hash(V) == hash(Twist(V.vector.copy()))
    assert V != Wrench(V.vector.copy())           # a twist is never equal to a wrench
    np.testing.assert_array_equal(np.asarray(V), V.vector)


@pytest.mark.parametrize("call, exc", [
    (lambda: revolute_twist([0, 0, 0], [0, 0, 0]), GeometryError),
    (lambda: force_wrench([1, 0, 0], [0, np.nan, 0]), InputError),
    (lambda: prismatic_twist([1, 0]), InputError),
    (lambda: helical_twist([0, 0, 1], [0, 0, 0], np.inf), InputError),
    (lambda: Twist(np.zeros(5)), InputError),
    (lambda: Wrench([0, 0, 0, np.inf, 0, 0]), InputError),
    (lambda: transform_twists(np.eye(2), np.zeros(3), np.zeros(6)), InputError),
])
def test_bad_input_raises_screwkit_errors(call, exc):
    with pytest.raises(exc):
        call()
