"""What screwkit's changes to numba's compiler share (private): their switches, and their
installation when numba starts its first compilation of a process.

:mod:`._inlining` and :mod:`._linking` change how numba compiles, never what a kernel
computes, and only while it compiles: a command that loads cached kernels never needs
them (nor the numba modules they import).  Each has an environment switch (unset: on) and
is installed by a listener of numba's ``numba:compile`` event, which a kernel loaded from
the cache does not raise.
"""

from __future__ import annotations

import os
import threading

__all__ = ["switch", "switched", "on_first_compile", "CompilerChange"]

_ON, _OFF = ("1", "yes", "on", "true"), ("0", "no", "off", "false")
_LOCK = threading.Lock()
_LISTENING: set = set()


def switch(name: str) -> bool:
    """Whether the environment variable ``name`` (unset: on) is on.  Raises
    :class:`~screwkit.errors.InputError` for a value other than 0/1, no/yes, off/on,
    false/true (any case, spaces around)."""
    value = os.environ.get(name)
    if value is None or value.strip().lower() in _ON:
        return True
    if value.strip().lower() in _OFF:
        return False
    from ...errors import InputError
    raise InputError(f"{name} must be 0 or 1 (no/yes, off/on, false/true), got {value!r}")


def switched(name: str):
    """The ``enabled()`` of a change switched by the environment variable ``name``."""
    def enabled() -> bool:
        return switch(name)
    enabled.__doc__ = (f"Whether ``{name}`` (unset: on) lets :func:`install` change numba. "
                       "Raises :class:`~screwkit.errors.InputError` for a value other than "
                       "0/1, no/yes, off/on, false/true.")
    return enabled


class CompilerChange:
    """One of screwkit's changes to numba's compiler: its environment switch ``name``
    (``enabled()``), its installation once a process (``install()``: under a lock, ``apply()``
    makes the change and returns whether it could, False leaving numba as it was), whether
    it is in place (``installed()``), and its installation at the process's first compile
    (``install_on_first_compile()``, :func:`on_first_compile`)."""

    def __init__(self, name: str, apply):
        self.enabled = switched(name)
        self._apply = apply
        self._lock = threading.Lock()
        self._installed = False

    def installed(self) -> bool:
        """Whether :meth:`install` made the change in this process."""
        return self._installed

    def install(self) -> bool:
        """Make the change, once (later calls return True); where switched off, nothing
        (returns whether it was made before).  Returns whether it is in place."""
        if not self.enabled():
            return self._installed
        with self._lock:
            if not self._installed:
                self._installed = bool(self._apply())
            return self._installed

    def install_on_first_compile(self) -> None:
        """:meth:`install` when numba starts compiling a function in this process (its
        ``numba:compile`` event: a cache miss), before that compilation; nothing before, or
        where switched off."""
        if self.enabled():
            on_first_compile(self.install, self.installed)


def on_first_compile(install, installed) -> None:
    """Call ``install()`` when numba starts compiling a function in this process (its
    ``numba:compile`` event: a cache miss), before that compilation, unless ``installed()``
    by then; one listener for each ``install``, whatever the number of calls."""
    with _LOCK:
        if install in _LISTENING or installed():
            return
        _LISTENING.add(install)
    from numba.core import event

    class _FirstCompile(event.Listener):
        def on_start(self, ev):
            if not installed():
                install()

        def on_end(self, ev):
            pass

    event.register("numba:compile", _FirstCompile())
