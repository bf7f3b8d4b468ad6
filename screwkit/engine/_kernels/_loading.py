"""Loading the cached kernels quickly (private; numba is imported by the caller).

A cold command loads one cached kernel per entry point it calls.  numba's own loading does
two things that the execution of cached machine code does not need, and that cost most of
a cold command's time after the imports:

* before every lookup, ``Cache.load_overload`` refreshes the target context: it imports and
  installs every typing and lowering registry (``numpy.linalg`` support imports
  scipy.linalg), which only the compilation of new code reads;
* each cached library holds, beside its object code, the LLVM bitcode of its functions for
  linking them into code compiled later; loading parses that bitcode (most of a load) to
  list the symbols the object defines;
* it rebuilds the environment (the module globals) of every function in the object,
  importing that function's module: numba's own array implementations (``np.empty``,
  ``np.zeros`` inlined into the kernels) make it import ``numba.np.arrayobj`` and with it
  most of numba's lowering (about 0.1 s), for globals that compiled nopython code never
  reads (only object mode and the Python wrapper of an entry point, whose module is the
  kernel's own, look globals up).

The kernels' dispatchers get a cache (:func:`install`) that loads a cached kernel after
initialising numba's runtime only (``rtsys.initialize``: the symbols the object code links
to; the parallel kernels start their threading layer by their own reload hooks), into a
library that parses its bitcode on first use for linking (never, unless new code is
compiled against it), and reads the names of the symbols from a list kept beside the
kernels (``symbols/<sha1 of the bitcode>``, a function of those bytes alone: written when the
kernel is cached, from the module in memory the bitcode was written from, else once from the
parsed bitcode by the first process that loads it), and with the environment of a function of a numba module not yet
imported built on that module's name alone (not kept in numba's table of environments, so
that code compiled later gets the real one).  A lookup that misses refreshes the registries as numba does, and
numba compiles as usual (its compiler refreshes too).  Other numba users in the process are
untouched; with a numba whose internals differ, nothing changes.
"""

from __future__ import annotations

import hashlib
import os
import sys

__all__ = ["install", "supported"]

#: The numba releases whose cache internals this module was written against and tested
#: with (major, minor); with any other, numba loads its cache itself (slower, as correct).
TESTED = ((0, 68),)


def supported(version: str | None = None) -> bool:
    """Whether the quick loading applies to numba ``version`` (default: the installed one)."""
    if version is None:
        import numba
        version = numba.__version__
    try:
        major, minor = (int(x) for x in version.split(".")[:2])
    except ValueError:
        return False
    return (major, minor) in TESTED

_MAX_SYMBOL_FILES = 1024


def _names_of(module) -> set:
    """The symbols ``module`` defines (numba's ``_load_defined_symbols``)."""
    return {gv.name for group in (module.functions, module.global_variables)
            for gv in group if not gv.is_declaration}


def _symbols(folder, bitcode, ll):
    """``(names, module or None)``: the symbols the bitcode defines, from the kept list, or
    parsed (the module then returned, and the list kept)."""
    digest = hashlib.sha1(bitcode).hexdigest()
    path = os.path.join(folder, digest)
    try:
        with open(path, encoding="utf-8") as f:
            text = f.read()
        if text.endswith("\n#end\n"):
            return set(text[:-len("#end\n")].splitlines()), None
    except OSError:
        pass
    module = ll.parse_bitcode(bitcode)
    names = _names_of(module)
    _keep(folder, digest, names)
    return names, module


def _keep(folder, digest, names) -> None:
    """Keep ``names`` as the symbol list of the bitcode of sha1 ``digest``."""
    if any("\n" in n for n in names):                  # not one name a line: not kept
        return
    try:
        from ...pm._catalog_cache import keep_file
        keep_file(folder, digest, ("".join(n + "\n" for n in sorted(names)) + "#end\n")
                  .encode("utf-8"), _MAX_SYMBOL_FILES)
    except OSError:
        pass


def _keep_saved(folder, library, reduced) -> None:
    """The symbol list of a library numba has just cached (``reduced``, its
    ``CompileResult._reduce``; its first element the library's state ``(name, "object",
    (object code, bitcode))``), from the module in memory the bitcode was written from: the
    first process that loads the kernel does not parse the bitcode for it (for the parallel
    analysis kernel some seconds and 0.9 GB of peak memory, once)."""
    try:
        name, kind, (_, bitcode) = reduced[0]
        module = library._get_module_for_linking()      # (made by the save: kept there)
    except Exception:                                   # (another numba: the load parses)
        return
    if kind == "object" and isinstance(bitcode, bytes):
        _keep(folder, hashlib.sha1(bitcode).hexdigest(), _names_of(module))


def install(dispatchers, symbol_folder: str) -> None:
    """Give ``dispatchers`` (numba's, with ``cache=True``) the quick cache loading (only
    for the numba releases it was tested with: :data:`TESTED`)."""
    if not supported():
        return
    try:
        from llvmlite import binding as ll
        from numba.core import environment
        from numba.core.caching import FunctionCache
        from numba.core.codegen import JITCodeLibrary
        from numba.core.runtime import rtsys
    except ImportError:
        return
    if not all(hasattr(environment, a) for a in ("_rebuild_env", "lookup_environment",
                                                  "Environment")):
        return
    if not (all(hasattr(FunctionCache, a) for a in ("_load_overload", "_save_overload",
                                                    "_guard_against_spurious_io_errors"))
            and all(hasattr(JITCodeLibrary, a) for a in ("_unserialize", "_set_compiled_object",
                                                         "_finalize_final_module"))):
        return

    class _LazyLinkLibrary(JITCodeLibrary):
        """A cached library whose bitcode for linking is parsed on first use."""

        _bitcode = None
        _shared = None

        @property
        def _shared_module(self):
            if self._shared is None and self._bitcode is not None:
                self._shared = ll.parse_bitcode(self._bitcode)
                self._bitcode = None
            return self._shared

        @_shared_module.setter
        def _shared_module(self, value):
            self._shared = value

        @classmethod
        def _unserialize(cls, codegen, state):
            name, kind, data = state
            engine = getattr(codegen, "_engine", None)
            if kind != "object" or not hasattr(engine, "_defined_symbols"):
                return JITCodeLibrary._unserialize.__func__(cls, codegen, state)
            object_code, bitcode = data
            names, module = _symbols(symbol_folder, bitcode, ll)
            self = cls(codegen, name)
            self.enable_object_caching()
            self._set_compiled_object(object_code)
            if module is None:
                self._bitcode = bitcode
            else:
                self._shared = module
            self._finalize_final_module()
            engine._defined_symbols |= names
            return self

    rebuild_env = environment._rebuild_env

    def _env_unimported(modname, consts, env_name):
        """numba's ``_rebuild_env``, without importing a numba module for its globals."""
        env = environment.lookup_environment(env_name)
        if env is None and modname not in sys.modules and modname.startswith("numba."):
            env = environment.Environment({"__name__": modname})
            env.consts[:] = consts
            env.env_name = env_name
            return env
        return rebuild_env(modname, consts, env_name)

    class _QuickCache(FunctionCache):
        def load_overload(self, sig, target_context):
            rtsys.initialize(target_context)
            codegen = target_context.codegen()
            had = codegen.__dict__.get("_library_class")
            codegen._library_class = _LazyLinkLibrary   # under numba's compiler lock
            environment._rebuild_env = _env_unimported  # (pickle looks it up by name)
            try:
                with self._guard_against_spurious_io_errors():
                    data = self._load_overload(sig, target_context)
            finally:
                environment._rebuild_env = rebuild_env
                if had is None:
                    del codegen._library_class
                else:
                    codegen._library_class = had
            if data is None:
                target_context.refresh()
            return data

        def _save_overload(self, sig, data):
            # numba's save, the reduced data it writes kept, for the library's symbol list
            impl, kept = self._impl, []
            reduce = impl.reduce

            def reducing(cres):
                out = reduce(cres)
                kept.append(out)
                return out

            impl.reduce = reducing
            try:
                super()._save_overload(sig, data)
            finally:
                del impl.reduce
            if kept and getattr(data, "library", None) is not None:
                _keep_saved(symbol_folder, data.library, kept[0])

    def quick(d):
        if type(getattr(d, "_cache", None)) is FunctionCache:
            d._cache.__class__ = _QuickCache

    from ._jit import when_made
    for d in dispatchers:           # (a deferred dispatcher when numba's state is made)
        when_made(d, quick)
