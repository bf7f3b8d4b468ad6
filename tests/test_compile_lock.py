"""One process at a time compiles into the kernels' cache (screwkit/engine/_kernels/
_compile_lock.py): a process that finds another compiling waits, says so, and then loads
what the other compiled instead of compiling it again.

Checked on a small cached numba function of a module written here (the engine's kernels take
minutes to compile), with its lock installed on its dispatcher as the engine installs one on
each kernel's: a first process holds the lock, a second calls the function and must wait
(its note on stderr) and, once the first has compiled the function into the cache and let
go, load it from there (one cache hit, no miss: it compiled nothing); the first compiled it
(one miss)."""

import os
import select
import subprocess
import sys
import textwrap

from screwkit.engine._kernels import _compile_lock

MODULE = textwrap.dedent('''
    import numba

    @numba.njit(cache=True)
    def cube_plus(x):
        return x * x * x + 1.0
''')

HOLDER = textwrap.dedent('''
    import sys
    from screwkit.engine._kernels import _compile_lock
    import small
    _compile_lock.install([small.cube_plus], sys.argv[1])
    with _compile_lock.holding("small.cube_plus"):       # (the function's own lock)
        print("locked", flush=True)
        sys.stdin.readline()                      # (until the test says go)
        value = small.cube_plus(2.0)              # (holding the lock already: re-entrant)
    print(value, sum(small.cube_plus.stats.cache_misses.values()), flush=True)
''')

CALLER = textwrap.dedent('''
    import sys
    from screwkit.engine._kernels import _compile_lock
    import small
    _compile_lock.install([small.cube_plus], sys.argv[1])
    value = small.cube_plus(3.0)
    stats = small.cube_plus.stats
    print(value, sum(stats.cache_hits.values()), sum(stats.cache_misses.values()), flush=True)
''')


def _env(tmp_path):
    root = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
    env = dict(os.environ)
    env["PYTHONPATH"] = os.pathsep.join([str(tmp_path), root])
    env["NUMBA_CACHE_DIR"] = str(tmp_path / "cache")
    env.pop("SCREWKIT_COMPILE_CHILD", None)
    return env


def _line(stream, timeout):
    """One line of ``stream`` within ``timeout`` seconds (else None)."""
    if not select.select([stream], [], [], timeout)[0]:
        return None
    return stream.readline()


def test_a_second_process_waits_for_the_compile_and_loads_it(tmp_path):
    (tmp_path / "small.py").write_text(MODULE)
    folder = str(tmp_path / "cache")
    env = _env(tmp_path)
    holder = subprocess.Popen([sys.executable, "-c", HOLDER, folder], env=env, text=True,
                              stdin=subprocess.PIPE, stdout=subprocess.PIPE)
    caller = None
    try:
        assert _line(holder.stdout, 60) == "locked\n"
        caller = subprocess.Popen([sys.executable, "-c", CALLER, folder], env=env, text=True,
                                  stdout=subprocess.PIPE, stderr=subprocess.PIPE)
        note = _line(caller.stderr, 60)
        assert note is not None and note.startswith(
            "screwkit: waiting for another process compiling the engine's kernels into "), note
        assert folder in note
        assert caller.poll() is None                # (still waiting: nothing printed)
        holder.stdin.write("go\n")
        holder.stdin.flush()
        out, _ = holder.communicate(timeout=120)
        value, misses = out.split()
        assert float(value) == 9.0 and int(misses) == 1           # it compiled
        out, err = caller.communicate(timeout=120)
        assert caller.returncode == 0, err
        value, hits, misses = out.split()
        # 3^3 + 1; loaded from the cache the holder wrote, not compiled again
        assert float(value) == 28.0 and (int(hits), int(misses)) == (1, 0)
    finally:
        for p in (holder, caller):
            if p is not None and p.poll() is None:
                p.kill()
                p.wait()


def test_a_folder_that_cannot_hold_the_lock_locks_nothing(tmp_path):
    (tmp_path / "a_file").write_text("")
    assert _compile_lock._acquire(str(tmp_path / "a_file" / "cache"), "a.f") is None


def test_the_lock_is_reentrant_and_released(tmp_path):
    import fcntl
    folder = str(tmp_path / "cache")
    saved = dict(_compile_lock._STATE)
    try:
        _compile_lock._STATE["folder"] = folder
        with _compile_lock.holding("a.f"):
            with _compile_lock.holding("a.f"):
                assert _compile_lock._HELD["a.f"][1] == 2
            with _compile_lock.holding("a.g"):          # (another kernel's: its own)
                assert set(_compile_lock._HELD) == {"a.f", "a.g"}
            assert _compile_lock._HELD["a.f"][0] is not None
        assert not _compile_lock._HELD
        for name in ("a.f", "a.g"):
            fd = os.open(os.path.join(folder, _compile_lock.LOCKS, f"{name}.lock"), os.O_RDWR)
            try:
                fcntl.flock(fd, fcntl.LOCK_EX | fcntl.LOCK_NB)      # (free again)
            finally:
                os.close(fd)
    finally:
        _compile_lock._STATE.clear()
        _compile_lock._STATE.update(saved)


def test_a_wait_for_the_first_compiles_own_child_is_not_announced(tmp_path, capsys):
    """The first compile's process waits for kernels its child compiles (``_warm``) without
    the note (its own says what is done); outside, a wait is told once."""
    import fcntl
    import threading
    import time
    folder = str(tmp_path / "cache")
    saved = dict(_compile_lock._STATE)

    def wait_for_another():
        other = os.open(os.path.join(folder, _compile_lock.LOCKS, "a.f.lock"),
                        os.O_RDWR | os.O_CREAT)
        fcntl.flock(other, fcntl.LOCK_EX)             # (another open file: another owner)
        threading.Timer(0.3, os.close, (other,)).start()
        t0 = time.monotonic()
        fd = _compile_lock._acquire(folder, "a.f")
        os.close(fd)
        return time.monotonic() - t0

    try:
        _compile_lock._STATE.update(folder=folder, said=False, quiet=False)
        os.makedirs(os.path.join(folder, _compile_lock.LOCKS))
        with _compile_lock.unannounced():
            assert wait_for_another() >= 0.2
        assert capsys.readouterr().err == ""
        assert not _compile_lock._STATE["quiet"]
        assert wait_for_another() >= 0.2
        assert capsys.readouterr().err.startswith(
            "screwkit: waiting for another process compiling the engine's kernels into ")
    finally:
        _compile_lock._STATE.clear()
        _compile_lock._STATE.update(saved)


def test_the_kernels_compile_under_their_locks():
    from numba.core.dispatcher import Dispatcher

    from screwkit.engine._kernels import _driver, _newton, kernels
    kernels()
    for d in (_driver.run_range, _driver.run_parallel, _newton.step_block):
        assert isinstance(d, Dispatcher) and "compile" in vars(d)
        assert d.compile.__wrapped__ == Dispatcher.compile.__get__(d)
