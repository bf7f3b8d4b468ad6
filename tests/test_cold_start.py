"""What a cold command is spared, and that it changes nothing.

* The finite motion kept on disk (``screwkit.engine._motion_cache``): a kept verdict is the
  one computed now, bit for bit; any change to the model or to the classification constants
  gives another file; a bad file is recomputed; the declared-motion check still runs on a
  kept verdict; ``SCREWKIT_DISK_CACHE=0`` keeps nothing.  The independent reference is
  :func:`screwkit.engine._motion._compute` run on the model in this process (the
  classification itself is tested against hand derivations in tests/test_finite_motion.py).
* The default catalog kept parsed (``screwkit.pm._catalog_cache``): the same bytes as one
  read now; edits and bad files read anew; invalid catalogs never kept.
* The quick loading of cached kernels (``screwkit.engine._kernels._loading``): new code
  compiled against a kernel loaded that way links and computes; a fresh ``analyze`` with its
  caches warm imports neither YAML, nor scipy, nor numba's implementation registries."""

import dataclasses
import json

import numpy as np
import pytest

import screwkit
from screwkit.engine import _motion, _motion_cache
from screwkit.errors import CatalogError
from screwkit.pm import load_pm


@pytest.fixture
def disk(tmp_path, monkeypatch):
    """An empty folder of kept verdicts; the in-process caches emptied around the test."""
    monkeypatch.setattr(_motion_cache, "_folder", lambda: str(tmp_path / "motion"))
    monkeypatch.setenv("SCREWKIT_DISK_CACHE", "1")
    _motion._BY_CONTENT.clear()
    yield tmp_path / "motion"
    _motion._BY_CONTENT.clear()


def _fresh(model):
    """The model's finite motion, the in-process caches bypassed (a copy of the model)."""
    _motion._BY_CONTENT.clear()
    return _motion.finite_motion(dataclasses.replace(model))


def _identical(a, b):
    for f in dataclasses.fields(a):
        x, y = getattr(a, f.name), getattr(b, f.name)
        assert type(x) is type(y), f.name
        if isinstance(y, np.ndarray):
            assert x.dtype == y.dtype and x.tobytes() == y.tobytes(), f.name
        else:
            assert x == y, f.name


def test_a_kept_verdict_is_the_computed_one_bit_for_bit(disk):
    for name in ("3RRPRR", "3UPU/spherical", "4UPU"):     # no array, a centre, an axis
        model = load_pm(name)
        first = _fresh(model)                       # computed and kept
        assert len(list(disk.glob("*.json"))) >= 1
        computed = _motion._compute(model)
        _identical(first, computed)
        kept = _fresh(model)                        # read back from the file
        _identical(kept, computed)


def test_another_model_or_constant_is_another_file(disk, monkeypatch):
    model = load_pm("3RRPRR")
    constants = (_motion.AMPLITUDE_DEG, _motion.AMPLITUDE_LENGTH, _motion.STEP, 1e-7, 1e-5)
    d0 = _motion_cache.model_digest(model, constants)
    assert d0 == _motion_cache.model_digest(dataclasses.replace(model), constants)
    longer = load_pm("3RRPRR", {"L": 130.0})
    assert _motion_cache.model_digest(longer, constants) != d0
    moved = dataclasses.replace(model, home_pose={**model.home_pose,
                                                  "Zo": model.home_pose["Zo"] + 1e-9})
    assert _motion_cache.model_digest(moved, constants) != d0
    assert _motion_cache.model_digest(model, constants[:-1] + (2e-5,)) != d0
    _fresh(model)
    monkeypatch.setattr(_motion, "STEP", 2e-3)       # a constant changed at the call
    _fresh(model)
    assert len(list(disk.glob("*.json"))) == 2


def test_a_bad_file_is_recomputed(disk):
    model = load_pm("3RRPRR")
    good = _fresh(model)
    (path,) = disk.glob("*.json")
    for text in ("{not json", json.dumps({"digest": "another", "motion": {}}),
                 json.dumps({"digest": path.stem, "motion": {"label": "3T"}})):
        path.write_text(text)
        _identical(_fresh(model), good)
    _identical(_fresh(model), good)                 # and kept again


def test_the_declared_motion_is_checked_on_a_kept_verdict(disk, tmp_path):
    from test_finite_motion import DECLARED
    path = tmp_path / "wrong.yaml"
    path.write_text(DECLARED.replace("MOTION", "3T"))
    for _ in range(2):                              # computed, then kept
        _motion._BY_CONTENT.clear()
        with pytest.raises(CatalogError, match="declares motion 3T.*computed from home is 1T2R"):
            screwkit.load_pm(str(path))
    assert len(list(disk.glob("*.json"))) == 1


def test_switched_off_nothing_is_kept(disk, monkeypatch):
    monkeypatch.setenv("SCREWKIT_DISK_CACHE", "0")
    _fresh(load_pm("3RRPRR"))
    assert not disk.exists() or not list(disk.glob("*.json"))


# --- the default catalog kept parsed on disk (screwkit.pm._catalog_cache) -----------------

@pytest.fixture
def catalog_disk(tmp_path, monkeypatch):
    from screwkit.pm import _catalog_cache
    monkeypatch.setattr(_catalog_cache, "cache_folder", lambda name: str(tmp_path / name))
    monkeypatch.setenv("SCREWKIT_DISK_CACHE", "1")
    return tmp_path / "catalog"


def test_a_kept_catalog_is_the_one_read_now(catalog_disk, tmp_path):
    import pickle
    from screwkit.pm import Catalog, _catalog_cache, catalog_path, load_catalog
    path = tmp_path / "legs.yaml"
    path.write_bytes(catalog_path().read_bytes())
    read = load_catalog(path)                               # the reference: read now
    first = _catalog_cache.kept_catalog(path, load_catalog, Catalog)  # read and kept
    assert len(list(catalog_disk.glob("*.pickle"))) == 1
    kept = _catalog_cache.kept_catalog(path, lambda p: pytest.fail("read again"), Catalog)
    for cat in (first, kept):
        assert type(cat) is type(read) and pickle.dumps(cat) == pickle.dumps(read)
    # an edit to the file is read anew (and kept under another name)
    path.write_text(path.read_text() + "\n# an edit\n")
    calls = []
    _catalog_cache.kept_catalog(path, lambda p: calls.append(p) or load_catalog(p), Catalog)
    assert calls == [path] and len(list(catalog_disk.glob("*.pickle"))) == 2
    # a bad kept file is read anew; an invalid catalog is refused, never kept
    for f in catalog_disk.glob("*.pickle"):
        f.write_bytes(b"not a pickle")
    again = _catalog_cache.kept_catalog(path, load_catalog, Catalog)
    assert pickle.dumps(again) == pickle.dumps(load_catalog(path))
    path.write_text("legs: 3\n")
    with pytest.raises(CatalogError):
        _catalog_cache.kept_catalog(path, load_catalog, Catalog)
    assert len(list(catalog_disk.glob("*.pickle"))) == 2


def test_the_default_catalog_command_output_is_unchanged_when_kept(catalog_disk, capsys):
    from screwkit.cli import main
    from screwkit.pm import default_catalog
    outs = []
    for _ in range(2):                                      # read, then kept
        default_catalog.cache_clear()
        assert main(["leg", "RRPRR"]) == 0
        outs.append(capsys.readouterr().out)
    default_catalog.cache_clear()
    assert outs[0] == outs[1] and "catalog expects" in outs[0]
    assert len(list(catalog_disk.glob("*.pickle"))) == 1


# --- the quick loading of cached kernels (screwkit.engine._kernels._loading) --------------

def _quick():
    from screwkit.engine._kernels import _loading
    if not _loading.supported():
        pytest.skip("this numba release loads its cache itself (not one the quick loading "
                    "was tested with)")


def test_the_quick_loading_is_limited_to_tested_numba_releases():
    from screwkit.engine._kernels._loading import supported
    assert supported("0.68.1") and not supported("0.99.0") and not supported("x.y")


def test_new_code_compiled_against_a_quickly_loaded_kernel_links_and_computes():
    _quick()
    import numba
    from screwkit.engine._kernels import _small, kernels
    kernels()
    assert type(_small.matmul3._cache).__name__ == "_QuickCache"

    @numba.njit
    def product(A, B):
        C = np.empty((3, 3))
        _small.matmul3(A, B, C)
        return C

    rng = np.random.default_rng(3)
    A, B = rng.normal(size=(3, 3)), rng.normal(size=(3, 3))
    want = np.array([[sum(A[i, k] * B[k, j] for k in range(3)) for j in range(3)]
                     for i in range(3)])
    assert np.allclose(product(A, B), want, rtol=1e-14, atol=1e-15)


def test_the_kept_symbol_lists_are_the_bitcodes_own():
    _quick()
    from llvmlite import binding as ll
    from screwkit.engine._kernels import _driver, _loading
    screwkit.analyze(load_pm("3RRPRR"), {"alpha": 0.05, "beta": -0.02, "Zo": 80.0})
    lib = next(iter(_driver.run_range.overloads.values())).library
    bitcode = getattr(lib, "_bitcode", None)
    if bitcode is None:
        pytest.skip("run_range was compiled in this process, not loaded from the cache")
    names = _loading._names_of(ll.parse_bitcode(bitcode))
    assert names <= lib.codegen._engine._defined_symbols
    import hashlib
    import os
    folder = os.path.join(_loading_folder(), hashlib.sha1(bitcode).hexdigest())
    with open(folder, encoding="utf-8") as f:
        assert set(f.read().splitlines()[:-1]) == names


def _loading_folder():
    import os
    from screwkit.engine import _kernels
    return os.path.join(_kernels._kernel_cache_path(_kernels._configure()), "symbols")


def _imports_of(argv, watched):
    """Run ``screwkit argv`` twice as fresh processes (the first warms the caches): the
    outputs, and which of ``watched`` the second imported."""
    import subprocess
    import sys
    # (the command's main, not ``python -m screwkit``, which ends the process at once)
    code = (f"import sys\nfrom screwkit.cli import main\nmain({list(argv)!r})\n"
            f"print(sorted(m for m in {tuple(watched)!r} if m in sys.modules), file=sys.stderr)")
    runs = [subprocess.run([sys.executable, "-c", code], capture_output=True, text=True,
                           timeout=600) for _ in range(2)]
    assert all(r.returncode == 0 for r in runs), runs[-1].stderr
    assert runs[0].stdout == runs[1].stdout
    return runs[1].stdout, runs[1].stderr.strip().splitlines()[-1]


def test_a_warm_cold_analyze_imports_no_scipy_nor_numba_registries():
    _quick()
    # (nor numba's inliner: screwkit changes it only once a compilation starts, _inlining)
    out, imported = _imports_of(["analyze", "3RRPRR"], ("scipy.linalg", "scipy.spatial",
                                                         "numba.np.arraymath",
                                                         "numba.core.inline_closurecall"))
    assert "1T2R" in out and imported == "[]"


def test_a_warm_cold_leg_imports_no_yaml_nor_the_engine():
    out, imported = _imports_of(["leg", "RRPRR"], ("yaml", "numba", "screwkit.engine"))
    assert "catalog expects" in out and imported == "[]"


def test_a_warm_cold_analyze_makes_no_callee_dispatcher():
    """The kernels Python never calls get their numba dispatchers on first use
    (``_jit._Deferred``): a process that loads its entry points from the cache makes none."""
    import subprocess
    import sys
    code = ("import gc, sys\nfrom screwkit.cli import main\nmain(['analyze', '3RRPRR'])\n"
            "from numba.core.dispatcher import Dispatcher\n"
            "from screwkit.engine._kernels._jit import is_deferred\n"
            "ds = [d for d in gc.get_objects() if isinstance(d, Dispatcher)\n"
            "      and d.py_func.__module__.startswith('screwkit.engine._kernels.')]\n"
            "made = [d.py_func.__qualname__ for d in ds if not is_deferred(d)\n"
            "        and d.targetoptions.get('no_cpython_wrapper')]\n"
            "print(len(ds), sum(map(is_deferred, ds)), made, file=sys.stderr)\n")
    runs = [subprocess.run([sys.executable, "-c", code], capture_output=True, text=True,
                           timeout=900) for _ in range(2)]       # (the first warms the caches)
    assert runs[1].returncode == 0, runs[1].stderr
    total, deferred, made = runs[1].stderr.strip().splitlines()[-1].split(" ", 2)
    assert made == "[]" and int(deferred) >= 150 and int(total) > int(deferred)


def test_a_deferred_kernel_is_made_once_on_first_use_as_numba_makes_it():
    import threading

    import numba
    from numba.core.dispatcher import Dispatcher
    from screwkit.engine._kernels import _jit

    def twice(x):
        return 2.0 * x

    options = dict(no_cpython_wrapper=True, no_cfunc_wrapper=True, error_model="numpy")
    d = _jit._deferred(twice, _jit._Inner, options)
    made = []
    _jit.when_made(d, made.append)
    # what the loaders read of every dispatcher, before it is made
    assert isinstance(d, Dispatcher) and d.py_func is twice and d.__name__ == "twice"
    assert _jit.is_deferred(d) and made == []
    # threads reading it at once: made once, by one of them, the others waiting for it
    seen = []
    threads = [threading.Thread(target=lambda: seen.append(dict(d.targetoptions)))
               for _ in range(4)]
    for t in threads:
        t.start()
    for t in threads:
        t.join()
    assert made == [d] and len(seen) == 4 and not _jit.is_deferred(d)
    assert type(d) is _jit._Inner
    assert seen[0] == numba.njit(**options)(twice).targetoptions
    later = []
    _jit.when_made(d, later.append)          # (made already: at once)
    assert later == [d]

    @numba.njit
    def caller(x):
        return d(x) + 1.0

    assert caller(1.5) == 4.0


def test_a_warm_cold_analyze_imports_none_of_numbas_array_implementations():
    _quick()
    out, imported = _imports_of(["analyze", "3RRPRR", "--json"], ("numba.np.arrayobj",))
    assert json.loads(out)["pm"] == "3RRPRR" and imported == "[]"



def test_a_serial_map_command_imports_no_dask_nor_scipy_ndimage():
    """xarray imports ``dask.array`` where it casts a numpy coordinate to an index or reduces
    a variable (0.2-0.3 s of a command): a map computed in this process never needs it; nor
    ``scipy.ndimage`` (0.25 s), whose ``label`` the workspace's flood fill replaced."""
    _quick()
    out, imported = _imports_of(["map", "3RRPRR", "--grid", "alpha=-5:5:3", "--grid",
                                 "beta=-5:5:3", "--grid", "Zo=70:90:3", "--json"],
                                ("dask", "xarray", "scipy.ndimage"))
    assert json.loads(out)["counts"]["cells"] == 27 and imported == "['xarray']"

# --- a one-pose command compiles (and loads) only what it runs ---------------------------

def test_a_one_pose_analysis_never_runs_the_parallel_kernel():
    """The home predictor's fit (64 poses) runs in the calling thread: a first ``analyze``
    does not compile the parallel kernel, a cold one does not load it."""
    import subprocess
    import sys
    code = ("import screwkit\n"
            "from screwkit.engine._kernels import _driver\n"
            "res = screwkit.analyze(screwkit.load_pm('3RRPRR'), "
            "{'alpha': 0.05, 'beta': -0.02, 'Zo': 80.0})\n"
            "print(bool(res.ok), len(_driver.run_range.overloads), "
            "len(_driver.run_parallel.overloads))\n")
    run = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True,
                         timeout=900)
    assert run.returncode == 0, run.stderr
    assert run.stdout.split() == ["True", "1", "0"]


def test_the_predictor_fit_in_one_thread_is_the_threaded_one_bit_for_bit():
    from screwkit.engine._chains import chains_of
    from screwkit.engine._launch import run_poses
    from screwkit.engine._solve import predictor_of
    ch = chains_of(load_pm("3RRPRR"))
    Z = predictor_of(ch)
    rng = np.random.default_rng(5)
    fixed = {p: ch.home[p] + rng.uniform(-0.15, 0.15, 64) * (ch.length if p == "Zo" else 1)
             for p in ch.fixed}
    args = (ch.flat, Z, ch.full_params(fixed, 64))
    kw = dict(X0=ch.home_vector(64).T, rows=False)
    one = run_poses(*args, workers=1, blocks=False, **kw)
    two = run_poses(*args, workers=2, per_thread=32, **kw)
    assert one["X"].tobytes() == two["X"].tobytes()
    assert one["residual"].tobytes() == two["residual"].tobytes()


def test_the_first_compile_of_a_kernel_is_noted_once(tmp_path, capsys):
    from types import SimpleNamespace
    from screwkit.engine import _kernels

    class Kernel:                   # what the note reads of a numba dispatcher
        def __init__(self, index):
            self.overloads = {}
            self._cache = SimpleNamespace(_cache_file=SimpleNamespace(_index_path=str(index)))

    kernel = Kernel

    fresh = kernel(tmp_path / "missing.nbi")
    for _ in range(2):
        _kernels.note_first_compile(fresh, "a kernel", "a while")
    err = capsys.readouterr().err
    assert err.count("screwkit: compiling a kernel (once, a while; cached in") == 1
    (tmp_path / "kept.nbi").write_text("")
    _kernels.note_first_compile(kernel(tmp_path / "kept.nbi"), "a kernel", "a while")
    loaded = kernel(tmp_path / "missing2.nbi")
    loaded.overloads[("sig",)] = object()
    _kernels.note_first_compile(loaded, "a kernel", "a while")
    assert capsys.readouterr().err == ""


# --- one compiled version per argument type (screwkit.engine._kernels._jit._Inner) -------

def test_an_inner_kernel_is_compiled_once_per_type_not_per_literal():
    import numba
    from numba import types
    from screwkit.engine._kernels._jit import _Inner

    def scaled(x, k):
        return x * (k + 1)

    def pick(t, k):                 # a heterogeneous tuple: needs its index as a literal
        return t[k]

    inner_scaled = numba.njit(no_cpython_wrapper=True)(scaled)
    inner_scaled.__class__ = _Inner
    inner_pick = numba.njit(no_cpython_wrapper=True)(pick)
    inner_pick.__class__ = _Inner

    @numba.njit
    def caller(x, k):
        t = (x, np.int64(3))
        return (inner_scaled(x, 0) + inner_scaled(x, 1) + inner_scaled(x, k)
                + inner_pick(t, 0) + inner_pick(t, 1))

    x = 1.5
    assert caller(x, 2) == x * 1 + x * 2 + x * 3 + x + 3
    assert [tuple(s) for s in inner_scaled.signatures] == [(types.float64, types.int64)]
    assert all(isinstance(s[1], types.IntegerLiteral) for s in inner_pick.signatures)


def test_the_kernels_hold_no_version_per_literal():
    """The kernels' cache (what the compiles of this and earlier processes kept) holds one
    version of each unpacking and kinematics function per argument type."""
    from numba import types
    from screwkit.engine._kernels import _kin, _pack
    screwkit.analyze(load_pm("3RRPRR"), {"alpha": 0.05, "beta": -0.02, "Zo": 80.0})
    # (_kin.chain is inlined into its callers, numba's IR inlining: it has no versions of
    # its own; _kin.platform is called with the literal lane 0 by the one-pose kernels)
    for fn in (_pack.f1, _pack.f2, _pack.f3, _kin.platform, _kin.forward):
        sigs = list(fn.signatures) + [key[0] for key in fn._cache._cache_file._load_index()]
        assert sigs, fn
        assert not any(isinstance(t, types.Literal) for s in sigs for t in s), fn



def test_the_path_team_thread_function_has_one_version():
    """The parallel kernel's team of a path (``_driver.team_levels``) is typed once: its
    thread index an int64 both where numba types the call and in the ``prange`` body
    (uint64 there unless cast), not one version of the same code for each."""
    from numba import types
    from screwkit.engine._kernels import _driver
    s = np.linspace(0.0, 1.0, 3000)
    path = {"alpha": np.radians(5 * np.sin(2 * np.pi * s)), "beta": np.radians(4 * s),
            "Zo": 75 + 10 * s}
    r = screwkit.analyze(load_pm("3RRPRR"), path, path=True, workers=2)
    assert np.all(r.ok)
    fn = _driver.team_levels
    sigs = list(fn.signatures) + [key[0] for key in fn._cache._cache_file._load_index()]
    assert sigs and {s[5] for s in sigs} == {types.int64}, sigs

# --- the console command ends at once when nothing is pending (screwkit.cli.run) ---------

def test_the_console_command_prints_all_and_exits_with_the_status(capsys):
    import subprocess
    import sys
    from screwkit.cli import main
    assert main(["analyze", "3RRPRR"]) == 0
    want = capsys.readouterr().out
    ok = subprocess.run([sys.executable, "-m", "screwkit", "analyze", "3RRPRR"],
                        capture_output=True, text=True, timeout=900)
    assert ok.returncode == 0 and ok.stdout == want
    bad = subprocess.run([sys.executable, "-m", "screwkit", "analyze", "NOPE"],
                         capture_output=True, text=True, timeout=300)
    assert bad.returncode == 2 and bad.stdout == ""
    assert bad.stderr.startswith("screwkit analyze: error:") and "Traceback" not in bad.stderr


def test_an_exit_with_work_pending_is_orderly():
    import threading
    from screwkit.cli._main import _nothing_pending
    before = _nothing_pending()             # (False where the test run keeps its own)
    release = threading.Event()
    worker = threading.Thread(target=release.wait)          # a non-daemon thread, alive
    worker.start()
    try:
        assert not _nothing_pending()
    finally:
        release.set()
        worker.join()
    assert _nothing_pending() == before


def test_a_kernel_cached_keeps_its_symbol_list_for_the_first_load(tmp_path):
    # the process that compiles a kernel writes its symbol list (the first process that
    # loads it would otherwise parse its bitcode for it: the parallel kernel's 0.9 GB);
    # the list is the names an independent parse of the cached bitcode gives
    import hashlib
    import os
    import pickle
    import subprocess
    import sys

    _quick()
    env = dict(os.environ, NUMBA_CACHE_DIR=str(tmp_path))
    code = ("from screwkit.engine._kernels import kernels\n"
            "k = kernels()\nprint(k.piece_of(100000, 2), k.threads_for(100000, 2))\n")
    run = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True,
                         env=env, timeout=600)
    assert run.returncode == 0, run.stderr
    from llvmlite import binding as ll
    from screwkit.engine._kernels import _loading
    data = [os.path.join(dp, f) for dp, _, fs in os.walk(tmp_path) for f in fs
            if f.startswith(("_threads.piece_of", "_threads.threads_for")) and f.endswith(".nbc")]
    assert len(data) == 2
    for path in data:
        with open(path, "rb") as f:
            reduced = pickle.load(f)                # (numba's data file: the reduced result)
        name, kind, (_, bitcode) = reduced[0]
        listed = os.path.join(os.path.dirname(path), "symbols",
                              hashlib.sha1(bitcode).hexdigest())
        with open(listed, encoding="utf-8") as f:
            text = f.read()
        assert kind == "object" and text.endswith("\n#end\n")
        assert set(text.splitlines()[:-1]) == _loading._names_of(ll.parse_bitcode(bitcode))
