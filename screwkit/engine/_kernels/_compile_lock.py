"""One process at a time compiles a kernel into the cache (private; numba is imported by the
caller).

Processes that share the kernels' cache and start together on an empty one (Dask workers,
the test suite's compiling process beside its tests, two commands at once) would each
compile every kernel they call, for minutes, and numba's cache index is not made for writers
at once: each writer reads a kernel's index, adds its entry under the next free file name and
writes it back, so two processes adding entries to one kernel's index at once (the kernel
compiled with other argument types in each) can name two compilations the same file, and
the index then lists a file that holds the other one's code.

:func:`install` gives every kernel's dispatcher a ``compile`` (the method numba calls on a
call it has no code for, and when it types a call of one kernel from another) that holds an
exclusive lock of that kernel (``fcntl.flock`` on ``locks/<module>.<function>.lock`` in the
cache's folder) around numba's own, whose first step is the lookup in the disk cache: a
process that waited loads what the other one compiled instead of compiling it again.  The
locks are taken inside numba's compiler lock (the order of every compile), each once per
process at a time (a kernel typed again within its own compile holds it already), and only
where a call finds no code in the process: a call of a kernel already loaded never comes
here.  A kernel's compile holds the locks of the kernels it compiles under it, in the order
of its calls: no two processes can wait for each other (a cycle of waits would be a cycle
of calls).  A process that has to wait says so on stderr, once (not the first compile's
process waiting for its own child: :func:`unannounced`).  Where the folder cannot
hold the lock files (read-only) or there is no ``fcntl`` (Windows), nothing is locked: as
numba is.
"""

from __future__ import annotations

import os
import sys
from contextlib import contextmanager

__all__ = ["install", "install_all", "holding", "folder", "unannounced", "LOCKS"]

#: The lock files' folder in the cache's folder.
LOCKS = "locks"

_STATE = {"folder": None, "said": False, "quiet": False}
#: The locks this process holds: name -> [descriptor or None, depth].
_HELD: dict = {}


def _acquire(folder: str, name: str):
    """The descriptor of lock ``name`` in ``folder``, locked (waiting for another process,
    with a note), or None where it cannot be had."""
    try:
        import fcntl
    except ImportError:                     # (Windows: no lock, as numba)
        return None
    try:
        path = os.path.join(folder, LOCKS)
        os.makedirs(path, exist_ok=True)
        fd = os.open(os.path.join(path, f"{name}.lock"), os.O_RDWR | os.O_CREAT, 0o666)
    except OSError:                         # (a read-only cache: numba copes alone)
        return None
    try:
        fcntl.flock(fd, fcntl.LOCK_EX | fcntl.LOCK_NB)
        return fd
    except BlockingIOError:
        pass
    except OSError:                         # (a file system without locks)
        os.close(fd)
        return None
    if not _STATE["said"] and not _STATE["quiet"]:
        _STATE["said"] = True
        print(f"screwkit: waiting for another process compiling the engine's kernels into "
              f"{folder} (then loading them from there)", file=sys.stderr, flush=True)
    try:
        fcntl.flock(fd, fcntl.LOCK_EX)
    except OSError:
        os.close(fd)
        return None
    return fd


@contextmanager
def holding(name: str):
    """Within: this process holds the lock ``name`` (numba's compiler lock taken first, as
    in every compile; re-entrant).  Without :func:`install` (no folder), nothing."""
    from numba.core.compiler_lock import global_compiler_lock
    with global_compiler_lock:
        folder = _STATE["folder"]
        if folder is None:
            yield
            return
        held = _HELD.get(name)
        if held is None:
            held = _HELD[name] = [_acquire(folder, name), 0]
        held[1] += 1
        try:
            yield
        finally:
            held[1] -= 1
            if held[1] == 0:
                del _HELD[name]
                if held[0] is not None:
                    os.close(held[0])       # (closing the descriptor releases the lock)


@contextmanager
def unannounced():
    """Within: a wait for another process's lock is not told on stderr (the first compile's
    process waiting for its own child, :mod:`._warm`, whose note says what is done)."""
    before = _STATE["quiet"]
    _STATE["quiet"] = True
    try:
        yield
    finally:
        _STATE["quiet"] = before


def folder() -> str | None:
    """The folder of the locks (the kernels' cache), None before :func:`install`."""
    return _STATE["folder"]


def _name(dispatcher) -> str:
    f = dispatcher.py_func
    return f"{f.__module__.rsplit('.', 1)[-1]}.{f.__qualname__}"


def _locked(compile_, name):
    from ._jit import made

    def compile(sig):
        with holding(name):
            # (a kernel's callee is made on first use: before numba's compile reads it)
            made(compile_.__self__)
            return compile_(sig)
    compile.__wrapped__ = compile_
    return compile


def install(dispatchers, folder: str) -> None:
    """Each of ``dispatchers`` compiles (or loads from the cache) holding its lock in
    ``folder`` (the kernels' cache)."""
    _STATE["folder"] = folder
    for d in dispatchers:
        if "compile" not in vars(d):        # (else installed already)
            # (a callee not made yet, _jit._Deferred: the compile of the class it will be,
            # made first by _locked)
            spec = vars(d).get("_deferred")
            compile_ = d.compile if spec is None else spec[0].compile.__get__(d)
            d.compile = _locked(compile_, _name(d))


def install_all(package: str, folder: str) -> None:
    """:func:`install` on every dispatcher of the modules of ``package`` imported so far."""
    from numba.core.dispatcher import Dispatcher
    prefix = package + "."
    install([v for key, mod in list(sys.modules.items()) if key.startswith(prefix)
             for v in list(vars(mod).values()) if isinstance(v, Dispatcher)], folder)
