"""Concrete legs: equivalent R/P/H chains with axes and points in the world frame.

A :class:`Leg` is an immutable value: the parsed string, one :class:`Joint` per
equivalent 1-DOF joint (with the letter and position it came from), and the
leg's end points.  Its screw-theoretic analysis (constraint wrenches,
observation rules, actuation wrench) is in :mod:`screwkit.legs._analysis`.
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from functools import cached_property
from typing import TYPE_CHECKING

import numpy as np
from numpy.typing import ArrayLike

from ..errors import InputError
from ..screws import (Line, Twist, as_rotation, as_vector3, helical_twist, prismatic_twist,
                      revolute_twist, unit)
from ._guards import MAX_MAGNITUDE
from ._parsing import EquivalentJoint, LegString

if TYPE_CHECKING:
    from ._analysis import LegAnalysis

__all__ = ["Joint", "Leg"]


@dataclass(frozen=True)
class Joint:
    """One joint of an equivalent chain, placed in space.

    Attributes
    ----------
    spec : EquivalentJoint
        Name, kind, origin letter and position, actuation flag.
    direction : ndarray (3,)
        Unit axis (R, H) or sliding direction (P).
    point : ndarray (3,)
        A point of the axis (R, H); for P a reference point used for drawing; for the P of
        a parallelogram ``Pa`` a point of its first hinge axis.
    pitch : float
        Helical pitch (length per radian), 0 for R and P.
    bar : ndarray (3,) or None
        For a parallelogram ``Pa`` only: the bar vector from its first hinge axis to its
        second (model lengths); ``direction`` is then the instantaneous translation,
        normal to the bars and to the hinges.
    """

    spec: EquivalentJoint
    direction: np.ndarray
    point: np.ndarray
    pitch: float = 0.0
    bar: np.ndarray | None = None

    def __post_init__(self):
        d = _unit3(self.direction)
        if d is None:                      # not a finite non-zero 3-vector: say so
            d = unit(self.direction, f"axis of {self.spec.name}")
        try:
            p = np.array(self.point, dtype=float)
            fine = p.shape == (3,) and all(abs(x) <= MAX_MAGNITUDE for x in p.tolist())
        except (TypeError, ValueError, OverflowError):
            fine = False                            # (NaN fails the comparison too)
        if not fine:
            p = as_vector3(self.point, f"point of {self.spec.name}", MAX_MAGNITUDE).copy()
        d.setflags(write=False)
        p.setflags(write=False)
        object.__setattr__(self, "direction", d)
        object.__setattr__(self, "point", p)
        if self.bar is not None or self.spec.parallelogram:
            if self.bar is None:
                raise InputError(f"{self.spec.name}: a parallelogram needs its bar vector")
            b = as_vector3(self.bar, f"bar of {self.spec.name}", MAX_MAGNITUDE).copy()
            n = float(np.linalg.norm(b))
            if not n > 0 or abs(float(b @ d)) > 1e-9 * n:
                raise InputError(f"{self.spec.name}: the bar {b.tolist()} must be non-zero and "
                                 "normal to the translation direction")
            b.setflags(write=False)
            object.__setattr__(self, "bar", b)

    @property
    def name(self) -> str:
        return self.spec.name

    @property
    def kind(self) -> str:
        return self.spec.kind

    @property
    def actuated(self) -> bool:
        return self.spec.actuated

    @property
    def twist(self) -> Twist:
        """Unit twist of the joint (about the base origin)."""
        if self.kind == "R":
            return revolute_twist(self.direction, self.point)
        if self.kind == "P":
            return prismatic_twist(self.direction)
        return helical_twist(self.direction, self.point, self.pitch)

    @cached_property
    def line(self) -> Line:
        """The joint axis as a line (immutable, computed once)."""
        return Line.through(self.point, self.direction)

    def moved(self, rotation: ArrayLike, translation: ArrayLike, scale: float = 1.0) -> "Joint":
        """The joint after ``x -> R (scale x) + p``."""
        R = np.asarray(rotation, float)
        return Joint(self.spec, R @ self.direction,
                     R @ (scale * self.point) + np.asarray(translation, float), self.pitch * scale,
                     None if self.bar is None else R @ (scale * self.bar))

    @property
    def hinge(self) -> np.ndarray | None:
        """For a parallelogram: the unit direction of its four hinges, ``bar x direction``
        normalised (None for other joints)."""
        if self.bar is None:
            return None
        h = np.cross(self.bar, self.direction)
        return h / np.linalg.norm(h)


def _unit3(x):
    """``screws.unit(x)`` (the same values) for a finite non-zero 3-vector, else None."""
    a = np.asarray(x, dtype=float)
    if a.shape != (3,):
        return None
    x0, x1, x2 = a.tolist()
    n = math.sqrt(x0 * x0 + x1 * x1 + x2 * x2)
    if not (math.isfinite(n) and n > 1e-12 * max(1.0, abs(x0), abs(x1), abs(x2))):
        return None
    return a / n


def _unit_twist_row(j: Joint) -> list:
    """``j.twist.vector`` as a list, on Python floats operation for operation as
    :func:`~screwkit.screws.revolute_twist` (and the prismatic and helical ones) compute it,
    without building and validating a :class:`~screwkit.screws.Twist` per joint."""
    d0, d1, d2 = j.direction.tolist()
    n = math.sqrt(d0 * d0 + d1 * d1 + d2 * d2)     # the twist constructors normalise again
    u0, u1, u2 = d0 / n, d1 / n, d2 / n
    if j.kind == "P":
        return [u0, u1, u2, 0.0, 0.0, 0.0]
    p0, p1, p2 = j.point.tolist()
    v = [p1 * u2 - p2 * u1, p2 * u0 - p0 * u2, p0 * u1 - p1 * u0]
    if j.kind != "R":                                 # helical: p x u + h u
        h = float(j.pitch)
        if not math.isfinite(h):
            return j.twist.vector.tolist()            # raises the constructor's InputError
        v = [v[0] + h * u0, v[1] + h * u1, v[2] + h * u2]
    return v + [u0, u1, u2]


@dataclass(frozen=True, eq=False)
class Leg:
    """A leg: a parsed string and its equivalent chain placed in space.

    Parameters
    ----------
    string : LegString
    joints : tuple of Joint
        In chain order from the base to the platform.
    A, a : ndarray (3,)
        Base and platform attachment points.
    name : str
        Catalog name (``"UPU/couple"``) or the string itself.
    """

    string: LegString
    joints: tuple
    A: np.ndarray
    a: np.ndarray
    name: str = ""

    def __post_init__(self):
        if len(self.joints) != len(self.string.equivalent):
            raise InputError(f"leg {self.string.text}: {len(self.joints)} joints given for an "
                             f"equivalent chain of {len(self.string.equivalent)}")
        for name in ("A", "a"):
            v = as_vector3(getattr(self, name), name, MAX_MAGNITUDE).copy()
            v.setflags(write=False)
            object.__setattr__(self, name, v)
        if not self.name:
            object.__setattr__(self, "name", self.string.text)

    @cached_property
    def twists(self) -> np.ndarray:
        """Joint twists, shape (m, 6), in chain order (read-only, computed once)."""
        T = np.array([_unit_twist_row(j) for j in self.joints]).reshape(-1, 6)
        T.setflags(write=False)
        return T

    @cached_property
    def points(self) -> np.ndarray:
        """Joint points and end points, shape (m + 2, 3): the geometry's extent (read-only,
        computed once)."""
        P = np.vstack([self.A, self.a] + [j.point for j in self.joints])
        P.setflags(write=False)
        return P

    @property
    def length(self) -> float:
        """Distance between the end points."""
        return float(np.linalg.norm(self.a - self.A))

    @property
    def actuated_index(self) -> int:
        return self.string.actuated_index

    @property
    def actuated_joint(self) -> Joint:
        return self.joints[self.actuated_index]

    def joint(self, name: str) -> Joint:
        """The joint called ``name`` (``"R1"``, ``"S1a"``...)."""
        for j in self.joints:
            if j.name == name:
                return j
        raise InputError(f"leg {self.name} has no joint {name!r}; joints: "
                         f"{', '.join(j.name for j in self.joints)}")

    def centres(self) -> dict:
        """Centres of the S and U joints: ``{"S1": point, ...}``."""
        out: dict[str, np.ndarray] = {}
        for j in self.joints:
            if j.spec.origin in "SU":
                out.setdefault(f"{j.spec.origin}{j.spec.position}", j.point)
        return out

    def letters(self) -> list:
        """The joints grouped by the letter of the leg string they come from, in order:
        ``[(letter, [(index, Joint), ...]), ...]`` (an S is three R joints through one
        centre, a U two crossed R, a C a P and an R on one axis; ``index`` in
        :attr:`joints`).  The drawings, the 3D view and the MJCF export read a leg so."""
        out: list = []
        where: dict = {}
        for k, j in enumerate(self.joints):
            key = (j.spec.origin, j.spec.position)
            if key not in where:
                where[key] = len(out)
                out.append((j.spec.origin, []))
            out[where[key]][1].append((k, j))
        return out

    def moved(self, rotation: ArrayLike, translation: ArrayLike, scale: float = 1.0) -> "Leg":
        """The leg after ``x -> R (scale x) + p`` (a change of base frame and/or of units):
        ``R`` a rotation, ``scale`` positive (else :class:`~screwkit.errors.InputError`)."""
        R = as_rotation(rotation)
        p = as_vector3(translation, "translation", MAX_MAGNITUDE)
        if isinstance(scale, bool) or not isinstance(scale, (int, float, np.integer,
                                                             np.floating)) or \
                not 1.0 / MAX_MAGNITUDE <= scale <= MAX_MAGNITUDE:
            raise InputError(f"scale must be a positive number from {1 / MAX_MAGNITUDE:g} to "
                             f"{MAX_MAGNITUDE:g}, got {scale!r}")
        return Leg(self.string, tuple(j.moved(R, p, scale) for j in self.joints),
                   R @ (scale * self.A) + p, R @ (scale * self.a) + p, self.name)

    def analyze(self) -> LegAnalysis:
        """Screw-theoretic analysis of the leg (see :func:`screwkit.legs.analyze_leg`)."""
        from ._analysis import analyze_leg
        return analyze_leg(self)

    def __repr__(self) -> str:
        return f"Leg({self.name!r}, {self.string.marked})"
