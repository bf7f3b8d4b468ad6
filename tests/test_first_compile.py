"""The first compile on two processes (screwkit/engine/_kernels/_warm.py).

The kernels of the whole analysis take a minute to compile: these tests run the machinery
on two small kernels in an empty cache, and check the list of kernels and argument types
the first run compiles against the kernels a real analysis calls."""

import os
import subprocess
import sys
import textwrap

import numpy as np
import pytest
from numba.core.dispatcher import Dispatcher

from screwkit.engine._kernels import _warm

GROUPS = {"closure", "handed", "main", "pose", "other"}


def _lines():
    with open(_warm.SIGNATURES, encoding="utf-8") as f:
        return [ln for ln in f.read().splitlines() if ln.strip() and not ln.startswith("#")]


def test_the_list_names_kernels_whose_argument_types_numba_rebuilds():
    import importlib
    sigs = _warm.signatures()
    assert len(sigs) == len(_lines()) > 40          # every line read back, none dropped
    for group, module, function, args in sigs:
        assert group in GROUPS
        fn = getattr(importlib.import_module(f"screwkit.engine._kernels.{module}"), function)
        assert isinstance(fn, Dispatcher), (module, function)
        assert isinstance(args, tuple) and args
    # no kernel compiled with other argument types by each process: both would add an
    # entry to its cache index at once, naming it the same file
    side = {}
    for group, module, function, _ in sigs:
        side.setdefault((module, function), set()).add(group in ("closure", "handed", "other"))
    assert all(len(s) == 1 for s in side.values()), [k for k, s in side.items() if len(s) > 1]
    where = {(m, f): g for g, m, f, _ in sigs}
    assert where[("_closures", "solve_pose")] == "closure"
    assert where[("_driver", "run_range")] == "pose"
    assert where[("_probe", "home_groups")] == "other"
    assert where[("_members", "template_one")] == "handed"


def test_the_listed_entry_points_are_those_an_analysis_calls(capsys):
    """Each entry point of the list (the ones Python calls) with the argument types of the
    list is what ``screwkit analyze 3RRPRR`` calls (loaded or compiled here): a stale
    line would compile a version nobody calls.  After a change of a kernel's arguments:
    ``python benchmarks/first_run.py --write``."""
    import importlib

    from screwkit.cli import main
    assert main(["analyze", "3RRPRR"]) == 0
    capsys.readouterr()
    entries = 0
    for group, module, function, args in _warm.signatures():
        fn = getattr(importlib.import_module(f"screwkit.engine._kernels.{module}"), function)
        if fn.targetoptions.get("no_cpython_wrapper"):
            continue                # (an inner kernel: compiled with its callers)
        entries += 1
        assert args in fn.signatures, f"{module}.{function}: stale argument types"
    assert entries >= 8


_SMALL = textwrap.dedent("""\
    # two small kernels, one a process
    closure\t_extra\tdet_sign_batch\t(Array(float64, 3, 'C', False, aligned=True), Array(float64, 1, 'C', False, aligned=True))
    main\t_extra\tnormalise_batch\t(Array(float64, 3, 'C', False, aligned=True), Array(float64, 2, 'C', False, aligned=True), Array(float64, 1, 'C', False, aligned=True), Array(float64, 3, 'C', False, aligned=True), Array(float64, 2, 'C', False, aligned=True))
    other\t_extra\tno_such_kernel\t(int64,)
    """)

_READ_ONLY_PACKAGE = textwrap.dedent("""\
    import os, sys
    os.environ["XDG_CACHE_HOME"] = sys.argv[1]
    os.environ.pop("NUMBA_CACHE_DIR", None)
    from screwkit.engine import _kernels
    _kernels._writable = lambda path: False     # a package directory nobody may write
    print(_kernels.cache_dir())
    """)


def test_a_child_compiles_into_the_user_cache_and_its_kernels_load_there(tmp_path):
    """Where the package directory is read-only, the cache goes to the user's cache
    directory, and the child compiles there too: its kernel and this process's are then
    loaded from that cache by a fresh process, which compiles nothing, and give the bits
    of the kernels compiled in one process (this test process's)."""
    path = tmp_path / "kernels.txt"
    path.write_text(_SMALL)
    code = _READ_ONLY_PACKAGE + textwrap.dedent(f"""\
        from screwkit.engine._kernels import kernels, _warm
        kernels()
        started = []
        start = _warm._start_child
        _warm._start_child = lambda p: started.append(start(p)) or started[-1]
        os.environ["SCREWKIT_COMPILE_PROCESSES"] = "2"
        print(_warm.compile_first({str(path)!r}), started[0].returncode)
        """)
    env = {k: v for k, v in os.environ.items() if k != "SCREWKIT_COMPILE_PROCESSES"}
    out = subprocess.run([sys.executable, "-c", code, str(tmp_path)], capture_output=True,
                         text=True, timeout=600, env=env)
    assert out.returncode == 0, out.stderr
    cache, result = out.stdout.splitlines()
    assert cache == str(tmp_path / "screwkit" / "numba")
    assert result == "True 0"                        # a child helped, and it has ended
    index = [n for _, _, names in os.walk(cache) for n in names if n.endswith(".nbi")]
    assert any("det_sign_batch" in n for n in index)          # the child's
    assert any("normalise_batch" in n for n in index)         # this process's

    rng = np.random.default_rng(3)
    J = rng.normal(size=(50, 6, 6))
    centre, length = rng.normal(size=(50, 3)), rng.uniform(0.5, 2.0, 50)
    np.savez(tmp_path / "in.npz", J=J, centre=centre, length=length)
    load = _READ_ONLY_PACKAGE + textwrap.dedent(f"""\
        import numpy as np
        from screwkit.engine._kernels import kernels, _extra
        k = kernels()
        d = np.load({str(tmp_path / 'in.npz')!r})
        sign = np.empty(50)
        k.det_sign_batch(d["J"], sign)
        Jn, D = np.empty((50, 6, 6)), np.empty((50, 6))
        k.normalise_batch(d["J"], d["centre"], d["length"], Jn, D)
        np.savez({str(tmp_path / 'out.npz')!r}, sign=sign, Jn=Jn, D=D)
        print(*(sum(c.values()) for f in (_extra.det_sign_batch, _extra.normalise_batch)
                for c in (f._cache_hits, f._cache_misses)))
        """)
    out = subprocess.run([sys.executable, "-c", load, str(tmp_path)], capture_output=True,
                         text=True, timeout=600, env=env)
    assert out.returncode == 0, out.stderr
    assert out.stdout.split()[1:] == ["1", "0", "1", "0"]      # loaded, not compiled
    got = np.load(tmp_path / "out.npz")
    np.testing.assert_array_equal(got["sign"], np.sign(np.linalg.det(J)))
    from screwkit.engine._kernels import kernels
    k = kernels()
    Jn, D = np.empty((50, 6, 6)), np.empty((50, 6))
    k.normalise_batch(J, centre, length, Jn, D)
    np.testing.assert_array_equal(got["Jn"], Jn)
    np.testing.assert_array_equal(got["D"], D)


_CHEAP = ("_pack", "_small", "_tridiagonal")


@pytest.mark.parametrize("locks", [False, True])
def test_the_lists_callees_compile_in_a_fresh_process(tmp_path, locks):
    """The list's kernels Python never calls (``inner``, ``borrowing``...: made on first
    use, ``_jit._Deferred``) compile from their lines in a fresh process, as the first run's
    two processes compile them (the child with the kernels' locks): none fails, each is
    made and holds the version of its line.  (A deferred dispatcher's ``compile`` once read
    numba's C state before it was made, "compilation disabled": every such line failed, and
    the first run's two processes compiled the analysis one after the other.)  The list's
    cheap modules only, in an empty cache."""
    code = textwrap.dedent(f"""\
        import importlib
        from screwkit.engine import _kernels
        from screwkit.engine._kernels import _jit, _warm
        _kernels.kernels()
        lines = [ln for ln in _warm.signatures() if ln[1] in {_CHEAP!r}]
        fns = [getattr(importlib.import_module("screwkit.engine._kernels." + ln[1]), ln[2])
               for ln in lines]
        deferred = sum(_jit.is_deferred(f) for f in fns)
        if {locks!r}:
            from screwkit.engine._kernels._compile_lock import install_all
            install_all("screwkit.engine._kernels", {str(tmp_path / "nc")!r})
        failed = [f for g in ("main", "closure", "handed", "other")
                  for f in _warm._compile(lines, g)]
        made = all(not _jit.is_deferred(f) and ln[3] in f.signatures
                   for ln, f in zip(lines, fns))
        print(len(lines), deferred, len(failed), made, failed[:1])
        """)
    env = dict(os.environ, NUMBA_CACHE_DIR=str(tmp_path / "nc"))
    out = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True,
                         timeout=600, env=env)
    assert out.returncode == 0, out.stderr
    n, deferred, failed, made = out.stdout.split()[:4]
    assert int(n) >= 10 and int(deferred) >= 10, out.stdout
    assert failed == "0" and made == "True", out.stdout


def test_an_interrupted_first_compile_leaves_no_child(tmp_path, monkeypatch):
    path = tmp_path / "kernels.txt"
    path.write_text(_SMALL)
    monkeypatch.setenv("NUMBA_CACHE_DIR", str(tmp_path / "nc"))
    monkeypatch.setenv("SCREWKIT_COMPILE_PROCESSES", "2")
    started = []
    start = _warm._start_child
    monkeypatch.setattr(_warm, "_start_child", lambda p: started.append(start(p)) or started[-1])

    def interrupted(lines, group, report=None):
        raise KeyboardInterrupt

    monkeypatch.setattr(_warm, "_compile", interrupted)
    with pytest.raises(KeyboardInterrupt):
        _warm.compile_first(str(path))
    assert len(started) == 1 and started[0].returncode is not None


def test_one_core_or_one_process_compiles_on_demand(tmp_path, monkeypatch):
    path = tmp_path / "kernels.txt"
    path.write_text(_SMALL)
    monkeypatch.setenv("SCREWKIT_COMPILE_PROCESSES", "1")
    calls = []
    monkeypatch.setattr(_warm, "_start_child", lambda p: calls.append(p))
    monkeypatch.setattr(_warm, "_compile", lambda *a, **k: calls.append(a))
    assert _warm.compile_first(str(path)) is False and calls == []
    monkeypatch.setenv(_warm._CHILD_ENV, "1")              # a child never starts a child
    monkeypatch.setenv("SCREWKIT_COMPILE_PROCESSES", "2")
    assert _warm.compile_first(str(path)) is False and calls == []


@pytest.mark.parametrize("script, timeout, low, high", [
    ("import time; time.sleep(120)", 1.0, 0.9, 6.0),              # silent: until the timeout
    ("import time; print('closure', flush=True); time.sleep(120)", 60.0, 0.0, 20.0),  # ready
    ("import sys; sys.exit(3)", 60.0, 0.0, 20.0),                 # ended without a word
])
def test_the_wait_for_the_childs_closure_is_bounded(script, timeout, low, high):
    import time
    child = subprocess.Popen([sys.executable, "-c", script], stdout=subprocess.PIPE,
                             stdin=subprocess.DEVNULL)
    try:
        t0 = time.monotonic()
        _warm._wait_ready(child, timeout)
        waited = time.monotonic() - t0
    finally:
        child.kill()
        child.wait()
        child.stdout.close()
    # a silent child is waited for until the timeout, no longer; one that says it is ready
    # or ends is not waited for beyond that (far below the 60 s timeout)
    assert low <= waited < high


@pytest.mark.parametrize("value", ["two", "0", "-3", "1.5", ""])
def test_a_bad_process_count_is_a_one_line_error(monkeypatch, value):
    from screwkit.errors import InputError
    monkeypatch.setenv("SCREWKIT_COMPILE_PROCESSES", value)
    with pytest.raises(InputError, match="SCREWKIT_COMPILE_PROCESSES must be a whole number"):
        _warm._processes()


def test_a_good_process_count_is_taken(monkeypatch):
    monkeypatch.setenv("SCREWKIT_COMPILE_PROCESSES", "1")
    assert _warm._processes() == 1
    monkeypatch.setenv("SCREWKIT_COMPILE_PROCESSES", "2")
    assert _warm._processes() == 2


def test_the_test_sessions_parallel_kernel_is_the_one_an_analysis_launches():
    # tests/conftest.py compiles the parallel analysis kernel from the serial one's listed
    # types: those must be the types a batch launches it with
    import conftest

    import screwkit
    from screwkit.engine._kernels import kernels
    from screwkit.engine._run import load_block_kernel
    load_block_kernel(screwkit.load_pm("3RRPRR"))
    k = kernels().run_parallel
    assert conftest.parallel_signature() in [tuple(s) for s in k.signatures]
