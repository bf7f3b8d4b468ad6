"""The first compile on two processes (private; numba is imported by the caller).

A first run (no cached kernels) compiles the kernels of a one-pose analysis: 60 to 80 s of
CPU, nearly all of it in one process and one thread (numba's typing and lowering, then LLVM
optimising and generating the code of each function with everything it calls linked in).
On a machine with a second core, that compile is split between this process and a child
process that compiles into the same disk cache:

* the child compiles the pose's loop closure (``_closures.solve_pose``, with the forward
  kinematics and Newton under it), then a few of the pose kernel's callees this process
  reaches last in its list (group ``handed``: the home predictor, a row template's
  members, a leg's rows by the general rules; without them this process's share was the
  longer, the child idle for its last 12 s), then the
  entry points the analysis calls besides the pose kernel (the row templates' probes at
  home, the transmission indices, the frames...);
* meanwhile this process compiles the rest of the pose kernel's callees (rows,
  conditioning, statics...), waits for the child's closure, loads it from the cache (numba
  links a cached callee's bitcode into its callers as it links a callee compiled in the
  same process: the machine code differs only by numba's function names and the link
  order; the results are the same bits), compiles the pose kernel itself (``run_range``),
  and waits for the child to finish (its kernels load from the cache on first use).

The block closure's kernels (``_block``, ``_solve_lanes.solve_block``) are not among them: only
the parallel kernel (``run_parallel``, every batch worth a thread) links them, and it
compiles with the first such batch (``_launch``: a note on stderr).

The kernels and their argument types come from :data:`SIGNATURES` (``first_compile.txt``
beside this file, one ``group, module, function, argument types`` a line, written by
``benchmarks/first_run.py --write`` from a serial compile; tests check it against the
kernels).  Nothing depends on the split for correctness: a line that no longer matches a
kernel compiles a version nobody calls, a child that fails or is slow only leaves its
kernels to be compiled on demand, as on one process.  numba writes each cache file
atomically (a temporary file renamed); a callee both processes would compile is compiled by
one, the other waiting for it and loading it (the kernels' locks, :mod:`._compile_lock`), and
all of a kernel's argument types are compiled by one process all the same (the list's
generator sees to it).  The child is silent, gets no input, and never outlives the call
(:func:`compile_first`).  ``SCREWKIT_COMPILE_PROCESSES=1`` (or a single core) compiles on
one process as before.
"""

from __future__ import annotations

import importlib
import os
import subprocess
import sys

__all__ = ["compile_first", "signatures", "SIGNATURES"]

_HERE = os.path.dirname(os.path.abspath(__file__))
#: The kernels a one-pose analysis compiles, with their argument types (see the docstring).
SIGNATURES = os.path.join(_HERE, "first_compile.txt")
_PACKAGE = "screwkit.engine._kernels"
#: Set in the child's environment (a child never starts a child of its own).
_CHILD_ENV = "SCREWKIT_COMPILE_CHILD"
#: Seconds this process waits for the child's closure, then for its end (then kills it).
_CHILD_TIMEOUT = 900
#: The child's line on stdout once the closure kernel is in the cache.
_READY = "closure"


def _type_names():
    from numba.core import types
    names = {k: v for k, v in vars(types).items() if not k.startswith("_")}
    names["bool"] = types.boolean
    return names


def signatures(path: str = SIGNATURES) -> list:
    """``[(group, module, function, argument types)]`` in compile order; a line whose
    types numba cannot rebuild from their text (a literal) is left out (its kernel then
    compiles on demand)."""
    names = _type_names()
    out = []
    try:
        with open(path, encoding="utf-8") as f:
            lines = f.read().splitlines()
    except OSError:
        return out
    for line in lines:
        if not line.strip() or line.startswith("#"):
            continue
        group, module, function, text = line.split("\t", 3)
        try:
            args = eval(text, {"__builtins__": {}}, names)     # numba's own type reprs
        except Exception:
            continue
        out.append((group, module, function, tuple(args)))
    return out


def _compile(lines, group, report=None) -> list:
    """Compile the ``group``'s kernels of ``lines``; ``report(function)`` after each.
    Returns the lines that failed, each with its exception (a stale line: that kernel then
    compiles on demand; the tests hold the list to none)."""
    failed = []
    for line in lines:
        g, module, function, args = line
        if g != group:
            continue
        try:
            fn = getattr(importlib.import_module(f"{_PACKAGE}.{module}"), function)
            fn.compile(args)
        except Exception as e:
            failed.append((line, e))
        if report is not None:
            report(function)
    return failed


def _processes() -> int:
    """The processes a first compile may use: ``SCREWKIT_COMPILE_PROCESSES`` (1 or 2; more
    are not used), else the cores this process may run on."""
    n = os.environ.get("SCREWKIT_COMPILE_PROCESSES")
    if n is not None:
        try:
            value = int(n)
        except ValueError:
            value = 0
        if value < 1:
            from ...errors import InputError
            raise InputError(f"SCREWKIT_COMPILE_PROCESSES must be a whole number >= 1 "
                             f"(1: compile on one process), got {n!r}")
        return value
    try:
        return len(os.sched_getaffinity(0))
    except AttributeError:
        return os.cpu_count() or 1


def _start_child(path):
    root = os.path.dirname(os.path.dirname(os.path.dirname(_HERE)))
    env = dict(os.environ)
    env[_CHILD_ENV] = "1"
    env["PYTHONPATH"] = os.pathsep.join([root] + ([env["PYTHONPATH"]]
                                                  if env.get("PYTHONPATH") else []))
    # (run from the package's root: ``-c`` puts the working directory first on the path)
    from ._compile_lock import folder
    return subprocess.Popen(
        [sys.executable, "-c", f"from {_PACKAGE} import _configure; _configure(); "
         f"from {_PACKAGE}._warm import _child; _child()", path, folder() or ""],
        stdin=subprocess.DEVNULL, stdout=subprocess.PIPE, stderr=subprocess.DEVNULL,
        env=env, cwd=root)


def _wait_ready(child, timeout: float) -> None:
    """Until the child says the closure kernel is cached, ends, or ``timeout`` seconds
    pass (then this process compiles the closure on demand)."""
    import select
    import time
    fd, seen = child.stdout.fileno(), b""
    deadline = time.monotonic() + timeout
    while (left := deadline - time.monotonic()) > 0:
        if not select.select([fd], [], [], left)[0]:
            return
        chunk = os.read(fd, 256)
        if not chunk:                       # (the child ended)
            return
        seen += chunk
        if _READY.encode() in seen.split():
            return


def compile_first(path: str = SIGNATURES) -> bool:
    """Compile the one-pose analysis kernels (those of ``path``), on two processes where
    there are two cores.  Returns whether a child helped.
    Called on a cache miss only; the child has ended when this returns."""
    if os.environ.get(_CHILD_ENV):
        return False
    lines = signatures(path)
    if not lines:
        return False
    if _processes() < 2:                    # (on one core: compiled on demand)
        return False
    try:
        child = _start_child(path)
    except OSError:
        return False
    from ._compile_lock import unannounced
    try:
        # (this process waits for kernels its child compiles: the first run's note says so)
        with unannounced():
            _compile(lines, "main")
            _wait_ready(child, _CHILD_TIMEOUT)
            _compile(lines, "pose")
        child.wait(timeout=_CHILD_TIMEOUT)
    except subprocess.TimeoutExpired:       # (its kernels compile on demand)
        pass
    finally:
        if child.poll() is None:            # (interrupted: the child does not outlive us)
            child.kill()
            child.wait()
        child.stdout.close()
    return True


def _child() -> None:
    """The child's work (numba configured as this package does): the closure kernel (then
    ``closure`` on stdout), the pose kernel's callees handed to it, the others."""
    lines = signatures(sys.argv[1])
    # (the kernels' locks, as in the parent: a callee both compile is compiled by one and
    # loaded by the other, :mod:`._compile_lock`)
    if len(sys.argv) > 2 and sys.argv[2]:
        from . import (_driver, _extra, _fk, _indices, _levels, _orient,  # noqa: F401
                       _probe, _reversed, _threads)
        from ._compile_lock import install_all
        install_all(_PACKAGE, sys.argv[2])
    _compile(lines, "closure")
    print(_READY, flush=True)
    _compile(lines, "handed")
    _compile(lines, "other")
