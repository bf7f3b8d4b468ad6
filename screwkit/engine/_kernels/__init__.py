"""The engine's compiled kernels (numba): loaded on first use, cached on disk (private).

:func:`kernels` imports numba and the kernel modules the first time a computation needs
them: commands that compute nothing never import numba.  The compiled kernels are cached
next to their sources when the package directory is writable, otherwise in a user cache
directory (``$XDG_CACHE_HOME/screwkit/numba``, ``~/.cache/screwkit/numba``;
``NUMBA_CACHE_DIR`` wins when it is set), set before numba is imported so that Dask workers
find the same cache.  The first run after an install compiles them once, with a note on
stderr (numba compiles an entry point on its first call: a one-pose command compiles the
serial ones; the first batch on several threads compiles the parallel kernel, with a note
of its own).  The first analysis of a process with no pose kernel in the cache compiles the
one-pose analysis kernels at once, on two processes where there are two cores
(:func:`compile_analysis`, :mod:`._warm`); numba's IR inlining copies each inlined function's
scope once (:mod:`._inlining`: a quarter of a first compile's time).  Parallel kernels run on numba's ``workqueue`` threading layer (safe across
``fork``), one launch at a time (:data:`LAUNCH_LOCK`): a launch from another Python thread
waits for the running one, which uses every thread it was given.

A kernel found in the cache is loaded without numba's refresh of its typing and lowering
registries, and without parsing the bitcode kept for linking until code is compiled
against it (:mod:`screwkit.engine._kernels._loading`): only a compilation needs them; a kernel
that is not in the cache refreshes and compiles as usual.
"""

from __future__ import annotations

import os
import sys
import threading
from types import SimpleNamespace

__all__ = ["kernels", "cache_dir", "LAUNCH_LOCK", "set_threads", "note_first_compile",
           "compile_analysis"]

#: Held while a parallel kernel runs (numba's workqueue layer takes one launch at a time).
LAUNCH_LOCK = threading.RLock()
_LOAD_LOCK = threading.Lock()
_K: SimpleNamespace | None = None
_NOTED: set = set()
_ANALYSIS_READY = False
#: ``{pid: n}``: the threads of this process's launches on ``n`` threads are pinned.
_PINNED: dict = {}
_HERE = os.path.dirname(os.path.abspath(__file__))
#: This folder's files that hold no kernel (left out of the kernels' source stamp).
_LOADER = ("__init__.py", "_compile_lock.py", "_flags.py", "_inlining.py", "_linking.py",
           "_loading.py", "_patching.py", "_warm.py")


def _writable(path: str) -> bool:
    pyc = os.path.join(path, "__pycache__")
    if os.path.isdir(pyc):
        return os.access(pyc, os.W_OK)
    return os.access(path, os.W_OK)


def _user_cache() -> str:
    from ...pm._catalog_cache import user_cache
    return user_cache("numba")


def cache_dir() -> str:
    """Where the compiled kernels are cached (set up before numba is imported)."""
    user = os.environ.get("NUMBA_CACHE_DIR")
    if user:
        return user
    if _writable(_HERE):
        return os.path.join(_HERE, "__pycache__")
    path = _user_cache()
    os.environ["NUMBA_CACHE_DIR"] = path
    return path


def wide_vector_features() -> str | None:
    """The host's CPU features for numba with LLVM's preference for 256-bit vectors turned
    off, on a CPU with AVX-512 (None elsewhere, or with ``SCREWKIT_WIDE_VECTORS`` set to
    ``0``, ``no`` or ``off``, as ``SCREWKIT_DISK_CACHE``).

    LLVM's models of Intel's AVX-512 CPUs prefer 256-bit vectors (older ones lowered their
    clock for the wider ones, which costs code that vectorises little).  The kernels' lane
    loops vectorise throughout, and measured on the benchmarks' machine (2 vCPUs, AVX-512,
    3RRPRR, one thread, two alternations) the wider vectors take a pose's Newton step
    about 15 % faster (closures from the home predictor 1.58 against 1.75-1.79 us of CPU a
    pose; rows, conditioning and statics from given unknowns 0.80-0.82 against 0.82-0.84):
    100,000 random poses on two threads 1.16M-1.21M against 1.03M-1.08M a second (three
    alternations); one pose alone through the serial kernel gains nothing (a warm 6-SPS pose
    73 against 69 us, docs/architecture.md).  The arithmetic is
    the same operation for operation (lanes are independent, no fast-math): the same bits
    (``benchmarks/compare_outputs.py``, ``compare_paths_maps.py``: no difference)."""
    if os.environ.get("SCREWKIT_WIDE_VECTORS", "1").strip().lower() in ("0", "no", "off"):
        return None
    try:
        import llvmlite.binding as ll
        features = ll.get_host_cpu_features()
    except Exception:                                 # (no LLVM host information)
        return None
    if not features.get("avx512f"):
        return None
    return features.flatten() + ",-prefer-256-bit"


def _configure():
    cache_dir()
    os.environ.setdefault("NUMBA_THREADING_LAYER", "workqueue")
    if "NUMBA_CPU_FEATURES" not in os.environ and "NUMBA_CPU_NAME" not in os.environ:
        # (in the environment: Dask workers and the compiling processes use the same, and
        # so find the same cached kernels)
        wide = wide_vector_features()
        if wide:
            os.environ["NUMBA_CPU_FEATURES"] = wide
    import numba
    if os.environ.get("NUMBA_CACHE_DIR") and not numba.config.CACHE_DIR:
        numba.config.CACHE_DIR = os.environ["NUMBA_CACHE_DIR"]     # numba imported before us
    if os.environ.get("NUMBA_CPU_FEATURES") and numba.config.CPU_FEATURES is None:
        numba.config.CPU_FEATURES = os.environ["NUMBA_CPU_FEATURES"]   # (the same)
    if os.environ["NUMBA_THREADING_LAYER"] == "workqueue":
        numba.config.THREADING_LAYER = "workqueue"
    # (numba's IR inlining without its quadratic copies, from the first compilation on:
    # a quarter of a first compile)
    from . import _flags, _inlining, _linking
    _inlining.install_on_first_compile()
    # (numba's compile flags compared without building two dicts of their 22 options, at
    # each lookup of an overloaded function's implementation: 5 % of a first compile)
    _flags.install_on_first_compile()
    # (the libraries of the parallel kernels' prange loops optimised and compiled only in
    # the kernel that links them in: half of the parallel kernel's first compile)
    _linking.install_on_first_compile()
    return numba


def _source_stamp() -> str:
    """A digest of every kernel source file (numba invalidates a cached function when its
    own file changes, not when a function it calls, in another file, does); the loader
    (``__init__.py``, ``_loading.py``, ``_warm.py``) holds no kernel and is left out."""
    import hashlib
    h = hashlib.sha1()
    for name in sorted(os.listdir(_HERE)):
        if name.endswith(".py") and name not in _LOADER:
            with open(os.path.join(_HERE, name), "rb") as f:
                h.update(name.encode() + f.read())
    return h.hexdigest()


def _kernel_cache_path(numba) -> str:
    """Where numba keeps this folder's cached kernels."""
    from numba.core.caching import _CacheLocator
    if numba.config.CACHE_DIR:
        sub = _CacheLocator.get_suitable_cache_subpath(os.path.join(_HERE, "_driver.py"))
        return os.path.join(numba.config.CACHE_DIR, sub)
    return os.path.join(_HERE, "__pycache__")


def _check_stamp(numba):
    """Drop this folder's cached kernels when any kernel source changed since they were
    compiled (a stamp file beside them)."""
    try:
        path = _kernel_cache_path(numba)
        stamp = os.path.join(path, "screwkit-kernels.stamp")
        want = _source_stamp()
        if os.path.exists(stamp):
            with open(stamp) as f:
                if f.read().strip() == want:
                    return
        mods = {name[:-3] for name in os.listdir(_HERE) if name.endswith(".py")}
        if os.path.isdir(path):
            for name in os.listdir(path):
                if name.split(".", 1)[0] in mods and name.endswith((".nbi", ".nbc")):
                    os.remove(os.path.join(path, name))
        os.makedirs(path, exist_ok=True)
        # (written whole, then renamed: a process reading it at once reads all of it)
        with open(f"{stamp}.{os.getpid()}", "w") as f:
            f.write(want + "\n")
        os.replace(f"{stamp}.{os.getpid()}", stamp)
    except OSError:              # a read-only cache: numba itself copes (or recompiles)
        pass


def _quick_loading(numba, modules) -> None:
    """The kernels' dispatchers load their cached code quickly (:mod:`._loading`)."""
    from numba.core.dispatcher import Dispatcher

    from ._loading import install
    install([v for mod in modules for v in vars(mod).values() if isinstance(v, Dispatcher)],
            os.path.join(_kernel_cache_path(numba), "symbols"))


def _compiled_before(fn) -> bool:
    """Whether ``fn``'s cache index exists (False: the first call compiles)."""
    try:
        return os.path.exists(fn._cache._cache_file._index_path)
    except AttributeError:
        return True


def note_first_compile(fn, what: str, how_long: str) -> None:
    """One line on stderr when the call of the kernel ``fn`` about to be made compiles it
    (neither loaded in this process nor in the cache): ``what`` it is, ``how_long``."""
    if fn.overloads or fn in _NOTED:
        return
    _NOTED.add(fn)
    if not _compiled_before(fn):
        print(f"screwkit: compiling {what} (once, {how_long}; cached in {cache_dir()})",
              file=sys.stderr, flush=True)


def kernels() -> SimpleNamespace:
    """The kernel functions (numba and the kernel modules imported on the first call)."""
    global _K
    if _K is not None:
        return _K
    with _LOAD_LOCK:
        if _K is None:
            numba = _configure()
            _check_stamp(numba)
            from . import (_driver, _extra, _fk, _indices, _levels, _orient, _probe,
                           _reversed, _threads)
            _quick_loading(numba, (_driver, _extra, _fk, _indices, _levels, _orient, _probe,
                                   _reversed, _threads))
            # (one process at a time compiles a kernel into the cache; the others wait for
            # it and load it)
            from ._compile_lock import install_all
            install_all(__name__, _kernel_cache_path(numba))
            if not _compiled_before(_driver.run_range):
                print(f"screwkit: compiling the engine's kernels (once, a minute or two; "
                      f"cached in {cache_dir()})", file=sys.stderr, flush=True)
            ns = SimpleNamespace(numba=numba)
            for mod in (_driver, _extra, _fk, _indices, _levels, _orient, _probe, _reversed,
                        _threads):
                for name in dir(mod):
                    if not name.startswith("_"):
                        setattr(ns, name, getattr(mod, name))
            _K = ns
    return _K


def compile_analysis() -> None:
    """Before the first analysis of a process: where the cache holds no analysis kernel
    yet (a first run), compile the kernels of a one-pose analysis now, on two processes
    where there are two cores (:mod:`._warm`); else nothing (numba compiles on demand)."""
    global _ANALYSIS_READY
    if _ANALYSIS_READY:
        return
    k = kernels()
    with _LOAD_LOCK:
        if not _ANALYSIS_READY and not k.run_range.overloads \
                and not _compiled_before(k.run_range):
            from ._compile_lock import holding
            from ._warm import compile_first
            # (another process may be compiling them: wait for it, and ask again)
            with holding("analysis"):
                if not _compiled_before(k.run_range):
                    compile_first()
        _ANALYSIS_READY = True


def set_threads(n: int) -> int:
    """Threads of the next parallel launch (at most numba's pool); returns the number.
    Where the process may use no more CPUs than that, each of the threads is kept on a CPU
    of its own (:mod:`._threads`), once per process and number of threads."""
    k = kernels().numba
    n = max(1, min(int(n), k.config.NUMBA_NUM_THREADS))
    k.set_num_threads(n)
    if n > 1 and _PINNED.get(os.getpid()) != n:
        _PINNED.clear()
        _PINNED[os.getpid()] = n
        _pin_threads(n)
    return n


def _pin_threads(n: int) -> None:
    """Worker ``i`` of the launches on ``n`` threads on the ``i``-th CPU the process may use,
    where those CPUs are no more than ``n`` (Linux; not with ``SCREWKIT_PIN_THREADS=0``;
    only on numba's ``workqueue`` layer, whose workers are threads of their own: with OpenMP
    the calling thread runs the first range, and would stay pinned)."""
    if os.environ.get("SCREWKIT_PIN_THREADS", "") == "0" or not sys.platform.startswith(
            "linux") or not hasattr(os, "sched_getaffinity"):
        return
    try:
        if kernels().numba.threading_layer() != "workqueue":
            return
    except ValueError:          # (no layer started: none to pin)
        return
    import numpy as np
    cpus = sorted(os.sched_getaffinity(0))
    if not cpus or len(cpus) > n:
        return
    masks = np.zeros((n, max(cpus) // 64 + 1), np.uint64)
    for i in range(n):
        c = cpus[i % len(cpus)]
        masks[i, c // 64] |= np.uint64(1) << np.uint64(c % 64)
    try:
        kernels().pin_threads(masks, np.zeros(n, np.int32))
    except Exception:       # (an optimisation only: where it cannot be had, threads as they are)
        pass
