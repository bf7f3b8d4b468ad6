"""Reciprocal-screw systems: constraint wrenches of a set of joint twists.

The constraint wrenches of a serial chain are the wrenches reciprocal to every
joint twist: the null space of the twist matrix under ``W o V = W . V``.  The
null space is computed by SVD on *length-normalised* screws (moved to the
centroid of the geometry and with lengths divided by its characteristic length,
see :mod:`screwkit.screws._tolerance`) so that the rank decision is invariant under a
change of base frame and of length units.

Examples
--------
>>> import numpy as np
>>> from screwkit.screws import revolute_twist, prismatic_twist
>>> T = np.array([revolute_twist([0, 0, 1], [0, 0, 0]).vector,
...               prismatic_twist([1, 0, 0]).vector])
>>> sys = reciprocal_system(T, points=[[0, 0, 0]])
>>> sys.rank, sys.dimension
(2, 4)
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from ..errors import InputError
from ._frozen import freeze_fields
from ._matrix import _check_matrix
from ._tolerance import RANK_RTOL, _centroid_and_length, check_rtol
from ._svd import small_rank, svd_full, svd_values
from ._vector import cross

__all__ = [
    "Normalisation",
    "ReciprocalSystem",
    "reciprocal_system",
    "independent_subset",
    "same_span",
    "span_contains",
    "compare_spans",
    "twist_rank",
]


@dataclass(frozen=True)
class Normalisation:
    """Map between physical screws and length-normalised screws.

    A twist ``[v; w]`` becomes ``[(v - c x w) / L; w]`` (moved to the centroid
    ``c`` and divided by the length ``L``); a wrench ``[f; m]`` becomes
    ``[f; (m - c x f) / L]``.  The reciprocal product of normalised screws is
    the physical one divided by ``L``, so null spaces correspond exactly.
    """

    centre: np.ndarray
    length: float

    def __post_init__(self):
        c = np.array(self.centre, float)            # (its own copy, read-only)
        c.setflags(write=False)
        object.__setattr__(self, "centre", c)

    @classmethod
    def for_points(cls, points, length: float | None = None) -> "Normalisation":
        try:
            p = np.asarray(points, dtype=float)
        except (TypeError, ValueError, OverflowError):
            raise InputError(f"points must be a (p, 3) array of numbers, got "
                             f"{str(points)[:60]}") from None
        if p.size % 3 or (p.ndim > 1 and p.shape[-1] != 3) or not np.all(np.isfinite(p)):
            raise InputError(f"points must be a (p, 3) array of finite numbers, got shape "
                             f"{p.shape}")
        p = p.reshape(-1, 3)
        if length is not None:
            c, L = (p.mean(axis=0) if p.size else np.zeros(3)), float(length)
        elif p.size:
            c, L = _centroid_and_length(p)
        else:
            c, L = np.zeros(3), 1.0          # characteristic_length of no points
        if not (np.isfinite(L) and L > 0):
            raise InputError(f"characteristic length must be positive and finite, got {L}")
        return cls(c, L)

    def twists(self, T) -> np.ndarray:
        T = np.asarray(T, float)
        if _small(T, self.length):
            return _shifted(T, self.centre, self.length, True, False)
        w = T[..., 3:]
        v = (T[..., :3] - cross(self.centre, w)) / self.length
        return np.concatenate([v, w], axis=-1)

    def wrenches(self, W) -> np.ndarray:
        W = np.asarray(W, float)
        if _small(W, self.length):
            return _shifted(W, self.centre, self.length, False, False)
        f = W[..., :3]
        m = (W[..., 3:] - cross(self.centre, f)) / self.length
        return np.concatenate([f, m], axis=-1)

    def wrenches_back(self, Wn) -> np.ndarray:
        Wn = np.asarray(Wn, float)
        if _small(Wn, self.length):
            return _shifted(Wn, self.centre, self.length, False, True)
        f = Wn[..., :3]
        m = Wn[..., 3:] * self.length + cross(self.centre, f)
        return np.concatenate([f, m], axis=-1)

    def twists_back(self, Tn) -> np.ndarray:
        Tn = np.asarray(Tn, float)
        if _small(Tn, self.length):
            return _shifted(Tn, self.centre, self.length, True, True)
        w = Tn[..., 3:]
        v = Tn[..., :3] * self.length + cross(self.centre, w)
        return np.concatenate([v, w], axis=-1)


#: Up to this many screws, the maps of :class:`Normalisation` and :func:`_unit_rows` work
#: on Python floats: numpy's per-call overhead dominates on a handful of 6-vectors.
_SMALL_ROWS = 16


def _small(S: np.ndarray, length) -> bool:
    # a zero length would raise ZeroDivisionError on floats where numpy gives inf/nan
    return ((S.ndim == 1 and S.shape == (6,)) or
            (S.ndim == 2 and S.shape[1] == 6 and 0 < len(S) <= _SMALL_ROWS)) and length != 0


def _shifted(S: np.ndarray, centre, length, moved_first: bool, back: bool) -> np.ndarray:
    """The maps of :class:`Normalisation` on Python floats, operation for operation the
    same as the array expressions (so bit for bit the same results).

    ``moved_first``: the first three components move (twists), else the last three
    (wrenches); ``back``: ``x L + c x r`` instead of ``(x - c x r) / L``."""
    c0, c1, c2 = np.asarray(centre, float).tolist()
    L = float(length)
    out = []
    for row in (S.tolist() if S.ndim == 2 else [S.tolist()]):
        if moved_first:
            x0, x1, x2, r0, r1, r2 = row
        else:
            r0, r1, r2, x0, x1, x2 = row
        m0, m1, m2 = c1 * r2 - c2 * r1, c2 * r0 - c0 * r2, c0 * r1 - c1 * r0   # c x r
        if back:
            y = [x0 * L + m0, x1 * L + m1, x2 * L + m2]
        else:
            y = [(x0 - m0) / L, (x1 - m1) / L, (x2 - m2) / L]
        out.append(y + [r0, r1, r2] if moved_first else [r0, r1, r2] + y)
    return np.array(out if S.ndim == 2 else out[0])


@dataclass(frozen=True)
class ReciprocalSystem:
    """Result of :func:`reciprocal_system`.

    Attributes
    ----------
    wrenches : ndarray, shape (k, 6)
        Basis of the constraint-wrench system ``[f; m]`` (moments about O).
        Orthonormal in normalised coordinates.
    singular_values : ndarray, shape (min(m, 6),)
        Singular values of the normalised twist matrix with its rows scaled to
        unit norm (scale-invariant), descending.
    rank : int
        Rank of the twists (the chain's connectivity).
    n_twists : int
    tolerance : float
        Absolute threshold used on the normalised singular values.
    normalisation : Normalisation
    residual : float
        Largest normalised ``|W . V|`` over basis wrenches and twists.
    """

    wrenches: np.ndarray
    singular_values: np.ndarray
    rank: int
    n_twists: int
    tolerance: float
    normalisation: Normalisation
    residual: float

    def __post_init__(self):
        freeze_fields(self, ("wrenches", "singular_values"))

    @property
    def dimension(self) -> int:
        """Number of independent constraint wrenches, ``6 - rank``."""
        return 6 - self.rank

    @property
    def dependent(self) -> bool:
        """True when the twists are linearly dependent (fewer independent joints than joints)."""
        return self.rank < self.n_twists

    @property
    def condition_number(self) -> float:
        """Ratio of the largest to the smallest *retained* singular value of the twists."""
        s = self.singular_values[: self.rank]
        return float(s[0] / s[-1]) if self.rank else float("inf")


def _unit_rows(M) -> np.ndarray:
    """Rows scaled to unit norm (zero rows left zero).

    Row scaling leaves the row space and the null space unchanged; it makes the
    singular values independent of the length unit for prismatic twists
    (``[u; 0]`` normalises to ``[u / L; 0]``) and for couples (``[0; t / L]``),
    so that rank decisions are scale-invariant.
    """
    M = np.asarray(M, float)
    if M.size == 0:
        return M
    if M.ndim == 2 and M.shape[1] == 6 and len(M) <= _SMALL_ROWS:
        # Python floats: the same sum of squares in the same order as numpy's row norm
        out = []
        for row in M.tolist():
            a0, a1, a2, a3, a4, a5 = row
            n = math.sqrt(a0 * a0 + a1 * a1 + a2 * a2 + a3 * a3 + a4 * a4 + a5 * a5)
            out.append([x / n for x in row] if n > 0 else row)
        return np.array(out)
    n = np.linalg.norm(M, axis=-1, keepdims=True)
    return M / np.where(n > 0, n, 1.0)


def reciprocal_system(twists, points=None, length: float | None = None,
                      rtol: float = RANK_RTOL) -> ReciprocalSystem:
    """Constraint-wrench system reciprocal to ``twists``.

    Parameters
    ----------
    twists : array_like, shape (m, 6)
        Joint twists ``[v; w]`` about the base origin.
    points : array_like, shape (p, 3), optional
        Points of the geometry (joint points); they set the centre and the
        characteristic length of the normalisation.  Default: the points of the
        twist axes closest to the origin.
    length : float, optional
        Overrides the characteristic length.
    rtol : float
        Relative rank tolerance on normalised singular values.

    Returns
    -------
    ReciprocalSystem
    """
    T = _check_matrix(twists, "twists")
    rtol = check_rtol(rtol)
    if points is None:
        w = T[:, 3:]
        ww = np.sum(w * w, axis=1)
        pts = [cross(w[i], T[i, :3]) / ww[i] for i in range(len(T)) if ww[i] > 0]
        points = np.array(pts) if pts else np.zeros((1, 3))
    norm = Normalisation.for_points(points, length)
    Tn = _unit_rows(norm.twists(T))
    if len(Tn) == 0:
        s = np.zeros(0)
        rank = 0
        Vt = np.eye(6)
        tol = rtol
    else:
        _, s, Vt = svd_full(Tn)
        tol = rtol * max(1.0, float(s[0]))
        rank = sum(x > tol for x in s.tolist())
    basis_n = Vt[rank:]
    W = norm.wrenches_back(basis_n)
    residual = float(np.abs(Tn @ basis_n.T).max()) if basis_n.size and len(Tn) else 0.0
    W.setflags(write=False)
    return ReciprocalSystem(W, s, rank, len(T), tol, norm, residual)


def twist_rank(twists, points=None, length: float | None = None, rtol: float = RANK_RTOL) -> int:
    """``reciprocal_system(twists, points, length, rtol).rank`` without the wrench basis."""
    T = _check_matrix(twists, "twists")
    rtol = check_rtol(rtol)
    if points is None:
        return reciprocal_system(T, None, length, rtol).rank
    norm = Normalisation.for_points(points, length)
    Tn = _unit_rows(norm.twists(T))
    if len(Tn) == 0:
        return 0
    s = svd_values(Tn).tolist()
    tol = rtol * max(1.0, s[0])
    return sum(x > tol for x in s)


def independent_subset(twists, points=None, rtol: float = RANK_RTOL) -> tuple[list[int], list[int]]:
    """Split joint indices into a maximal independent prefix-greedy set and the dependent rest.

    A joint is *dependent* when its twist lies in the span of the twists of the
    joints before it (in chain order).

    Returns
    -------
    independent, dependent : list of int
    """
    T = _check_matrix(twists, "twists")
    rtol = check_rtol(rtol)
    if points is None:
        points = np.zeros((1, 3))
    norm = Normalisation.for_points(points)
    Tn = _unit_rows(norm.twists(T))
    independent: list[int] = []
    dependent: list[int] = []
    if _orth_rank(Tn, rtol) == len(Tn):
        # every subset of independent rows is independent: the singular values of a
        # subset of rows are no smaller (interlacing) and its threshold no larger
        return list(range(len(Tn))), []
    for i in range(len(Tn)):
        if _rank_of(Tn[independent + [i]], rtol) == len(independent) + 1:
            independent.append(i)
        else:
            dependent.append(i)
    return independent, dependent


def _orth_rank(M, rtol):
    if M.size == 0:
        return 0
    return _rank_of(_unit_rows(M), rtol)


def _rank_of(M: np.ndarray, rtol) -> int:
    """Singular values of M above ``rtol * max(1, s_max)``: in closed form for one or two
    rows (the same decisions, see :mod:`screwkit.screws._svd`), else by the SVD."""
    r = small_rank(M.tolist(), rtol) if len(M) <= 2 else None
    if r is None:
        s = svd_values(M).tolist()
        tol = rtol * max(1.0, s[0])
        r = sum(x > tol for x in s)
    return r


def same_span(A, B, norm: Normalisation, rtol: float = 1e-7, kind: str = "wrench") -> bool:
    """True when two sets of screws (rows) span the same subspace (normalised comparison)."""
    f = norm.wrenches if kind == "wrench" else norm.twists
    An = f(_check_matrix(A, "A")) if len(A) else np.zeros((0, 6))
    Bn = f(_check_matrix(B, "B")) if len(B) else np.zeros((0, 6))
    ra, rb = _orth_rank(An, rtol), _orth_rank(Bn, rtol)
    return ra == rb == _orth_rank(np.vstack([An, Bn]), rtol)


def compare_spans(A, W, norm: Normalisation, rtol: float = 1e-7,
                  kind: str = "wrench") -> tuple[tuple, bool]:
    """Whether each row of ``W`` lies in the span of the rows of ``A``, and whether the two
    sets span the same subspace: :func:`span_contains` for each row and :func:`same_span`,
    every rank they need taken from one stacked SVD call.

    Returns
    -------
    contained : tuple of bool
    same : bool
    """
    f = norm.wrenches if kind == "wrench" else norm.twists
    An = f(_check_matrix(A, "A")) if len(A) else np.zeros((0, 6))
    Wr = np.asarray(W, float).reshape(-1, 6)
    Wn = f(_check_matrix(Wr, "B")) if len(Wr) else np.zeros((0, 6))
    a, w = _unit_rows(An).tolist(), _unit_rows(Wn).tolist()
    # rank(A), rank(W), rank([W; A]) and each rank([A; w_i]) in one stacked SVD: the
    # matrices padded with zero rows, which add only zero singular values
    mats = [a, w, w + a] + [a + [wi] for wi in w]
    ranks = [0 if not m else small_rank(m, rtol) for m in mats]
    if None not in ranks:              # one or two rows each: closed forms
        return tuple(r == ranks[0] for r in ranks[3:]), ranks[1] == ranks[0] == ranks[2]
    height = max(1, len(a) + len(w))
    zero = [0.0] * 6
    stack = np.array([m + [zero] * (height - len(m)) for m in mats])
    ranks = []
    for sv in svd_values(stack).tolist():
        tol = rtol * max(1.0, sv[0])
        ranks.append(sum(x > tol for x in sv))
    ra, rw, raw = ranks[:3]
    return tuple(r == ra for r in ranks[3:]), rw == ra == raw


def span_contains(A, w, norm: Normalisation, rtol: float = 1e-7, kind: str = "wrench") -> bool:
    """True when screw ``w`` lies in the span of the rows of ``A`` (normalised comparison)."""
    f = norm.wrenches if kind == "wrench" else norm.twists
    An = f(_check_matrix(A, "A")) if len(A) else np.zeros((0, 6))
    wn = f(np.asarray(w, float).reshape(1, 6))
    wn = wn / max(np.linalg.norm(wn), 1e-300)
    return _orth_rank(An, rtol) == _orth_rank(np.vstack([An, wn]), rtol)
