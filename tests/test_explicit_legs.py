"""Legs built from explicit joints (kind, axis, point, pitch) without the rule language.

Independent check: every catalog leg, rebuilt joint by joint from its placed chain, has the
same constraint system (same span, by the length-normalised rank test) as the catalog leg
built by its rules, and the same actuation wrench modulo that system.
"""

import numpy as np
import pytest

import screwkit
from screwkit.errors import InputError
from screwkit.legs import leg_from_joints
from screwkit.pm import default_catalog
from screwkit.screws import same_span

CATALOG = default_catalog()


@pytest.mark.parametrize("name", sorted(CATALOG.legs))
def test_every_catalog_leg_rebuilt_from_its_joints(name):
    lg = CATALOG.legs[name].build()
    joints = [(j.kind, j.direction, j.point, j.pitch) for j in lg.joints]
    ex = leg_from_joints(joints, lg.A, lg.a, actuated=lg.actuated_index)
    assert len(ex.joints) == len(lg.joints)
    a1, a2 = lg.analyze(), ex.analyze()
    W1, W2 = a1.system.wrenches, a2.system.wrenches
    assert W1.shape == W2.shape
    assert same_span(W1, W2, a1.system.normalisation) if len(W1) else len(W2) == 0
    assert a1.summary() == a2.summary()
    if a1.actuation is not None:
        d = a1.actuation.wrench - a2.actuation.wrench
        if len(W1):
            Wn = a1.system.normalisation.wrenches(W1)
            Q = np.linalg.qr(Wn.T)[0]
            dn = a1.system.normalisation.wrenches(d)
            d = dn - Q @ (Q.T @ dn)
        assert np.linalg.norm(d) < 1e-9 * np.linalg.norm(a1.actuation.wrench)


def test_a_helical_joint_and_mappings():
    leg = leg_from_joints([{"kind": "H", "axis": [0, 0, 1], "point": [0, 0, 0], "pitch": 2.0},
                           {"kind": "P", "axis": [1, 0, 0]}], actuated=1)
    # the string carries the H's pitch, as a leg type's does (a model written from the leg
    # reads it there: "H_P" made it an R joint)
    assert leg.string.marked == "H(2)_P"
    # the H twist is [p x d + h d; d] with h = 2
    np.testing.assert_allclose(leg.twists[0], [0, 0, 2.0, 0, 0, 1])


@pytest.mark.parametrize("joints, kw, words", [
    ([], {}, "at least one joint"),
    ([("S", [0, 0, 1], [0, 0, 0])], {}, "kind must be"),
    ([("R", [0, 0, 1])], {}, "needs a point"),
    ([("R", [0, 0, 0], [0, 0, 0])], {}, r"joints\[0\]"),
    ([("R", [0, 0, 1], [0, 0, 0], 1.0)], {}, "only an H"),
    ([("R", [0, 0, 1], [0, 0, 0])], {"actuated": 3}, "actuated"),
    ([{"kind": "R", "axis": [0, 0, 1], "point": [0, 0, 0], "pich": 1}], {}, "unknown key"),
    ([("R", [0, 0, 1], [0, 0, 0])] * 40, {}, "at most"),
])
def test_bad_joints_are_named(joints, kw, words):
    with pytest.raises(InputError, match=words):
        leg_from_joints(joints, **kw)


def test_explicit_leg_in_the_unified_jacobian():
    """Six explicit S-P-S legs (each S as three R) make the Stewart platform's Jacobian:
    rows are the Pluecker lines of the legs (built by hand)."""
    ang = np.radians([-10, 10, 110, 130, 230, 250])
    A = np.c_[100 * np.cos(ang), 100 * np.sin(ang), np.zeros(6)]
    angp = np.radians([-50, 50, 70, 170, 190, 290])
    o = np.array([4.0, -3.0, 85.0])
    a = np.c_[45 * np.cos(angp), 45 * np.sin(angp), np.zeros(6)] + o
    legs = []
    for i in range(6):
        d = a[i] - A[i]
        joints = [("R", e, A[i]) for e in np.eye(3)] + [("P", d, A[i])] + \
                 [("R", e, a[i]) for e in np.eye(3)]
        legs.append(leg_from_joints(joints, A[i], a[i], actuated=3))
    from screwkit.engine import unified_jacobian

    jac = unified_jacobian(legs, o)
    d = (a - A) / np.linalg.norm(a - A, axis=1, keepdims=True)
    np.testing.assert_allclose(jac.J, np.c_[d, np.cross(a, d)], atol=1e-10)
