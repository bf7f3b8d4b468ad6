"""Target constraint systems of the synthesis: the hand-derived layouts and their loci.

A :class:`Layout` is a concrete target (pure forces on lines, pure couples along
directions) together with the strata (:class:`Locus`) that cover every admissible
joint centre of that layout (derived by hand, see ``docs/validation.md``);
:data:`LAYOUTS` lists the layouts tried for each composition ``(n_forces, n_couples)``.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from ..errors import InputError
from ..screws import couple_wrench, force_wrench
from ..screws._svd import small_rank, svd_full, svd_values
from ._linalg import (NULL_RTOL, cross, null_basis, null_dimension, perpendicular_unit,
                      random_unit, unit)

__all__ = ["LAYOUTS", "Locus", "Layout", "compositions", "layouts_for", "make_layout"]

#: Layout names tried for each composition ``(n_forces, n_couples)``, in order.
LAYOUTS = {
    (1, 0): ("line",),
    (0, 1): ("couple",),
    (2, 0): ("concurrent", "parallel", "skew"),
    (1, 1): ("general", "perpendicular", "coaxial"),
    (0, 2): ("couples",),
    (3, 0): ("concurrent", "coplanar"),
    (2, 1): ("concurrent", "normal"),
    (1, 2): ("line", "normal"),
    (0, 3): ("couples",),
}


def compositions(k: int) -> tuple:
    """The compositions ``(n_forces, n_couples)`` of a ``k``-system, forces first."""
    return tuple((k - c, c) for c in range(k + 1))


# --------------------------------------------------------------------------- targets
@dataclass(frozen=True)
class Locus:
    """A stratum of admissible joint points of a layout.

    Attributes
    ----------
    name : str
        ``"generic"``, ``"L"``, ``"L1"``, ``"X"``, ``"pi"``, ``"N"``, ``"Pt"``.
    kind : str
        ``"space"``, ``"line"``, ``"point"`` or ``"plane"``.
    point : ndarray (3,)
        A point of the locus (unused for ``"space"``).
    direction : ndarray (3,) or None
        Line direction, or plane normal.
    """

    name: str
    kind: str
    point: np.ndarray | None = None
    direction: np.ndarray | None = None

    def sample(self, near, rng, scale: float) -> np.ndarray:
        """A random point of the locus close to ``near`` (spread ``scale``)."""
        near = np.asarray(near, float)
        if self.kind == "space":
            return near + 0.15 * scale * rng.standard_normal(3)
        if self.kind == "point":
            return np.array(self.point, float)
        d = self.direction
        if self.kind == "line":
            s = float(np.dot(near - self.point, d)) + 0.1 * scale * rng.standard_normal()
            return self.point + s * d
        # plane: project, then move inside the plane
        x = near + 0.15 * scale * rng.standard_normal(3)
        return x - np.dot(x - self.point, d) * d


@dataclass(frozen=True)
class Layout:
    """A concrete target constraint system and the strata of its admissible points.

    Attributes
    ----------
    composition : tuple (n_forces, n_couples)
    name : str
        Layout name (``"concurrent"``...; see :data:`LAYOUTS`).
    force_lines : tuple of (point, direction)
        One per target force (unit directions), named ``L`` or ``L1, L2, ...``.
    couples : tuple of ndarray (3,)
        Unit couple directions ``t`` or ``t1, t2, ...``.
    loci : tuple of Locus
        Strata of admissible points, generic first.
    words : str
        The layout in words (``"2 forces meeting at X"``).
    """

    composition: tuple
    name: str
    force_lines: tuple
    couples: tuple
    loci: tuple
    words: str

    def __post_init__(self):
        rows = [_force_row(d, p) for p, d in self.force_lines]
        rows += [_couple_row(t) for t in self.couples]
        W = np.array(rows, float).reshape(-1, 6)
        W.setflags(write=False)
        object.__setattr__(self, "_W", W)
        object.__setattr__(self, "_rows", W.tolist())     # for moment_matrix on floats
        object.__setattr__(self, "_cache", {})            # derived immutable arrays

    def _cached(self, key, make):
        out = self._cache.get(key)
        if out is None:
            out = self._cache[key] = make()
            if isinstance(out, np.ndarray):
                out.setflags(write=False)
        return out

    @property
    def k(self) -> int:
        return len(self.force_lines) + len(self.couples)

    @property
    def wrenches(self) -> np.ndarray:
        """The target wrenches ``[f; m]`` (moments about O), shape (k, 6): forces then couples."""
        return self._W.copy()

    @property
    def force_rank(self) -> int:
        """Rank of the force directions (the system's forces span this many directions)."""
        return self._cached("force_rank", self._force_rank)

    def _force_rank(self) -> int:
        if not self.force_lines:
            return 0
        D = np.array([d for _, d in self.force_lines])
        r = small_rank(D.tolist(), NULL_RTOL, 0.0)
        if r is None:
            s = svd_values(D)
            r = int(np.sum(s > NULL_RTOL * s[0]))
        return r

    def force_null_dimension(self) -> int:
        """``len(force_null())``, from the singular values alone."""
        if "force_null" in self._cache:
            return len(self._cache["force_null"])
        return self._cached("force_null_dim", lambda: null_dimension(self._W[:, :3]))

    def force_null(self) -> np.ndarray:
        """``null_basis(F)``: the directions perpendicular to every force (read-only)."""
        return self._cached("force_null", lambda: null_basis(self._W[:, :3]))

    def couple_space(self) -> np.ndarray:
        """Orthonormal basis (rows) of the directions of the couples in the system's span
        (the combinations with zero force), shape (c, 3)."""
        return self._cached("couple_space", self._couple_space).copy()

    def _couple_space(self) -> np.ndarray:
        F = self._W[:, :3]
        _, s, Vt = svd_full(F.T)
        r = int(np.sum(s > NULL_RTOL * max(1.0, float(s[0]) if s.size else 1.0)))
        M = Vt[r:] @ self._W[:, 3:]
        if len(M) == 0:
            return np.zeros((0, 3))
        return null_basis(null_basis(M))

    def force_matrix(self) -> np.ndarray:
        """``F``, shape (k, 3)."""
        return self._W[:, :3]

    def moment_matrix(self, p) -> np.ndarray:
        """``M_p``: moments of the target wrenches about ``p``, shape (k, 3)."""
        # on floats, operation for operation ``W[:, 3:] - cross(p, W[:, :3])``
        p0, p1, p2 = np.asarray(p, float).tolist()
        return np.array([[m0 - (p1 * f2 - p2 * f1), m1 - (p2 * f0 - p0 * f2),
                          m2 - (p0 * f1 - p1 * f0)]
                         for f0, f1, f2, m0, m1, m2 in self._rows]).reshape(-1, 3)


def _unit_floats(d):
    # screws.unit on floats (the same sum of squares); None where unit would raise
    x0, x1, x2 = np.asarray(d, float).tolist()
    n = math.sqrt(x0 * x0 + x1 * x1 + x2 * x2)
    return (x0 / n, x1 / n, x2 / n) if n > 1e-12 * max(1.0, abs(x0), abs(x1), abs(x2)) and \
        math.isfinite(n) else None


def _force_row(d, p) -> list:
    """``force_wrench(d, p).vector`` as a list, operation for operation."""
    u = _unit_floats(d)
    q = np.asarray(p, float)
    if u is None or q.shape != (3,) or not np.isfinite(q).all():
        return force_wrench(d, p).vector.tolist()          # raises its error
    f0, f1, f2 = u
    p0, p1, p2 = q.tolist()
    return [f0, f1, f2, p1 * f2 - p2 * f1, p2 * f0 - p0 * f2, p0 * f1 - p1 * f0]


def _couple_row(t) -> list:
    """``couple_wrench(t).vector`` as a list."""
    u = _unit_floats(t)
    return [0.0, 0.0, 0.0, *u] if u is not None else couple_wrench(t).vector.tolist()


def make_layout(composition, name: str, rng, centre, scale: float) -> Layout:
    """Draw a target system of ``composition`` in layout ``name`` around ``centre``.

    Parameters
    ----------
    composition : tuple (n_forces, n_couples)
    name : str
        One of ``LAYOUTS[composition]``.
    rng : numpy.random.Generator
    centre : array_like (3,)
        Where the force lines pass (the middle of the leg).
    scale : float
        The leg length.
    """
    comp = tuple(int(c) for c in composition)
    if comp not in LAYOUTS or name not in LAYOUTS[comp]:
        raise InputError(f"no layout {name!r} for {comp[0]} forces and {comp[1]} couples; "
                         f"known: {LAYOUTS.get(comp, ())}")
    c0 = np.asarray(centre, float)
    near = lambda: c0 + 0.1 * scale * rng.standard_normal(3)  # noqa: E731
    generic = Locus("generic", "space")
    nf, nc = comp
    lines: list = []
    couples: list = []
    loci = [generic]
    if comp == (1, 0):
        q, c = near(), random_unit(rng)
        lines = [(q, c)]
        loci.append(Locus("L", "line", q, c))
        words = "1 force on a line L"
    elif comp == (0, 1):
        couples = [random_unit(rng)]
        words = "1 couple along t"
    elif comp == (2, 0) and name == "concurrent":
        X = near()
        c1, c2 = random_unit(rng), random_unit(rng)
        lines = [(X, c1), (X, c2)]
        loci += [Locus("X", "point", X), Locus("pi", "plane", X, unit(cross(c1, c2)))]
        words = "2 forces L1, L2 meeting at X (plane pi)"
    elif comp == (2, 0) and name == "parallel":
        c = random_unit(rng)
        u = perpendicular_unit(rng, c)
        q = near()
        lines = [(q - 0.2 * scale * u, c), (q + 0.2 * scale * u, c)]
        loci.append(Locus("pi", "plane", q, unit(cross(c, u))))
        words = "2 parallel forces L1, L2 (plane pi)"
    elif comp == (2, 0):  # skew
        q1, q2 = near(), near()
        c1, c2 = random_unit(rng), random_unit(rng)
        n = unit(cross(c1, c2))
        # feet of the common perpendicular N
        A = np.array([[c1 @ c1, -(c1 @ c2)], [c1 @ c2, -(c2 @ c2)]])
        s, t = np.linalg.solve(A, [(q2 - q1) @ c1, (q2 - q1) @ c2])
        lines = [(q1, c1), (q2, c2)]
        loci += [Locus("L1", "line", q1, c1), Locus("L2", "line", q2, c2),
                 Locus("N", "line", q1 + s * c1, n)]
        words = "2 forces on skew lines L1, L2 (common perpendicular N)"
    elif comp == (1, 1):
        q, c = near(), random_unit(rng)
        if name == "general":
            t = random_unit(rng)
            words = "1 force on L and 1 couple along t (t oblique to L)"
        elif name == "perpendicular":
            t = perpendicular_unit(rng, c)
            words = "1 force on L and 1 couple along t perpendicular to L"
        else:
            t = c
            words = "1 force on L and 1 couple along L"
        lines, couples = [(q, c)], [t]
        loci.append(Locus("L", "line", q, c))
        if name == "perpendicular":
            loci.append(Locus("Pt", "plane", q, t))
    elif comp == (0, 2):
        couples = [random_unit(rng), random_unit(rng)]
        words = "2 couples t1, t2 (normal n = t1 x t2)"
    elif comp == (3, 0) and name == "concurrent":
        X = near()
        lines = [(X, random_unit(rng)) for _ in range(3)]
        loci.append(Locus("X", "point", X))
        words = "3 forces meeting at X"
    elif comp == (3, 0):  # coplanar
        q, nrm = near(), random_unit(rng)
        lines = [(q + 0.2 * scale * perpendicular_unit(rng, nrm), perpendicular_unit(rng, nrm))
                 for _ in range(3)]
        loci.append(Locus("pi", "plane", q, nrm))
        words = "3 forces in a plane pi"
    elif comp == (2, 1):
        X = near()
        c1, c2 = random_unit(rng), random_unit(rng)
        n = unit(cross(c1, c2))
        t = random_unit(rng) if name == "concurrent" else n
        lines, couples = [(X, c1), (X, c2)], [t]
        loci += [Locus("X", "point", X), Locus("pi", "plane", X, n)]
        words = ("2 forces meeting at X (plane pi) and 1 couple t" if name == "concurrent" else
                 "2 forces meeting at X (plane pi) and 1 couple normal to pi")
    elif comp == (1, 2):
        q, c = near(), random_unit(rng)
        if name == "line":
            couples = [random_unit(rng), random_unit(rng)]
            words = "1 force on L and 2 couples t1, t2"
        else:
            couples = [perpendicular_unit(rng, c)]
            couples.append(unit(cross(c, couples[0])))
            words = "1 force on L and 2 couples t1, t2 perpendicular to L"
        lines = [(q, c)]
        loci.append(Locus("L", "line", q, c))
    else:  # (0, 3)
        couples = [np.eye(3)[i] for i in range(3)]
        words = "3 couples (every couple)"
    assert len(lines) == nf and len(couples) == nc
    return Layout(comp, name, tuple((np.asarray(p, float), unit(d)) for p, d in lines),
                  tuple(unit(t) for t in couples), tuple(loci), words)


def layouts_for(composition) -> tuple:
    """Layout names tried for ``composition`` (empty when none is implemented)."""
    return LAYOUTS.get(tuple(composition), ())
