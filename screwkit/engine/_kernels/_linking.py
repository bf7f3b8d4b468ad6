"""numba's parfor wrapper libraries optimised and compiled only in the kernel (private).

numba compiles a ``prange`` loop of a parallel kernel (``_driver.run_parallel``) into three
libraries of LLVM code besides the kernel's own: the loop's body (a gufunc), its gufunc
wrapper and the parallel launcher's wrapper.  Each library links in the code of every
library it calls (for the engine's loops, the whole tree of the body's callees: some 50
functions), then runs LLVM's full module pipeline over it all and makes its machine code,
before the next library links it in again.  The kernel links them all, optimises and
compiles once more: its machine code is the one that runs and the one the on-disk cache
keeps.  numba never takes a pointer to a function of the wrappers: it only links their
code into the kernel's.

Timed inside numba (the parallel kernel's first compile, 277-285 s on the development
machine of session 53), each wrapper library spent 10.8-11.9 s optimising and 11.1-12.6 s
making the machine code of its linked-in tree (two loops, two wrappers each: some 93 s).
With this change the first batch's compile took 162 s against 245 s without (side by side).

:func:`install` defers both for those two kinds of library (numba's
``parallelgufuncwrapper`` and the gufunc wrapper of a ``prange`` loop) until something asks
for the machine code: a pointer to one of its functions or its object code (numba's object
cache and serialisation read it).  The kernel links in the wrapper's module as built (its
functions optimised one by one, as numba does on adding them) and optimises it with
everything else, once.  A library asked for its machine code is optimised and compiled
then, as numba would have done at once (numba's ``guvectorize`` asks at once, so its
wrappers are made as before).  The kernel's floating-point operations are the same (no
fast-math: LLVM's passes do not change them); its loops' addressing may differ, since
numba's machine code of a wrapper had rewritten the module the kernel then linked in
(LLVM's code generation runs passes on the module, loop strength reduction among them):
they now run once, on the kernel.  Checked: ``tests/test_numba_linking.py`` (the same
operations and results as numba without the change, in another process), and the engine's
outputs of 25 catalog PMs x 2,000 poses on two threads and of 759 arrays of paths and maps
are the same bit for bit (``benchmarks/compare_outputs.py``,
``benchmarks/compare_paths_maps.py``); the batches as fast (alternated runs).

Only where numba's classes are the ones this was written against; once per process, from
the first compilation on (a listener of numba's ``numba:compile`` event, as
:mod:`._inlining`).  ``SCREWKIT_NUMBA_LINKING=0`` leaves numba alone (a value other than
0/1, no/yes, off/on, false/true is a one-line error).
"""

from __future__ import annotations

import os
import threading
import weakref

__all__ = ["enabled", "install", "install_on_first_compile", "installed", "deferred",
           "counts"]

_LOCK = threading.Lock()
#: How many libraries had their machine code deferred, and how many of them were then asked
#: for it (made), in this process.
_COUNTS = {"deferred": 0, "made": 0}
_INSTALLED = False
_LISTENING = False
#: The names of the libraries whose machine code is deferred: numba's parallel launcher
#: wrapper, and the gufunc wrapper of a ``prange`` loop (``str`` of numba's
#: ``_GufuncWrapper``; a ``guvectorize`` gufunc's wrapper, which numba caches, asks for its
#: object code at once and so gets it at once).
_LAUNCHER = "parallelgufuncwrapper"
_GUFUNC_WRAPPER = "<numba.np.ufunc.wrappers._GufuncWrapper object at "
_ON, _OFF = ("1", "yes", "on", "true"), ("0", "no", "off", "false")


def enabled() -> bool:
    """Whether ``SCREWKIT_NUMBA_LINKING`` (unset: on) lets :func:`install` change numba.
    Raises :class:`~screwkit.errors.InputError` for a value other than 0/1, no/yes,
    off/on, false/true."""
    value = os.environ.get("SCREWKIT_NUMBA_LINKING")
    if value is None or value.strip().lower() in _ON:
        return True
    if value.strip().lower() in _OFF:
        return False
    from ...errors import InputError
    raise InputError(f"SCREWKIT_NUMBA_LINKING must be 0 or 1 (no/yes, off/on, "
                     f"false/true), got {value!r}")


def installed() -> bool:
    """Whether :func:`install` changed numba's libraries in this process."""
    return _INSTALLED


def deferred(library) -> bool:
    """Whether ``library`` (a numba code library) has its machine code still to make."""
    return getattr(library, "_screwkit_deferred", False)


def counts() -> dict:
    """``{"deferred": n, "made": m}``: the libraries of this process whose machine code was
    deferred, and those of them that were asked for it since (and got it)."""
    return dict(_COUNTS)


def _wrapper_only(library) -> bool:
    name = getattr(library, "name", "")
    return name == _LAUNCHER or name.startswith(_GUFUNC_WRAPPER)


def install() -> bool:
    """Defer the optimisation and machine code of numba's parfor wrapper libraries until
    asked for (module docstring).
    Returns whether the change is (now or before) in place: False where numba's classes
    are not as expected or ``SCREWKIT_NUMBA_LINKING=0``."""
    global _INSTALLED
    if not enabled():
        return _INSTALLED
    with _LOCK:
        if _INSTALLED:
            return True
        try:
            from numba.core import codegen, config
            library_class = codegen.JITCodeLibrary
            finish = codegen.CPUCodeLibrary._finalize_final_module
            optimise = codegen.CPUCodeLibrary._optimize_final_module
            steps = (codegen.CPUCodeLibrary._finalize_dynamic_globals,
                     codegen.CPUCodeLibrary._verify_declare_only_symbols)
            # (the ones that finalise the library first, and the object code's reader)
            finalising = ("get_pointer_to_function", "serialize_using_object_code")
            names = finalising + ("_get_compiled_object",)
            originals = {n: getattr(library_class, n) for n in names}
            originals["_finalize_specific"] = library_class._finalize_specific
        except AttributeError:
            return False
        if not all(callable(f) for f in (finish, optimise, *steps, *originals.values())):
            return False
        mangled = "_CPUCodeLibrary__library"       # numba's ``module.__library``

        def _deferring(self):
            return type(self) is library_class and _wrapper_only(self) and \
                not (config.DUMP_OPTIMIZED or config.DUMP_ASSEMBLY)

        def _optimize_final_module(self):
            if not _deferring(self):
                return optimise(self)
            # the module stays as linked (its functions optimised one by one); the kernel
            # linking it in optimises it with all the rest
            self._screwkit_unoptimised = True
            return None

        def _finalize_final_module(self):
            if not _deferring(self):
                return finish(self)
            # numba's steps up to the engine (the module is optimised and linked in by
            # finalize(), before this): the symbols checked and the module kept as is
            self._finalize_dynamic_globals()
            self._verify_declare_only_symbols()
            setattr(self._final_module, mangled, weakref.proxy(self))
            self._screwkit_deferred = True
            self._finalized = True
            _COUNTS["deferred"] += 1

        def _make_machine_code(self):
            # the rest of numba's _finalize_final_module, once, when first needed
            if self.__dict__.pop("_screwkit_deferred", False):
                if self.__dict__.pop("_screwkit_unoptimised", False):
                    optimise(self)
                cleanup = self._codegen._add_module(self._final_module)
                if cleanup:
                    weakref.finalize(self, cleanup)
                originals["_finalize_specific"](self)
                _COUNTS["made"] += 1

        def forcing(name):
            original = originals[name]

            def method(self, *args, **kwargs):
                if name in finalising:
                    self._ensure_finalized()
                _make_machine_code(self)
                return original(self, *args, **kwargs)

            method.__name__ = original.__name__
            method.__doc__ = original.__doc__
            method.__wrapped__ = original
            return method

        codegen.CPUCodeLibrary._finalize_final_module = _finalize_final_module
        codegen.CPUCodeLibrary._optimize_final_module = _optimize_final_module
        for name in names:
            setattr(library_class, name, forcing(name))
        _INSTALLED = True
        return True


def install_on_first_compile() -> None:
    """:func:`install` when numba starts compiling a function in this process (its
    ``numba:compile`` event: a cache miss), before that compilation; nothing before."""
    global _LISTENING
    if not enabled():
        return
    with _LOCK:
        if _LISTENING or _INSTALLED:
            return
        _LISTENING = True
    from numba.core import event

    class _FirstCompile(event.Listener):
        def on_start(self, ev):
            if not _INSTALLED:
                install()

        def on_end(self, ev):
            pass

    event.register("numba:compile", _FirstCompile())
