"""Freedoms of a body held by constraint wrenches: the twists reciprocal to a wrench system.

The dual of :func:`~screwkit.screws.reciprocal_system` (Hale's freedom and constraint
topologies): given constraint wrenches ``[f; m]`` (moments about O), the body may move
with every twist ``[v; w]`` with ``f . v + m . w = 0`` for each wrench.  The null space is
taken by SVD of the *length-normalised* wrenches (moved to the centroid of the geometry,
moments divided by its characteristic length, rows scaled to unit norm) with the rank
tolerance :data:`~screwkit.screws.RANK_RTOL`, so the rank decision does not change with
the base frame or the length unit.

The freedom space is then classified by its screws:

* **translations**: the twists with ``w = 0`` (their directions);
* the rest (the twists with independent rotations, taken modulo the translations) by its
  **principal screws**, the stationary values of the pitch ``w . v / w . w`` (a generalised
  symmetric eigenproblem, independent of the basis): a principal pitch within
  :data:`~screwkit.screws.GEOMETRY_RTOL` times the characteristic length of zero is a
  **rotation** about a line, any other a **helical** freedom with that pitch
  (length per radian).  When every rotational twist is a rotation about a line through
  one point (modulo the translations), the rotations are reported through that point.

Examples
--------
Three forces through one point P allow three rotations about lines through P:

>>> import numpy as np
>>> from screwkit.screws import force_wrench, freedoms
>>> P = [1.0, 2.0, 3.0]
>>> res = freedoms([force_wrench(d, P).vector for d in np.eye(3)])
>>> res.label, res.dof
('3R', 3)
>>> print(res.freedoms[0].describe())
rotation about the line through (1, 2, 3) along (1, 0, 0)
"""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass, field

import numpy as np
from numpy.typing import ArrayLike

from ..errors import InputError
from ._matrix import _check_matrix
from ._reciprocal import Normalisation, _unit_rows
from ._screw import Wrench
from ._svd import svd_full
from ._tolerance import GEOMETRY_RTOL, RANK_RTOL, check_rtol
from ._vector import cross

__all__ = ["Freedom", "FreedomResult", "freedoms", "classify_freedoms", "MAX_WRENCHES"]

#: Most constraint wrenches accepted (a bound on what a user sizes).
MAX_WRENCHES = 64


@dataclass(frozen=True)
class Freedom:
    """One classified freedom of a body.

    Attributes
    ----------
    kind : {"translation", "rotation", "helical"}
    direction : ndarray (3,)
        Unit translation direction, or unit rotation / screw axis direction (sign chosen
        with the largest component positive).
    point : ndarray (3,) or None
        A point of the rotation or screw axis (model lengths, world frame): the common
        point when the rotations are concurrent, else the point of the axis closest to
        the centre of the geometry; None for a translation.
    pitch : float
        ``0`` for a rotation, the lead per radian (model lengths per radian) for a helical
        freedom, ``inf`` for a translation.
    twist : ndarray (6,)
        The unit twist ``[v; w]`` about the origin (``|w| = 1``, or ``|v| = 1`` for a
        translation).
    shift : ndarray (k, 3)
        For a rotation or helical freedom: orthonormal directions ``s`` the axis may move
        along (k = 0, 1 or 2; the twist gains ``s x d``, a translation the freedoms hold);
        with k = 2 any parallel line is an axis too.
    """

    kind: str
    direction: np.ndarray
    point: np.ndarray | None
    pitch: float
    twist: np.ndarray
    shift: np.ndarray = field(default_factory=lambda: np.zeros((0, 3)))

    def describe(self, unit: str = "") -> str:
        """In words, e.g. ``"helical about the line through (0, 0, 0) along (0, 0, 1),
        pitch 2.5 mm/rad"``; ``unit`` is the length unit printed after lengths."""
        d = _fmt(self.direction)
        if self.kind == "translation":
            return f"translation along {d}"
        u = f" {unit}" if unit else ""
        where = f"the line through {_fmt(self.point)}{u} along {d}"
        if len(self.shift) == 2:
            where = f"any line along {d}"
        elif len(self.shift) == 1:
            where += f" (or that line moved along {_fmt(self.shift[0])})"
        if self.kind == "rotation":
            return f"rotation about {where}"
        return f"helical about {where}, pitch {self.pitch:.6g}{u}/rad"

    def as_dict(self) -> dict:
        """JSON-ready: kind, direction, point (None for a translation), pitch (None for a
        translation), twist."""
        return {"kind": self.kind, "direction": self.direction.tolist(),
                "point": None if self.point is None else self.point.tolist(),
                "pitch": None if self.kind == "translation" else float(self.pitch),
                "twist": self.twist.tolist(), "shift": self.shift.tolist()}


@dataclass(frozen=True)
class FreedomResult:
    """Result of :func:`freedoms`.

    Attributes
    ----------
    twists : ndarray (dof, 6)
        A basis of the freedom space ``[v; w]`` about O (orthonormal in normalised
        coordinates).
    freedoms : tuple of Freedom
        The classified basis: translations first, then rotations, then helical freedoms.
    wrenches : ndarray (m, 6)
        The constraint wrenches given.
    constraint_rank : int
        Rank of the wrenches (``6 - dof``).
    singular_values : ndarray
        Of the normalised, row-scaled wrench matrix, descending.
    tolerance : float
        The absolute threshold on those singular values.
    residual : float
        Largest ``|W . V|`` over the given wrenches and the basis twists, normalised
        (both unit in normalised coordinates): ~1e-15 when the basis is reciprocal.
    condition_number : float
        Largest over smallest retained singular value of the wrenches (``inf`` for
        none): large values mean the rank decision is close.
    margin : float
        Smallest retained singular value over the tolerance (``inf`` when none is
        retained; > 1 always): how far the rank decision is from flipping.
    normalisation : Normalisation
    """

    twists: np.ndarray
    freedoms: tuple
    wrenches: np.ndarray
    constraint_rank: int
    singular_values: np.ndarray
    tolerance: float
    residual: float
    condition_number: float
    margin: float
    normalisation: Normalisation

    @property
    def dof(self) -> int:
        """Number of independent freedoms, ``6 - constraint_rank``."""
        return 6 - self.constraint_rank

    @property
    def translations(self) -> int:
        return sum(f.kind == "translation" for f in self.freedoms)

    @property
    def rotations(self) -> int:
        return sum(f.kind == "rotation" for f in self.freedoms)

    @property
    def helical(self) -> int:
        return sum(f.kind == "helical" for f in self.freedoms)

    @property
    def pitches(self) -> tuple:
        """Pitches of the helical freedoms (model lengths per radian)."""
        return tuple(float(f.pitch) for f in self.freedoms if f.kind == "helical")

    @property
    def label(self) -> str:
        """``"3T"``, ``"1T2R"``, ``"1H"``, ``"2R1H"``..., ``"0"`` for a rigid body: counts of
        translations, rotations and helical freedoms."""
        out = "".join(f"{n}{c}" for n, c in ((self.translations, "T"), (self.rotations, "R"),
                                             (self.helical, "H")) if n)
        return out or "0"

    def summary(self, unit: str = "") -> str:
        """One line: the label and each freedom in words."""
        if not self.freedoms:
            return "0: no freedom (rigid)"
        return f"{self.label}: " + "; ".join(f.describe(unit) for f in self.freedoms)


def _fmt(v) -> str:
    v = np.asarray(v, float)
    v = np.where(np.abs(v) < 5e-13 * max(1.0, float(np.abs(v).max())), 0.0, v)
    return "(" + ", ".join(f"{x:.6g}" for x in v + 0.0) + ")"


def _signed(d):
    """A direction with its largest component positive (independent of the SVD's sign)."""
    d = np.asarray(d, float)
    return d if d[np.argmax(np.abs(d))] >= 0 else -d


def _skew(p):
    return np.array([[0.0, -p[2], p[1]], [p[2], 0.0, -p[0]], [-p[1], p[0], 0.0]])


def freedoms(wrenches: ArrayLike | Sequence[Wrench], points: ArrayLike | None = None,
             length: float | None = None,
             rtol: float = RANK_RTOL, geometry_rtol: float = GEOMETRY_RTOL) -> FreedomResult:
    """The twists reciprocal to a system of constraint wrenches, classified.

    Parameters
    ----------
    wrenches : array_like, shape (m, 6), or a sequence of Wrench
        Constraint wrenches ``[f; m]`` (moments about O), any scale; ``m = 0`` (no
        constraint) gives the six freedoms of a free body.  At most :data:`MAX_WRENCHES`.
    points : array_like, shape (p, 3), optional
        Points of the geometry; they set the centre and characteristic length of the
        normalisation.  Default: the points of the force lines closest to the origin
        (the origin when there are only couples).
    length : float, optional
        Overrides the characteristic length.
    rtol : float
        Relative rank tolerance (default :data:`~screwkit.screws.RANK_RTOL`).
    geometry_rtol : float
        A principal pitch below ``geometry_rtol`` times the characteristic length is a
        rotation (default :data:`~screwkit.screws.GEOMETRY_RTOL`).

    Returns
    -------
    FreedomResult

    Raises
    ------
    InputError
        Not an ``(m, 6)`` array of finite numbers, more than :data:`MAX_WRENCHES` rows, or
        a zero wrench.
    """
    W = _check_matrix(wrenches, "wrenches")                   # (Wrench objects too)
    rtol, geometry_rtol = check_rtol(rtol), check_rtol(geometry_rtol, "geometry_rtol")
    if len(W) > MAX_WRENCHES:
        raise InputError(f"{len(W)} wrenches: at most {MAX_WRENCHES}")
    zero = [i for i, row in enumerate(W) if not np.any(row)]
    if zero:
        raise InputError(f"wrenches[{zero[0]}] is zero: a constraint needs a force or a couple")
    Ws = W / np.abs(W).max(axis=1, keepdims=True) if len(W) else W   # (magnitude-free: 1e200)
    if points is None:
        f = Ws[:, :3]
        ff = np.sum(f * f, axis=1)
        pts = [cross(f[i], Ws[i, 3:]) / ff[i] for i in range(len(Ws)) if ff[i] > 0]
        points = np.array(pts) if pts else np.zeros((1, 3))
    norm = Normalisation.for_points(points, length)
    Wn = _unit_rows(norm.wrenches(Ws)) if len(W) else np.zeros((0, 6))
    if len(Wn):
        _, s, Vt = svd_full(Wn)
        tol = rtol * max(1.0, float(s[0]))
        rank = sum(x > tol for x in s.tolist())
    else:
        s, Vt, tol, rank = np.zeros(0), np.eye(6), rtol, 0
    Vn = Vt[rank:]                                    # normalised twists, orthonormal
    residual = float(np.abs(Wn @ Vn.T).max()) if len(Wn) and len(Vn) else 0.0
    cond = float(s[0] / s[rank - 1]) if rank else float("inf")
    margin = float(s[rank - 1] / tol) if rank else float("inf")
    items = classify_freedoms(Vn, norm, geometry_rtol)
    T = norm.twists_back(Vn) if len(Vn) else np.zeros((0, 6))
    for a in (T, W, s):
        a.setflags(write=False)
    return FreedomResult(T, items, W, rank, s, tol, residual, cond, margin, norm)


def classify_freedoms(Vn: np.ndarray, norm: Normalisation,
                     geometry_rtol: float = GEOMETRY_RTOL) -> tuple:
    """Translations, rotations and helical freedoms of a basis of normalised twists.

    Parameters
    ----------
    Vn : ndarray, shape (k, 6)
        An orthonormal basis of a twist space in the coordinates of ``norm``
        (``[(v - c x w) / L; w]``), e.g. the null space of normalised wrenches.
    norm : Normalisation
        Its centre ``c`` and length ``L``.
    geometry_rtol : float
        A principal pitch below ``geometry_rtol * L`` is a rotation.

    Returns
    -------
    tuple of Freedom
        Translations, then rotations, then helical freedoms (see the module docstring);
        a rotation whose direction has a component along a translation of the space is a
        rotation (the translation makes its pitch zero), whatever its pitch in the basis.
    """
    k = len(Vn)
    if k == 0:
        return ()
    L, c = norm.length, norm.centre
    w = Vn[:, 3:]
    # split into twists without rotation (null space of the angular parts) and the rest
    _, sw, Vh = np.linalg.svd(w.T, full_matrices=True)      # w.T: 3 x k
    r = int(np.sum(sw > RANK_RTOL * max(1.0, float(sw[0]) if sw.size else 1.0)))
    trans = (Vh[r:] @ Vn)[:, :3]                             # (t, 3), w = 0
    rot = Vh[:r] @ Vn                                        # (r, 6), independent rotations
    out = []
    if len(trans):
        Q = trans.T          # orthonormal translation directions (rows of two orthonormal bases)
        basis = np.eye(3) if len(trans) == 3 else Q.T
        for d in basis:
            d = _signed(d)
            out.append(Freedom("translation", d, None, float("inf"),
                               np.concatenate([d, np.zeros(3)])))
    else:
        Q = np.zeros((3, 0))
    if not r:
        return tuple(out)
    Pt = np.eye(3) - Q @ Q.T                                  # removes the translations
    v, wr = rot[:, :3] @ Pt.T, rot[:, 3:]                    # normalised: v is (v - c x w) / L
    # rotations about lines through one point X (normalised, relative to c):
    # Pt (v_i - X x w_i) = 0 for every i; the minimum-norm X puts a free location at c
    concurrent = False
    if r > 1:
        M = np.vstack([Pt @ _skew(wi) for wi in wr])         # -(X x w) = w x X = skew(w) X
        b = -v.reshape(-1)
        X, *_ = np.linalg.lstsq(M, b, rcond=None)
        res = float(np.linalg.norm(M @ X - b))
        concurrent = res <= geometry_rtol * max(1.0, float(np.linalg.norm(b)))
    if concurrent:
        # any line through X is a freedom: report an orthonormal basis of the directions
        dirs = np.eye(3) if r == 3 else np.linalg.qr(wr.T)[0][:, :r].T
        for d in dirs:
            d = _signed(d)
            out.append(_screw_freedom("rotation", d, X, 0.0, L, c, Q))
        return tuple(out)
    # rotational twists whose rotation has a component along a translation: adding that
    # translation sets their pitch to any value, zero included, so they are rotations
    # (group 2, ``s`` of them); the others (group 1, w normal to every translation) have a
    # pitch that no translation changes: their principal screws decide
    G = wr @ Q                                                # (r, t)
    if G.size:
        U, sg, _ = np.linalg.svd(G, full_matrices=True)
        ns = int(np.sum(sg > RANK_RTOL * max(1.0, float(sg[0]))))
    else:
        U, ns = np.eye(r), 0
    Y1, Y2 = U[:, ns:].T, U[:, :ns].T
    w1, v1 = Y1 @ wr, Y1 @ v
    if len(w1):
        A = 0.5 * (w1 @ v1.T + v1 @ w1.T)
        # B^(-1/2) for B = w1 w1^T, from the singular values of w1 (the eigenvalues of B
        # would be their squares: an angular part just above the rank tolerance, 1e-8,
        # gives an eigenvalue of 1e-16, which rounding can make negative)
        Ub, sb, _ = np.linalg.svd(w1, full_matrices=False)
        Bm = Ub @ np.diag(1.0 / sb) @ Ub.T
        hs, Y = np.linalg.eigh(Bm @ A @ Bm)
        for h, y in zip(hs.tolist(), (Bm @ Y).T):
            wd, vd = y @ w1, y @ v1
            n = float(np.linalg.norm(wd))
            wd, vd = wd / n, vd / n
            # axis point (normalised, relative to c): X = w x v / |w|^2
            kind = "rotation" if abs(h) <= geometry_rtol else "helical"
            out.append(_screw_freedom(kind, _signed(wd), cross(wd, vd),
                                      h * L if kind == "helical" else 0.0, L, c, Q))
    if ns:
        # group 2 made B-orthogonal to group 1 (its rotations' components along the
        # translations are unchanged), each made a rotation by its translation
        w2, v2 = Y2 @ wr, Y2 @ v
        if len(w1):
            C = np.linalg.solve(w1 @ w1.T, w1 @ w2.T).T           # (ns, r - ns)
            w2, v2 = w2 - C @ w1, v2 - C @ v1
        Qw = np.linalg.qr(w2.T)[0][:, :ns].T                      # orthonormal directions
        Cw = np.linalg.lstsq(w2.T, Qw.T, rcond=None)[0].T
        for wd, vd in zip(Cw @ w2, Cw @ v2):
            n = float(np.linalg.norm(wd))
            wd, vd = wd / n, vd / n
            q = Q @ (Q.T @ wd)                                    # its part along translations
            vd = vd - (wd @ vd) / (wd @ q) * q                    # pitch zero
            out.append(_screw_freedom("rotation", _signed(wd), cross(wd, vd), 0.0, L, c, Q))
    return tuple(out)


def _normal_shifts(d, Q) -> np.ndarray:
    """Directions ``s = d x t`` (``t``: the translations ``Q (3, t)`` normal to ``d``) the
    axis along ``d`` may move along: the twist gains ``s x d = t``, a translation held."""
    if Q.shape[1] == 0:
        return np.zeros((0, 3))
    N = Q - np.outer(d, d @ Q)                        # the translations' parts normal to d
    U, s, _ = np.linalg.svd(N, full_matrices=False)
    k = int(np.sum(s > GEOMETRY_RTOL))
    out = np.array([_signed(cross(d, u)) for u in U[:, :k].T]).reshape(k, 3)
    out.setflags(write=False)
    return out


def _screw_freedom(kind, d, Xn, pitch, L, c, Q) -> Freedom:
    """A rotation or helical freedom from its unit direction, its normalised axis point
    (relative to the centre c, divided by L) and its physical pitch."""
    P = c + L * np.asarray(Xn, float)
    v = cross(P, d) + pitch * d
    return Freedom(kind, d, P, float(pitch), np.concatenate([v, d]), _normal_shifts(d, Q))
