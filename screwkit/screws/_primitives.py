"""Screw primitives: lines, twists and wrenches.

Conventions (see ``docs/conventions.md``)
-----------------------------------------
* A twist is ``V = [v; w]``: ``v`` is the velocity of the body point that
  coincides with the base origin ``O``, ``w`` the angular velocity.
* A wrench is ``W = [f; m]``: ``f`` the resultant force, ``m`` its moment about ``O``.
* The reciprocal product is ``W o V = f.v + m.w`` (virtual power), which in this
  ordering is the plain dot product of the two 6-vectors.

These are the paper's and Pinocchio's orders (linear part first).  The batched
helpers work on arrays of shape ``(..., 6)``; the value types wrap one screw.

Examples
--------
>>> import numpy as np
>>> from screwkit.screws import revolute_twist, force_wrench
>>> V = revolute_twist([0, 0, 1], [1, 0, 0])      # R axis along Z through (1, 0, 0)
>>> W = force_wrench([0, 0, 1], [1, 0, 0])        # force on that same line
>>> float(W.reciprocal(V))
0.0
"""

from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np

from ..errors import GeometryError, InputError

__all__ = [
    "Line",
    "Twist",
    "Wrench",
    "as_vector3",
    "unit",
    "revolute_twist",
    "prismatic_twist",
    "helical_twist",
    "force_wrench",
    "couple_wrench",
    "reciprocal_product",
    "transform_twists",
    "transform_wrenches",
    "screw_pitch",
    "screw_axis_point",
]

_EPS = 1e-12


def as_vector3(x, name: str = "vector") -> np.ndarray:
    """Return ``x`` as a finite float array of shape (3,), or raise :class:`InputError`."""
    a = np.asarray(x, dtype=float)
    if a.shape != (3,):
        raise InputError(f"{name} must have 3 components, got shape {a.shape}")
    if not np.all(np.isfinite(a)):
        raise InputError(f"{name} must be finite, got {a.tolist()}")
    return a


def unit(x, name: str = "direction") -> np.ndarray:
    """Normalise a 3-vector; raise :class:`GeometryError` for a zero vector."""
    a = as_vector3(x, name)
    n = float(np.linalg.norm(a))
    if n <= _EPS * max(1.0, float(np.max(np.abs(a)))) or n == 0.0:
        raise GeometryError(f"{name} is the zero vector and has no direction")
    return a / n


def _as_screw6(x, name: str) -> np.ndarray:
    a = np.asarray(x, dtype=float)
    if a.shape[-1:] != (6,):
        raise InputError(f"{name} must have 6 components in its last axis, got shape {a.shape}")
    if not np.all(np.isfinite(a)):
        raise InputError(f"{name} must be finite")
    return a


# ---------------------------------------------------------------------------
# batched helpers on (..., 6) arrays
# ---------------------------------------------------------------------------

def reciprocal_product(wrenches, twists) -> np.ndarray:
    """Reciprocal product ``f.v + m.w`` of wrenches and twists, broadcast over ``...``.

    Parameters
    ----------
    wrenches, twists : array_like, shape (..., 6)

    Returns
    -------
    ndarray, shape (...)
    """
    return np.sum(np.asarray(wrenches, float) * np.asarray(twists, float), axis=-1)


def _rotation_and_translation(rotation, translation):
    R = np.asarray(rotation, dtype=float)
    p = np.asarray(translation, dtype=float)
    if R.shape[-2:] != (3, 3) or p.shape[-1:] != (3,):
        raise InputError("rotation must be (..., 3, 3) and translation (..., 3)")
    return R, p


def transform_twists(rotation, translation, twists) -> np.ndarray:
    """Express twists given in frame {b} in frame {a}, where ``x_a = R x_b + p``.

    The angular part rotates; the reference point moves from the origin of {b}
    to the origin of {a}: ``w' = R w``, ``v' = R v + p x (R w)``.

    Parameters
    ----------
    rotation : array_like, shape (..., 3, 3)
    translation : array_like, shape (..., 3)
    twists : array_like, shape (..., 6)
    """
    R, p = _rotation_and_translation(rotation, translation)
    V = np.asarray(twists, float)
    w = np.einsum("...ij,...j->...i", R, V[..., 3:])
    v = np.einsum("...ij,...j->...i", R, V[..., :3]) + np.cross(p, w)
    return np.concatenate([v, w], axis=-1)


def transform_wrenches(rotation, translation, wrenches) -> np.ndarray:
    """Express wrenches given in frame {b} in frame {a}, where ``x_a = R x_b + p``.

    ``f' = R f``, ``m' = R m + p x (R f)``.  Reciprocal products are invariant:
    ``transform_wrenches(R, p, W) . transform_twists(R, p, V) == W . V``.
    """
    R, p = _rotation_and_translation(rotation, translation)
    W = np.asarray(wrenches, float)
    f = np.einsum("...ij,...j->...i", R, W[..., :3])
    m = np.einsum("...ij,...j->...i", R, W[..., 3:]) + np.cross(p, f)
    return np.concatenate([f, m], axis=-1)


def screw_pitch(screws, kind: str = "twist") -> np.ndarray:
    """Pitch of twists (``v.w / w.w``) or wrenches (``f.m / f.f``); ``inf`` for pure
    translations or pure couples.

    Parameters
    ----------
    screws : array_like, shape (..., 6)
    kind : {"twist", "wrench"}
    """
    S = np.asarray(screws, float)
    lin, ang = S[..., :3], S[..., 3:]
    prim = ang if kind == "twist" else lin
    sec = lin if kind == "twist" else ang
    den = np.sum(prim * prim, axis=-1)
    num = np.sum(prim * sec, axis=-1)
    with np.errstate(divide="ignore", invalid="ignore"):
        return np.where(den > 0, num / np.where(den > 0, den, 1.0), np.inf)


def screw_axis_point(screws, kind: str = "twist") -> np.ndarray:
    """Point of the screw axis closest to the origin, shape (..., 3) (NaN for infinite pitch).

    For a twist the axis direction is ``w`` and the point is ``w x v / |w|^2``;
    for a wrench the direction is ``f`` and the point is ``f x m / |f|^2``.
    """
    S = np.asarray(screws, float)
    lin, ang = S[..., :3], S[..., 3:]
    d, sec = (ang, lin) if kind == "twist" else (lin, ang)
    if kind == "twist":
        # v = p x w + h w  ->  p = w x v / |w|^2
        num = np.cross(d, sec)
    else:
        # m = p x f + h f  ->  p = f x m / |f|^2
        num = np.cross(d, sec)
    den = np.sum(d * d, axis=-1)[..., None]
    with np.errstate(divide="ignore", invalid="ignore"):
        return np.where(den > 0, num / np.where(den > 0, den, 1.0), np.nan)


# ---------------------------------------------------------------------------
# value types
# ---------------------------------------------------------------------------

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
        return cls(d, np.cross(p, d))

    @classmethod
    def joining(cls, p, q) -> "Line":
        """The line from point ``p`` to point ``q``."""
        p = as_vector3(p, "point")
        return cls.through(p, as_vector3(q, "point") - p)

    @property
    def point(self) -> np.ndarray:
        """The point of the line closest to the origin."""
        return np.cross(self.direction, self.moment)

    def distance_to_point(self, x) -> float:
        """Distance from point ``x`` to the line."""
        x = as_vector3(x, "point")
        return float(np.linalg.norm(np.cross(x - self.point, self.direction)))

    def contains(self, x, atol: float) -> bool:
        """True when ``x`` lies on the line within absolute distance ``atol``."""
        return self.distance_to_point(x) <= atol

    def is_parallel(self, other: "Line", rtol: float = 1e-7) -> bool:
        """True when the directions are parallel or antiparallel (``|d1 x d2| <= rtol``)."""
        return float(np.linalg.norm(np.cross(self.direction, other.direction))) <= rtol

    def distance_to_line(self, other: "Line") -> float:
        """Shortest distance between two lines."""
        c = np.cross(self.direction, other.direction)
        n = float(np.linalg.norm(c))
        if n < 1e-12:
            return other.distance_to_point(self.point)
        return abs(float(np.dot(self.direction, other.moment) + np.dot(other.direction, self.moment))) / n

    def closest_points(self, other: "Line"):
        """Closest points ``(x1 on self, x2 on other)``; for parallel lines ``x1`` is ``self.point``."""
        p1, d1 = self.point, self.direction
        p2, d2 = other.point, other.direction
        c = np.cross(d1, d2)
        n2 = float(np.dot(c, c))
        if n2 < 1e-24:
            x1 = p1
            x2 = p2 + np.dot(p1 - p2, d2) * d2
            return x1, x2
        t1 = np.dot(np.cross(p2 - p1, d2), c) / n2
        t2 = np.dot(np.cross(p2 - p1, d1), c) / n2
        return p1 + t1 * d1, p2 + t2 * d2

    def transformed(self, rotation, translation) -> "Line":
        """The line moved by ``x -> R x + p``."""
        R = np.asarray(rotation, float)
        return Line.through(R @ self.point + as_vector3(translation, "translation"), R @ self.direction)

    def __repr__(self) -> str:
        p = np.round(self.point, 6).tolist()
        d = np.round(self.direction, 6).tolist()
        return f"Line(point={p}, direction={d})"


class _Screw:
    """Shared behaviour of :class:`Twist` and :class:`Wrench` (6-vector, linear part first)."""

    vector: np.ndarray
    _kind = "screw"

    def __post_init__(self):
        v = _as_screw6(self.vector, self._kind).astype(float).reshape(6).copy()
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

    def transformed(self, rotation, translation) -> "Twist":
        """This twist expressed in frame {a} when ``x_a = R x_b + p`` (self in {b})."""
        return Twist(transform_twists(rotation, translation, self.vector))

    def reciprocal(self, wrench: "Wrench") -> float:
        """Reciprocal product with a wrench."""
        return float(reciprocal_product(wrench.vector, self.vector))

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

    def moment_about(self, point) -> np.ndarray:
        """Moment of the wrench about ``point``: ``m - point x f``."""
        return self.moment - np.cross(as_vector3(point, "point"), self.force)

    def transformed(self, rotation, translation) -> "Wrench":
        """This wrench expressed in frame {a} when ``x_a = R x_b + p`` (self in {b})."""
        return Wrench(transform_wrenches(rotation, translation, self.vector))

    def reciprocal(self, twist: Twist) -> float:
        """Reciprocal product (virtual power) with a twist."""
        return float(reciprocal_product(self.vector, twist.vector))

    def __repr__(self) -> str:
        return f"Wrench({np.round(self.vector, 9).tolist()})"


# ---------------------------------------------------------------------------
# constructors
# ---------------------------------------------------------------------------

def revolute_twist(direction, point) -> Twist:
    """Unit twist of a revolute joint: ``[p x u; u]`` (``v = w x (O - p)``)."""
    u = unit(direction, "revolute axis")
    p = as_vector3(point, "revolute point")
    return Twist(np.concatenate([np.cross(p, u), u]))


def prismatic_twist(direction) -> Twist:
    """Unit twist of a prismatic joint: ``[u; 0]``."""
    u = unit(direction, "prismatic direction")
    return Twist(np.concatenate([u, np.zeros(3)]))


def helical_twist(direction, point, pitch: float) -> Twist:
    """Unit twist of a helical joint of ``pitch`` (length per radian): ``[p x u + h u; u]``."""
    u = unit(direction, "helical axis")
    p = as_vector3(point, "helical point")
    h = float(pitch)
    if not np.isfinite(h):
        raise InputError("helical pitch must be finite")
    return Twist(np.concatenate([np.cross(p, u) + h * u, u]))


def force_wrench(direction, point, magnitude: float = 1.0) -> Wrench:
    """A pure force of ``magnitude`` along ``direction`` through ``point``: ``[f; p x f]``."""
    f = float(magnitude) * unit(direction, "force direction")
    p = as_vector3(point, "force point")
    return Wrench(np.concatenate([f, np.cross(p, f)]))


def couple_wrench(direction, magnitude: float = 1.0) -> Wrench:
    """A pure couple of ``magnitude`` about ``direction``: ``[0; t]``."""
    t = float(magnitude) * unit(direction, "couple direction")
    return Wrench(np.concatenate([np.zeros(3), t]))
