"""The unified 6x6 Jacobian of a parallel manipulator: actuation and constraint wrenches.

Given the legs of a PM placed at one pose, every leg contributes

* one **actuation row**: the wrench its actuator transmits to the platform
  (:attr:`screwkit.legs.LegAnalysis.actuation`), reciprocal to the leg's
  passive joints and scaled to unit reciprocal product with the actuated
  joint's unit twist, so that ``row . V`` is the actuator velocity;
* its **constraint rows**: the leg's constraint wrenches (unit pure forces,
  unit pure couples, finite-pitch screws with ``|f| = 1``), reciprocal to
  every joint of the leg, so that ``row . V = 0`` for every twist the leg
  allows.

``J = [J_a; J_c]`` (actuation rows first, in leg order, then constraint rows in
leg order) maps the platform twist ``V = [v_O; w]`` to ``[actuator velocities;
0]`` (paper eq. 7b).  Rows are wrenches ``[f; m]`` with moments about the base
origin ``O``; the paper writes them about the platform centre ``o``
(``[c; rho x c]``, ``rho`` from ``o``) with ``V = [v_o; w]``: the products are
equal, so both give the same statics (:meth:`JacobianResult.rows_about`).

Condition number
----------------
The rows are *length-normalised* before any rank or conditioning decision:
moments are taken about the centroid ``c`` of the geometry (all leg points and
``o``) and divided by its characteristic length ``L``
(:class:`screwkit.screws.Normalisation`), then each row is scaled to unit
Euclidean norm (row scaling does not change the rank and removes the arbitrary
scale of each row: a unit couple becomes comparable with a unit force at arm
``L``).  The condition number is the ratio of the largest to the 6th singular
value of that matrix: it is unit-free and does not change when the base frame
is moved or every length is multiplied by 1000.

Singularity
-----------
The pose is singular when the normalised condition number exceeds
:data:`COND_THRESHOLD` (``1 / RANK_RTOL = 1e8``) or ``J`` has fewer than 6
independent rows.  ``kind="constraint"`` when the constraint rows alone lose
their expected rank ``6 - n`` (``n`` actuation rows; condition of their first
``6 - n`` singular values above the threshold, or too few rows): the legs no
longer constrain the platform; otherwise ``kind="actuation"``: the constraints
hold but the actuators cannot control (or balance) some twist.

Examples
--------
>>> import numpy as np
>>> from screwkit.engine import unified_jacobian
>>> from screwkit.legs import Leg
>>> import screwkit
>>> from screwkit.legs import Placement
>>> A = [[100, 0, 0], [-50, 86.6, 0], [-50, -86.6, 0], [100, 20, 0], [-50, 70, 0], [-50, -100, 0]]
>>> a = [[40, 10, 80], [-30, 40, 80], [-10, -40, 80], [30, -40, 80], [-40, -10, 80], [10, 40, 80]]
>>> legs = [screwkit.leg("SPS", Placement(A[i], a[i], o=[0, 0, 80])) for i in range(6)]
>>> jac = unified_jacobian(legs, [0, 0, 80])
>>> jac.J.shape, jac.n_actuated, jac.rank
((6, 6), 6, 6)
"""

from __future__ import annotations

from dataclasses import dataclass, field
from functools import cached_property

import numpy as np

from ..errors import InputError, SingularityError
from ..legs import Leg, point_label
from ..screws import Normalisation, RANK_RTOL, as_vector3

__all__ = ["COND_THRESHOLD", "JacobianRow", "JacobianResult", "unified_jacobian"]

#: Largest normalised condition number of ``J`` still treated as regular.
COND_THRESHOLD = 1.0 / RANK_RTOL


@dataclass(frozen=True)
class JacobianRow:
    """What one row of the unified Jacobian is.

    Attributes
    ----------
    leg : int
        Index of the leg in the sequence given to :func:`unified_jacobian`.
    leg_name : str
    kind : str
        ``"actuation"``, ``"force"``, ``"couple"`` or ``"screw"``.
    member : str
        Geometric kind of the row's wrench: ``"force"``, ``"couple"`` or
        ``"screw"`` (for a constraint row equal to ``kind``).
    direction : ndarray (3,)
        Unit direction of the force (``force``/``screw``) or of the couple.
    point : ndarray (3,) or None
        A point of the force line (of the screw axis); None for a couple.
    point_name : str or None
        The named point of the leg on that line (``"A"``, ``"R1^R5"``...), if any.
    pitch : float
        0 for a force, ``inf`` for a couple.
    scale : float
        The row is ``scale`` times the unit member wrench (1 for constraint rows;
        for an actuation row, the factor that makes its reciprocal product with
        the actuated joint's unit twist equal to 1).
    joint : str or None
        The actuated joint (actuation rows), None for constraint rows.
    """

    leg: int
    leg_name: str
    kind: str
    member: str
    direction: np.ndarray
    point: np.ndarray | None
    point_name: str | None
    pitch: float
    scale: float
    joint: str | None

    def describe(self) -> str:
        """One line, e.g. ``leg 0 (RRPRR) force along (...) through Q (where R1 meets R5)``."""
        d = "(" + ", ".join(f"{x:.6g}" for x in np.where(np.abs(self.direction) < 5e-13, 0.0,
                                                          self.direction)) + ")"
        if self.member == "couple":
            what = f"couple about {d}"
        else:
            where = point_label(self.point_name) or "(" + ", ".join(f"{x:.6g}" for x in self.point) + ")"
            what = f"{self.member} along {d} through {where}"
        head = f"leg {self.leg} ({self.leg_name}) "
        return head + (f"actuation of {self.joint}: {what}" if self.kind == "actuation" else what)


@dataclass(frozen=True, eq=False)
class JacobianResult:
    """The unified Jacobian at one pose and what its conditioning says.

    Attributes
    ----------
    J : ndarray (m, 6)
        Rows ``[f; m]`` about the base origin: ``n`` actuation rows, then the
        constraint rows.
    rows : tuple of JacobianRow
        Metadata, one per row of ``J``.
    n_actuated : int
        Number of actuation rows ``n``.
    legs : tuple of Leg
    analyses : tuple of LegAnalysis
    o : ndarray (3,)
        Platform centre (the paper's reference point for rows and workload).
    normalisation : Normalisation
        Centroid and characteristic length used for every rank decision.
    singular_values : ndarray (min(m, 6),)
        Singular values of the normalised, row-equilibrated ``J``, descending.
    rank : int
    condition_number : float
        ``s_1 / s_6`` of the normalised ``J`` (``inf`` when fewer than 6 rows
        or rank-deficient).
    constraint_rank : int
        Rank of the constraint rows.
    constraint_condition_number : float
        ``s_1 / s_(6-n)`` of the normalised constraint rows (1 when ``n >= 6``,
        ``inf`` when there are fewer than ``6 - n`` constraint rows).
    threshold : float
        Condition number above which the pose is singular.
    """

    J: np.ndarray
    rows: tuple = field(repr=False)
    n_actuated: int
    legs: tuple = field(repr=False)
    analyses: tuple = field(repr=False)
    o: np.ndarray = field(repr=False)
    normalisation: Normalisation = field(repr=False)
    singular_values: np.ndarray
    rank: int
    condition_number: float
    constraint_rank: int
    constraint_condition_number: float
    threshold: float
    _Jn: np.ndarray = field(repr=False)
    _row_norms: np.ndarray = field(repr=False)
    _Vt: np.ndarray = field(repr=False)

    def __repr__(self) -> str:
        return (f"JacobianResult({self.n_rows}x6, {self.n_actuated} actuation rows, rank {self.rank}, "
                f"condition {self.condition_number:.4g}"
                + (f", {self.singularity_kind} singularity" if self.singular else "") + ")")

    # -- blocks -----------------------------------------------------------------
    @property
    def J_a(self) -> np.ndarray:
        """Actuation rows, shape (n, 6)."""
        return self.J[: self.n_actuated]

    @property
    def J_c(self) -> np.ndarray:
        """Constraint rows, shape (m - n, 6)."""
        return self.J[self.n_actuated:]

    @property
    def n_rows(self) -> int:
        return len(self.J)

    @property
    def kinds(self) -> tuple:
        """Row kinds (``"actuation"``, ``"force"``, ``"couple"``, ``"screw"``)."""
        return tuple(r.kind for r in self.rows)

    @cached_property
    def leg_of_row(self) -> np.ndarray:
        """Leg index of every row, shape (m,)."""
        return np.array([r.leg for r in self.rows], dtype=int)

    def leg_rows(self, i: int) -> np.ndarray:
        """Indices of the rows of leg ``i`` (its actuation row first)."""
        return np.flatnonzero(self.leg_of_row == i)

    # -- conditioning -----------------------------------------------------------
    @property
    def expected_constraint_rank(self) -> int:
        """``max(0, 6 - n)``: the constraint rank a PM with ``n`` actuators needs."""
        return max(0, 6 - self.n_actuated)

    @property
    def dof(self) -> int:
        """Degrees of freedom of the platform allowed by the constraint rows, ``6 - rank(J_c)``."""
        return 6 - self.constraint_rank

    @property
    def singular(self) -> bool:
        """True when the normalised condition number exceeds the threshold."""
        return not (self.condition_number <= self.threshold)

    @property
    def singularity_kind(self) -> str | None:
        """``"constraint"``, ``"actuation"``, or None at a regular pose."""
        if not self.singular:
            return None
        if self.expected_constraint_rank and not (self.constraint_condition_number <= self.threshold):
            return "constraint"
        return "actuation"

    @property
    def indeterminacy(self) -> int:
        """Dimension of the self-stress space, ``m - rank``: 0 when statically determinate."""
        return self.n_rows - self.rank

    @property
    def indeterminate(self) -> bool:
        """True when the legs' rows are more than the 6 independent ones (redundant
        constraints or redundant actuation): the statics has a family of solutions."""
        return self.indeterminacy > 0

    @property
    def square(self) -> bool:
        return self.J.shape == (6, 6)

    @property
    def uncontrolled_twist(self) -> np.ndarray:
        """Platform twist ``[v_O; w]`` (unit in normalised coordinates) that ``J`` maps
        closest to zero: at a singularity, the motion nothing controls or resists."""
        return self.normalisation.twists_back(self._Vt[-1])

    def check(self) -> "JacobianResult":
        """Return self, or raise :class:`SingularityError` at a singular pose."""
        if self.singular:
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
                f"twist [v_O; w] ~ {np.round(w / max(np.abs(w).max(), 1e-300), 4).tolist()}",
                kind=kind, condition_number=self.condition_number)
        return self

    # -- other reference points -------------------------------------------------
    def rows_about(self, point) -> np.ndarray:
        """``J`` with the moments taken about ``point``: rows ``[f; m - point x f]``.

        About ``o`` these are the paper's rows ``[delta; e x delta]``,
        ``[c; rho x c]``; they act on the twist ``[v_point; w]``.
        """
        p = as_vector3(point, "point")
        return np.concatenate([self.J[:, :3], self.J[:, 3:] - np.cross(p, self.J[:, :3])], axis=1)

    def describe(self) -> str:
        lines = [f"unified Jacobian: {self.n_rows} rows ({self.n_actuated} actuation, "
                 f"{self.n_rows - self.n_actuated} constraint), rank {self.rank}, "
                 f"normalised condition number {self.condition_number:.6g}"]
        lines += ["  " + r.describe() for r in self.rows]
        return "\n".join(lines)


def _row_from_member(i, leg, kind, member, scale, joint) -> JacobianRow:
    point = None if member.kind == "couple" or member.point is None else np.array(member.point, float)
    return JacobianRow(i, leg.name, kind, member.kind, np.array(member.direction, float), point,
                       member.point_name, float(member.pitch), float(scale), joint)


def _check_legs(legs, analyses):
    legs = tuple(legs)
    if not legs:
        raise InputError("unified_jacobian needs at least one leg")
    for i, leg in enumerate(legs):
        if not isinstance(leg, Leg):
            raise InputError(f"legs[{i}] is a {type(leg).__name__}, not a screwkit Leg")
    if analyses is None:
        analyses = tuple(leg.analyze() for leg in legs)
    else:
        analyses = tuple(analyses)
        if len(analyses) != len(legs):
            raise InputError(f"{len(analyses)} analyses given for {len(legs)} legs")
        for i, (leg, an) in enumerate(zip(legs, analyses)):
            if getattr(an, "leg", None) is not leg:
                raise InputError(f"analyses[{i}] is not the analysis of legs[{i}] ({leg.name})")
    return legs, analyses


def unified_jacobian(legs, o, analyses=None, *, threshold: float = COND_THRESHOLD) -> JacobianResult:
    """The unified Jacobian ``J = [J_a; J_c]`` of placed legs.

    Parameters
    ----------
    legs : sequence of Leg
        The legs at the pose (world = base frame, moments about its origin ``O``).
    o : array_like (3,)
        Platform centre: the reference point of the paper's rows and of the workload.
    analyses : sequence of LegAnalysis, optional
        Precomputed ``leg.analyze()`` results, one per leg (recomputed if omitted).
    threshold : float
        Normalised condition number above which the pose counts as singular.

    Returns
    -------
    JacobianResult
        Never raises at a singular pose: call :meth:`JacobianResult.check` (or use
        :func:`screwkit.engine.statics`) to raise :class:`SingularityError`.
        A leg whose actuated joint is dependent on its passive joints contributes a
        zero actuation row (the Jacobian is then singular, kind ``"actuation"``).
    """
    o = as_vector3(o, "platform centre o")
    if not (np.isfinite(threshold) and threshold > 1):
        raise InputError(f"threshold must be a finite number > 1, got {threshold}")
    legs, analyses = _check_legs(legs, analyses)

    act_rows, act_meta, con_rows, con_meta = [], [], [], []
    for i, (leg, an) in enumerate(zip(legs, analyses)):
        aw = an.actuation
        if aw is None:
            d = leg.actuated_joint.direction
            act_rows.append(np.zeros(6))
            act_meta.append(JacobianRow(i, leg.name, "actuation", "none", np.array(d, float), None,
                                        None, float("nan"), 0.0, leg.actuated_joint.name))
        else:
            act_rows.append(np.asarray(aw.wrench, float))
            act_meta.append(_row_from_member(i, leg, "actuation", aw.member, aw.scale, aw.joint))
        for c in an.constraints:
            con_rows.append(np.asarray(c.wrench.vector, float))
            con_meta.append(_row_from_member(i, leg, c.kind, c, 1.0, None))

    J = np.array(act_rows + con_rows, float).reshape(-1, 6)
    J.setflags(write=False)
    n = len(act_rows)
    pts = np.vstack([leg.points for leg in legs] + [o[None, :]])
    norm = Normalisation.for_points(pts)

    Jn = norm.wrenches(J)
    row_norms = np.linalg.norm(Jn, axis=1)
    safe = np.where(row_norms > 0, row_norms, 1.0)
    Jn = Jn / safe[:, None]
    _, s, Vt = np.linalg.svd(Jn, full_matrices=True)
    rank = int(np.sum(s > RANK_RTOL * max(float(s[0]), 1e-300))) if s.size else 0
    cond = float(s[0] / s[5]) if len(s) >= 6 and s[5] > 0 else float("inf")

    k = max(0, 6 - n)
    Jc = Jn[n:]
    if len(Jc):
        sc = np.linalg.svd(Jc, compute_uv=False)
        c_rank = int(np.sum(sc > RANK_RTOL * max(float(sc[0]), 1e-300)))
    else:
        sc, c_rank = np.zeros(0), 0
    if k == 0:
        c_cond = 1.0
    elif len(sc) >= k and sc[k - 1] > 0:
        c_cond = float(sc[0] / sc[k - 1])
    else:
        c_cond = float("inf")

    for a in (s, row_norms, Jn, Vt):
        a.setflags(write=False)
    return JacobianResult(J, tuple(act_meta + con_meta), n, legs, analyses, o, norm, s, rank, cond,
                          c_rank, c_cond, float(threshold), Jn, row_norms, Vt)
