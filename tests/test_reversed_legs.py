"""Linear actuators run to a negative length (``screwkit.engine._reversal``): such a solution
is solved again, or the pose is unreachable with the reason; never reported as ok.

The poses are those an independent audit found solved with a leg turned through its base
point and reported ok: a 2UPS+2SPR pose beyond a singular surface from home, and a
3UPS+UP/passive pose.  The references: the statics built here from the geometry alone
(each leg's actuation a force along ``delta_i = (a_i - A_i) / |a_i - A_i|`` through
``A_i``, an SPR leg's constraint a force through its S centre along its R axis), and the
same pose reached along a path from home (continuation: the levels' solver).
"""

import numpy as np
import pytest

import screwkit
from screwkit import errors
from screwkit.engine import _run
from screwkit.engine._reversal import actuator_lines, reversed_legs

F, T = np.array([-20.0, -30.0, -60.0]), np.array([-30.0, -30.0, 100.0])
UPS_SPR = ("2UPS+2SPR", {"alpha": 0.0913, "beta": 0.0364, "gamma": 0.5859, "Zo": 44.3144})
UPS_UP = ("3UPS+UP/passive", {"alpha": 0.0529, "beta": -0.5479, "Zo": 701.2321})


def _signed_lengths(sol):
    """``(a_i - A_i) . u_i`` of every active leg, ``u_i`` its actuated joint's axis at the
    pose (the legs' frames)."""
    out = []
    for lg in sol.legs:
        if lg.actuated_index is None:
            continue
        u = np.asarray(lg.actuated_joint.direction, float)
        out.append(float((np.asarray(lg.a) - np.asarray(lg.A)) @ u / np.linalg.norm(u)))
    return np.array(out)


def _ups_spr_statics(pm, sol):
    """The actuator forces of a 2UPS+2SPR from its geometry at the solved pose: rows
    ``[d; A x d]`` (actuation along ``delta_i``, constraint along the SPR's R axis through
    its S centre), ``J^T x = -[F; T + o x F]``."""
    A, a = np.asarray(sol.base_points), np.asarray(sol.platform_points)
    o, R = np.asarray(sol.position), np.asarray(sol.rotation)
    rows = []
    for i in range(4):
        d = (a[i] - A[i]) / np.linalg.norm(a[i] - A[i])
        rows.append(np.r_[d, np.cross(A[i], d)])
    for i, lg in enumerate(pm.home_legs):
        if lg.string.text == "SPR":
            n = R @ np.asarray(lg.joints[-1].direction, float)     # (fixed in the platform)
            rows.append(np.r_[n, np.cross(A[i], n)])
    J = np.array(rows)
    assert J.shape == (6, 6)
    return np.linalg.solve(J.T, -np.r_[F, T + np.cross(o, F)])[:4]


def test_a_pose_beyond_a_singular_surface_keeps_its_actuators_the_right_way_round():
    name, pose = UPS_SPR
    pm = screwkit.load_pm(name)
    r = screwkit.analyze(pm, pose, force=F, torque=T)
    assert r.ok and r.solution.status == "ok"
    assert np.all(_signed_lengths(r.solution) > 0)
    # solved again (its first solve reversed a leg), its outputs written in place into a
    # copy of the first launch's read-only ones (_outputs.owned), read-only again
    assert r.solution.closures.how.tolist() == [1]
    for a in (r.jacobian.J, r.jacobian.conditioning.condition_number, r.statics.values):
        assert not a.flags.writeable
    np.testing.assert_allclose(r.statics.active, _ups_spr_statics(pm, r.solution),
                               rtol=1e-9, atol=1e-9)
    # the same pose along a path from home: the same assembly, beyond the same surface
    t = np.linspace(0.0, 1.0, 201)
    home = {"alpha": 0.0, "beta": 0.0, "gamma": 0.0, "Zo": 80.0}
    along = screwkit.analyze(pm, {k: home[k] + t * (pose[k] - home[k]) for k in pose},
                             path=True, force=F, torque=T)
    np.testing.assert_allclose(r.statics.active, along.statics.active[-1], rtol=1e-9)
    assert r.quality.beyond_singular_surface == along.quality.beyond_singular_surface[-1]
    assert r.quality.beyond_singular_surface       # (reversed, its det's sign hid it)


def test_a_passive_legged_pm_has_no_leg_turned_through_its_base_point():
    name, pose = UPS_UP
    pm = screwkit.load_pm(name)
    one = screwkit.analyze(pm, pose, force=F, torque=T)
    assert one.ok and np.all(_signed_lengths(one.solution) > 0)
    batch = screwkit.analyze(pm, {k: np.full(3, v) for k, v in pose.items()}, force=F,
                             torque=T)
    assert batch.ok.all()
    np.testing.assert_array_equal(batch.statics.active, np.tile(one.statics.active, (3, 1)))
    assert not reversed_legs(pm, batch.solution.closures.X).any()


def test_a_pose_whose_only_assembly_found_is_reversed_is_unreachable(monkeypatch):
    name, pose = UPS_SPR
    pm = screwkit.load_pm(name)
    resolve = _run.resolve

    def failing(model, fixed, X, side, workers):        # (no other assembly found)
        X, its, done = resolve(model, fixed, X, side, workers)
        return X, its, np.zeros_like(done)

    monkeypatch.setattr(_run, "resolve", failing)
    with pytest.raises(errors.UnreachablePoseError, match="leg 4 to a negative length"):
        screwkit.analyze(pm, pose, force=F, torque=T)
    two = screwkit.analyze(pm, {k: np.array([v, 80.0 if k == "Zo" else 0.0])
                                for k, v in pose.items()}, force=F, torque=T)
    assert two.solution.status.tolist() == ["unreachable", "ok"]
    assert two.ok.tolist() == [False, True]
    assert two.conditioning.tolist() == ["unreachable", "regular"]
    assert np.isnan(two.statics.active[0]).all() and np.isfinite(two.statics.active[1]).all()
    assert any("leg 4 to a negative length" in n for n in two.solution.pose_notes[0])


def test_the_test_applies_to_legs_whose_actuator_carries_their_length():
    # SPS, UPS, SPR and RPS legs carry their length on their actuator; an RPRU's does not
    # (its R joints' axes miss A and a)
    assert actuator_lines(screwkit.load_pm("6SPS")).legs.tolist() == [0, 1, 2, 3, 4, 5]
    assert actuator_lines(screwkit.load_pm("3RPS")).legs.tolist() == [0, 1, 2]
    assert actuator_lines(screwkit.load_pm("3RPRU")).legs.size == 0
    pm = screwkit.load_pm("6SPS")
    lines = actuator_lines(pm)
    home = np.array([np.linalg.norm(np.asarray(lg.a) - np.asarray(lg.A)) for lg in pm.home_legs])
    np.testing.assert_allclose(np.abs(lines.home), home, rtol=1e-12)
    # q = -2 s_home turns leg 3 through its base point (s = -s_home); q = -s_home / 2 does not
    from screwkit.engine._chains import chains_of
    X = chains_of(pm).home_vector(3)
    X[lines.rows[2], 1] = -2 * lines.home[2] / lines.scale[2]
    X[lines.rows[2], 2] = -0.5 * lines.home[2] / lines.scale[2]
    rev = reversed_legs(pm, X)
    assert rev.tolist() == [[False] * 6, [False, False, True, False, False, False], [False] * 6]


@pytest.mark.parametrize("name", ["6SPS", "2UPS+2SPR", "3RPS"])
def test_every_launch_returns_the_legs_its_poses_reverse(name):
    # the analysis kernel's bit mask of each pose's reversed legs (``reversed_mask``),
    # against the signed length of each leg from the legs' frames at the given unknowns (the
    # forward pass): (p - A_i) . u_i, u_i the actuated P joint's axis as the joints before it
    # turned it, p the point of the joint after it (its home point a_i, carried along the
    # axis by the P joint), compared with its sign at home
    from screwkit.engine._chains import chains_of
    from screwkit.engine._launch import frames, run_poses
    from screwkit.engine._solve import predictor_of
    pm = screwkit.load_pm(name)
    ch = chains_of(pm)
    lines = actuator_lines(pm)
    rng = np.random.default_rng(5)
    N = 200
    X = ch.home_vector(N) + rng.normal(0.0, 0.05, (ch.n_unknowns, N))
    turned = rng.random((N, lines.legs.size)) < 0.3        # some legs turned through A_i
    for c in range(lines.legs.size):
        X[lines.rows[c], turned[:, c]] = -2.0 * lines.home[c] / lines.scale[c] \
            * rng.uniform(0.9, 1.1, turned[:, c].sum())
    P6 = ch.full_params({p: np.full(N, ch.home[p]) for p in ch.fixed}, N)
    Z = predictor_of(ch)
    mask = run_poses(ch.flat, Z, P6, X=X.T, rows=False)["reversed_mask"]
    axes_points = frames(ch.flat, Z, P6, np.ascontiguousarray(X.T))["axes_points"]
    expect = np.zeros(N, np.int64)
    for i, lg in enumerate(pm.home_legs):
        k = lg.actuated_index
        if i not in lines.legs:
            continue
        A = np.asarray(lg.A, float)
        assert np.allclose(lg.joints[k + 1].point, lg.a)
        u = axes_points[:, i, k, :3] / np.linalg.norm(axes_points[:, i, k, :3], axis=1)[:, None]
        s = np.einsum("ni,ni->n", axes_points[:, i, k + 1, 3:] - A, u)
        u0 = np.asarray(lg.joints[k].direction, float)
        s_home = float((np.asarray(lg.a) - A) @ u0 / np.linalg.norm(u0))
        expect |= (np.sign(s_home) * s <= 1e-7 * pm.normalisation.length).astype(np.int64) << i
    assert turned.any() and (mask != 0).any() and (mask == 0).any()
    np.testing.assert_array_equal(mask, expect)
    # the batch test of unknowns given from Python: the same
    np.testing.assert_array_equal(lines.mask(X), expect)


def test_a_model_with_other_dimensions_tests_its_own_lengths():
    # an optimiser's candidate (reflatten: the first model's arrays, the candidate's
    # geometry) carries the candidate's home lengths and limits, as the candidate loaded
    # afresh does; an actuator moved by q = -0.6 of the first model's home length runs the
    # candidate's leg, of less than half that length, through zero, not the first model's
    from screwkit.engine import reflatten
    from screwkit.engine._chains import chains_of
    from screwkit.engine._kernels._layout import REV
    pm = screwkit.load_pm("3RPS")
    cand = pm.with_dimensions({"R": 30.0, "r": 15.0})
    fresh = screwkit.load_pm("3RPS", {"R": 30.0, "r": 15.0})
    flat = reflatten(pm, cand)
    from screwkit.engine._flat import flatten
    np.testing.assert_allclose(flat.M[REV], flatten(fresh).M[REV], rtol=1e-12)
    home = np.array([np.linalg.norm(np.asarray(lg.a) - np.asarray(lg.A))
                     for lg in cand.home_legs])
    lines = actuator_lines(cand)
    np.testing.assert_allclose(np.abs(lines.home), home, rtol=1e-12)
    first = actuator_lines(pm)
    assert np.abs(first.home[0]) > 1.9 * np.abs(lines.home[0])
    q = -0.6 * first.home[0]                       # (model lengths; the unknown is q / scale)
    X = chains_of(cand).home_vector(2)
    X[lines.rows[0], 1] = q / lines.scale[0]
    assert reversed_legs(cand, X).tolist() == [[False] * 3, [True, False, False]]
    X = chains_of(pm).home_vector(2)
    X[first.rows[0], 1] = q / first.scale[0]
    assert not reversed_legs(pm, X).any()
