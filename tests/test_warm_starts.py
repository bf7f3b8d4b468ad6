"""Warm starts from a solution (``guess=``): each start moved by the home predictor's change
between the guess's pose and the pose solved (``_kernels/_solve_lanes.moved_starts``).

Expected values: the paper's closed forms of the 3RRPRR (eq. 11, with the sign of ``Yo``
fixed, as in ``test_pm_kinematics``), the 6-SPS's leg lengths from its joint points (a hand
derivation: ``|R b_i + o - a_i|``), and the one-pose analyses that a batch equals bit for bit.
"""

import numpy as np
import pytest

import screwkit

E3, e3 = 120 / np.sqrt(3), 60 / np.sqrt(3)


def _closed_3rrprr(a, b, Zo):
    sa, ca, sb, cb = np.sin(a), np.cos(a), np.sin(b), np.cos(b)
    den = -sa ** 2 + ca ** 2 * cb
    Xo = (Zo * ca + e3 * sa) * sb / den
    Yo = (-Zo * sa * ca * (1 + cb) + e3 * (cb - ca ** 2 + sa ** 2 * cb) / 2) / den
    return Xo, Yo


@pytest.mark.parametrize("step", [0.002, 0.01, 0.05])
def test_a_neighbours_solution_starts_one_step_closer_on_the_closed_forms(step):
    """A guess from a pose ``step`` rad (and ``50 step`` cm) away: two Gauss-Newton steps
    (three from the guess as it is, the benchmark's warm pose before the move), and the pose
    of the closed forms."""
    pm = screwkit.load_pm("3RRPRR")
    a, b, Zo = 0.09, -0.05, 80.0
    prev = screwkit.solve(pm, {"alpha": a, "beta": b, "Zo": Zo})
    a2, b2, Z2 = a + step, b - step / 2, Zo + 50 * step
    sol = screwkit.solve(pm, {"alpha": a2, "beta": b2, "Zo": Z2}, guess=prev)
    assert sol.success and sol.residual <= 1e-12
    assert int(sol.closures.iterations[0]) <= 2
    Xo, Yo = _closed_3rrprr(a2, b2, Z2)
    assert sol.params["gamma"] == pytest.approx(a2, abs=1e-10)
    assert sol.params["Xo"] == pytest.approx(Xo, abs=1e-9)
    assert sol.params["Yo"] == pytest.approx(Yo, abs=1e-9)


def test_the_6sps_from_a_neighbour_in_two_steps_on_its_leg_lengths():
    pm = screwkit.load_pm("6SPS")
    one = dict(pm.default_pose)
    near = {p: v + (0.002 if p in ("alpha", "beta", "gamma") else 0.1) for p, v in one.items()}
    prev = screwkit.solve(pm, one)
    sol = screwkit.solve(pm, near, guess=prev)
    assert sol.success and int(sol.closures.iterations[0]) <= 2
    from scipy.spatial.transform import Rotation
    R = Rotation.from_euler(pm.order, [near["alpha"], near["beta"], near["gamma"]]).as_matrix()
    o = np.array([near["Xo"], near["Yo"], near["Zo"]])
    # the platform's joint points at home are given about o at home (the default pose)
    R0 = Rotation.from_euler(pm.order, [one["alpha"], one["beta"], one["gamma"]]).as_matrix()
    o0 = np.array([one["Xo"], one["Yo"], one["Zo"]])
    b_local = (np.asarray(pm.platform_points) - o0) @ R0 if _points_at_default(pm) else \
        np.asarray(pm.platform_points)
    lengths = np.linalg.norm(b_local @ R.T + o - np.asarray(pm.base_points), axis=1)
    np.testing.assert_allclose(sol.extensions, lengths, rtol=1e-10)


def _points_at_default(pm) -> bool:
    """Whether the model's platform points are placed at its default pose (else in the
    platform's own frame): the leg lengths at the default pose tell."""
    sol = screwkit.solve(pm, dict(pm.default_pose))
    d = np.linalg.norm(np.asarray(pm.platform_points) - np.asarray(pm.base_points), axis=1)
    return bool(np.allclose(sol.extensions, d, rtol=1e-9))


def test_a_batch_with_guesses_equals_its_poses_alone_bit_for_bit():
    """The block kernel moves each lane's start as the one-pose kernel moves a pose's."""
    pm = screwkit.load_pm("3RRPRR")
    rng = np.random.default_rng(7)
    n = 300
    pose = {"alpha": rng.uniform(-0.15, 0.15, n), "beta": rng.uniform(-0.15, 0.15, n),
            "Zo": rng.uniform(65, 95, n)}
    prev = screwkit.analyze(pm, pose)
    moved = {"alpha": pose["alpha"] + 0.004, "beta": pose["beta"] - 0.003,
             "Zo": pose["Zo"] + 0.3}
    batch = screwkit.analyze(pm, moved, guess=prev.solution, workers=2)
    assert batch.ok.all()
    its = np.asarray(batch.solution.closures.iterations)
    assert its.max() <= 2
    for i in range(0, n, 15):
        alone = screwkit.analyze(pm, {k: float(v[i]) for k, v in moved.items()},
                                 guess=prev[i].solution)
        assert np.array_equal(alone.solution.closures.X[:, 0], batch.solution.closures.X[:, i])
        assert np.array_equal(alone.statics.F_r[0], batch.statics.F_r[i])
        assert int(alone.solution.closures.iterations[0]) == its[i]


def test_a_guess_off_the_predictors_branch_is_taken_as_it_is():
    """A guess a whole turn of gamma away is no start of the predictor's branch: it is not
    moved (the solution keeps its turn, as from the guess alone) and converges."""
    pm = screwkit.load_pm("3RRPRR")
    one = {"alpha": 0.05, "beta": 0.03, "Zo": 80.0}
    turned = screwkit.solve(pm, one, guess={"gamma": 0.05 + 2 * np.pi})
    assert turned.params["gamma"] == pytest.approx(0.05 + 2 * np.pi, abs=1e-9)
    near = dict(one, alpha=0.052)
    sol = screwkit.solve(pm, near, guess=turned)
    assert sol.success
    assert sol.params["gamma"] == pytest.approx(0.052 + 2 * np.pi, abs=1e-9)   # (11c)


def test_an_unreachable_guess_is_not_moved_and_its_pose_is_solved():
    """A guess pose without a solution (its parameters NaN): the start is the guess as it
    is, and the pose is solved (from there, or by the rescue from home)."""
    pm = screwkit.load_pm("3RRPRR")
    prev = screwkit.analyze(pm, {"alpha": [0.05, 1.4], "beta": [0.02, 0.02],
                                 "Zo": [80.0, 80.0]})
    assert list(prev.solution.reachable_mask) == [True, False]
    res = screwkit.analyze(pm, {"alpha": [0.051, 0.06], "beta": [0.021, 0.03],
                                "Zo": [80.1, 81.0]}, guess=prev.solution)
    assert res.ok.all()
    Xo, Yo = _closed_3rrprr(np.array([0.051, 0.06]), np.array([0.021, 0.03]),
                            np.array([80.1, 81.0]))
    np.testing.assert_allclose(res.solution.params["Xo"], Xo, rtol=0, atol=1e-9)
    np.testing.assert_allclose(res.solution.params["Yo"], Yo, rtol=0, atol=1e-9)
