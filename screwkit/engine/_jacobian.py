"""The unified 6x6 Jacobian ``J = [J_a; J_c]`` of N poses, and what its conditioning says.

Every leg contributes one **actuation row** (the wrench its actuator transmits
to the platform, reciprocal to the leg's passive joints and scaled to unit
reciprocal product with the actuated joint's unit twist, so that ``row . V``
is the actuator velocity) and its **constraint rows** (unit pure forces, unit
pure couples or finite-pitch screws with ``|f| = 1``, reciprocal to every
joint of the leg).  ``J`` maps the platform twist ``V = [v_O; w]`` to
``[actuator velocities; 0]`` (paper eq. 7b).  Rows are wrenches ``[f; m]``
with moments about the base origin ``O``; the paper's rows about the platform
centre ``o`` give the same products with ``[v_o; w]`` (:meth:`JacobianResult.rows_about`).

Condition number.  Rows are moved to the centroid of the geometry (every
leg's points and ``o``), their moments divided by its characteristic length,
and scaled to unit norm; ``s_1 / s_6`` of that matrix is unit-free and does
not change with the base frame.  The pose is **singular** above
:data:`COND_THRESHOLD`: ``kind="constraint"`` when the constraint rows alone
lose the rank ``6 - n`` the ``n`` actuators need, else ``"actuation"``.

Examples
--------
>>> import screwkit
>>> from screwkit.engine import unified_jacobian
>>> from screwkit.legs import Placement
>>> A = [[100, 0, 0], [-50, 86.6, 0], [-50, -86.6, 0], [100, 20, 0], [-50, 70, 0], [-50, -100, 0]]
>>> a = [[40, 10, 80], [-30, 40, 80], [-10, -40, 80], [30, -40, 80], [-40, -10, 80], [10, 40, 80]]
>>> legs = [screwkit.leg("SPS", Placement(A[i], a[i], o=[0, 0, 80])) for i in range(6)]
>>> jac = unified_jacobian(legs, [0, 0, 80])
>>> jac.J.shape, jac.n_actuated, jac.rank
((6, 6), 6, 6)
"""

from __future__ import annotations

import functools
from dataclasses import dataclass, field
from functools import cached_property
from typing import Callable

import numpy as np
from numpy.typing import ArrayLike

from ._frozen import freeze_fields
from ._inputs import pose_index
from ._pipeline import COND_THRESHOLD, Conditioning
from ._subsets import _legs_of_pose, _legs_of_subset, _rows_of_pose, _rows_of_subset
from ._row import JacobianRow
from ..screws import cross
from ..errors import InputError, MisuseError

__all__ = ["COND_THRESHOLD", "JacobianRow", "JacobianResult"]


def _squeeze(x, single):
    return x[0] if single else x


@dataclass(frozen=True, eq=False)
class JacobianResult:
    """The unified Jacobian at N poses (``single``: one pose, arrays without the pose axis).

    Attributes
    ----------
    matrix : ndarray (N, m, 6)
        Rows ``[f; m]`` about ``O``: ``n`` actuation rows (leg order), then the constraint
        rows (leg order).  :attr:`J` is the same (squeezed for one pose).
    info : tuple of RowInfo
        What each row is (the same at every pose).
    n_actuated : int
    scale : ndarray (N, m)
    points : ndarray (N, m, 3)
        A point of each row's line, NaN for couples and for rows that are not forces.
    origin : ndarray (N, 3)
        The platform centre ``o`` at each pose.
    conditioning : Conditioning
    threshold : float
    single : bool
    leg_provider : callable, optional
        ``i -> tuple of Leg``: the placed legs at pose ``i``.
    """

    matrix: np.ndarray
    info: tuple
    n_actuated: int
    scale: np.ndarray
    points_: np.ndarray | Callable[[slice], np.ndarray] = field(repr=False)
    origin_: np.ndarray | Callable[[], np.ndarray] = field(repr=False)
    conditioning: Conditioning = field(repr=False)
    threshold: float = COND_THRESHOLD
    single: bool = True
    leg_provider: Callable[[int], tuple] | None = field(default=None, repr=False)
    given_analyses: tuple | None = field(default=None, repr=False)

    def __post_init__(self):
        # what it hands out is read-only: a written J or condition number changed later
        # analyses of this result (res.under) and its classification, silently
        freeze_fields(self, ("matrix", "scale"))
        freeze_fields(self.conditioning, tuple(self.conditioning.__dataclass_fields__))

    def normalised(self) -> tuple[np.ndarray, np.ndarray]:
        """The normalised, row-equilibrated rows ``Jn (N, m, 6)`` and row norms ``d (N, m)``."""
        return self.conditioning.normalised(self.matrix)

    def __len__(self) -> int:
        return self.matrix.shape[0]

    def __getitem__(self, i) -> "JacobianResult":
        """The Jacobian at pose ``i`` (a one-pose result)."""
        if self.single:
            raise MisuseError("a one-pose JacobianResult cannot be indexed")
        i = pose_index(i, len(self))
        if not isinstance(i, int):
            return self._subset(i)
        sl = slice(i, i + 1)
        cond = self.conditioning.take(sl)
        prov = self.leg_provider
        base = self.points_
        pts: np.ndarray | Callable[[slice], np.ndarray]
        if callable(base):
            pts = functools.partial(_rows_of_pose, base, sl)      # the points of pose i
        else:
            pts = base[sl]
        return JacobianResult(self.matrix[sl], self.info, self.n_actuated, self.scale[sl],
                              pts, self.origin[sl], cond, self.threshold, True,
                              functools.partial(_legs_of_pose, prov, i) if prov else None)

    def _subset(self, idx) -> "JacobianResult":
        """The poses ``idx`` (an integer array) as a batch."""
        base, prov = self.points_, self.leg_provider
        pts = functools.partial(_rows_of_subset, base, idx) if callable(base) else base[idx]
        return JacobianResult(self.matrix[idx], self.info, self.n_actuated, self.scale[idx],
                              pts, self.origin[idx], self.conditioning.take(idx),
                              self.threshold, False,
                              functools.partial(_legs_of_subset, prov, idx) if prov else None)

    def __repr__(self) -> str:
        if not self.single:
            return (f"JacobianResult({len(self)} poses, {self.n_rows}x6, {self.n_actuated} "
                    f"actuation rows, {int(np.sum(self.singular_mask))} singular)")
        return (f"JacobianResult({self.n_rows}x6, {self.n_actuated} actuation rows, rank "
                f"{self.rank}, condition {self.condition_number:.4g}"
                + (f", {self.singularity_kind} singularity" if self.singular else "") + ")")

    # -- arrays -----------------------------------------------------------------------
    @property
    def J(self) -> np.ndarray:
        """``(m, 6)`` for one pose, ``(N, m, 6)`` for several."""
        return _squeeze(self.matrix, self.single)

    @property
    def J_a(self) -> np.ndarray:
        return self.J[..., : self.n_actuated, :]

    @property
    def J_c(self) -> np.ndarray:
        return self.J[..., self.n_actuated:, :]

    @property
    def n_rows(self) -> int:
        return self.matrix.shape[1]

    @property
    def kinds(self) -> tuple:
        return tuple(r.kind for r in self.info)

    @property
    def labels(self) -> tuple:
        return tuple(r.label for r in self.info)

    @cached_property
    def leg_of_row(self) -> np.ndarray:
        return np.array([r.leg for r in self.info], dtype=int)

    def leg_rows(self, i: int) -> np.ndarray:
        """Indices of the rows of leg ``i`` (0-based; its actuation row first)."""
        n = 1 + int(np.max(self.leg_of_row)) if len(self.leg_of_row) else 0
        if isinstance(i, (bool, np.bool_)) or not isinstance(i, (int, np.integer)) or \
                not 0 <= i < n:
            raise InputError(f"leg index must be an integer from 0 to {n - 1}, got {i!r:.40}")
        return np.flatnonzero(self.leg_of_row == i)

    @cached_property
    def origin(self) -> np.ndarray:
        """The platform centre ``o`` at each pose, ``(N, 3)``."""
        return self.origin_() if callable(self.origin_) else self.origin_

    @property
    def o(self) -> np.ndarray:
        return _squeeze(self.origin, self.single)

    @property
    def directions(self) -> np.ndarray:
        """Unit direction of each row's force or couple, ``(N, m, 3)`` (squeezed)."""
        J = self.matrix
        couple = np.array([r.member == "couple" for r in self.info])
        part = np.where(couple[None, :, None], J[..., 3:], J[..., :3])
        n = np.linalg.norm(part, axis=-1, keepdims=True)
        return _squeeze(part / np.where(n > 0, n, 1.0), self.single)

    @cached_property
    def _points(self) -> np.ndarray:
        p = self.points_(slice(None)) if callable(self.points_) else self.points_
        p.setflags(write=False)
        return p

    @property
    def points(self) -> np.ndarray:
        """A point of each row's line (its named point), ``(N, m, 3)``; NaN for couples."""
        return _squeeze(self._points, self.single)

    @cached_property
    def rows(self) -> tuple:
        """One :class:`JacobianRow` per row (one pose only)."""
        self._one("rows")
        out = []
        D = self.directions
        for k, r in enumerate(self.info):
            p = self._points[0, k]
            has_point = r.member not in ("couple", "none") and bool(np.all(np.isfinite(p)))
            if r.member not in ("couple", "none") and not has_point:
                # a force without a named point: the point of its line nearest o
                f, m = self.matrix[0, k, :3], self.matrix[0, k, 3:]
                p = cross(f, m) / max(float(f @ f), 1e-300)
                has_point = True
            w = self.matrix[0, k]
            if r.member == "couple":
                pitch = np.inf
            elif r.member == "none":
                pitch = float("nan")
            else:                 # read off the row: 0 to rounding for a force
                pitch = float(w[:3] @ w[3:] / max(float(w[:3] @ w[:3]), 1e-300))
            member = r.member
            if member in ("force", "screw"):
                zero = abs(pitch) <= 1e-9 * float(self.conditioning.length[0])
                member, pitch = ("force", 0.0) if zero else ("screw", pitch)
            out.append(JacobianRow(r.leg, r.leg_name, r.kind, member, D[k],
                                   p if has_point else None, r.point_name, pitch,
                                   float(self.scale[0, k]), r.joint, r.label))
        return tuple(out)

    def _one(self, what):
        if not self.single:
            raise MisuseError(f"{what} is defined for one pose: index the result first (res[i])")

    @property
    def legs(self) -> tuple:
        """The placed legs (one pose)."""
        self._one("legs")
        return self.leg_provider(0) if self.leg_provider else ()

    @cached_property
    def analyses(self) -> tuple:
        """Each placed leg's :class:`~screwkit.legs.LegAnalysis` (one pose; computed on demand)."""
        if self.given_analyses is not None:
            return tuple(self.given_analyses)
        return tuple(lg.analyze() for lg in self.legs)

    @property
    def normalisation(self):
        """The :class:`~screwkit.screws.Normalisation` of the rank decisions (one pose)."""
        from ..screws import Normalisation
        self._one("normalisation")
        return Normalisation(self.conditioning.centre[0], float(self.conditioning.length[0]))

    # -- conditioning -----------------------------------------------------------------
    @property
    def singular_values(self):
        return _squeeze(self.conditioning.singular_values, self.single)

    @property
    def rank(self):
        r = self.conditioning.rank
        return int(r[0]) if self.single else r

    @property
    def condition_number(self):
        c = self.conditioning.condition_number
        return float(c[0]) if self.single else c

    @property
    def constraint_rank(self):
        r = self.conditioning.constraint_rank
        return int(r[0]) if self.single else r

    @property
    def constraint_condition_number(self):
        c = self.conditioning.constraint_condition_number
        return float(c[0]) if self.single else c

    @property
    def expected_constraint_rank(self) -> int:
        return max(0, 6 - self.n_actuated)

    @property
    def dof(self):
        """``6 - rank(J_c)``: the platform freedoms the constraint rows allow."""
        return 6 - self.constraint_rank

    @property
    def singular_mask(self) -> np.ndarray:
        return ~(self.conditioning.condition_number <= self.threshold)

    @property
    def singular(self):
        m = self.singular_mask
        return bool(m[0]) if self.single else m

    @property
    def kind_array(self) -> np.ndarray:
        """``""``, ``"actuation"`` or ``"constraint"`` per pose, ``(N,)``."""
        k = self.expected_constraint_rank
        c = self.conditioning
        con = (k > 0) & ~(c.constraint_condition_number <= self.threshold)
        return np.where(~self.singular_mask, "", np.where(con, "constraint", "actuation"))

    @property
    def singularity_kind(self):
        k = self.kind_array
        if self.single:
            return str(k[0]) or None
        return k

    @property
    def indeterminacy(self):
        """``m - rank``: the dimension of the self-stress space (0: determinate)."""
        d = self.n_rows - self.conditioning.rank
        return int(d[0]) if self.single else d

    @property
    def indeterminate(self):
        d = self.indeterminacy
        return d > 0 if self.single else d > 0

    @property
    def square(self) -> bool:
        return self.matrix.shape[1:] == (6, 6)

    @property
    def uncontrolled_twist(self) -> np.ndarray:
        """The platform twist ``[v_O; w]`` that ``J`` maps closest to zero (one pose), with
        a canonical sign (free both ways): the first significant component of ``w``, or of
        ``v_O`` for a translation, positive."""
        self._one("uncontrolled_twist")
        from ..screws._echelon import canonical_twist_sign
        Jn = self.normalised()[0][0]
        u = np.linalg.svd(Jn, full_matrices=True)[2][-1]           # [v_O / L; w], unit
        return self.normalisation.twists_back(canonical_twist_sign(u))

    def check(self) -> "JacobianResult":
        """Return self, or raise :class:`SingularityError` at a singular pose (the first)."""
        if not self.singular_mask.any():
            return self
        from ..errors import SingularityError
        if not self.single:
            i = int(np.flatnonzero(self.singular_mask)[0])
            self[i].check()
        kind = self.singularity_kind
        if kind == "constraint":
            why = (f"the constraint rows keep only rank {self.constraint_rank} "
                   f"(condition {self.constraint_condition_number:.3g}) of the "
                   f"{self.expected_constraint_rank} the {self.n_actuated} actuators need")
        else:
            why = ("the constraint rows keep their rank but the actuation rows do not "
                   "complete them to 6 independent wrenches")
        w = self.uncontrolled_twist
        raise SingularityError(
            f"{kind} singularity at o = {np.round(self.o, 9).tolist()}: normalised condition "
            f"number {self.condition_number:.3g} > {self.threshold:.3g}; {why}; uncontrolled "
            f"twist [v_O; w] ~ {(np.round(w / max(np.abs(w).max(), 1e-300), 4) + 0.0).tolist()}",
            kind=kind, condition_number=self.condition_number)

    def rows_about(self, point: ArrayLike) -> np.ndarray:
        """``J`` with the moments about ``point`` ``(3,)`` or ``(N, 3)``: ``[f; m - point x f]``."""
        from ._statics_inputs import _finite3
        p, J = _finite3(point, "point"), self.J
        if p.ndim > 2 or (p.ndim == 2 and (self.single or p.shape[0] != len(self))):
            raise InputError(f"point must be (3,) or ({len(self)}, 3), one a pose, got {p.shape}")
        p = p[:, None, :] if p.ndim == 2 else p       # (N, 1, 3): against each pose's rows
        return np.concatenate([J[..., :3], J[..., 3:] - cross(np.broadcast_to(p, J[..., :3].shape),
                                                             J[..., :3])], axis=-1)

    def describe(self) -> str:
        self._one("describe")
        lines = [f"unified Jacobian: {self.n_rows} rows ({self.n_actuated} actuation, "
                 f"{self.n_rows - self.n_actuated} constraint), rank {self.rank}, "
                 f"normalised condition number {self.condition_number:.6g}"]
        lines += ["  " + r.describe() for r in self.rows]
        return "\n".join(lines)
