"""Evaluation of the references of a leg's rules (directions and points) at one placement.

:class:`_Context` reads the direction references, direction rules and point
references listed in :mod:`screwkit.legs._rules` for a
:class:`~screwkit.legs.Placement`, with the joints placed so far.  It is shared by
the builder (:func:`screwkit.legs.build_leg`) and the structure checks
(:mod:`screwkit.legs._structure`).
"""

from __future__ import annotations

import numpy as np

from ._guards import MAX_MAGNITUDE, real, real_vector, shorten
from ..errors import GeometryError
from ..screws import GEOMETRY_RTOL, Line
from ._placement import Placement
from ..screws import cross

# ``rules`` arguments are :class:`screwkit.legs.LegRules` (the rules module imports this one).

_FRAME_REFS = {"base.X", "base.Y", "base.Z", "platform.x", "platform.y", "platform.z",
               "base.AO", "base.OA", "platform.ao", "platform.oa", "base.tangent",
               "platform.tangent", "leg"}
_POINT_NAMES = {"A", "a", "O", "o"}  # and C, the placement's centre of rotation


class _Context:
    """Evaluates references for one placement while the joints are being built."""

    def __init__(self, rules: "LegRules", pl: Placement):
        self.rules, self.pl = rules, pl
        self.dirs: dict[str, np.ndarray] = {}
        self.pts: dict[str, np.ndarray] = {}
        self.where = rules.name

    def fail(self, msg):
        raise GeometryError(f"leg {self.where}: {msg}")

    def _unit(self, v, what):
        n = np.linalg.norm(v)
        if n < 1e-12:
            self.fail(f"{what} is undefined here (zero vector)")
        return v / n

    def frame_dir(self, ref: str) -> np.ndarray:
        pl = self.pl
        Rb, Rp = pl.base_rotation, pl.platform_rotation
        if ref == "leg":
            return self._unit(pl.a - pl.A, "the leg line")
        if ref.startswith("base.") and ref[5:] in "XYZ" and len(ref) == 6:
            return Rb[:, "XYZ".index(ref[5])]
        if ref.startswith("platform.") and ref[9:] in "xyz" and len(ref) == 10:
            return Rp[:, "xyz".index(ref[9])]
        if ref == "base.AO":
            return self._unit(pl.O - pl.A, "base.AO (A is at the base centre)")
        if ref == "base.OA":
            return -self.frame_dir("base.AO")
        if ref == "platform.ao":
            return self._unit(pl.o - pl.a, "platform.ao (a is at the platform centre)")
        if ref == "platform.oa":
            return -self.frame_dir("platform.ao")
        if ref == "base.tangent":
            return self._unit(cross(Rb[:, 2], pl.A - pl.O), "base.tangent")
        if ref == "platform.tangent":
            return self._unit(cross(Rp[:, 2], pl.a - pl.o), "platform.tangent")
        raise KeyError(ref)

    def direction(self, ref) -> np.ndarray:
        """A direction reference (not a rule)."""
        if isinstance(ref, str):
            neg = ref.startswith("-")
            r = ref[1:] if neg else ref
            if r in _FRAME_REFS:
                d = self.frame_dir(r)
            elif r in self.dirs:
                d = self.dirs[r]
            else:
                raise _Unresolved(r)
            return -d if neg else d
        if isinstance(ref, dict) and len(ref) == 1 and "toward" in ref:
            p, q = (self.point(x) for x in self._pair(ref["toward"], "toward"))
            return self._unit(q - p, f"direction toward {ref['toward']}")
        if isinstance(ref, dict) and len(ref) == 1:
            (k, v), = ref.items()
            if not (isinstance(v, (list, tuple)) and len(v) == 3):
                self.fail(f"cannot read direction reference {shorten(ref)} (a direction rule such "
                          "as 'perpendicular' is not allowed here)")
            v = self._vector(v, k)
            if v.shape == (3,):
                if k == "base":
                    return self._unit(self.pl.base_rotation @ v, "explicit base vector")
                if k == "platform":
                    return self._unit(self.pl.platform_rotation @ v, "explicit platform vector")
                if k == "world":
                    return self._unit(v, "explicit world vector")
        if isinstance(ref, (list, tuple)) and len(ref) == 3:
            return self._unit(self._vector(ref, "explicit vector"), "explicit vector")
        self.fail(f"cannot read direction reference {shorten(ref)}")

    def direction_rule(self, rule) -> np.ndarray:
        if isinstance(rule, dict) and len(rule) == 1:
            (k, v), = rule.items()
            if k in ("along", "parallel"):
                return self.direction(v)
            if k == "perpendicular":
                if not (isinstance(v, (list, tuple)) and len(v) == 2):
                    self.fail(f"'perpendicular' needs two references, got {v!r}")
                d1, d2 = self.direction(v[0]), self.direction(v[1])
                c = cross(d1, d2)
                if np.linalg.norm(c) < 1e-9:
                    self.fail(f"{v[0]} and {v[1]} are parallel here: their common perpendicular "
                              "is undefined")
                return c / np.linalg.norm(c)
        return self.direction(rule)

    def point(self, ref) -> np.ndarray:
        pl = self.pl
        if isinstance(ref, str):
            if ref in _POINT_NAMES:
                return {"A": pl.A, "a": pl.a, "O": pl.O, "o": pl.o}[ref]
            if ref == "C":
                return pl.centre
            if ref in self.pts:
                return self.pts[ref]
            raise _Unresolved(ref)
        if isinstance(ref, dict):
            if "between" in ref:
                p, q = (self.point(x) for x in self._pair(ref["between"], "between"))
                t = self._number(ref.get("t", 0.5), "t")
                return (1 - t) * p + t * q
            if "meet" in ref:
                j1, j2 = self._pair(ref["meet"], "meet")
                if not (isinstance(j1, str) and isinstance(j2, str)):
                    self.fail(f"'meet' takes two joint names, got {shorten(ref['meet'])}")
                l1 = Line.through(self.point(j1), self.direction(j1))
                l2 = Line.through(self.point(j2), self.direction(j2))
                if l1.is_parallel(l2):
                    self.fail(f"{j1} and {j2} are parallel: they do not meet at a point")
                x1, x2 = l1.closest_points(l2)
                if np.linalg.norm(x1 - x2) > GEOMETRY_RTOL * max(pl.length, 1e-300) * 10:
                    self.fail(f"{j1} and {j2} do not meet (distance {np.linalg.norm(x1 - x2):.3g})")
                return 0.5 * (x1 + x2)
            if "offset" in ref:
                p = self.point(ref["offset"])
                d = self.direction(ref.get("along", "leg"))
                return p + self._number(ref.get("fraction", 0.0), "fraction") * pl.length * d
            if len(ref) == 1 and next(iter(ref)) in ("world", "base", "platform"):
                # a literal point (model lengths): world coordinates, or coordinates in the
                # base frame (origin O) or the platform frame (origin o)
                (k, v), = ref.items()
                x = self._vector(v, f"{k} point")
                if k == "base":
                    return pl.O + pl.base_rotation @ x
                if k == "platform":
                    return pl.o + pl.platform_rotation @ x
                return x
        self.fail(f"cannot read point reference {shorten(ref)}")

    def _pair(self, v, what):
        if not (isinstance(v, (list, tuple)) and len(v) == 2):
            self.fail(f"{what!r} takes two references, got {shorten(v)}")
        return v

    def _number(self, v, what) -> float:
        """A number of a rule (``t``, ``fraction``): real, finite, at most 1e6 in magnitude."""
        return real(v, what, bound=1e6, error=lambda m: GeometryError(f"leg {self.where}: {m}"))

    def _vector(self, v, what) -> np.ndarray:
        return real_vector(v, what, 3, bound=MAX_MAGNITUDE,
                           error=lambda m: GeometryError(f"leg {self.where}: {m}"))


class _Unresolved(Exception):
    """A reference to a joint not yet placed (resolved on a later pass)."""
