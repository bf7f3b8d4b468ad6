"""Freedoms of a constraint-wrench system (issue 14, item 3).

Each constraint set is derived by hand here: the expected freedom twist T is written
first and every wrench W is chosen with ``W . T = f . v + m . w = 0``.
"""

import json

import numpy as np
import pytest
from scipy.spatial.transform import Rotation

import screwkit
from screwkit.cli import main
from screwkit.errors import InputError
from screwkit.pm import mobility_of_legs
from screwkit.screws import couple_wrench, force_wrench, freedoms

H = 2.5            # pitch of the helical freedom, length per radian


def _helical_set(h=H):
    """Five forces reciprocal to T = [0, 0, h; 0, 0, 1] (helical about Z through O):
    W . T = h f_z + m_z.  Forces along X and Y through O and through (0, 0, 1) have
    f_z = m_z = 0; a force through (1, 0, 0) along (0, 1, c) has f_z = c and
    m_z = ((1, 0, 0) x (0, 1, c))_z = 1, so c = -1 / h."""
    return np.array([force_wrench([1, 0, 0], [0, 0, 0]).vector,
                     force_wrench([0, 1, 0], [0, 0, 0]).vector,
                     force_wrench([1, 0, 0], [0, 0, 1]).vector,
                     force_wrench([0, 1, 0], [0, 0, 1]).vector,
                     force_wrench([0, 1, -1 / h], [1, 0, 0]).vector])


def test_five_lines_leave_one_helical_freedom_with_its_pitch():
    res = freedoms(_helical_set())
    assert (res.dof, res.label, res.constraint_rank) == (1, "1H", 5)
    (f,) = res.freedoms
    assert f.kind == "helical" and f.pitch == pytest.approx(H, rel=1e-9)
    np.testing.assert_allclose(f.direction, [0, 0, 1], atol=1e-12)
    np.testing.assert_allclose(f.point[:2], [0, 0], atol=1e-12)       # on the Z axis
    np.testing.assert_allclose(f.twist, [0, 0, H, 0, 0, 1], atol=1e-12)
    assert res.residual < 1e-12 and np.isfinite(res.condition_number) and res.margin > 1


def test_three_concurrent_forces_leave_three_rotations_about_lines_through_the_point():
    P = np.array([1.0, 2.0, 3.0])
    dirs = [[1, 0, 0], [1, 1, 0], [0.3, -0.2, 1]]                      # not coplanar
    res = freedoms([force_wrench(d, P).vector for d in dirs])
    assert (res.dof, res.label) == (3, "3R")
    for f in res.freedoms:
        assert f.kind == "rotation" and f.pitch == 0
        np.testing.assert_allclose(f.point, P, atol=1e-9)
        # a rotation about a line through P: v = P x w, reciprocal to every force through P
        np.testing.assert_allclose(f.twist[:3], np.cross(P, f.direction), atol=1e-9)
    assert np.linalg.matrix_rank(np.array([f.direction for f in res.freedoms])) == 3


def test_three_non_coplanar_couples_leave_three_translations():
    res = freedoms([couple_wrench(d) for d in ([1, 0, 0], [1, 1, 0], [1, 1, 1])])  # Wrench objects
    assert (res.dof, res.label, res.translations) == (3, "3T", 3)
    assert all(f.point is None and f.pitch == np.inf for f in res.freedoms)
    np.testing.assert_allclose(res.twists[:, 3:], 0, atol=1e-12)


def test_planar_set_and_free_body():
    # a force along Z through O and couples about X and Y: rotations about Z, XY translations
    res = freedoms([force_wrench([0, 0, 1], [0, 0, 0]).vector, couple_wrench([1, 0, 0]).vector,
                    couple_wrench([0, 1, 0]).vector])
    assert res.label == "2T1R"
    rot = [f for f in res.freedoms if f.kind == "rotation"][0]
    np.testing.assert_allclose(np.abs(rot.direction), [0, 0, 1], atol=1e-12)
    free = freedoms(np.zeros((0, 6)))
    assert (free.dof, free.label, free.constraint_rank) == (6, "3T3R", 0)


@pytest.mark.parametrize("scale", [1.0, 1000.0])
def test_invariant_under_a_base_frame_move_and_units(scale):
    """Moving the base frame moves the axis with it; scaling lengths by k scales the pitch."""
    R = Rotation.from_euler("xyz", [20, -35, 50], degrees=True).as_matrix()
    p = np.array([40.0, -15.0, 7.0])
    W = _helical_set()
    Wm = np.array([np.r_[R @ w[:3], R @ (scale * w[3:]) + np.cross(p, R @ w[:3])] for w in W])
    (f,) = freedoms(Wm).freedoms
    assert f.kind == "helical" and f.pitch == pytest.approx(scale * H, rel=1e-8)
    np.testing.assert_allclose(abs(f.direction @ (R @ [0, 0, 1])), 1, atol=1e-12)
    # the axis is the moved Z axis: it passes through p
    assert np.linalg.norm(np.cross(f.point - p, f.direction)) < 1e-8 * scale


def test_bad_input_is_named():
    with pytest.raises(InputError, match="shape"):
        freedoms(np.zeros((2, 5)))
    with pytest.raises(InputError, match=r"wrenches\[1\] is zero"):
        freedoms([[1, 0, 0, 0, 0, 0], [0] * 6])
    with pytest.raises(InputError, match="at most"):
        freedoms(np.tile([1.0, 0, 0, 0, 0, 0], (100, 1)))


def test_mobility_of_no_leg_is_six_dof_and_a_helical_platform_is_labelled_so():
    m = mobility_of_legs([])
    assert (m.dof, m.motion_type, m.constraint_rank) == (6, "3T3R", 0)
    # a platform on one H joint (pitch 2.5 along Z through (1, 0, 0)): one helical freedom
    leg = screwkit.leg_from_joints([("H", [0, 0, 1], [1, 0, 0], H)])
    m = mobility_of_legs([leg])
    assert (m.dof, m.motion_type) == (1, "1H(p=2.5)")


def test_cli_freedom(capsys):
    args = ["freedom", "--length-unit", "mm"]
    for P, d in ((0, 0, 0), (1, 0, 0)), ((0, 0, 0), (0, 1, 0)), ((0, 0, 1), (1, 0, 0)), \
            ((0, 0, 1), (0, 1, 0)), ((1, 0, 0), (0, 1, -1 / H)):
        args += ["--force", ",".join(map(str, P)) + ":" + ",".join(map(str, d))]
    assert main(args + ["--json"]) == 0
    d = json.loads(capsys.readouterr().out)
    assert d["label"] == "1H" and d["freedoms"][0]["pitch"] == pytest.approx(H)
    assert d["units"]["pitch"] == "mm/rad"
    assert main(args) == 0
    assert "pitch 2.5 mm/rad" in capsys.readouterr().out
    assert main(["freedom", "--leg", "RRPRR", "--json"]) == 0
    assert json.loads(capsys.readouterr().out)["dof"] == 5       # one constraint force
    assert main(["freedom", "--force", "1,2:3"]) == 2
    assert "expected" in capsys.readouterr().err


def test_a_screw_along_a_translation_is_a_rotation_and_one_normal_to_it_stays_helical():
    """Cylindrical set: forces along X and Y through O and couples about X and Y are
    reciprocal to [0, 0, 1; 0, 0, 0] and to any [0, 0, h; 0, 0, 1]: the translation along Z
    makes every pitch about Z reachable, so the freedoms are 1T1R, never a helical one.
    With the translation along X instead (wrenches: force along Y, couples about X and Y,
    and [0, 0, 1; 0, 0, -h], for which h f_z + m_z = 0), the screw about Z keeps its
    pitch h: 1T1H."""
    h = 1.7
    cyl = [force_wrench([1, 0, 0], [0, 0, 0]).vector, force_wrench([0, 1, 0], [0, 0, 0]).vector,
           couple_wrench([1, 0, 0]).vector, couple_wrench([0, 1, 0]).vector]
    res = freedoms(cyl)
    assert res.label == "1T1R"
    rot = [f for f in res.freedoms if f.kind == "rotation"][0]
    np.testing.assert_allclose(np.abs(rot.direction), [0, 0, 1], atol=1e-12)
    np.testing.assert_allclose(rot.point[:2], [0, 0], atol=1e-12)
    mixed = [force_wrench([0, 1, 0], [0, 0, 0]).vector, couple_wrench([1, 0, 0]).vector,
             couple_wrench([0, 1, 0]).vector, [0, 0, 1, 0, 0, -h]]
    res = freedoms(mixed)
    assert res.label == "1T1H" and res.pitches == pytest.approx((h,), rel=1e-9)
    (tr,) = [f for f in res.freedoms if f.kind == "translation"]
    np.testing.assert_allclose(tr.direction, [1, 0, 0], atol=1e-12)
    # every classified twist is reciprocal to every wrench
    for f in res.freedoms:
        np.testing.assert_allclose(np.asarray(mixed, float) @ f.twist, 0, atol=1e-9)


@pytest.mark.parametrize("forces", [
    [([0, 0, 1], [0, 0, 0])],                        # one force along z through O
    [([0, 0, 1], [1, 2, 0]), ([1, 0, 0], [0, 0, 3])],
])
def test_a_rotation_axis_moved_along_its_shift_is_still_a_freedom(forces):
    """The line a rotation freedom may be moved along (``shift``): its twist moved by s,
    [v + s x d; d], is reciprocal to every constraint force (f . v + m . w = 0), checked
    with the forces' own wrenches [f; p x f]."""
    from screwkit.screws import freedoms
    W = [np.concatenate([np.asarray(f, float), np.cross(p, f)]) for f, p in forces]
    res = freedoms(np.array(W))
    moved = 0
    for fr in res.freedoms:
        for s in fr.shift:
            v = fr.twist[:3] + np.cross(s, fr.direction)
            for w in W:
                assert abs(w[:3] @ v + w[3:] @ fr.twist[3:]) < 1e-12
            moved += 1
    assert moved
