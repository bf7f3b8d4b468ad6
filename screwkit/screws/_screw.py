"""Twist and wrench value types (6-vectors ``[v; w]`` and ``[f; m]`` about the base origin) and
the unit screws of joints, forces and couples.

See :mod:`screwkit.screws._primitives` for the conventions.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
from numpy.typing import ArrayLike

from ..errors import InputError
from ._line import Line
from ._primitives import (_as_screw6, as_vector3, reciprocal_product, screw_axis_point, screw_pitch,
                          transform_twists, transform_wrenches, unit)
from ._vector import cross

__all__ = ["Twist", "Wrench", "revolute_twist", "prismatic_twist", "helical_twist", "force_wrench",
           "couple_wrench"]


class _Screw:
    """Shared behaviour of :class:`Twist` and :class:`Wrench` (6-vector, linear part first)."""

    vector: np.ndarray
    _kind = "screw"

    def __post_init__(self):
        v = _as_screw6(self.vector, self._kind)
        if v.shape != (6,):
            raise InputError(f"a {self._kind} is one 6-vector, got shape {v.shape}")
        v = v.astype(float).copy()
        v.setflags(write=False)
        object.__setattr__(self, "vector", v)

    @property
    def linear(self) -> np.ndarray:
        return self.vector[:3]

    @property
    def angular(self) -> np.ndarray:
        return self.vector[3:]

    def __array__(self, dtype=None, copy=None):
        return np.asarray(self.vector, dtype=dtype)

    def __eq__(self, other):
        return type(self) is type(other) and np.array_equal(self.vector, other.vector)

    def __hash__(self):
        return hash((type(self).__name__, self.vector.tobytes()))


@dataclass(frozen=True, eq=False)
class Twist(_Screw):
    """A twist ``[v; w]`` about the base origin (see module conventions).

    Parameters
    ----------
    vector : array_like, shape (6,)
    """

    vector: np.ndarray
    _kind = "twist"

    @property
    def v(self) -> np.ndarray:
        """Velocity of the body point at the origin."""
        return self.vector[:3]

    @property
    def omega(self) -> np.ndarray:
        """Angular velocity."""
        return self.vector[3:]

    @property
    def pitch(self) -> float:
        """``v.w / w.w``; ``inf`` for a pure translation."""
        return float(screw_pitch(self.vector, "twist"))

    @property
    def axis(self) -> Line | None:
        """The screw axis (None for a pure translation or the zero twist)."""
        if np.linalg.norm(self.omega) == 0:
            return None
        return Line.through(screw_axis_point(self.vector, "twist"), self.omega)

    def transformed(self, rotation: ArrayLike, translation: ArrayLike) -> "Twist":
        """This twist expressed in frame {a} when ``x_a = R x_b + p`` (self in {b})."""
        return Twist(transform_twists(rotation, translation, self.vector))

    def reciprocal(self, wrench: "Wrench") -> float:
        """Reciprocal product with a wrench."""
        return float(reciprocal_product(_other(wrench, Wrench, self).vector, self.vector))

    def __repr__(self) -> str:
        return f"Twist({np.round(self.vector, 9).tolist()})"


@dataclass(frozen=True, eq=False)
class Wrench(_Screw):
    """A wrench ``[f; m]`` with the moment taken about the base origin.

    Parameters
    ----------
    vector : array_like, shape (6,)
    """

    vector: np.ndarray
    _kind = "wrench"

    @property
    def force(self) -> np.ndarray:
        return self.vector[:3]

    @property
    def moment(self) -> np.ndarray:
        return self.vector[3:]

    @property
    def pitch(self) -> float:
        """``f.m / f.f``; ``inf`` for a pure couple."""
        return float(screw_pitch(self.vector, "wrench"))

    @property
    def axis(self) -> Line | None:
        """Line of action (None for a pure couple or the zero wrench)."""
        if np.linalg.norm(self.force) == 0:
            return None
        return Line.through(screw_axis_point(self.vector, "wrench"), self.force)

    def moment_about(self, point: ArrayLike) -> np.ndarray:
        """Moment of the wrench about ``point``: ``m - point x f``."""
        return self.moment - cross(as_vector3(point, "point"), self.force)

    def transformed(self, rotation: ArrayLike, translation: ArrayLike) -> "Wrench":
        """This wrench expressed in frame {a} when ``x_a = R x_b + p`` (self in {b})."""
        return Wrench(transform_wrenches(rotation, translation, self.vector))

    def reciprocal(self, twist: Twist) -> float:
        """Reciprocal product (virtual power) with a twist."""
        return float(reciprocal_product(self.vector, _other(twist, Twist, self).vector))

    def __repr__(self) -> str:
        return f"Wrench({np.round(self.vector, 9).tolist()})"


def _other(x, kind, own):
    """``x`` when it is a ``kind``: the reciprocal product pairs a twist with a wrench."""
    if not isinstance(x, kind):
        from ..errors import MisuseError
        raise MisuseError(f"the reciprocal product of a {type(own).__name__} is taken with a "
                          f"{kind.__name__}, got {type(x).__name__}")
    return x


# ---------------------------------------------------------------------------
# constructors
# ---------------------------------------------------------------------------

def revolute_twist(direction: ArrayLike, point: ArrayLike) -> Twist:
    """Unit twist of a revolute joint: ``[p x u; u]`` (``v = w x (O - p)``)."""
    u = unit(direction, "revolute axis")
    p = as_vector3(point, "revolute point")
    return Twist(np.concatenate([cross(p, u), u]))


def prismatic_twist(direction: ArrayLike) -> Twist:
    """Unit twist of a prismatic joint: ``[u; 0]``."""
    u = unit(direction, "prismatic direction")
    return Twist(np.concatenate([u, np.zeros(3)]))


def helical_twist(direction: ArrayLike, point: ArrayLike, pitch: float) -> Twist:
    """Unit twist of a helical joint of ``pitch`` (length per radian): ``[p x u + h u; u]``."""
    u = unit(direction, "helical axis")
    p = as_vector3(point, "helical point")
    h = float(pitch)
    if not np.isfinite(h):
        raise InputError("helical pitch must be finite")
    return Twist(np.concatenate([cross(p, u) + h * u, u]))


def force_wrench(direction: ArrayLike, point: ArrayLike, magnitude: float = 1.0) -> Wrench:
    """A pure force of ``magnitude`` along ``direction`` through ``point``: ``[f; p x f]``."""
    f = float(magnitude) * unit(direction, "force direction")
    p = as_vector3(point, "force point")
    return Wrench(np.concatenate([f, cross(p, f)]))


def couple_wrench(direction: ArrayLike, magnitude: float = 1.0) -> Wrench:
    """A pure couple of ``magnitude`` about ``direction``: ``[0; t]``."""
    t = float(magnitude) * unit(direction, "couple direction")
    return Wrench(np.concatenate([np.zeros(3), t]))
