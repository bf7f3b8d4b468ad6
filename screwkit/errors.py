"""Exception hierarchy of screwkit.

Every error screwkit raises on bad input or an impossible request is a
:class:`ScrewkitError`; the CLI prints its message on one line and exits
non-zero.  The subclasses say *what kind* of thing went wrong, the message
says *what* and *where*.
"""

from __future__ import annotations

__all__ = [
    "ScrewkitError",
    "PoseIndexError",
    "ParseError",
    "CatalogError",
    "GeometryError",
    "SingularityError",
    "UnreachablePoseError",
    "InputError",
    "MisuseError",
]


class ScrewkitError(Exception):
    """Base class of every error screwkit raises on purpose."""


class InputError(ScrewkitError, ValueError):
    """A value given by the user is not acceptable (NaN, wrong shape, unknown name)."""


class PoseIndexError(InputError, IndexError):
    """A pose index that does not fit a batch (out of range, of no pose, of two axes): an
    :class:`InputError` and an ``IndexError``, as numpy's ``AxisError`` is both."""


class MisuseError(ScrewkitError, TypeError):
    """An operation a value does not support: writing a constant (a model's poses), indexing
    a one-pose result, a one-pose member read on a batch (also a ``TypeError``)."""


class ParseError(ScrewkitError, ValueError):
    """A leg or PM string cannot be parsed.

    Attributes
    ----------
    text : str
        The string that was parsed.
    position : int or None
        0-based index of the offending character, or None for whole-string errors.
    """

    def __init__(self, message: str, text: str = "", position: int | None = None) -> None:
        self.text = text
        self.position = position
        if position is not None:
            message = f"{message} at position {position} of {text!r}"
        super().__init__(message)


class CatalogError(ScrewkitError, ValueError):
    """The catalog (or a user model) is malformed: names the entry and field at fault."""

    def __init__(self, message: str, entry: str | None = None, field: str | None = None,
                 source: str | None = None, line: int | None = None) -> None:
        self.entry, self.field, self.source, self.line = entry, field, source, line
        self.detail = message                  # the message without the location
        where = []
        if source:
            where.append(str(source))
        if line:
            where.append(f"line {line}")
        if entry:
            where.append(f"entry {entry!r}")
        if field:
            where.append(f"field {field!r}")
        if where:
            message = f"{', '.join(where)}: {message}"
        super().__init__(message)


class GeometryError(ScrewkitError, ValueError):
    """A geometric construction is impossible or degenerate (parallel vectors to cross, ...)."""


class SingularityError(ScrewkitError, ArithmeticError):
    """A Jacobian is singular at the requested pose.

    Attributes
    ----------
    kind : str
        ``"actuation"``, ``"constraint"`` or ``"representation"``.
    condition_number : float
    """

    def __init__(self, message: str, kind: str = "", condition_number: float = float("inf")) -> None:
        self.kind = kind
        self.condition_number = condition_number
        super().__init__(message)


class UnreachablePoseError(ScrewkitError, ArithmeticError):
    """The loop closures cannot be satisfied at the requested pose.

    Attributes
    ----------
    residual : float
        Length-normalised closure residual reached by the solver.
    """

    def __init__(self, message: str, residual: float = float("nan")) -> None:
        self.residual = residual
        super().__init__(message)
