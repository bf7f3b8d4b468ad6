"""One leg of a PM at N poses as arrays, its named points and reference directions (private)."""

from __future__ import annotations

from dataclasses import dataclass
from functools import cached_property

import numpy as np

from . import _algebra as alg
from ..screws import cross

#: Smallest |cosine| (or Gram-Schmidt remainder) of a reference direction chosen at home.
REF_MIN = 0.2
#: Below this |cosine| (remainder) at a pose the basis is flagged as ill-defined there.
REF_FLAG = 1e-3

__all__ = ["REF_MIN", "REF_FLAG", "LegGeometry", "point_ref", "named_point", "leg_length", "leg_centroid",
           "geometry_of"]


@dataclass(frozen=True, eq=False)
class LegGeometry:
    """One leg at ``N`` poses (arrays, pose axis last).

    Attributes
    ----------
    axes, points : ndarray (m, 3, N)
        Current joint axes and points (world).
    rotation, translation : ndarray (m,)
        Per unit joint value (see :class:`~screwkit.engine._chains.Chains`).
    A : ndarray (3,) ; a : ndarray (3, N)
        End points.
    base_rotation : ndarray (3, 3) ; O : ndarray (3,)
        World <- base; the base origin.
    platform_rotation : ndarray (3, 3, N) ; o : ndarray (3, N)
    """

    axes: np.ndarray
    points: np.ndarray
    rotation: np.ndarray
    translation: np.ndarray
    A: np.ndarray
    a: np.ndarray
    base_rotation: np.ndarray
    O: np.ndarray
    platform_rotation: np.ndarray
    o: np.ndarray

    @property
    def N(self) -> int:
        return self.a.shape[-1]

    @cached_property
    def twists(self):
        """Every joint's unit twist about the base origin, ``(v, w)`` each ``(3, m, N)``
        (formed once per geometry, every joint at once)."""
        d = self.axes.transpose(1, 0, 2)                 # (3, m, N)
        p = self.points.transpose(1, 0, 2)
        w = np.asarray(self.rotation, float)[:, None] * d
        return alg.cross(p, w) + np.asarray(self.translation, float)[:, None] * d, w

    def twist(self, j):
        """Joint ``j``'s unit twist ``(v (3, N), w (3, N))`` about the base origin."""
        v, w = self.twists
        return v[:, j], w[:, j]

    def point_velocity(self, j, X):
        """Velocity of the point ``X (3, N)`` under joint ``j``'s unit twist."""
        v, w = self.twist(j)
        return v - alg.cross(X, w)

    def point_velocities(self, joints, X):
        """Velocities ``(3, len(joints), N)`` of the point ``X (3, N)`` under the unit twists
        of ``joints`` (a sequence of slots)."""
        v, w = self.twists
        idx = list(joints)
        return v[:, idx] - alg.cross(X[:, None], w[:, idx])

    def direction(self, ref, names):
        """A reference direction ``(3, N)`` (see :data:`DEFAULT_REFERENCES`), unit."""
        N = self.N
        if isinstance(ref, dict):
            (k, v), = ref.items()
            if k == "perpendicular":
                return alg.unit(alg.cross(self.direction(v[0], names), self.direction(v[1], names)))
            if k in ("along", "parallel"):
                return self.direction(v, names)
            raise ValueError(ref)
        neg = ref.startswith("-")
        r = ref[1:] if neg else ref
        if r == "leg":
            d = self.a - self.A[:, None]
        elif r.startswith("base.") and r[5:] in ("X", "Y", "Z"):
            d = np.broadcast_to(self.base_rotation[:, "XYZ".index(r[5])][:, None], (3, N))
        elif r.startswith("platform.") and r[9:] in ("x", "y", "z"):
            d = self.platform_rotation[:, "xyz".index(r[9])]
        elif r in ("base.OA", "base.AO"):
            d = np.broadcast_to((self.A - self.O)[:, None], (3, N)) * (1 if r == "base.OA" else -1)
        elif r in ("platform.oa", "platform.ao"):
            d = (self.a - self.o) * (1 if r == "platform.oa" else -1)
        elif r == "base.tangent":
            d = np.broadcast_to(cross(self.base_rotation[:, 2], self.A - self.O)[:, None], (3, N))
        elif r == "platform.tangent":
            d = alg.cross(self.platform_rotation[:, 2], self.a - self.o)
        elif r in names:
            d = self.axes[names.index(r)]
        else:
            raise ValueError(f"unknown reference direction {ref!r}")
        d = alg.unit(d)
        return -d if neg else d


# --------------------------------------------------------------------------- named points

def point_ref(leg, name):
    """How to find a named point of ``leg`` at any pose: ('A',), ('a',), ('joint', j) or
    ('meet', i, j)."""
    if name in ("A", "a"):
        return (name,)
    if "^" in name:
        n1, n2 = name.split("^", 1)
        return ("meet", _slot(leg, n1), _slot(leg, n2))
    for j, jt in enumerate(leg.joints):
        if jt.name == name or f"{jt.spec.origin}{jt.spec.position}" == name:
            return ("joint", j)
    raise ValueError(f"leg {leg.name}: no point named {name!r}")


def _slot(leg, name):
    for j, jt in enumerate(leg.joints):
        if jt.name == name:
            return j
    raise ValueError(f"leg {leg.name}: no joint {name!r}")


def named_point(geo: LegGeometry, ref):
    """The named point ``ref`` (:func:`point_ref`) at every pose, ``(3, N)`` (formed once
    per geometry; read it, do not write to it)."""
    memo = geo.__dict__.setdefault("_named_points", {})
    p = memo.get(ref)
    if p is None:
        p = memo[ref] = _named_point(geo, ref)
    return p


def _named_point(geo: LegGeometry, ref):
    if ref[0] == "A":
        return np.broadcast_to(geo.A[:, None], (3, geo.N))
    if ref[0] == "a":
        return geo.a
    if ref[0] == "joint":
        return geo.points[ref[1]]
    _, i, j = ref          # meeting point of two axes: midpoint of their common perpendicular
    d1, d2, p1, p2 = geo.axes[i], geo.axes[j], geo.points[i], geo.points[j]
    w = p1 - p2
    b, d, e = alg.dot(d1, d2), alg.dot(d1, w), alg.dot(d2, w)
    den = np.maximum(1.0 - b * b, 1e-300)
    s, t = (b * e - d) / den, (e - b * d) / den
    return 0.5 * (p1 + s * d1 + p2 + t * d2)


def leg_length(geo):
    """Characteristic length of the leg at each pose: its end-point distance."""
    return alg.norm(geo.a - geo.A[:, None])


def leg_centroid(geo):
    return (geo.A[:, None] + geo.a + geo.points.sum(0)) / (2 + geo.points.shape[0])


def geometry_of(leg, base_rotation, O, platform_rotation, o):
    axes = np.array([j.direction for j in leg.joints])[:, :, None]
    pts = np.array([j.point for j in leg.joints])[:, :, None]
    rot = np.array([0.0 if j.kind == "P" else 1.0 for j in leg.joints])
    tra = np.array([1.0 if j.kind == "P" else (j.pitch if j.kind == "H" else 0.0)
                    for j in leg.joints])
    return LegGeometry(axes, pts, rot, tra, np.asarray(leg.A, float),
                       np.asarray(leg.a, float)[:, None], np.asarray(base_rotation, float),
                       np.asarray(O, float), np.asarray(platform_rotation, float)[:, :, None],
                       np.asarray(o, float)[:, None])


