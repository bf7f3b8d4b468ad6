"""Directed lines in Plücker coordinates (the axes of joints and the lines of forces)."""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
from numpy.typing import ArrayLike

from ._primitives import as_rotation, as_vector3, unit
from ._vector import cross

__all__ = ["Line"]


@dataclass(frozen=True)
class Line:
    """A directed line in Plücker coordinates: unit direction ``d`` and moment ``p x d``.

    Parameters
    ----------
    direction : array_like, shape (3,)
        Normalised on construction.
    moment : array_like, shape (3,)
        ``p x d`` for any point ``p`` of the line; its component along ``d``
        is removed so that the pair satisfies the Plücker condition.
    """

    direction: np.ndarray
    moment: np.ndarray

    def __post_init__(self):
        d = unit(self.direction, "line direction")
        m = as_vector3(self.moment, "line moment")
        m = m - np.dot(m, d) * d
        d.setflags(write=False)
        m.setflags(write=False)
        object.__setattr__(self, "direction", d)
        object.__setattr__(self, "moment", m)

    @classmethod
    def through(cls, point, direction) -> "Line":
        """The line through ``point`` with ``direction``."""
        p = as_vector3(point, "point")
        d = unit(direction)
        return cls(d, cross(p, d))

    @classmethod
    def joining(cls, p, q) -> "Line":
        """The line from point ``p`` to point ``q``."""
        p = as_vector3(p, "point")
        return cls.through(p, as_vector3(q, "point") - p)

    @property
    def point(self) -> np.ndarray:
        """The point of the line closest to the origin."""
        return cross(self.direction, self.moment)

    def distance_to_point(self, x: ArrayLike) -> float:
        """Distance from point ``x`` to the line."""
        x = as_vector3(x, "point")
        return float(np.linalg.norm(cross(x - self.point, self.direction)))

    def contains(self, x: ArrayLike, atol: float) -> bool:
        """True when ``x`` lies on the line within absolute distance ``atol``."""
        return self.distance_to_point(x) <= atol

    def is_parallel(self, other: "Line", rtol: float = 1e-7) -> bool:
        """True when the directions are parallel or antiparallel (``|d1 x d2| <= rtol``)."""
        other = _line(other)
        return float(np.linalg.norm(cross(self.direction, other.direction))) <= rtol

    def distance_to_line(self, other: "Line") -> float:
        """Shortest distance between two lines."""
        other = _line(other)
        c = cross(self.direction, other.direction)
        n = float(np.linalg.norm(c))
        if n < 1e-12:
            return other.distance_to_point(self.point)
        return abs(float(np.dot(self.direction, other.moment) + np.dot(other.direction, self.moment))) / n

    def closest_points(self, other: "Line") -> tuple[np.ndarray, np.ndarray]:
        """Closest points ``(x1 on self, x2 on other)``; for parallel lines ``x1`` is ``self.point``."""
        other = _line(other)
        p1, d1 = self.point, self.direction
        p2, d2 = other.point, other.direction
        c = cross(d1, d2)
        n2 = float(np.dot(c, c))
        if n2 < 1e-24:
            x1 = p1
            x2 = p2 + np.dot(p1 - p2, d2) * d2
            return x1, x2
        t1 = np.dot(cross(p2 - p1, d2), c) / n2
        t2 = np.dot(cross(p2 - p1, d1), c) / n2
        return p1 + t1 * d1, p2 + t2 * d2

    def transformed(self, rotation: ArrayLike, translation: ArrayLike) -> "Line":
        """The line moved by ``x -> R x + p``."""
        R = as_rotation(rotation)
        return Line.through(R @ self.point + as_vector3(translation, "translation"), R @ self.direction)

    def __repr__(self) -> str:
        p = np.round(self.point, 6).tolist()
        d = np.round(self.direction, 6).tolist()
        return f"Line(point={p}, direction={d})"


def _line(x):
    """``x`` when it is a :class:`Line`, else a MisuseError."""
    if not isinstance(x, Line):
        from ..errors import MisuseError
        raise MisuseError(f"expected a Line, got {type(x).__name__}")
    return x
