"""The batched engine: one pose is N = 1, a batch equals a loop over its poses, flagged
poses are kept, inputs in every accepted form; Euler angles pinned to scipy.

Independent references: scipy's ``Rotation.from_euler`` (the definition of the 24 Euler
conventions), finite differences of it (the angular Jacobian), the engine's own per-pose
results (each pose solved alone, from home) against the batch.
"""

import os

import numpy as np
import pytest
from scipy.spatial.transform import Rotation

import screwkit
from screwkit.engine import PAPER_FORCE, PAPER_TORQUE
from screwkit.screws import euler_matrices
from screwkit.errors import InputError, SingularityError, UnreachablePoseError
from screwkit.pm import pm_names
from random_poses import random_pose

# the paper's workload, stated (only 3RRPRR and 2SPS+2SPR declare it as their default)
PAPER_LOAD = {"force": (-20.0, -30.0, -60.0), "torque": (-30.0, -30.0, 100.0)}
PAPER_ARGS = ["--force=-20,-30,-60", "--torque=-30,-30,100"]

#: Poses per PM of the loop comparison (SCREWKIT_TEST_POSES raises it, e.g. to 1000).
N_LOOP = int(os.environ.get("SCREWKIT_TEST_POSES", "40"))


def _random_pose(pm, n, seed):
    return random_pose(pm, n, seed, span=8.0, frac=0.08)


@pytest.mark.parametrize("name", pm_names())
def test_batch_equals_a_loop_of_single_poses(name):
    pm = screwkit.load_pm(name)
    pose = _random_pose(pm, N_LOOP, 7)
    res = screwkit.analyze(pm, pose, **PAPER_LOAD)
    assert res.statics.active.shape == (N_LOOP, len(pm.active))     # one per actuator
    assert res.jacobian.matrix.shape[:2] == (N_LOOP, res.jacobian.n_rows)
    L = pm.normalisation.length
    for i in range(N_LOOP):
        one = {p: float(v[i]) for p, v in pose.items()}
        try:
            a = screwkit.analyze(pm, one, **PAPER_LOAD)
        except (SingularityError, UnreachablePoseError):
            assert not res.ok[i]
            continue
        assert res.ok[i]
        fs = np.abs(a.statics.values).max()
        tol = 1e-10 * max(1.0, a.jacobian.condition_number / 100)
        for p in a.solution.params:
            scale = L if p in ("Xo", "Yo", "Zo") else 1.0
            assert abs(res.solution.params[p][i] - a.solution.params[p]) <= 1e-10 * scale
        np.testing.assert_allclose(res.statics.values[i], a.statics.values, rtol=0, atol=tol * fs)
        np.testing.assert_allclose(res.statics.T_r[i], a.statics.T_r, rtol=0, atol=tol * fs * L)
        assert res.jacobian.condition_number[i] == pytest.approx(a.jacobian.condition_number,
                                                                 rel=1e-8)
        # the one-pose view of the batch is the one-pose analysis
        b = res[i]
        np.testing.assert_allclose(b.statics.values, a.statics.values, rtol=0, atol=tol * fs)
        assert b.jacobian.rows[0].describe() == a.jacobian.rows[0].describe()


def test_one_pose_is_n_equals_one():
    pm = screwkit.load_pm("3RRPRR")
    one = screwkit.analyze(pm, {"alpha": 5, "beta": -3, "Zo": 80}, degrees=True, **PAPER_LOAD)
    batch = screwkit.analyze(pm, {"alpha": [5], "beta": [-3], "Zo": [80]}, degrees=True, **PAPER_LOAD)
    assert one.single and not batch.single and len(batch) == 1
    assert one.statics.active.shape == (3,) and batch.statics.active.shape == (1, 3)
    assert one.jacobian.J.shape == (6, 6) and batch.jacobian.matrix.shape == (1, 6, 6)
    np.testing.assert_array_equal(batch.statics.values[0], one.statics.values)
    assert isinstance(one.solution.params["Zo"], float)
    assert batch.solution.params["Zo"].shape == (1,)
    # scalars broadcast against arrays (another batch size: the same numbers up to rounding)
    mixed = screwkit.analyze(pm, {"alpha": [5, 6, 7], "beta": -3, "Zo": 80}, degrees=True, **PAPER_LOAD)
    np.testing.assert_allclose(mixed.statics.values[0], one.statics.values, rtol=1e-12)


def test_unreachable_poses_are_flagged_and_the_others_stand():
    pm = screwkit.load_pm("3RSR")             # fixed-length links: the platform cannot rise far
    good = {"alpha": 0.02, "beta": -0.01, "Zo": pm.default_pose["Zo"]}
    far = dict(good, Zo=400.0)
    batch = {k: np.array([good[k], far[k], good[k]]) for k in good}
    res = screwkit.analyze(pm, batch, **PAPER_LOAD)
    assert len(res) == 3 and res.ok.tolist() == [True, False, True]
    assert res.unreachable.tolist() == [False, True, False]
    assert res.solution.status.tolist() == ["ok", "unreachable", "ok"]
    assert res.solution.residual[1] > 1e-6
    assert np.isnan(res.statics.values[1]).all() and np.isnan(res.solution.params["Xo"][1])
    assert res.solution.params["Zo"][1] == 400.0                 # the given values are kept
    ref = screwkit.analyze(pm, good, **PAPER_LOAD)
    for i in (0, 2):
        np.testing.assert_allclose(res.statics.values[i], ref.statics.values, rtol=1e-12)
    with pytest.raises(UnreachablePoseError):
        screwkit.analyze(pm, far, **PAPER_LOAD)


def test_singular_poses_are_flagged_and_the_others_stand():
    pm = screwkit.load_pm("2SPS+2SPR")
    good = {"alpha": 0.02, "beta": 0.01, "gamma": -0.03, "Zo": 80.0}

    # the actuation singularity at beta = 0, Zo = 80, alpha = gamma (NOTES.md: alpha + gamma
    # near 17.2 deg): bisect det J of single-pose analyses
    def det(t):
        a = screwkit.analyze(pm, {"alpha": t / 2, "beta": 0.0, "gamma": t / 2, "Zo": 80.0},
                             raise_on_singular=False, **PAPER_LOAD)
        return np.linalg.det(a.jacobian.J)
    lo, hi = np.radians(10.0), np.radians(25.0)
    assert np.sign(det(lo)) != np.sign(det(hi))
    for _ in range(60):
        mid = 0.5 * (lo + hi)
        lo, hi = (mid, hi) if np.sign(det(mid)) == np.sign(det(lo)) else (lo, mid)
    sing = {"alpha": lo / 2, "beta": 0.0, "gamma": lo / 2, "Zo": 80.0}
    batch = {k: np.array([good[k], sing[k], good[k]]) for k in good}
    res = screwkit.analyze(pm, batch, **PAPER_LOAD)
    assert res.ok.tolist() == [True, False, True]
    assert res.singular.tolist() == [False, True, False]
    assert res.jacobian.singularity_kind[1] == "actuation"
    assert np.isnan(res.statics.values[1]).all()
    assert np.isfinite(res.solution.extensions[1]).all()     # the singular pose is assembled
    ref = screwkit.analyze(pm, good, **PAPER_LOAD)
    for i in (0, 2):
        np.testing.assert_allclose(res.statics.values[i], ref.statics.values, rtol=1e-12)
    with pytest.raises(SingularityError):
        screwkit.analyze(pm, sing, **PAPER_LOAD)


@pytest.mark.parametrize("bad, words", [
    ({"alpha": np.nan, "beta": 0, "Zo": 80}, "finite"),       # one pose: the call is the pose
    ({"alpha": [0.1, 0.2], "beta": [0, 0, 0], "Zo": 80}, "has 3 values"),
    ({"alpha": [[0.1]], "beta": 0, "Zo": 80}, "1-D"),
    ({"alpha": [], "beta": 0, "Zo": 80}, "no poses"),
    ({"alpha": True, "beta": 0, "Zo": 80}, "number"),
    ({"gamma": [0.1], "beta": 0, "Zo": 80}, "dependent"),
])
def test_bad_pose_arrays_raise_input_errors(bad, words):
    pm = screwkit.load_pm("3RRPRR")
    with pytest.raises(InputError, match=words):
        screwkit.analyze(pm, bad, **PAPER_LOAD)


def test_a_dataframe_of_poses():
    pd = pytest.importorskip("pandas")
    pm = screwkit.load_pm("3RRPRR")
    df = pd.DataFrame({"alpha": [0.05, 0.1], "beta": [-0.02, 0.03], "Zo": [75.0, 85.0]})
    res = screwkit.analyze(pm, df, **PAPER_LOAD)
    ref = screwkit.analyze(pm, {k: df[k].to_numpy() for k in df.columns}, **PAPER_LOAD)
    np.testing.assert_array_equal(res.statics.values, ref.statics.values)


def test_path_warm_starts_give_the_poses_of_cold_starts():
    pm = screwkit.load_pm("3RRPRR")
    s = np.linspace(0, 1, 500)
    path = {"alpha": 0.15 * np.sin(2 * np.pi * s), "beta": 0.12 * np.cos(2 * np.pi * s),
            "Zo": 70 + 20 * s}
    warm = screwkit.analyze(pm, path, path=True, **PAPER_LOAD)
    cold = screwkit.analyze(pm, path, **PAPER_LOAD)
    assert warm.ok.all() and cold.ok.all()
    assert warm.diagnostics["anchors"] < 100
    fs = np.abs(cold.statics.values).max()
    np.testing.assert_allclose(warm.statics.values, cold.statics.values, rtol=0, atol=1e-9 * fs)
    assert warm.solution.iterations.mean() < cold.solution.iterations.mean()


def test_threads_do_not_change_a_bit_and_chunks_only_rounding():
    pm = screwkit.load_pm("3RPS")
    pose = _random_pose(pm, 300, 3)
    a = screwkit.analyze(pm, pose, chunk=37, workers=1, **PAPER_LOAD)
    b = screwkit.analyze(pm, pose, chunk=37, workers=2, **PAPER_LOAD)
    np.testing.assert_array_equal(a.statics.values, b.statics.values)
    np.testing.assert_array_equal(a.jacobian.condition_number, b.jacobian.condition_number)
    c = screwkit.analyze(pm, pose, chunk=4096, workers=1, **PAPER_LOAD)
    np.testing.assert_allclose(c.statics.values, a.statics.values, rtol=1e-11,
                               atol=1e-11 * np.abs(a.statics.values).max())


@pytest.mark.parametrize("name", ["2SPS+2SPR", "4UPU"])
def test_chunks_written_in_place_equal_one_launch(name):
    # a batch of several chunks writes each chunk's rows of one set of output buffers; the
    # same poses in one launch (its own outputs) give every output bit for bit
    from screwkit.engine._launch import output_buffers, run_poses
    from screwkit.engine._run import compute
    from screwkit.engine._solve import predictor_of
    pm = screwkit.load_pm(name)
    pose = _random_pose(pm, 1500, 5)
    load = dict(F=np.array([-20.0, -30.0, -60.0]), T=np.array([-30.0, -30.0, 100.0]))
    for kw in (dict(load, twists=True, lines=True), {}, dict(rows=False)):
        parts = compute(pm, pose, chunk=400, **kw)
        whole = compute(pm, pose, chunk=10 ** 6, **kw)
        for f in ("X", "residual", "iterations", "how", "singular_beta"):
            a, b = getattr(parts.closures, f), getattr(whole.closures, f)
            assert a.dtype == b.dtype
            np.testing.assert_array_equal(a, b)
        for f in ("J", "scale", "rows_ok", "structure_ok", "values", "equilibrium",
                  "amplification", "det_sign", "twists", "lines", "platform"):
            a, b = getattr(parts, f), getattr(whole, f)
            assert (a is None) == (b is None), f
            if a is not None:
                assert a.dtype == b.dtype and a.shape == b.shape, f
                np.testing.assert_array_equal(a, b)
        if whole.conditioning is not None:
            for f in ("singular_values", "rank", "condition_number",
                      "constraint_condition_number"):
                np.testing.assert_array_equal(getattr(parts.conditioning, f),
                                              getattr(whole.conditioning, f))
    # buffers laid out for other outputs, or rows past their end, are refused
    from screwkit.engine._chains import chains_of
    ch = chains_of(pm)
    P6 = ch.full_params(pose, 1500)
    b = output_buffers(ch.flat, 1500, rows=True, statics=True)
    with pytest.raises(ValueError, match="output buffers"):
        run_poses(ch.flat, predictor_of(ch), P6[:10], rows=False, out=(b, 0))
    with pytest.raises(ValueError, match="output buffers"):
        run_poses(ch.flat, predictor_of(ch), P6[:10], out=(b, 1495))


@pytest.mark.parametrize("name, workers", [("3RRPRR", 1), ("2SPS+2SPR", 2), ("4UPU", 2)])
def test_launches_written_at_rows_given_equal_one_launch(name, workers):
    # launches given the rows of their poses (a path's levels: out=(buffers, rows)) fill
    # one set of output buffers in any order; every row equals that pose's row of one
    # launch on all the poses in order, bit for bit, solved from warm starts or from the
    # unknowns given
    from screwkit.engine._chains import chains_of
    from screwkit.engine._launch import OUTPUTS, output_buffers, run_poses
    from screwkit.engine._solve import predictor_of
    pm = screwkit.load_pm(name)
    N = 700
    pose = _random_pose(pm, N, 11)
    ch = chains_of(pm)
    Z, P6 = predictor_of(ch), ch.full_params(pose, N)
    F, T = np.array([-20.0, -30.0, -60.0]), np.array([-30.0, -30.0, 100.0])
    kw = dict(F=F, T=T, twists=True, lines=True, workers=workers)
    X0 = run_poses(ch.flat, Z, P6, rows=False)["X"] * (1 + 1e-4)
    order = np.random.default_rng(3).permutation(N)
    for given in ("X0", "X"):
        whole = run_poses(ch.flat, Z, P6, **{given: X0}, **kw)
        b = output_buffers(ch.flat, N, twists=True, lines=True)
        for part in np.array_split(order, [13, 300, 301]):   # sizes 13, 287, 1, 399
            out = run_poses(ch.flat, Z, P6[part], **{given: X0[part]}, **kw, out=(b, part))
        assert set(out) == set(OUTPUTS)
        for key, v in b.arrays().items():
            if given == "X" and key in ("iterations", "how", "singular_beta"):
                continue                # (not solved: the kernel leaves them unwritten)
            assert v.dtype == whole[key].dtype and v.shape == whole[key].shape, key
            np.testing.assert_array_equal(v, whole[key], err_msg=key)
    with pytest.raises(ValueError, match="output buffers"):
        run_poses(ch.flat, Z, P6[:3], out=(b, np.array([0, 1, N])), **kw)
    with pytest.raises(ValueError, match="output buffers"):
        run_poses(ch.flat, Z, P6[:3], out=(b, np.array([0, 1])), **kw)


@pytest.mark.parametrize("order", ["XYX", "XZX", "YXY", "YZY", "ZXZ", "ZYZ", "XYZ", "XZY", "YXZ",
                                   "YZX", "ZXY", "ZYX"])
@pytest.mark.parametrize("extrinsic", [False, True])
def test_batched_euler_rotations_are_scipys(order, extrinsic):
    o = order.lower() if extrinsic else order
    rng = np.random.default_rng(1)
    ang = rng.uniform(-np.pi, np.pi, (50, 3))
    R, E = euler_matrices(o, ang[:, 0], ang[:, 1], ang[:, 2])
    ref = Rotation.from_euler(o, ang).as_matrix()
    np.testing.assert_allclose(R.transpose(2, 0, 1), ref, atol=1e-14)
    # omega = E @ d(angles)/dt: skew(omega) = dR/dt R^T, by central differences of scipy
    h = 1e-6
    for k in range(3):
        d = np.zeros(3)
        d[k] = h
        dR = (Rotation.from_euler(o, ang + d).as_matrix()
              - Rotation.from_euler(o, ang - d).as_matrix()) / (2 * h)
        W = dR @ np.transpose(ref, (0, 2, 1))
        w = np.stack([W[:, 2, 1], W[:, 0, 2], W[:, 1, 0]], axis=1)
        np.testing.assert_allclose(E[:, k].T, w, atol=1e-8)


def test_workloads_default_to_the_papers():
    pm = screwkit.load_pm("3RRPRR")
    a = screwkit.analyze(pm, **PAPER_LOAD)
    b = screwkit.analyze(pm, force=PAPER_FORCE, torque=PAPER_TORQUE)
    np.testing.assert_array_equal(a.statics.values, b.statics.values)


def test_a_pose_whose_solve_diverges_is_unreachable_not_invalid_input():
    """A batch pose far out (Zo = 1e5 cm: within the inputs' limits, beyond the legs'
    reach) is unreachable with its given parameters kept and no stale note, as the same pose
    alone raises UnreachablePoseError; a NaN given is invalid input."""
    import screwkit
    pm = screwkit.load_pm("3RRPRR")
    sol = screwkit.solve(pm, {"alpha": [0.0, 0.0, np.nan], "beta": 0.0, "Zo": [80.0, 1e5, 80.0]})
    assert sol.status.tolist() == ["ok", "unreachable", "invalid input"]
    assert sol.params["Zo"][1] == 1e5 and np.isnan(sol.params["Zo"][2])
    assert not any("resolved by continuity" in n for n in sol.notes[1])
    with pytest.raises(screwkit.UnreachablePoseError):
        screwkit.solve(pm, {"alpha": 0.0, "beta": 0.0, "Zo": 1e5})
    with pytest.raises(screwkit.errors.MisuseError, match="takes no keyword 'force'"):
        screwkit.solve(pm, {"alpha": 0.0, "beta": 0.0, "Zo": 80.0}, force=[0, 0, 1])


def test_rows_about_one_point_a_pose_is_each_poses_own():
    """JacobianResult.rows_about with (N, 3) points: pose by pose as the one-pose results
    give them (6 poses of a 6-row J broadcast the pose axis against the rows: 25 off)."""
    pm = screwkit.load_pm("3RRPRR")
    b = screwkit.analyze(pm, {"alpha": np.linspace(0, 0.1, 6), "beta": 0.02, "Zo": 80.0})
    jac = b.jacobian
    got = jac.rows_about(jac.origin)
    for i in range(6):
        o = np.asarray(b[i].jacobian.origin).reshape(3)
        J = np.asarray(b[i].jacobian.J)
        f = J[:, :3]
        np.testing.assert_array_equal(got[i], np.hstack([f, J[:, 3:] - np.cross(o, f)]))
    with pytest.raises(screwkit.InputError, match="point must be"):
        jac.rows_about(np.zeros((5, 3)))


def test_flags_are_true_or_false_not_truthy_strings():
    """degrees="no" read as True (a truthy string): flags are refused unless booleans."""
    from screwkit.dynamics import stiffness
    from screwkit.engine import statics, unified_jacobian
    pm = screwkit.load_pm("3RRPRR")
    with pytest.raises(screwkit.InputError, match="degrees must be True or False"):
        screwkit.map(pm, {"alpha": (-5, 5, 3)}, degrees="no")
    with pytest.raises(screwkit.InputError, match="geometric must be True or False"):
        stiffness(pm, actuator=2000, force=[0, 0, -1], torque=[0, 0, 0], geometric="no")
    with pytest.raises(screwkit.InputError, match="degrees must be True or False"):
        screwkit.forward(pm, [0.0, 0.0, 0.0], degrees="yes")
    sol = screwkit.analyze(pm).solution
    jac = unified_jacobian(sol.legs, np.asarray(sol.position).reshape(3))
    with pytest.raises(screwkit.InputError, match="raise_on_singular must be True or False"):
        statics(jac, [0, 0, -1.0], [0, 0, 0.0], raise_on_singular="no")


def test_a_map_grid_tuple_is_start_stop_and_an_integer_count():
    pm = screwkit.load_pm("3RRPRR")
    for spec, piece in (((-5, 5, 3.0), "integer count"), ((5, 5, 3), "repeat one value"),
                        ([1.0, 2.0, 1.0], "the values repeat")):
        with pytest.raises(screwkit.InputError, match=piece):
            screwkit.map(pm, {"alpha": spec}, degrees=True)
    ds = screwkit.map(pm, {"alpha": (-5, 5, 3)}, degrees=True)
    assert ds["alpha"].values.tolist() == [-5.0, 0.0, 5.0]


@pytest.mark.parametrize("name", ["3RRPRR", "2SPS+2SPR"])
@pytest.mark.parametrize("rows, extras", [(True, True), (True, False), (False, False)])
def test_a_launch_of_one_pose_gives_the_outputs_of_a_batch_row(name, rows, extras):
    # one pose's outputs are fields of records over its buffers (_outputs.OnePose), a batch's
    # slices of them: every output of a one-pose launch has the name, dtype, shape and bits
    # of that pose's row of a batch launch (workers=1: the serial kernel, each pose alone),
    # is writable, and shares no memory with another launch's
    from screwkit.engine._chains import chains_of
    from screwkit.engine._launch import OUTPUTS, run_poses
    from screwkit.engine._solve import predictor_of
    pm = screwkit.load_pm(name)
    ch = chains_of(pm)
    P6 = ch.full_params(_random_pose(pm, 3, 5), 3)
    kw = dict(F=np.array([-20.0, -30.0, -60.0]), T=np.array([-30.0, -30.0, 100.0]), rows=rows,
              twists=extras, lines=extras, workers=1)
    Z = predictor_of(ch)
    batch = run_poses(ch.flat, Z, P6, **kw)
    for j in range(3):
        one = run_poses(ch.flat, Z, P6[j:j + 1], **kw)
        again = run_poses(ch.flat, Z, P6[j:j + 1], **kw)
        assert list(one) == list(OUTPUTS)
        for key in OUTPUTS:
            v, w = one[key], batch[key][j:j + 1]
            assert v.dtype == w.dtype and v.shape == w.shape, key
            np.testing.assert_array_equal(v, w, err_msg=key)
            if v.size:
                assert v.flags.writeable and v.flags.c_contiguous, key
                assert not np.shares_memory(v, again[key]), key
