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

import threading

from ._patching import first_compile_installer, switched

__all__ = ["enabled", "install", "install_on_first_compile", "installed"]

_LOCK = threading.Lock()
_INSTALLED = False
#: ``{config class: hash}``: numba's hash of a config depends on its class alone.
_HASHES: dict = {}


#: Whether ``SCREWKIT_NUMBA_FLAGS`` (unset: on) lets :func:`install` change numba.
enabled = switched("SCREWKIT_NUMBA_FLAGS")


def installed() -> bool:
    """Whether :func:`install` changed numba's flags in this process."""
    return _INSTALLED


def install() -> bool:
    """Compare and hash numba's configs without building their dicts (module docstring).
    Returns whether the change is (now or before) in place: False where numba's
    ``TargetConfig`` is not as expected or ``SCREWKIT_NUMBA_FLAGS=0``."""
    global _INSTALLED
    if not enabled():
        return _INSTALLED
    with _LOCK:
        if _INSTALLED:
            return True
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
        _INSTALLED = True
        return True


#: :func:`install` at the first compile of the process (:mod:`._patching`).
install_on_first_compile = first_compile_installer(install, installed, enabled)
