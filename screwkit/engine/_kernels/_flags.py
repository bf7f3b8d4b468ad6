"""numba's compile flags compared option by option, not as two dicts (private).

numba keys its cache of an overloaded function's implementations
(``numba.core.typing.templates._OverloadFunctionTemplate._get_impl``: each call a kernel
makes of a numpy function, an array method, a math function, every time it is typed) by
the argument types and the flags of the compile (a ``numba.core.targetconfig.TargetConfig``).
``TargetConfig.__eq__`` builds the dict of every option's value on both sides (the 22
options of numba's ``Flags``, each read through a property), and its ``__hash__`` (the
hash of the sorted option names, the same for every config of a class) sorts them, at
every lookup: a first run of ``screwkit analyze 3RRPRR`` (empty cache, one process)
compares flags some 450,000 times and hashes them some 100,000 times, about 5 % of its
CPU.

:func:`install` gives ``TargetConfig`` the same comparison made on the options either side
set (an option neither sets is its default on both sides; configs of two classes are
compared as numba does) and the same hash, computed once per class.  Equal and unequal
configs stay what they were (``tests/test_numba_flags.py`` checks both against numba's own
methods on random configs), so the same implementations are found: the kernels' code does
not change.  Measured: a first run on one process 112.4 s of CPU against 118.0 s (the two
in the same minutes), the same output.

Installed when numba starts its first compilation of a process (a listener of numba's
``numba:compile`` event, as :mod:`._inlining`), only where ``TargetConfig`` is as this was
written against (its options a class mapping, its values a dict); any other numba code of
the process compares its flags the same way, faster.  ``SCREWKIT_NUMBA_FLAGS=0`` leaves
numba as it is (a value other than 0/1, no/yes, off/on, false/true is a one-line error).
"""

from __future__ import annotations

from ._patching import CompilerChange

__all__ = ["enabled", "install", "install_on_first_compile", "installed"]

#: ``{config class: hash}``: numba's hash of a config depends on its class alone.
_HASHES: dict = {}


def _apply() -> bool:
    """Compare and hash numba's configs without building their dicts (module docstring).
    Returns whether it could: False where numba's ``TargetConfig`` is not as expected
    (numba left as it is)."""
    try:
        from numba.core.compiler import Flags
        from numba.core.targetconfig import TargetConfig
        equal, hashed = TargetConfig.__eq__, TargetConfig.__hash__
        probe = Flags()
        as_expected = (isinstance(probe._values, dict) and "nrt" in Flags.options
                       and hasattr(Flags.options["nrt"], "default")
                       and probe.values() == {k: o.default
                                              for k, o in Flags.options.items()})
    except (ImportError, AttributeError, TypeError):
        return False
    if not as_expected:
        return False

    def __eq__(self, other):
        if not isinstance(other, TargetConfig):
            return NotImplemented
        if self is other:
            return True
        if type(self) is not type(other):
            return equal(self, other)
        a, b = self._values, other._values
        if a == b:
            return True
        options = type(self).options
        for name in a.keys() | b.keys():
            default = options[name].default
            x, y = a.get(name, default), b.get(name, default)
            # (as a dict's comparison of two values: the same object, else ==)
            if x is not y and not x == y:
                return False
        return True

    def __hash__(self):
        cls = type(self)
        h = _HASHES.get(cls)
        if h is None:
            h = _HASHES[cls] = hashed(self)
        return h

    __eq__.__doc__, __eq__.__wrapped__ = equal.__doc__, equal
    __hash__.__doc__, __hash__.__wrapped__ = hashed.__doc__, hashed
    TargetConfig.__eq__ = __eq__
    TargetConfig.__hash__ = __hash__
    return True


#: The change to numba's flags (:class:`._patching.CompilerChange`): ``enabled()``
#: (``SCREWKIT_NUMBA_FLAGS``, unset: on), ``install()`` (:func:`_apply` once), ``installed()``,
#: ``install_on_first_compile()``.
_CHANGE = CompilerChange("SCREWKIT_NUMBA_FLAGS", _apply)
enabled, install, installed = _CHANGE.enabled, _CHANGE.install, _CHANGE.installed
install_on_first_compile = _CHANGE.install_on_first_compile
