"""Where a leg sits: its end points, and the base and platform frames around it.

A :class:`Placement` is the context in which the structural rules of a leg are
evaluated: the base attachment point ``A``, the platform attachment point
``a``, the base origin ``O`` and platform centre ``o``, and the orientations of
the base and the platform (world <- frame).
"""

from __future__ import annotations

from dataclasses import dataclass, field
from functools import cached_property, lru_cache

import numpy as np
from numpy.typing import ArrayLike

from ..errors import GeometryError, InputError
from ..screws import as_rotation, as_vector3
from ._guards import MAX_MAGNITUDE

__all__ = ["Placement", "default_placement"]


@dataclass(frozen=True)
class Placement:
    """End points and frames of one leg (all in world = base-frame coordinates).

    Parameters
    ----------
    A : array_like (3,)
        Base attachment point.
    a : array_like (3,)
        Platform attachment point.
    O : array_like (3,), default origin
        Base centre.
    o : array_like (3,), optional
        Platform centre (default: ``a`` moved by ``O - A`` scaled to half, i.e. a
        point above the base centre at the height of ``a``).
    base_rotation, platform_rotation : array_like (3, 3), default identity
        World <- base and world <- platform rotations.
    C : array_like (3,), optional
        A centre of rotation fixed to the base (rule reference ``C``), default
        half-way from ``O`` to ``o``.
    """

    A: np.ndarray
    a: np.ndarray
    O: np.ndarray = field(default_factory=lambda: np.zeros(3))
    o: np.ndarray | None = None
    base_rotation: np.ndarray = field(default_factory=lambda: np.eye(3))
    platform_rotation: np.ndarray = field(default_factory=lambda: np.eye(3))
    C: np.ndarray | None = None

    def __post_init__(self):
        A = as_vector3(self.A, "A", MAX_MAGNITUDE)
        a = as_vector3(self.a, "a", MAX_MAGNITUDE)
        O = as_vector3(self.O, "O", MAX_MAGNITUDE)
        if self.o is None:
            o = O + np.array([0.0, 0.0, float(np.dot(a - O, self.base_rotation @ [0, 0, 1]))])
        else:
            o = as_vector3(self.o, "o", MAX_MAGNITUDE)
        C = O + 0.5 * (o - O) if self.C is None else as_vector3(self.C, "C", MAX_MAGNITUDE)
        object.__setattr__(self, "C", C)
        if np.linalg.norm(a - A) <= 1e-12 * max(1.0, np.linalg.norm(A)):
            raise GeometryError("the leg's end points A and a coincide")
        for name, val in (("A", A), ("a", a), ("O", O), ("o", o),
                          ("base_rotation", as_rotation(self.base_rotation, "base_rotation")),
                          ("platform_rotation",
                           as_rotation(self.platform_rotation, "platform_rotation"))):
            val = np.array(val, dtype=float)
            val.setflags(write=False)
            object.__setattr__(self, name, val)

    @property
    def centre(self) -> np.ndarray:
        """``C`` (never None once the placement is made)."""
        return self._filled(self.C)

    @staticmethod
    def _filled(v: np.ndarray | None) -> np.ndarray:
        assert v is not None, "o and C are filled in by __post_init__"
        return v

    @cached_property
    def length(self) -> float:
        """Distance from ``A`` to ``a``: the leg's characteristic length (computed once)."""
        return float(np.linalg.norm(self.a - self.A))

    def transformed(self, rotation: ArrayLike, translation: ArrayLike) -> "Placement":
        """The placement moved rigidly by ``x -> R x + p``."""
        R = as_rotation(rotation, "rotation")
        p = as_vector3(translation, "translation", MAX_MAGNITUDE)
        o, C = self._filled(self.o), self._filled(self.C)
        return Placement(R @ self.A + p, R @ self.a + p, R @ self.O + p, R @ o + p,
                         R @ self.base_rotation, R @ self.platform_rotation, R @ C + p)

    def scaled(self, k: float) -> "Placement":
        """All lengths multiplied by ``k``."""
        o, C = self._filled(self.o), self._filled(self.C)
        return Placement(k * self.A, k * self.a, k * self.O, k * o,
                         self.base_rotation, self.platform_rotation, k * C)


@lru_cache(maxsize=64)
def _default_placement(s: float) -> Placement:
    return Placement(A=np.array([s, 0.0, 0.0]), a=np.array([0.5 * s, 0.0, 0.8 * s]),
                     O=np.zeros(3), o=np.array([0.0, 0.0, 0.8 * s]))


def default_placement(scale: float = 100.0) -> Placement:
    """The default placement used to analyse a single leg.

    Base centre at the origin, ``A`` on the base X axis at ``scale``, the
    platform parallel to the base at height ``0.8 scale`` with its centre above
    ``O`` and ``a`` at half the base radius, in the radial plane of ``A``.
    """
    return _default_placement(float(scale))      # immutable: built once per scale
