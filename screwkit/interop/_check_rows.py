"""The rows of a Pinocchio cross-check (name, deviation, tolerance) and their reports, and the
dimensionless deviations they are made of."""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from ..errors import InputError
from ..screws import RANK_RTOL

__all__ = ["CHECK_RTOL", "CheckRow", "CheckReport"]


#: Default relative tolerance of every deviation (closure, twists, statics).
CHECK_RTOL = 1e-9

_TINY = 1e-300


@dataclass(frozen=True)
class CheckRow:
    """One comparison: its largest dimensionless deviation against its tolerance."""

    name: str
    deviation: float
    tolerance: float
    passed: bool


class _RowLookup:
    """``failed`` and ``row(name)`` for reports that hold a tuple of :class:`CheckRow`."""

    rows: tuple

    @property
    def failed(self) -> tuple:
        """Names of the rows that failed."""
        return tuple(r.name for r in self.rows if not r.passed)

    def row(self, name: str) -> CheckRow:
        for r in self.rows:
            if r.name == name:
                return r
        raise InputError(f"no check row {name!r}; rows: {', '.join(r.name for r in self.rows)}")


@dataclass(frozen=True)
class CheckReport(_RowLookup):
    """Result of a cross-check.

    Attributes
    ----------
    rows : tuple of CheckRow
    values : tuple of (str, float)
        Measured quantities that are not deviations (DOF, ranks, condition).
    """

    rows: tuple
    values: tuple = ()

    @property
    def passed(self) -> bool:
        return all(r.passed for r in self.rows)

    def value(self, name: str):
        for k, v in self.values:
            if k == name:
                return v
        raise InputError(f"no value {name!r}; values: {', '.join(k for k, _ in self.values)}")

    def as_dict(self) -> dict:
        return {"passed": self.passed,
                "rows": [{"name": r.name, "deviation": r.deviation, "tolerance": r.tolerance,
                          "passed": r.passed} for r in self.rows],
                "values": dict(self.values)}

    def __str__(self) -> str:
        lines = [f"{'ok ' if r.passed else 'BAD'} {r.name:<32} {r.deviation:.3e} (tol {r.tolerance:.0e})"
                 for r in self.rows]
        lines += [f"    {k:<32} {v}" for k, v in self.values]
        return "\n".join(lines)


def _row(name, dev, tol) -> CheckRow:
    dev = float(dev)
    return CheckRow(name, dev, float(tol), bool(np.isfinite(dev) and dev <= tol))


def _rel_product(wn, Vn) -> float:
    """|wn . Vn| / (|wn| |Vn|): a reciprocal product relative to its largest possible size."""
    return abs(float(wn @ Vn)) / max(float(np.linalg.norm(wn) * np.linalg.norm(Vn)), _TINY)


def _orth(M, rtol=RANK_RTOL):
    """Orthonormal basis (rows) of the row space of M."""
    _, s, Vt = np.linalg.svd(np.atleast_2d(M), full_matrices=False)
    return Vt[: int(np.sum(s > rtol * max(1.0, float(s[0]) if s.size else 1.0)))]


def _span_gap(A, B) -> float:
    """Largest distance of a unit row of A from span(B) and of B from span(A)."""
    gap = 0.0
    for X, Y in ((A, B), (B, A)):
        Q = _orth(Y)
        for x in X:
            x = x / max(np.linalg.norm(x), _TINY)
            gap = max(gap, float(np.linalg.norm(x - (Q @ x) @ Q)))
    return gap
