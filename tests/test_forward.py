"""Forward kinematics: round trips through the inverse displacement, and the assembly modes of
the 3RPS counted independently.

* Round trip: random regular poses of every catalog PM near the pose the forward kinematics
  starts from (home, or the default pose where home is singular) -> inverse displacement
  (``screwkit.analyze``) -> actuated joint values -> ``screwkit.forward`` from the start with
  continuation.  Every pose comes back to 1e-9 (of the characteristic length, and of the
  rotation matrix), or the forward solution is another valid assembly of the same actuator
  values: its own inverse displacement gives those actuator values back and its pose differs.
* 3RPS: the real solutions at one set of leg lengths are counted from the geometry alone:
  each RPS leg keeps its S centre a_i in the plane through A_i normal to the base R axis (the
  tangent of the base circle) at the distance r_i, a_i = A_i + r_i (cos t_i u_i + sin t_i z),
  and the three centres must be the platform triangle: |a_i - a_j| = r sqrt(3).  For t_1 on a
  fine grid, t_2 and t_3 follow in closed form from |a_1 - a_2| and |a_1 - a_3| (two branches
  each), and the roots of |a_2 - a_3|^2 - 3 r^2 are bracketed and refined (brentq).
"""

from __future__ import annotations

import numpy as np
import pytest
from scipy.optimize import brentq

import screwkit
from screwkit.engine._fk_inputs import extension_offset as _extension_leg
from screwkit.engine._forward import reference
from screwkit.pm import pm_names

# the paper's workload, stated (only 3RRPRR and 2SPS+2SPR declare it as their default)
PAPER_LOAD = {"force": (-20.0, -30.0, -60.0), "torque": (-30.0, -30.0, 100.0)}
PAPER_ARGS = ["--force=-20,-30,-60", "--torque=-30,-30,100"]

N_POSES = 1000


def _random_poses(pm, ref, n, rng):
    L = pm.normalisation.length
    out = {}
    for p in pm.independent:
        v = ref[p]
        out[p] = v + (rng.uniform(-0.05, 0.05, n) * L if p in ("Xo", "Yo", "Zo")
                      else np.radians(rng.uniform(-5.0, 5.0, n)))
    return out


@pytest.mark.parametrize("name", pm_names())
def test_round_trip_ik_fk(name):
    pm = screwkit.load_pm(name)
    L = pm.normalisation.length
    rng = np.random.default_rng(7)
    ref = reference(pm)[1]
    ik = screwkit.analyze(pm, _random_poses(pm, ref, N_POSES, rng), **PAPER_LOAD)
    keep = ik.ok & np.isin(ik.level, ["ok", "ill-conditioned"])
    assert keep.sum() >= 100, f"{name}: too few regular poses near the start"
    act = ik.solution.actuator_values[keep]
    fk = screwkit.forward(pm, act)
    R0, o0 = ik.solution.rotation[keep], ik.solution.position[keep]
    err = np.maximum(np.max(np.abs(fk.rotation - R0), axis=(1, 2)),
                     np.max(np.abs(fk.position - o0), axis=1) / L)
    back = err <= 1e-9
    other = ~back
    # every pose is solved: back to 1e-9, or another assembly of the same actuator values
    assert np.all(fk.success), f"{name}: {int(np.sum(~fk.success))} poses not solved"
    if other.any():
        # another assembly of the same actuators: where the actuator is a P joint on the line
        # A_i a_i, the leg lengths of the forward pose (from the geometry alone) are those of
        # the inverse displacement; otherwise the analysis at the forward pose (warm-started
        # there) gives the actuator values back
        a = np.einsum("nij,kj->nki", fk.rotation[other], pm.platform_points) + \
            fk.position[other][:, None, :]
        r_fk = np.linalg.norm(a - pm.world_base_points[None], axis=2)
        try:
            [_extension_leg(pm, i) for i in range(pm.n_legs)]
            np.testing.assert_allclose(r_fk, ik.solution.extensions[keep][other],
                                       atol=1e-8 * L)
        except screwkit.InputError:
            np.testing.assert_allclose(np.asarray(fk.analysis.solution.actuator_values)[other],
                                       act[other], atol=1e-8 * L)
        assert np.all(err[other] > 1e-6), "a pose neither back nor distinct"
    # most poses near the start come back; the others are other assembly modes: beyond a
    # singular surface (det J of the other sign), or (3RSR, whose home lies next to its
    # actuation singularity) valid distinct solutions of the same sign
    assert back.mean() >= 0.75, f"{name}: only {back.mean():.0%} of the poses came back"
    # the FK residual is far below the inverse displacement's
    assert np.max(fk.residual) <= 1e-12
    # the assembly mode it reports: a pose that came back has the det J sign of its inverse
    # displacement (np.linalg.det of the analysis' J, computed here), and every solution's
    # sign is stated beside the start's
    if ik.jacobian.square:
        ik_sign = _assembly_sign_by_hand(pm, ik[np.flatnonzero(keep)], ref)
        np.testing.assert_array_equal(fk.det_sign[back], ik_sign[back])
        assert fk.reference_det_sign in (-1, 1)


def _leg_orientations(pm, res):
    """``(N,)``: the product over the legs of ``sign det [t_1; ...; t_m; c_1; ...; c_k]`` (the
    leg's joint twists over its constraint rows, which span the space together), formed here
    with numpy from the engine's link frames and rows."""
    from screwkit.engine import link_frames
    lf = link_frames(res.solution)
    T = np.array(lf.twists)                                 # (m, 6, n, N)
    for i, lg in enumerate(pm.home_legs):       # an S joint: rotations about X, Y, Z (a ball)
        for j, jt in enumerate(lg.joints):
            if jt.spec.origin == "S":
                e = np.eye(3)[jt.spec.part]
                s = lf.points[j, :, i].T                    # (N, 3): its centre
                T[j, :3, i] = np.cross(s, e).T
                T[j, 3:, i] = e[:, None]
    J = res.jacobian.matrix
    legs = np.array([r.leg for r in res.jacobian.info])
    out = np.ones(len(J))
    for i, lg in enumerate(pm.home_legs):
        rows = np.flatnonzero(legs == i)[1:] if i in legs[:res.jacobian.n_actuated] else \
            np.flatnonzero(legs == i)
        rows = rows[rows >= res.jacobian.n_actuated]
        m = len(lg.joints)
        if not rows.size:
            continue
        assert m + rows.size == 6, "a leg with idle motions and constraints"
        M = np.concatenate([T[:m, :, i].transpose(2, 0, 1), J[:, rows]], axis=1)
        out *= np.sign(np.linalg.det(M))
    return out


def _assembly_sign_by_hand(pm, res, ref):
    """The assembly-mode sign of ``det J`` (docs/conventions.md): its plain sign times the
    legs' orientations, relative to those at the reference pose ``ref``."""
    at_ref = _leg_orientations(pm, screwkit.analyze(pm, {p: np.array([ref[p]])
                                                         for p in pm.independent}))
    return np.sign(np.linalg.det(res.jacobian.matrix)) * _leg_orientations(pm, res) * at_ref[0]


def _rps_geometry():
    R, r = 60.0, 30.0
    ang = np.radians([-30.0, 90.0, 210.0])
    u = np.stack([np.cos(ang), np.sin(ang), np.zeros(3)], axis=1)      # radial, outward
    return R * u, u, r


def _independent_3rps_solutions(ext):
    """All (t1, t2, t3) with |a_i - a_j| = r sqrt(3), a_i = A_i + r_i (cos t u_i + sin t z)."""
    A, u, r = _rps_geometry()
    z = np.array([0.0, 0.0, 1.0])
    side2 = 3.0 * r * r

    def a_of(i, t):
        t = np.asarray(t, float)
        return A[i] + ext[i] * (np.cos(t)[..., None] * u[i] + np.sin(t)[..., None] * z)

    def partner(t1, j, branch):
        # |a1 - a_j|^2 = side2: P cos t + Q sin t = W with a1 given
        a1 = a_of(0, t1)
        d = a1 - A[j]
        P = 2 * ext[j] * (d @ u[j])
        Q = 2 * ext[j] * (d @ z)
        W = np.sum(d * d, axis=-1) + ext[j] ** 2 - side2
        rho = np.hypot(P, Q)
        c = np.clip(W / np.where(rho > 0, rho, 1.0), -1.0, 1.0)
        valid = np.abs(W) <= rho
        return np.arctan2(Q, P) + branch * np.arccos(c), valid

    def f(t1, b2, b3):
        t2, v2 = partner(t1, 1, b2)
        t3, v3 = partner(t1, 2, b3)
        g = np.sum((a_of(1, t2) - a_of(2, t3)) ** 2, axis=-1) - side2
        return g, v2 & v3

    t = np.linspace(-np.pi, np.pi, 40001)
    sols = []
    for b2 in (-1, 1):
        for b3 in (-1, 1):
            g, v = f(t, b2, b3)
            for k in np.flatnonzero(v[:-1] & v[1:] & (np.sign(g[:-1]) != np.sign(g[1:]))):
                t1 = brentq(lambda x: f(np.array([x]), b2, b3)[0][0], t[k], t[k + 1],
                            xtol=1e-14)
                t2 = partner(np.array([t1]), 1, b2)[0][0]
                t3 = partner(np.array([t1]), 2, b3)[0][0]
                pts = np.array([a_of(0, t1), a_of(1, t2), a_of(2, t3)])
                sols.append(pts.mean(axis=0))                 # the platform centre o
    # distinct centres
    out = []
    for c in sols:
        if not any(np.linalg.norm(c - d) < 1e-6 for d in out):
            out.append(c)
    return np.array(out)


def test_3rps_assembly_modes_match_an_independent_count():
    pm = screwkit.load_pm("3RPS")
    sol = screwkit.solve(pm, dict(pm.default_pose))
    ext = sol.extensions
    indep = _independent_3rps_solutions(ext)
    modes = screwkit.assembly_modes(pm, {f"r{i + 1}": ext[i] for i in range(3)}, seeds=1000)
    found = modes.solutions.position
    assert np.all(modes.solutions.success)
    assert len(indep) >= 2 and len(modes) == len(indep), (len(modes), len(indep))
    for c in indep:
        assert np.min(np.linalg.norm(found - c, axis=1)) < 1e-7
    # one of them is the pose the leg lengths came from, in the home assembly mode
    d = np.linalg.norm(found - sol.position, axis=1)
    i = int(np.argmin(d))
    assert d[i] < 1e-9 * pm.normalisation.length
    assert modes.solutions.det_sign[i] == modes.solutions.reference_det_sign


def test_forward_by_extensions_and_errors():
    pm = screwkit.load_pm("3RRPRR")
    sol = screwkit.solve(pm, {"alpha": 4, "beta": -2, "Zo": 85}, degrees=True)
    fk = screwkit.forward(pm, {f"r{i + 1}": r for i, r in enumerate(sol.extensions)})
    assert fk.success[0]
    assert fk.pose(0, degrees=True)["alpha"] == pytest.approx(4.0, abs=1e-9)
    assert fk.pose(0, degrees=True)["Zo"] == pytest.approx(85.0, abs=1e-9)
    assert fk.pose(0)["alpha"] == pytest.approx(np.radians(4.0), abs=1e-11)   # (radians)
    with pytest.raises(screwkit.InputError, match="q3"):
        screwkit.forward(pm, {"q1": 0.0, "q2": 0.0})
    with pytest.raises(screwkit.InputError, match="3 finite"):
        screwkit.forward(pm, [0.0, np.nan, 0.0])
    with pytest.raises(screwkit.InputError, match="extension is not"):
        screwkit.forward(screwkit.load_pm("3RSR"), {"r1": 50.0, "q2": 0.0, "q3": 0.0})


def test_fk_at_a_representation_singularity_uses_the_models_split():
    """3RRPRR at beta = 0 (XYX singular): gamma = alpha is the model's limit (NOTES.md)."""
    pm = screwkit.load_pm("3RRPRR")
    sol = screwkit.solve(pm, {"alpha": 6.0, "beta": 0.0, "Zo": 80.0}, degrees=True)
    fk = screwkit.forward(pm, sol.actuator_values)
    p = fk.pose(0, degrees=True)
    assert fk.success[0]
    assert p["alpha"] == pytest.approx(6.0, abs=1e-8) and p["gamma"] == pytest.approx(6.0, abs=1e-8)


@pytest.mark.parametrize("beta", [3e-9, 2e-8, 6e-8])
def test_fk_next_to_a_representation_singularity_gives_the_given_angle(beta):
    """3RRPRR a hair off beta = 0 (inside the inverse displacement's band, 1e-7): the
    forward kinematics gives back the alpha the pose was solved from and succeeds.  (Between
    1e-9 and 1e-7 it used to report scipy's split, alpha + gamma and 0, as a failure.)"""
    pm = screwkit.load_pm("3RRPRR")
    sol = screwkit.solve(pm, {"alpha": 0.3, "beta": beta, "Zo": 80.0})
    fk = screwkit.forward(pm, sol.actuator_values)
    assert fk.success[0]
    assert fk.params["alpha"][0] == pytest.approx(0.3, abs=1e-8)
    assert fk.params["alpha"][0] + fk.params["gamma"][0] == pytest.approx(
        0.3 + float(sol._params["gamma"][0]), abs=1e-8)


def test_scipy_splits_euler_angles_only_outside_the_band_the_fk_splits_itself():
    """The forward kinematics splits alpha and gamma itself where |sin beta| <= 1e-7 (proper
    orders; |cos beta| for Tait-Bryan ones) and takes scipy's angles elsewhere: scipy's own
    split (third angle 0) must stay inside that band."""
    from scipy.spatial.transform import Rotation
    import warnings
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        for order, b0 in (("XYX", 0.0), ("xyz", np.pi / 2)):
            outside = Rotation.from_euler(order, [0.3, b0 + 1.2e-7, 0.3]).as_euler(order)
            assert abs(outside[2]) > 0.1, order          # two angles of their own

def test_cli_fk(capsys):
    import json

    from screwkit.cli import main
    pm = screwkit.load_pm("3RPS")
    ext = screwkit.solve(pm, dict(pm.default_pose)).extensions
    arg = ",".join(f"r{i + 1}={e:.12f}" for i, e in enumerate(ext))
    assert main(["fk", "3RPS", "--actuators", arg, "--json"]) == 0
    out = json.loads(capsys.readouterr().out)
    assert out["count"] == 1 and out["solutions"][0]["pose"]["alpha"] == pytest.approx(5, abs=1e-7)
    assert main(["fk", "3RPS", "--actuators", arg, "--all", "--seeds", "300", "--json"]) == 0
    out = json.loads(capsys.readouterr().out)
    assert out["count"] >= 2 and {s["det_sign"] for s in out["solutions"]} == {-1, 1}
    assert main(["fk", "3RPS", "--actuators", "r1=60"]) == 2
    assert "no value for" in capsys.readouterr().err


def test_cli_fk_units_si_converts_the_pose_and_extensions_not_the_angles(capsys):
    """``fk --units SI`` of the 3RPS (a cm model): the pose solved from the default pose's
    leg extensions, its lengths in m (1 cm = 0.01 m), its angles and conditioning as they
    are; the --all search's solutions too."""
    import json

    from screwkit.cli import main
    pm = screwkit.load_pm("3RPS")
    assert pm.units.length == "cm"
    ext = screwkit.solve(pm, dict(pm.default_pose)).extensions
    arg = ",".join(f"r{i + 1}={e:.12f}" for i, e in enumerate(ext))
    runs = {}
    for units in ("model", "SI"):
        assert main(["fk", "3RPS", "--actuators", arg, "--units", units, "--json"]) == 0
        runs[units] = json.loads(capsys.readouterr().out)["solutions"][0]
    cm, m = runs["model"], runs["SI"]
    assert (cm["units"]["length"], m["units"]["length"]) == ("cm", "m")
    assert m["pose"]["Zo"] == pytest.approx(pm.default_pose["Zo"] / 100, rel=1e-9)
    for k in ("Xo", "Yo", "Zo"):
        assert m["pose"][k] == pytest.approx(cm["pose"][k] / 100, rel=1e-12, abs=1e-15)
    for k in ("alpha", "beta", "gamma"):
        assert m["pose"][k] == cm["pose"][k]
    assert np.allclose(m["extensions"], np.asarray(ext) / 100, rtol=1e-9)
    assert m["condition_number"] == cm["condition_number"]
    assert main(["fk", "3RPS", "--actuators", arg, "--units", "SI"]) == 0
    text = capsys.readouterr().out
    assert "lengths m, angles deg (converted from the model's cm)" in text
    zo = float(text.split("Zo=")[1].split()[0])
    assert zo == pytest.approx(pm.default_pose["Zo"] / 100, rel=1e-8)
    assert main(["fk", "3RPS", "--actuators", arg, "--all", "--seeds", "200", "--units", "SI",
                 "--json"]) == 0
    out = json.loads(capsys.readouterr().out)
    assert all(s["units"]["length"] == "m" and abs(s["pose"]["Zo"]) < 2 for s in out["solutions"])


def test_fk_modes_at_a_representation_singularity_are_poses_or_say_why():
    """3RRPRR at its home actuator values: every listed mode is confirmed by the analysis or,
    at beta = 0 where no split of alpha + gamma is reached, said to close unconfirmed; such a
    pose is checked here against home's geometry alone (each leg's actuated P joint carries
    its length |a_i - A_i|, so at q = 0 every leg has its home extension)."""
    pm = screwkit.load_pm("3RRPRR")
    home = screwkit.solve(pm, {k: pm.home_pose[k] for k in pm.independent})
    A, a0 = home.base_points, home._platform[2][0]
    R0, o0 = home._platform[0][0], home._platform[1][0]
    local = (a0 - o0) @ R0                       # the platform points in the platform frame
    modes = screwkit.assembly_modes(pm, {"q1": 0.0, "q2": 0.0, "q3": 0.0}, seeds=1000)
    sols = modes.solutions
    assert np.all(sols.success | sols.unsplit)
    L = pm.normalisation.length
    for i in np.flatnonzero(sols.unsplit):
        R, o = sols.rotation[i], sols.position[i]
        a = local @ R.T + o
        assert np.allclose(np.linalg.norm(a - A, axis=1), home.extensions, atol=1e-9 * L)
        assert abs(R[0, 0] - 1.0) < 1e-12            # a turn about x: beta = 0 (XYX)
        assert sols.to_dict(i)["closed_unconfirmed"]
    # a guess a full turn away finds home itself, confirmed
    fk = screwkit.forward(pm, [0.0, 0.0, 0.0], {"alpha": 2 * np.pi})
    assert fk.success[0] and np.allclose(fk.rotation[0], np.eye(3), atol=1e-9)
    assert np.allclose(fk.position[0], o0, atol=1e-9 * L)


def test_cli_fk_all_lists_unconfirmed_modes_and_succeeds(capsys):
    from screwkit.cli import main
    assert main(["fk", "3RRPRR", "--actuators", "q1=0,q2=0,q3=0", "--all", "--seeds", "300"]) == 0
    out = capsys.readouterr().out
    assert "the working mode's sign pattern" in out
    assert main(["fk", "3RRPRR", "--actuators", "q1=0,q2=0,q3=0", "--guess", "alpha=360"]) == 0


def test_fk_all_says_when_singular_solutions_form_a_continuum(capsys):
    """3SPR at its home actuator values: besides home and its mirror, the seeds land on a
    continuum of singular poses (the platform turned about 90 deg, J rank-deficient): the
    text lists a few and says what they are; --json keeps them all and counts them."""
    import json

    from screwkit.cli import main
    from screwkit.cli._commands.fk import SINGULAR_SHOWN
    args = ["fk", "3SPR", "--actuators", "q1=0,q2=0,q3=0", "--all", "--seeds", "400"]
    assert main(args + ["--json"]) == 0
    out = json.loads(capsys.readouterr().out)
    conds = [s["condition_number"] for s in out["solutions"]]
    singular = sum(1 for c in conds if c > 1e12)    # J's own condition, not the label
    assert singular > SINGULAR_SHOWN and out["singular_count"] == singular
    assert main(args) == 0
    text = capsys.readouterr().out
    assert f"{singular} of them singular" in text and "continuum" in text
    assert text.count("(singular)") == SINGULAR_SHOWN
    assert text.count("(regular)") == out["count"] - singular


def test_fk_json_of_no_solution_claims_no_mode(capsys):
    """An actuator far beyond reach: the last iterate is listed as not solved, with no
    assembly mode, conditioning or sign pattern claimed for it."""
    import json

    from screwkit.cli import main
    assert main(["fk", "3RRPRR", "--actuators", "q1=1e9,q2=0,q3=0", "--json"]) == 2
    out = json.loads(capsys.readouterr().out)
    s = out["solutions"][0]
    assert out["solved"] == 0 and not s["success"]
    assert s["working_mode"] is None and s["same_assembly_mode_as_reference"] is None
    assert s["det_sign"] is None and s["mode"].startswith("not solved")


def test_a_guess_reads_its_angles_as_the_call_does():
    """degrees=True: a guess dict's angles in degrees too (a guess of gamma = 5 read as 5
    rad made the solution a whole turn away, gamma = 365 deg); in radians without it."""
    pm = screwkit.load_pm("3RRPRR")
    pose = {"alpha": 5, "beta": 0.5, "Zo": 80}
    g = {"alpha": 5, "beta": 0.5, "Zo": 80, "gamma": 5}
    sol = screwkit.solve(pm, pose, degrees=True, guess=g)
    assert np.degrees(sol.params["gamma"]) == pytest.approx(5.0, abs=1e-6)   # gamma = alpha
    rad = screwkit.solve(pm, {k: np.radians(v) if k != "Zo" else v for k, v in pose.items()},
                         guess={k: np.radians(v) if k != "Zo" else v for k, v in g.items()})
    assert rad.params["gamma"] == pytest.approx(sol.params["gamma"], abs=1e-12)
    fk = screwkit.forward(pm, sol.actuator_values, {"alpha": 5.0}, degrees=True)
    assert fk.success[0] and fk.pose(0, degrees=True)["alpha"] == pytest.approx(5.0, abs=1e-8)


def test_fk_says_one_solution_when_the_sign_pattern_is_shared(capsys):
    """A 3-RSR's actuator values close two poses above the base with home's det J sign (the
    two solved again here by the inverse displacement give the same actuator values): the
    default output named its one pose "the working mode's sign pattern" as if unique; it
    says it is one solution and that --all searches the others."""
    import json as _json

    from screwkit.cli import main
    q = "q1=0.07373305330850823,q2=0.061272511366854174,q3=0.005332840203186904"
    assert main(["fk", "3RSR", "--actuators", q, "--all", "--json"]) == 0
    sols = _json.loads(capsys.readouterr().out)["solutions"]
    working = [s["pose"] for s in sols if s["working_mode"]]
    assert len(working) >= 2
    pm = screwkit.load_pm("3RSR")
    acts = [np.asarray(screwkit.solve(pm, {k: p[k] for k in pm.independent},
                                      degrees=True).actuator_values, float).ravel()
            for p in working[:2]]
    np.testing.assert_allclose(acts[0], acts[1], atol=1e-7)
    assert abs(working[0]["alpha"] - working[1]["alpha"]) > 1.0      # two distinct poses
    assert main(["fk", "3RSR", "--actuators", q]) == 0
    assert "one solution" in capsys.readouterr().out
