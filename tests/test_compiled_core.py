"""The compiled core: one implementation of the per-pose maths, numba kernels over a model
flattened to arrays.

Independent references: a fresh interpreter's ``sys.modules`` (commands that compute nothing
import no numba); the kernels' own one-pose calls against their batch, bit for bit (each pose
is computed alone); a model loaded with other dimensions against the same model re-flattened
(no recompilation, the same numbers); the 6-SPS's statics written here from its leg lines
(``[d; a x d]`` rows, scipy's Euler angles, ``J^T F = -W`` by numpy); the actuated joints'
twists from the placed legs' joints; a passive leg against the same leg actuated.
"""

import dataclasses
import os
import subprocess
import sys

import numpy as np
import pytest
from scipy.spatial.transform import Rotation

import screwkit
from screwkit.pm import PARAMS, pm_names
from random_poses import random_pose

F = np.array([-20.0, -30.0, -60.0])
T = np.array([-30.0, -30.0, 100.0])


def _fresh(code):
    out = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True,
                         timeout=300, env=dict(os.environ, MPLBACKEND="Agg"))
    assert out.returncode == 0, out.stderr
    return out.stdout.strip()


@pytest.mark.parametrize("argv", [["--help"], ["leg", "RRPRR"], ["catalog"],
                                  ["model", "schema"]])
def test_commands_that_compute_nothing_never_import_numba(argv):
    code = ("import sys, contextlib, io\nfrom screwkit.cli import main\n"
            "with contextlib.redirect_stdout(io.StringIO()):\n"
            "    try:\n        main(%r)\n    except SystemExit:\n        pass\n"
            "print('numba' in sys.modules)" % (argv,))
    assert _fresh(code) == "False"


_HOME_MODEL = """\
units: {length: cm, force: N}
pms:
  H3SPR:
    dimensions: {R: 80, r: 30}
    base: {shape: triangle, circumradius: R}
    platform: {shape: triangle, circumradius: r}
    legs: [SPR, SPR, SPR]
    euler: XYZ
    independent: [alpha, beta, Zo]
    pose: {alpha: 0, beta: 0, Zo: R}
    dof: 3
    motion: 1T2R
"""


_RSR_MODEL = """\
pms:
  H3RSR:
    units: {length: cm, force: kN}
    dimensions: {R: 80, r: 20}
    base: {shape: triangle, circumradius: R}
    platform: {shape: triangle, circumradius: r}
    legs: [RSR, RSR, RSR]
    euler: XYZ
    independent: [alpha, beta, Zo]
    home: {alpha: 0, beta: 0, Zo: R/2}
    pose: {alpha: 0, beta: 0, Zo: R}
    dof: 3
    motion: 1T2R
"""


@pytest.mark.parametrize("model, pose, valid", [
    (_HOME_MODEL, "{alpha: 0, beta: 0, Zo: R}", True),          # home
    (_HOME_MODEL, "{alpha: 5, beta: -3, Zo: R}\n    home: {alpha: 0, beta: 0, Zo: R}",
     True),                                                     # solved from home
    (_RSR_MODEL, "{alpha: 0, beta: 0, Zo: R}", False)])         # RSR legs too short
def test_a_model_file_checked_again_does_not_import_numba(tmp_path, model, pose, valid):
    """``model check`` of a file computes what it must (the finite motion; the default pose,
    where it is not home; both kept on disk: numba imported) and nothing more: checked again
    in a fresh process, numba and scipy are never imported, and the verdict, the default
    pose's notes and a pose out of reach's message are the same."""
    if os.environ.get("SCREWKIT_DISK_CACHE", "1").strip().lower() in ("0", "no", "off"):
        pytest.skip("the disk cache is off")
    f = tmp_path / "home.yaml"
    f.write_text(model.replace("pose: {alpha: 0, beta: 0, Zo: R}", "pose: " + pose),
                 encoding="utf-8")
    code = ("import sys, contextlib, io\nfrom screwkit.cli import main\n"
            "with contextlib.redirect_stdout(io.StringIO()) as out:\n"
            f"    rc = main(['model', 'check', {str(f)!r}])\n"
            "print(rc, 'numba' in sys.modules, 'scipy' in sys.modules)\n"
            "print(out.getvalue().strip())")
    first, again = _fresh(code).split("\n", 1), _fresh(code).split("\n", 1)
    assert first[0].split()[0] == ("0" if valid else "2"), first
    assert again[0] == ("0" if valid else "2") + " False False"
    assert again[1] == first[1]
    if not valid:
        assert "the default pose cannot be assembled" in again[1]
    if valid and "5" in pose:
        notes = ("import screwkit\nprint(screwkit.load_pm(%r).notes)" % f"{f}#H3SPR")
        assert _fresh(notes) == _fresh(notes)


def test_the_motion_caches_versions_are_the_packages_own():
    """The finite motion's disk cache names numba's and scipy's versions without importing
    them (the name of the installed ``.dist-info`` folder): the versions the packages give
    once imported."""
    import numba
    import scipy

    from screwkit.engine._motion_cache import installed_version
    assert installed_version("numba") == numba.__version__
    assert installed_version("scipy") == scipy.__version__
    assert installed_version("numpy") == np.__version__


def test_numba_is_imported_only_inside_the_engine():
    import ast
    from pathlib import Path
    root = Path(screwkit.__file__).parent
    bad = []
    for p in root.rglob("*.py"):
        for node in ast.walk(ast.parse(p.read_text())):
            names = [a.name for a in node.names] if isinstance(node, ast.Import) else \
                [node.module or ""] if isinstance(node, ast.ImportFrom) else []
            if any(n.split(".")[0] == "numba" for n in names) and \
                    "engine/_kernels" not in p.as_posix():
                bad.append(str(p.relative_to(root)))
    assert bad == [], bad


def test_the_cache_goes_to_a_user_directory_where_the_package_is_read_only(monkeypatch,
                                                                          tmp_path):
    from screwkit.engine import _kernels
    # (set first, so that the environment is restored as it was, whatever cache_dir() sets)
    monkeypatch.setenv("NUMBA_CACHE_DIR", "placeholder")
    monkeypatch.delenv("NUMBA_CACHE_DIR")
    monkeypatch.setenv("XDG_CACHE_HOME", str(tmp_path))
    monkeypatch.setattr(_kernels, "_writable", lambda path: False)
    if sys.platform.startswith("linux"):
        assert _kernels.cache_dir() == str(tmp_path / "screwkit" / "numba")
        assert os.environ["NUMBA_CACHE_DIR"] == str(tmp_path / "screwkit" / "numba")
    monkeypatch.setenv("NUMBA_CACHE_DIR", "/somewhere/else")
    assert _kernels.cache_dir() == "/somewhere/else"         # the user's choice wins


def _one_by_one(flat, Z, P6):
    from screwkit.engine._launch import run_poses
    outs = [run_poses(flat, Z, P6[i:i + 1], F=F, T=T) for i in range(len(P6))]
    return {k: np.concatenate([o[k] for o in outs]) for k in ("X", "J", "values", "residual")}


@pytest.mark.parametrize("name", pm_names())
def test_a_batch_equals_its_poses_one_by_one_bit_for_bit(name):
    """1,000 random poses of every catalog PM: the batch of ``screwkit.analyze`` (on two
    threads) and the kernel called for each pose alone give the same bits."""
    from screwkit.engine._chains import chains_of
    from screwkit.engine._solve import predictor_of
    pm = screwkit.load_pm(name)
    pose = random_pose(pm, 1000, 11, span=8.0, frac=0.08)
    res = screwkit.analyze(pm, pose, workers=2, raise_on_singular=False,
                           force=F, torque=T)
    ch = chains_of(pm)
    one = _one_by_one(ch.flat, predictor_of(ch), ch.full_params(pose, 1000))
    ok = res.solution.reachable_mask
    np.testing.assert_array_equal(res.solution.closures.X.T[ok], one["X"][ok])
    np.testing.assert_array_equal(res.jacobian.matrix[ok], one["J"][ok])
    good = ok & ~res.jacobian.singular_mask
    np.testing.assert_array_equal(res.statics.values[good], one["values"][good])


def test_other_dimensions_are_other_arrays_never_a_recompilation():
    from screwkit.engine._flat import flatten, reflatten
    from screwkit.engine._kernels import kernels
    from screwkit.engine._launch import run_poses
    pm = screwkit.load_pm("3RRPRR")
    pose = {"alpha": 0.05, "beta": -0.03, "Zo": 85.0}
    screwkit.analyze(pm, pose)
    k = kernels()
    before = (len(k.run_range.signatures), len(k.run_parallel.signatures))
    big = screwkit.load_pm("3RRPRR", {"L": 150, "l": 70})
    res = screwkit.analyze(big, pose)
    assert (len(k.run_range.signatures), len(k.run_parallel.signatures)) == before
    # re-flattening the first model's arrays with the second's dimensions: the same arrays
    # (the same legs and templates) and the same analysis
    re = reflatten(pm, screwkit.load_pm("3RRPRR", {"L": 150, "l": 70}))
    ref = flatten(big)
    for a, b in zip(ref.M, re.M):
        np.testing.assert_allclose(a, b, rtol=0, atol=1e-12)
    P6 = np.array([[0.0, 0.0, 85.0, 0.05, -0.03, 0.0]])
    X0 = res.solution.closures.X.T
    out = run_poses(re, re.Z, P6, X=X0, F=F, T=T)
    np.testing.assert_allclose(out["values"][0], res.statics.values, rtol=1e-12)


def test_six_sps_statics_from_its_leg_lines():
    """The 6-SPS: every row of ``J`` is a leg line (no constraint), so ``F_a`` solves
    ``sum_i F_i [d_i; a_i x d_i] = -W`` with the leg directions of the pose (scipy's
    intrinsic XYZ angles, the catalog's geometry written here)."""
    pm = screwkit.load_pm("6SPS")
    pose = random_pose(pm, 20, 5, span=6.0, frac=0.05)
    res = screwkit.analyze(pm, pose, force=F, torque=T)
    assert res.ok.all() and res.jacobian.matrix.shape[1:] == (6, 6)
    ang_b = np.radians([-2.5, 2.5, 117.5, 122.5, 237.5, 242.5])
    ang_p = np.radians([-50, 50, 70, 170, 190, 290])
    A = 300.0 * np.column_stack([np.cos(ang_b), np.sin(ang_b), np.zeros(6)])
    ap = 100.0 * np.column_stack([np.cos(ang_p), np.sin(ang_p), np.zeros(6)])
    for i in range(20):
        R = Rotation.from_euler("XYZ", [pose[p][i] for p in ("alpha", "beta", "gamma")]).as_matrix()
        o = np.array([pose["Xo"][i], pose["Yo"][i], pose["Zo"][i]])
        a = ap @ R.T + o
        d = (a - A) / np.linalg.norm(a - A, axis=1, keepdims=True)
        J = np.hstack([d, np.cross(a, d)])
        W = np.concatenate([F, T + np.cross(o, F)])
        want = np.linalg.solve(J.T, -W)
        np.testing.assert_allclose(res.statics.active[i], want, rtol=1e-9,
                                   atol=1e-9 * np.abs(want).max())
        np.testing.assert_allclose(res.solution.extensions[i], np.linalg.norm(a - A, axis=1),
                                   rtol=1e-12)


def test_the_actuated_twists_come_with_J():
    pm = screwkit.load_pm("3RRPRR")
    pose = random_pose(pm, 6, 3)
    res = screwkit.analyze(pm, pose, twists=True)
    tw = res.actuated_twists
    assert tw.shape == (6, 3, 6)
    lazy = screwkit.analyze(pm, pose).actuated_twists
    np.testing.assert_array_equal(lazy, tw)
    for i in range(6):
        legs = res.solution.legs_at(i)
        for k, leg in enumerate(legs):
            jt = leg.joints[leg.actuated_index]          # the prismatic joint: [u; 0]
            np.testing.assert_allclose(tw[i, k], np.r_[jt.direction, 0, 0, 0], atol=1e-12)
            # reciprocal product 1 with the leg's actuation row
            assert res.jacobian.matrix[i, k] @ tw[i, k] == pytest.approx(1.0, rel=1e-12)


def test_a_passive_leg_adds_its_constraint_rows_and_no_actuation_row():
    pm = screwkit.load_pm("4SPS+SPR")
    passive = dataclasses.replace(pm, passive=(2,))
    pose = random_pose(pm, 5, 2)
    full = screwkit.analyze(pm, pose)
    part = screwkit.analyze(passive, pose, raise_on_singular=False)
    labels = [r.label for r in part.jacobian.info]
    assert "F_a3" not in labels and len(labels) == len(full.jacobian.info) - 1
    keep = [k for k, r in enumerate(full.jacobian.info) if r.label != "F_a3"]
    np.testing.assert_allclose(part.jacobian.matrix, full.jacobian.matrix[:, keep], rtol=0,
                               atol=1e-12)
    assert part.jacobian.n_actuated == 4
    assert (part.jacobian.rank <= 5).all()           # four actuators for five freedoms


def test_an_empty_cache_gets_a_one_line_note_on_stderr(tmp_path):
    """The first run after an install (no compiled kernel in the cache) says, once, on
    stderr, that it compiles; a warm cache says nothing.  (Loading the kernels compiles
    nothing: the compilation itself is timed by the benchmark.)"""
    code = "from screwkit.engine import _kernels\n_kernels.kernels()\n_kernels.kernels()"
    cold = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True,
                          timeout=300, env=dict(os.environ, NUMBA_CACHE_DIR=str(tmp_path)))
    assert cold.returncode == 0, cold.stderr
    notes = [ln for ln in cold.stderr.splitlines() if "compiling" in ln]
    assert len(notes) == 1 and str(tmp_path) in notes[0]
    screwkit.analyze("3RRPRR")                      # this process's cache is warm
    warm = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True,
                          timeout=300, env={k: v for k, v in os.environ.items()
                                            if k != "NUMBA_CACHE_DIR"})
    assert "compiling" not in warm.stderr


def test_a_kernel_compiled_afresh_gives_the_cached_kernels_bits(tmp_path):
    """The conditioning of a 3RRPRR map's Jacobians (the map of tests/test_maps_dask.py) by
    this process's kernels, and by the conditioning kernel compiled alone in a fresh
    interpreter with an empty cache: the same bits.  (With multiply-adds contracted into
    FMAs, which pairs LLVM fused depended on how the kernel was built: 130 of these 2,501
    cells' constraint condition numbers differed in the last bits, and so did a Dask
    worker's map from the serial one.)"""
    grid = np.radians(np.linspace(-20.0, 20.0, 61)), np.radians(np.linspace(-20.0, 20.0, 41))
    a, b = (g.ravel() for g in np.meshgrid(*grid, indexing="ij"))
    res = screwkit.analyze("3RRPRR", {"alpha": a, "beta": b, "Zo": np.full(a.size, 75.0)},
                           raise_on_singular=False)
    jac = res.jacobian
    c = jac.conditioning
    np.savez(tmp_path / "in.npz", J=jac.matrix, centre=c.centre, length=c.length)
    code = ("import numpy as np\nfrom screwkit.engine._pipeline import conditioning_of\n"
            f"d = np.load({str(tmp_path / 'in.npz')!r})\n"
            f"c = conditioning_of(d['J'], {jac.n_actuated}, d['centre'], d['length'])\n"
            f"np.savez({str(tmp_path / 'out.npz')!r}, sv=c.singular_values, "
            "cond=c.condition_number, ccond=c.constraint_condition_number)")
    out = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True,
                         timeout=300, env=dict(os.environ, NUMBA_CACHE_DIR=str(tmp_path / "nc")))
    assert out.returncode == 0, out.stderr
    assert "compiling" in out.stderr                   # it was compiled there, not loaded
    fresh = np.load(tmp_path / "out.npz")
    assert np.isfinite(c.constraint_condition_number).all()
    np.testing.assert_array_equal(fresh["ccond"], c.constraint_condition_number)
    np.testing.assert_array_equal(fresh["cond"], c.condition_number)
    np.testing.assert_array_equal(fresh["sv"], c.singular_values)


def test_dimensions_and_params_layout():
    """The flattened model keeps the pose parametrisation in PARAMS order."""
    from screwkit.engine._flat import flatten
    pm = screwkit.load_pm("2SPS+2SPR")
    f = flatten(pm)
    assert f.unknown == tuple(p for p in PARAMS if p not in pm.independent)
    assert [PARAMS[k] for k in f.Z[0]] == list(f.unknown)


@pytest.mark.parametrize("name", ["3RRPRR", "4UPU", "3SPU+SP"])
def test_the_indices_kernel_batch_equals_its_poses_one_by_one(name):
    """The transmission indices of 1,000 poses launched on two threads against the same
    kernel called for each pose alone: the same bits (square, over-determined and
    redundant-constraint row sets)."""
    from screwkit.engine._transmission import leg_screws, transmission_indices
    pm = screwkit.load_pm(name)
    res = screwkit.analyze(pm, random_pose(pm, 1000, 5, span=8.0, frac=0.08), workers=2,
                           raise_on_singular=False)
    jac, sol = res.jacobian, res.solution
    info = jac.info
    act = [k for k, r in enumerate(info) if r.kind == "actuation"]
    con = [k for k, r in enumerate(info) if r.kind != "actuation"]
    V_in, il, ol = leg_screws(sol, [info[k].leg for k in act])
    J = np.where(np.isfinite(jac.matrix), jac.matrix, 0.0)
    couple = np.array([r.member == "couple" for r in info])
    cond = jac.conditioning
    crank = np.asarray(cond.constraint_rank)
    batch = transmission_indices(J, couple, act, con, V_in, il, ol, jac.leg_of_row,
                                 cond.centre, cond.length, crank, workers=2)
    for i in range(0, 1000, 7):
        s = slice(i, i + 1)
        one = transmission_indices(J[s], couple, act, con, V_in[s], (il[0][s], il[1][s]),
                                   (ol[0][s], ol[1][s]), jac.leg_of_row, cond.centre[s],
                                   cond.length[s], crank[s], workers=1)
        for b, o in zip(batch, one):
            np.testing.assert_array_equal(b[s], o)
