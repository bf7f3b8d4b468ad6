"""Read-only views of the arrays a value or a result holds (private).

A frozen dataclass cannot be rebound, but its arrays could be written in place, and what
it says afterwards would not be what it computed: the values and results hand out read-only
views of their arrays (views, so that whoever made the buffer keeps writing it).
"""

from __future__ import annotations

import numpy as np

__all__ = ["freeze_fields", "read_only"]


def read_only(a):
    """A read-only view of the array ``a`` (anything else as it is)."""
    if isinstance(a, np.ndarray) and a.flags.writeable:
        a = a.view()
        a.setflags(write=False)
    return a


def freeze_fields(obj, names) -> None:
    """The array fields ``names`` of the (frozen) dataclass ``obj`` made read-only views."""
    for name in names:
        value = getattr(obj, name)
        if isinstance(value, np.ndarray) and value.flags.writeable:
            object.__setattr__(obj, name, read_only(value))
