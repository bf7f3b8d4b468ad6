"""The reciprocal-screw solver: reciprocity, completeness, rank, invariance.

Expected values are identities (every basis wrench does no work on every joint
twist; the system maps to itself under a change of frame or of units), a second
method (scipy's null space of the twist matrix) or hand-built screw sets.
"""

import numpy as np
import pytest
import scipy.linalg
from hypothesis import given, settings
from hypothesis import strategies as st
from scipy.spatial.transform import Rotation

import screwkit
from screwkit.errors import InputError
from screwkit.legs import JOINT_DOF, generic_leg
from screwkit.screws import (Normalisation, characteristic_length, couple_wrench, force_wrench,
                             independent_subset, prismatic_twist, reciprocal_system,
                             revolute_twist, same_span, span_contains, transform_wrenches)

SETTINGS = settings(max_examples=50, deadline=None)


@st.composite
def leg_strings(draw):
    """A string over R, P, H, U, S, C with 1..6 degrees of freedom in all."""
    budget = draw(st.integers(1, 6))
    s = ""
    while True:
        room = [c for c in "RPHUSC" if JOINT_DOF[c] <= budget - sum(JOINT_DOF[x] for x in s)]
        if not room or (s and draw(st.booleans()) and draw(st.booleans())):
            break
        s += draw(st.sampled_from(room))
    # a leg of helical joints only has no default actuated joint: mark the first one
    return s if any(c in "PCRUS" for c in s) else "_" + s


generic_legs = st.builds(lambda s, seed: generic_leg(s, seed=seed), leg_strings(),
                         st.integers(0, 10_000))
rotations = st.integers(0, 2**31 - 1).map(lambda s: Rotation.random(random_state=s).as_matrix())
translations = st.tuples(*[st.floats(-500, 500)] * 3).map(np.array)


def _normalised_max_product(W, T, norm):
    """max |W.V| / (|W| |V|) on normalised screws (dimensionless)."""
    Wn, Tn = norm.wrenches(W), norm.twists(T)
    num = np.abs(Wn @ Tn.T)
    return float(np.max(num / np.outer(np.linalg.norm(Wn, axis=1), np.linalg.norm(Tn, axis=1)),
                        initial=0.0))


# ---------------------------------------------------------------- properties on generic legs

@SETTINGS
@given(generic_legs)
def test_every_constraint_wrench_is_reciprocal_to_every_joint_twist(leg):
    sys = reciprocal_system(leg.twists, leg.points)
    T = leg.twists
    assert sys.dimension == 6 - sys.rank == len(sys.wrenches)
    assert _normalised_max_product(sys.wrenches, T, sys.normalisation) < 1e-9
    # the decomposed members too (forces, couples, finite-pitch screws)
    res = leg.analyze()
    members = np.array([c.wrench.vector for c in res.constraints]).reshape(-1, 6)
    assert len(members) == sys.dimension
    assert _normalised_max_product(members, T, sys.normalisation) < 1e-8
    assert all(c.reciprocity < 1e-8 for c in res.constraints)


@SETTINGS
@given(generic_legs)
def test_system_is_the_whole_null_space(leg):
    """Second method: scipy's null space of the (unscaled) twist matrix."""
    T = leg.twists
    sys = reciprocal_system(T, leg.points)
    # generic legs are well conditioned: an ordinary rank decision agrees
    Ts = np.hstack([T[:, :3] / leg.length, T[:, 3:]])
    assert sys.rank == np.linalg.matrix_rank(Ts, tol=1e-8)
    N = scipy.linalg.null_space(T, rcond=1e-10).T if len(T) else np.eye(6)
    assert len(N) == sys.dimension
    assert same_span(N, sys.wrenches, sys.normalisation)


@SETTINGS
@given(generic_legs, rotations, translations,
       st.sampled_from([1.0, 1e3, 1e-3]))
def test_system_is_invariant_under_change_of_frame_and_units(leg, R, p, k):
    """x -> R (k x) + p maps a wrench [f; m] to transform_wrenches(R, p, [f; k m])."""
    res = leg.analyze()
    moved = leg.moved(R, p, k)
    res2 = moved.analyze()
    assert res2.connectivity == res.connectivity
    assert res2.system.dimension == res.system.dimension
    assert res2.dependent_joints == res.dependent_joints
    np.testing.assert_allclose(res2.system.singular_values, res.system.singular_values,
                               rtol=1e-6, atol=1e-9)
    mapped = transform_wrenches(R, p, res.system.wrenches * np.r_[1, 1, 1, k, k, k])
    assert same_span(mapped, res2.system.wrenches, res2.system.normalisation)
    assert (res2.n_forces, res2.n_couples, res2.n_screws) == (res.n_forces, res.n_couples, res.n_screws)
    assert res2.agrees()
    # each force line of the original maps to a force of the moved system
    for c in res.constraints:
        if c.kind == "force":
            w = force_wrench(R @ c.direction, R @ (k * c.point) + p).vector
            assert span_contains(res2.system.wrenches, w, res2.system.normalisation)
        elif c.kind == "couple":
            assert span_contains(res2.system.wrenches, couple_wrench(R @ c.direction).vector,
                                 res2.system.normalisation)


@pytest.mark.parametrize("seed", [4, 119])
@pytest.mark.parametrize("k", [1e-3, 1.0, 1e3])
@pytest.mark.parametrize("turn", [None, 0, 1, 2])
def test_generic_pru_rules_agree_in_every_frame_and_unit(seed, k, turn):
    """Regression (hypothesis examples of the property above): a generic PRU moved by p =
    (0, 0, 64) and scaled by 1e-3 got a second force 'through U3' 5e-6 from the first one
    (a near-null vector of the parallel-to-a-direction condition written on moments about
    O in the model's units, with an absolute floor in its tolerance).  The rules must find
    the same members in every frame and unit: the force through U3 and one force that
    meets R2 and is perpendicular to P1, each reciprocal to every joint twist."""
    leg = generic_leg("PRU", seed=seed)
    R = np.eye(3) if turn is None else Rotation.random(random_state=turn).as_matrix()
    p = np.array([0.0, 0.0, 64.0])
    res, res2 = leg.analyze(), leg.moved(R, p, k).analyze()
    assert res.agrees() and res2.agrees()
    assert [c.kind for c in res2.constraints] == [c.kind for c in res.constraints] == \
        ["force", "force"]
    assert [c.point_name for c in res2.constraints] == [c.point_name for c in res.constraints]
    assert max(c.reciprocity for c in res2.constraints) < 1e-9
    # the two forces are distinct lines: the second is not a copy of the first
    d1, d2 = (c.direction for c in res2.constraints)
    assert np.linalg.norm(np.cross(d1, d2)) > 0.1
    mapped = transform_wrenches(R, p, res.system.wrenches * np.r_[1, 1, 1, k, k, k])
    assert same_span(mapped, [c.wrench.vector for c in res2.constraints],
                     res2.system.normalisation)


@pytest.mark.parametrize("name", ["PPPP", "PRRR", "RRPRR", "SP", "UPU/couple"])
@pytest.mark.parametrize("k", [1e-6, 1e6])
def test_extreme_units_do_not_change_ranks(name, k):
    """Prismatic twists [u; 0] and couples [0; t] have no length of their own: metres to
    micrometres must not change a rank (regression: P rows used to shrink as 1/L)."""
    leg = screwkit.leg(name)
    res, res2 = leg.analyze(), leg.moved(np.eye(3), np.zeros(3), k).analyze()
    assert res2.connectivity == res.connectivity
    assert res2.dependent_joints == res.dependent_joints
    assert (res2.n_forces, res2.n_couples) == (res.n_forces, res.n_couples)
    np.testing.assert_allclose(res2.system.singular_values, res.system.singular_values,
                               rtol=1e-6, atol=1e-9)


# ---------------------------------------------------------------- hand-built systems

def test_r_and_p_example_by_hand():
    # R about Z through O, P along X: W.V = 0 demands m_z = 0 and f_x = 0
    T = np.array([revolute_twist([0, 0, 1], [0, 0, 0]).vector, prismatic_twist([1, 0, 0]).vector])
    sys = reciprocal_system(T, points=[[0, 0, 0]])
    assert (sys.rank, sys.dimension, sys.dependent) == (2, 4, False)
    hand = np.array([[0, 1, 0, 0, 0, 0], [0, 0, 1, 0, 0, 0], [0, 0, 0, 1, 0, 0], [0, 0, 0, 0, 1, 0]])
    assert same_span(hand, sys.wrenches, sys.normalisation)
    assert not span_contains(sys.wrenches, [1, 0, 0, 0, 0, 0], sys.normalisation)
    assert not span_contains(sys.wrenches, couple_wrench([0, 0, 1]).vector, sys.normalisation)


def test_three_coplanar_parallel_axes_are_dependent():
    # axes along Y through (0,0,0), (1,0,0), (2,0,0): [p x y; y] is affine in p, so the
    # third twist is 2*(second) - (first)
    T = np.array([revolute_twist([0, 1, 0], [x, 0, 0]).vector for x in (0.0, 1.0, 2.0)])
    np.testing.assert_allclose(T[2], 2 * T[1] - T[0], atol=1e-15)
    sys = reciprocal_system(T, points=[[0, 0, 0], [2, 0, 0]])
    assert sys.rank == 2 and sys.dependent
    assert independent_subset(T, [[0, 0, 0], [2, 0, 0]]) == ([0, 1], [2])
    # off the line the third axis is independent
    T[2] = revolute_twist([0, 1, 0], [1, 0, 1]).vector
    assert reciprocal_system(T).rank == 3


def test_four_prismatic_joints():
    # X, Y, X + Y, Z: the third lies in the span of the first two
    T = np.array([prismatic_twist(d).vector for d in ([1, 0, 0], [0, 1, 0], [1, 1, 0], [0, 0, 1])])
    ind, dep = independent_subset(T, [[0, 0, 0], [1, 1, 1]])
    assert (ind, dep) == ([0, 1, 3], [2])
    sys = reciprocal_system(T, [[0, 0, 0], [1, 1, 1]])
    assert sys.rank == 3
    couples = np.hstack([np.zeros((3, 3)), np.eye(3)])
    assert same_span(couples, sys.wrenches, sys.normalisation)


def test_empty_and_full_systems():
    sys = reciprocal_system(np.zeros((0, 6)))
    assert sys.rank == 0 and sys.dimension == 6 and np.isinf(sys.condition_number)
    T = np.eye(6)
    sys = reciprocal_system(T, points=[[0, 0, 0], [1, 1, 1]])
    assert sys.rank == 6 and sys.dimension == 0 and sys.wrenches.shape == (0, 6)
    assert np.isfinite(sys.condition_number)


def test_same_span_and_span_contains():
    norm = Normalisation.for_points([[0, 0, 0], [10, 0, 0]])
    a = force_wrench([0, 0, 1], [0, 0, 0]).vector
    b = force_wrench([0, 0, 1], [10, 0, 0]).vector
    # two parallel forces span the parallel forces in their plane and the couple between them
    c = couple_wrench([0, 1, 0]).vector
    mid = force_wrench([0, 0, 1], [5, 0, 0]).vector
    assert same_span([a, b], [mid, c], norm)
    assert span_contains([a, b], mid, norm) and span_contains([a, b], c, norm)
    assert not span_contains([a, b], couple_wrench([1, 0, 0]).vector, norm)
    assert not same_span([a, b], [a], norm)


# ---------------------------------------------------------------- normalisation

@SETTINGS
@given(st.lists(st.tuples(*[st.floats(-100, 100)] * 3), min_size=2, max_size=6),
       st.lists(st.floats(-10, 10), min_size=6, max_size=6),
       st.lists(st.floats(-10, 10), min_size=6, max_size=6))
def test_normalisation_identities(points, W, V):
    P = np.array(points)
    norm = Normalisation.for_points(P)
    W, V = np.array(W), np.array(V)
    np.testing.assert_allclose(norm.wrenches_back(norm.wrenches(W)), W, atol=1e-9 * (1 + abs(W).max()) * 100)
    np.testing.assert_allclose(norm.twists_back(norm.twists(V)), V, atol=1e-9 * (1 + abs(V).max()) * 100)
    # normalised product = physical product / L
    lhs = norm.wrenches(W) @ norm.twists(V) * norm.length
    assert lhs == pytest.approx(W @ V, abs=1e-8 * (1 + np.abs(W).sum() * np.abs(V).sum()) * 100)


def test_characteristic_length_by_hand():
    # two points 2 apart: centroid midway, RMS distance 1
    assert characteristic_length([[0, 0, 0], [2, 0, 0]]) == pytest.approx(1.0)
    # scales with the units, ignores translations
    P = np.random.default_rng(0).normal(size=(5, 3))
    L = characteristic_length(P)
    assert characteristic_length(1000 * P + 7) == pytest.approx(1000 * L)
    assert characteristic_length(np.zeros((0, 3))) == 1.0 and characteristic_length([[0, 0, 0]] * 3) == 1.0


@pytest.mark.parametrize("T", [np.zeros((2, 5)), np.full((1, 6), np.nan), np.zeros((2, 3, 6))])
def test_bad_twist_matrices(T):
    with pytest.raises(InputError):
        reciprocal_system(T)


def test_bad_characteristic_length():
    with pytest.raises(InputError, match="characteristic length"):
        reciprocal_system(np.eye(6)[:2], length=-1.0)
