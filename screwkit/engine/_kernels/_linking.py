"""The libraries of numba's ``prange`` loops optimised and compiled once, in the kernel, and
the kernels' callees without machine code (private).

numba compiles a ``prange`` loop of a parallel kernel (``_driver.run_parallel``) into three
libraries of LLVM code besides the kernel's own: the loop's body (a gufunc), its gufunc
wrapper and the parallel launcher's wrapper.  Each library links in the code of every
library it calls (for the engine's loops, the whole tree of the body's callees: some 50
functions), then runs LLVM's full module pipeline over it all and makes its machine code,
before the next library links it in again.  The kernel links them all, optimises and
compiles once more: its machine code is the one that runs and the one the on-disk cache
keeps.  numba only links the loop's libraries into the kernel: it takes a pointer to the
body's Python wrapper alone (which nothing calls).

Timed inside numba (the parallel kernel's first compile, 277-285 s on the development
machine of session 53), each of the six libraries of the two loops spent 10.8-11.9 s
optimising and 11.1-12.6 s making the machine code of its linked-in tree: some 140 s for
code that never runs.  With this change that compile took 124.1 s against 247.7 s without
(side by side, one process each).

:func:`install` compiles a loop's body without the Python and C wrappers nothing calls, and
defers the optimisation and machine code of those three kinds of library (the body,
numba's gufunc wrapper of a ``prange`` loop and its ``parallelgufuncwrapper``) until
something asks for the machine code: a pointer to a function the library defines, or its
object code (numba's object cache and serialisation read it).  The kernel links their
modules in as built (their functions optimised one by one, as numba does on adding them)
and optimises them with everything else, once.  A library asked for its machine code is
optimised and compiled then, as numba would have done at once (numba's ``guvectorize``
asks at once, so its wrappers are made as before).  An environment numba sets for a
function whose library is deferred (its global defined by no module of numba's engine yet)
is set where the engine finds its global once one is, as numba's ``set_env`` does: in the
kernel's module.  The kernel's code may differ (optimised once instead of once a library:
what LLVM unrolls and inlines, the loops' addressing), never its arithmetic: no flag lets
LLVM change a floating-point result (no fast-math, not even ``contract``).  Checked:
``tests/test_numba_linking.py`` (against numba without the change, in another process: no
such flag, the same results, and deferred libraries asked for a pointer made right), and
the engine's outputs of 25 catalog PMs x 2,000 poses on two threads and of 759 arrays of
paths and maps are the same bit for bit as the kernels compiled without the change
(``benchmarks/compare_outputs.py``, ``benchmarks/compare_paths_maps.py``); the batches as
fast (alternated runs).

The kernels' callees (``_jit.inner`` and the others: a library defining a kernel's function
and no wrapper Python or C code calls; :func:`_kernel_callee`) make no machine code either:
numba optimises such a library with everything it calls linked in, then makes its machine
code, which nothing runs (its callers link its module in and make their own), for the
on-disk cache's object code.  The library is optimised as numba does, keeps its module
without machine code, and is cached as that module's bitcode (numba's own ``bitcode`` kind
of cached library, which a later compile links in as it would the object kind's bitcode);
a first run (``screwkit analyze 3RRPRR``, empty cache, one process) took 106-110 s of CPU
against 123-129 s.  numba's machine code changed the module in place (its code-generation
passes) before the callers linked it in, and the code LLVM makes of a caller depends on it:
the parallel kernels, whose speed was measured against that (a 6-SPS batch ran 5 % slower
linking the modules as optimised), are compiled as before: a callee a parallel kernel links
makes its machine code first, and one compiled or loaded while a parallel kernel compiles
is not deferred (``_PARALLEL``, set by a listener of numba's ``numba:compile`` event).  The
serial kernels link the optimised modules: their code differs (not their arithmetic), the
same bits (``compare_outputs.py``), as fast (alternated runs).

Only with the numba releases this was tested with (:data:`._loading.TESTED`) and where
their code libraries and parfor lowering's ``_create_gufunc_for_parfor_body`` are as
expected; once per process, from the first
compilation on (a listener of numba's ``numba:compile`` event, as :mod:`._inlining`).
``SCREWKIT_NUMBA_LINKING=0`` leaves numba alone (a value other than 0/1, no/yes, off/on,
false/true is a one-line error).
"""

from __future__ import annotations

import threading
import weakref

from ._patching import CompilerChange

__all__ = ["enabled", "install", "install_on_first_compile", "installed", "deferred",
           "counts"]

#: ``depth``: the parallel kernels this thread is compiling (their callees are compiled, and
#: those loaded from the cache made, as numba does: see _callee).
_PARALLEL = threading.local()
#: How many libraries of this process had their machine code deferred, and how many of
#: them were then asked for it (made).
_COUNTS = {"deferred": 0, "made": 0}
#: ``{name: environment}``: the environments numba set before any module in its engine
#: defined their global (a deferred library's); set once one does (numba's ``set_env``).
_PENDING_ENVS: dict = {}
#: The names of the libraries whose optimisation and machine code are deferred: the body of
#: a ``prange`` loop (compiled without the Python and C wrappers nothing calls), its gufunc
#: wrapper (``str`` of numba's ``_GufuncWrapper``; a ``guvectorize`` gufunc's wrapper, which
#: numba asks for a pointer at once, gets it at once) and the parallel launcher's wrapper.
_BODY = "__numba_parfor_gufunc_"
_GUFUNC_WRAPPER = "<numba.np.ufunc.wrappers._GufuncWrapper object at "
_LAUNCHER = "parallelgufuncwrapper"
#: The mangled names of screwkit's kernels, and of the wrappers numba makes for a function
#: Python (``cpython.``) or C (``cfunc.``) calls.
_KERNEL = "_ZN8screwkit6engine8_kernels"
_WRAPPERS = ("_ZN7cpython", "cfunc.")


def deferred(library) -> bool:
    """Whether ``library`` (a numba code library) has its machine code still to make."""
    return getattr(library, "_screwkit_deferred", False)


def counts() -> dict:
    """``{"deferred": n, "made": m, "pending_envs": e}``: the libraries of this process
    whose machine code was deferred, those of them that were asked for it since (and got
    it), and the environments still waiting for a module that defines their global."""
    return dict(_COUNTS, pending_envs=len(_PENDING_ENVS))


def _linked_only(library) -> bool:
    name = getattr(library, "name", "")
    return name == _LAUNCHER or name.startswith((_GUFUNC_WRAPPER, _BODY))


def _kernel_callee(library) -> bool:
    """Whether ``library`` is one of screwkit's kernels that only other kernels call: it
    defines a kernel's function and no wrapper Python or C code calls it through
    (``_jit.inner`` and the others are compiled without them)."""
    kernel = False
    for fn in library._final_module.functions:
        if fn.is_declaration:
            continue
        name = fn.name
        if name.startswith(_WRAPPERS):
            return False
        kernel = kernel or name.startswith(_KERNEL)
    return kernel


def _apply() -> bool:
    """Defer the optimisation and machine code of the libraries of numba's ``prange`` loops,
    and the machine code of the kernels' callees, until asked for (module docstring).
    Returns whether it could: False where numba is not as expected (numba left as it
    is)."""
    from ._loading import supported
    if not supported():           # (numba's internals as in the releases tested)
        return False
    try:
        from numba.core import codegen, config
        from numba.parfors import parfor_lowering
        library_class, jit_codegen = codegen.JITCodeLibrary, codegen.JITCPUCodegen
        finish = codegen.CPUCodeLibrary._finalize_final_module
        optimise = codegen.CPUCodeLibrary._optimize_final_module
        link_module = codegen.CPUCodeLibrary._get_module_for_linking
        steps = (codegen.CPUCodeLibrary._finalize_dynamic_globals,
                 codegen.CPUCodeLibrary._verify_declare_only_symbols)
        pointer = library_class.get_pointer_to_function
        serialise = library_class.serialize_using_object_code
        compiled_object = library_class._get_compiled_object
        specific = library_class._finalize_specific
        set_env = jit_codegen.set_env
        body = parfor_lowering._create_gufunc_for_parfor_body
    except (ImportError, AttributeError):
        return False
    if not all(callable(f) for f in (finish, optimise, link_module, *steps, pointer,
                                     serialise, compiled_object, specific, set_env,
                                     body)):
        return False
    mangled = "_CPUCodeLibrary__library"       # numba's ``module.__library``

    def _callee(self):
        # (once a library: its functions are those it was finalised with; none while a
        # parallel kernel compiles, see _PARALLEL)
        verdict = self.__dict__.get("_screwkit_callee")
        if verdict is None:
            verdict = self._screwkit_callee = (
                isinstance(self, library_class) and not getattr(_PARALLEL, "depth", 0)
                and _kernel_callee(self))
        return verdict

    def _deferring(self):
        if config.DUMP_OPTIMIZED or config.DUMP_ASSEMBLY:
            return False
        return (type(self) is library_class and _linked_only(self)) or _callee(self)

    def _optimize_final_module(self):
        if not (_deferring(self) and _linked_only(self)):
            # (a kernel's callee is optimised as numba does: its callers link it in so)
            return optimise(self)
        # the module stays as linked (its functions optimised one by one); the kernel
        # linking it in optimises it with all the rest
        self._screwkit_unoptimised = True
        return None

    def _finalize_final_module(self):
        if not _deferring(self):
            return finish(self)
        # numba's steps up to the engine (finalize() linked the module in before): the
        # symbols checked and the module kept as it is
        self._finalize_dynamic_globals()
        self._verify_declare_only_symbols()
        setattr(self._final_module, mangled, weakref.proxy(self))
        self._screwkit_deferred = True
        self._finalized = True
        _COUNTS["deferred"] += 1

    def _make_machine_code(self):
        # the rest of numba's finalize, once, when first needed
        if self.__dict__.pop("_screwkit_deferred", False):
            if self.__dict__.pop("_screwkit_unoptimised", False):
                optimise(self)
            cleanup = self._codegen._add_module(self._final_module)
            if cleanup:
                weakref.finalize(self, cleanup)
            self._finalize_specific()
            _COUNTS["made"] += 1

    def _defines(self, name):
        try:
            return not self._final_module.get_function(name).is_declaration
        except NameError:
            return False

    def get_pointer_to_function(self, name):
        self._ensure_finalized()
        # a name the library does not define (a function compiled without its Python
        # wrapper is asked for it all the same: null) needs none of its machine code
        if deferred(self) and _defines(self, name):
            _make_machine_code(self)
        return pointer(self, name)

    def _get_module_for_linking(self):
        if getattr(_PARALLEL, "depth", 0) and deferred(self) and _callee(self):
            # a parallel kernel links its callees as numba hands them on, after their
            # machine code (whose passes change the module in place: the code LLVM
            # makes of the kernel depends on it; a 6-SPS batch ran 5 % slower without)
            _make_machine_code(self)
            self._shared_module = None
        return link_module(self)

    def serialize_using_object_code(self):
        self._ensure_finalized()
        if deferred(self) and _callee(self):
            # a kernel's callee is cached as its optimised module's bitcode, all its
            # callers link in (numba's own kind for it; its machine code never runs)
            return (self.name, "bitcode", self._final_module.as_bitcode())
        _make_machine_code(self)
        return serialise(self)

    def _get_compiled_object(self):
        _make_machine_code(self)
        return compiled_object(self)

    def _finalize_specific(self):
        specific(self)
        # environments numba set while no module of the engine defined their global
        # (a deferred library's): set where the engine now finds one
        engine = self._codegen._engine
        for name in [n for n in _PENDING_ENVS if engine.is_symbol_defined(n)]:
            set_env(self._codegen, name, _PENDING_ENVS.pop(name))

    def _set_env(self, env_name, env):
        if self._engine.is_symbol_defined(env_name):
            return set_env(self, env_name, env)
        _PENDING_ENVS[env_name] = env
        return None

    def _create_gufunc_for_parfor_body(lowerer, parfor, typemap, typingctx, targetctx,
                                       flags, *args, **kwargs):
        # the loop's body is called by its gufunc wrapper alone: no Python or C wrapper
        # (numba would ask for a pointer to the Python one, and so for machine code)
        flags = flags.copy()
        flags.no_cpython_wrapper = True
        flags.no_cfunc_wrapper = True
        return body(lowerer, parfor, typemap, typingctx, targetctx, flags, *args,
                    **kwargs)

    for new, old in ((get_pointer_to_function, pointer),
                     (serialize_using_object_code, serialise),
                     (_get_compiled_object, compiled_object),
                     (_finalize_specific, specific), (_set_env, set_env),
                     (_create_gufunc_for_parfor_body, body)):
        new.__doc__ = old.__doc__
        new.__wrapped__ = old
    from numba.core import event

    class _ParallelCompiles(event.Listener):
        def on_start(self, ev):
            if ev.data["dispatcher"].targetoptions.get("parallel"):
                _PARALLEL.depth = getattr(_PARALLEL, "depth", 0) + 1

        def on_end(self, ev):
            if ev.data["dispatcher"].targetoptions.get("parallel"):
                _PARALLEL.depth -= 1

    event.register("numba:compile", _ParallelCompiles())
    codegen.CPUCodeLibrary._finalize_final_module = _finalize_final_module
    codegen.CPUCodeLibrary._optimize_final_module = _optimize_final_module
    codegen.CPUCodeLibrary._get_module_for_linking = _get_module_for_linking
    library_class.get_pointer_to_function = get_pointer_to_function
    library_class.serialize_using_object_code = serialize_using_object_code
    library_class._get_compiled_object = _get_compiled_object
    library_class._finalize_specific = _finalize_specific
    jit_codegen.set_env = _set_env
    parfor_lowering._create_gufunc_for_parfor_body = _create_gufunc_for_parfor_body
    return True


#: The change to numba's libraries (:class:`._patching.CompilerChange`): ``enabled()``
#: (``SCREWKIT_NUMBA_LINKING``, unset: on), ``install()`` (:func:`_apply` once), ``installed()``,
#: ``install_on_first_compile()``.
_CHANGE = CompilerChange("SCREWKIT_NUMBA_LINKING", _apply)
enabled, install, installed = _CHANGE.enabled, _CHANGE.install, _CHANGE.installed
install_on_first_compile = _CHANGE.install_on_first_compile
