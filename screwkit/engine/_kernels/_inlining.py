"""numba's IR inlining without its quadratic copies of a callee's scope (private).

The kernels type many functions into their callers (``_jit.inlined``: numba's
``inline="always"``).  For every such call numba copies the callee's IR twice
(``numba.core.inline_closurecall.InlineWorker.inline_ir``), one ``copy.deepcopy`` call a
block.  All blocks of a function share one scope, which holds every variable of the
function, so each block's copy copies that whole scope again: the work grows with the
blocks times the variables.  A first run (``screwkit analyze 3RRPRR`` with an empty cache,
on one process) spent 25.7 s of its 105 s there, in 71 inlined calls; the pose kernel's
template rows alone 10 of their 12 s.

:func:`install` makes the blocks of one IR share their copies: the blocks copied in one
call of ``inline_ir`` whose source blocks share a scope are copied with one ``deepcopy``
memo, so that the scope and its variables are copied once, and the copied blocks share one
scope, as the blocks they copy do.  The second copy ``inline_ir`` makes (of the first) has
its own scope, so its own memo: the two copies stay independent, as before.  numba renames
the copy's variables from that one scope, as it did from the first block's copy (the
others were equal to it), so the inlined code is the same.  Measured (this change, the
same minutes): a first run on one process 75-78 s of CPU against 99-105 s; on two
processes 43-57 s of wall time against 57-67 s.

The change is made to numba's module as loaded (its ``copy`` name, and
``InlineWorker.inline_ir`` to delimit one call's copies), once per process, only where
that module is as this was written against (``copy`` is the standard module and
``inline_ir`` is defined), else nothing is changed and numba copies as it does.  Any
other numba code of the process that inlines gets the same copies, faster.  It is made
when numba starts its first compilation of the process (:func:`install_on_first_compile`,
a listener of numba's ``numba:compile`` event, which a kernel loaded from the cache does
not raise): importing numba's inliner costs 0.13 s, which a command that only loads
cached kernels does not pay.  Set ``SCREWKIT_NUMBA_INLINING=0`` to leave numba as it is (a
value other than 0/1, no/yes, off/on, false/true is a one-line error).
"""

from __future__ import annotations

import copy
import threading

from ._patching import CompilerChange

__all__ = ["enabled", "install", "install_on_first_compile", "installed"]

#: The memos of the running ``inline_ir`` call of this thread (``{id(scope): memo}``), or
#: None outside one.
_STATE = threading.local()


class _SharedScopeCopies:
    """Stands in for the ``copy`` module inside ``numba.core.inline_closurecall``: its
    ``deepcopy`` of an IR block, within a call of ``inline_ir``, uses one memo for all
    blocks of the same scope; every other use is the standard module's."""

    def __init__(self, block_type):
        self._block = block_type

    def __getattr__(self, name):
        return getattr(copy, name)

    def deepcopy(self, x, memo=None, *args):
        memos = getattr(_STATE, "memos", None)
        if memo is None and not args and memos is not None and isinstance(x, self._block):
            memo = memos.setdefault(id(x.scope), {})
        return copy.deepcopy(x, memo, *args)


def _apply() -> bool:
    """Make numba's IR inlining copy a callee's scope once per copy (module docstring).
    Returns whether it could: False where numba's module is not as expected (numba left as
    it is)."""
    try:
        from numba.core import inline_closurecall as ic, ir
        original = ic.InlineWorker.inline_ir
    except (ImportError, AttributeError):
        return False
    if getattr(ic, "copy", None) is not copy or not callable(original):
        return False

    def inline_ir(self, *args, **kwargs):
        outer = getattr(_STATE, "memos", None)
        _STATE.memos = {}
        try:
            return original(self, *args, **kwargs)
        finally:
            _STATE.memos = outer

    inline_ir.__doc__ = original.__doc__
    inline_ir.__wrapped__ = original
    ic.InlineWorker.inline_ir = inline_ir
    ic.copy = _SharedScopeCopies(ir.Block)
    return True


#: The change to numba's inlining (:class:`._patching.CompilerChange`): ``enabled()``
#: (``SCREWKIT_NUMBA_INLINING``, unset: on), ``install()`` (:func:`_apply` once), ``installed()``,
#: ``install_on_first_compile()``.
_CHANGE = CompilerChange("SCREWKIT_NUMBA_INLINING", _apply)
enabled, install, installed = _CHANGE.enabled, _CHANGE.install, _CHANGE.installed
install_on_first_compile = _CHANGE.install_on_first_compile
