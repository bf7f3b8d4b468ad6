"""The test session: the parallel analysis kernel compiled on the second core beside the
first tests.

On an empty kernel cache (a fresh checkout: CI), the tests compile the engine's kernels as
they first need them, one after the other in the one process that runs them, while the
machine's second core idles; the parallel analysis kernel alone takes one to four minutes
of it.  The session starts a process that loads that kernel (compiling it into the cache
where it is not there yet, at once, from its argument types: :func:`precompile`);
a test that needs it meanwhile waits for it and then loads it from the cache
(``screwkit/engine/_kernels/_compile_lock.py``: one process at a time compiles a kernel).
Nothing a test computes changes: the kernel is the same one, compiled by another process.
With the kernel cached, the process loads it and ends within a second or two.  The process
ends with the session (killed if it is still compiling).  ``SCREWKIT_TEST_PRECOMPILE=0``
leaves it out.
"""

import os
import subprocess
import sys

_HERE = os.path.dirname(os.path.abspath(__file__))
_ROOT = os.path.dirname(_HERE)
_CODE = f"import sys; sys.path.insert(0, {_HERE!r}); import conftest; conftest.precompile()"
_PROCESS = []


def parallel_signature():
    """The parallel analysis kernel's argument types: the serial one's, listed for the first
    compile (``_kernels/first_compile.txt``), with the thread count for its range (``first,
    stop``); None where the list has none."""
    from screwkit.engine._kernels import _warm
    for _, _, name, args in _warm.signatures():
        if name == "run_range":
            return args[:14] + args[15:]
    return None


def precompile():
    """The session's process: the parallel analysis kernel compiled (or loaded) at once, from
    its argument types (not after the one-pose kernels its first launch would need: the
    tests compile those meanwhile), then loaded by a launch."""
    import screwkit
    from screwkit.engine._kernels import kernels
    from screwkit.engine._run import load_block_kernel
    sig = parallel_signature()
    if sig is not None:
        kernels().run_parallel.compile(sig)
    load_block_kernel(screwkit.load_pm("3RRPRR"))


def pytest_sessionstart(session):
    config = session.config
    if os.environ.get("SCREWKIT_TEST_PRECOMPILE", "1") == "0" or config.option.collectonly \
            or hasattr(config, "workerinput"):
        return
    env = dict(os.environ)
    env["PYTHONPATH"] = os.pathsep.join([_ROOT] + ([env["PYTHONPATH"]]
                                                   if env.get("PYTHONPATH") else []))
    _PROCESS.append(subprocess.Popen([sys.executable, "-c", _CODE], cwd=_ROOT, env=env,
                                     stdin=subprocess.DEVNULL, stdout=subprocess.DEVNULL,
                                     stderr=subprocess.DEVNULL))


def pytest_sessionfinish(session, exitstatus):
    while _PROCESS:
        p = _PROCESS.pop()
        if p.poll() is None:
            p.kill()
        p.wait()
