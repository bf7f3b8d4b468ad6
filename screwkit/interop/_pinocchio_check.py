"""Cross-check of screwkit's kinematics and statics with Pinocchio.

Given what screwkit computed for a leg or a PM at a pose (joint values, the
legs placed at the pose, leg wrenches, actuator forces), rebuild the
mechanism in Pinocchio (:mod:`screwkit.pinocchio_model`) and compare:

a) **closure** - Pinocchio's FK of each leg at screwkit's joint values reaches
   the platform pose (position of the platform origin divided by the length
   scale, and orientation angle); for an S-ended leg only the S centre is
   compared with the platform's attachment point (the S angles of the last joint
   do not have to be meaningful to a caller that only solved positions);
b) **twists** - the columns of the leg's WORLD-frame Jacobian, mapped to the
   screwkit joints (:meth:`LegChain.velocity_map`), equal screwkit's current
   joint twists one to one; on an S, the three Pinocchio columns span the same
   3-D space as the three equivalent R twists (a map-free span comparison);
c) **mobility** - the closed-loop model's constraint Jacobian
   (``pin.getConstraintsJacobian``) has rank ``r``; DOF = ``nv - r - idle`` where
   ``idle`` counts the legs' dependent joints (the spin of an SPS leg about its
   line), and the platform twists over the null space of ``J_c`` have that rank
   and span screwkit's twist space; with the actuated columns removed no
   platform motion is left at a regular pose;
d) **statics** - ``J_leg(q)^T w`` (``w`` the leg's wrench on the platform about O)
   vanishes on the passive joints and equals the actuator force on the actuated
   joint; on the closed loop, the virtual work ``sum_i F_ai qdot_ai + W . V_p``
   of the actuator forces and the load vanishes for every motion of the loop.

For an assembled PM (:mod:`screwkit.pm`): :class:`PMChecker` builds the models
once from the home geometry and checks any pose; :func:`check_pm` (a pose
solution or a :class:`~screwkit.pm_analysis.PMAnalysis`) gives the detailed
rows, :func:`check_analysis` a :class:`PMCheckReport` with one row per check
(:data:`SUMMARY_CHECKS`), :func:`regular_analyses` draws regular poses around a
PM's default pose and :func:`check_all` runs the whole catalog
(``screwkit check``).

Every deviation is dimensionless (length-normalised with the geometry's
characteristic length, see :class:`screwkit.reciprocal.Normalisation`) and
compared with ``rtol`` (default :data:`CHECK_RTOL`); ranks use
:data:`screwkit.tolerance.RANK_RTOL`.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from ..errors import InputError
from ..legs import Leg
from ..screws import Normalisation, RANK_RTOL, reciprocal_system
from ._pinocchio_model import (ClosedLoopModel, LegChain, as_pose, build_closed_loop_model,
                               build_leg_model)

__all__ = [
    "CHECK_RTOL",
    "SUMMARY_CHECKS",
    "CheckRow",
    "CheckReport",
    "Mobility",
    "PMChecker",
    "PMCheckReport",
    "check_leg",
    "check_closed_loop",
    "check_pm",
    "check_analysis",
    "check_all",
    "regular_analyses",
    "summarize",
    "constraint_jacobian",
    "mobility",
]

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


def _leg_frames(model, data, chain: LegChain, qpin):
    import pinocchio as pin
    pin.computeJointJacobians(model, data, qpin)
    pin.updateFramePlacements(model, data)
    J = pin.getFrameJacobian(model, data, chain.frame_id, pin.WORLD)
    return data.oMf[chain.frame_id], data.oMf[chain.end_frame_id], J


def _leg_rows(chain: LegChain, model, data, q, platform_pose, placed_leg, wrench, actuator_force,
              rtol, prefix, full_closure: bool = False) -> list:
    """Checks a), b), d) of one leg; ``model``/``data`` may hold other legs too.

    ``full_closure``: compare the whole platform pose for S-ended legs too (their
    S angles come from a loop-closure solver), plus the S centre (``closure.sphere``).
    """
    import pinocchio as pin
    qpin = pin.neutral(model)
    chain.fill_q(q, qpin)
    F, E, J = _leg_frames(model, data, chain, qpin)
    pts = placed_leg.points if isinstance(placed_leg, Leg) else chain.leg.points
    norm = Normalisation.for_points(pts)
    L = norm.length
    rows = []
    if platform_pose is not None:
        R, p = as_pose(platform_pose, "platform_pose")
        if chain.ends_with_sphere:
            R_h, o_h = chain.platform_home
            c_home = chain.leg.joints[chain.blocks[-1].sk[0]].point
            target = R @ (R_h.T @ (c_home - o_h)) + p
            name = "closure.sphere" if full_closure else "closure.position"
            rows.append(_row(f"{prefix}{name}", np.linalg.norm(E.translation - target) / L, rtol))
        if full_closure or not chain.ends_with_sphere:
            rows.append(_row(f"{prefix}closure.position", np.linalg.norm(F.translation - p) / L, rtol))
            rows.append(_row(f"{prefix}closure.orientation",
                             np.linalg.norm(pin.log3(F.rotation.T @ R)), rtol))
    M = chain.velocity_map(q, model.nv)
    Jsk = J @ M                                            # (6, m): Pinocchio twists of the screwkit joints
    if placed_leg is not None:
        T = _twists_of(placed_leg, chain.m)
        Tn, Pn = norm.twists(T), norm.twists(Jsk.T)
        dev = max(float(np.linalg.norm(Pn[i] - Tn[i]) / max(np.linalg.norm(Tn[i]), _TINY))
                  for i in range(chain.m))
        rows.append(_row(f"{prefix}twists", dev, rtol))
        for b in chain.blocks:
            if b.kind == "spherical":
                name = chain.leg.joints[b.sk[0]].spec
                cols = norm.twists(J[:, b.idx_v:b.idx_v + 3].T)
                rows.append(_row(f"{prefix}twists.span.S{name.position}",
                                 _span_gap(cols, Tn[list(b.sk)]), rtol))
    if wrench is not None:
        w = np.asarray(wrench, float).reshape(-1)
        if w.shape != (6,) or not np.all(np.isfinite(w)):
            raise InputError(f"{prefix}wrench must be 6 finite numbers, got shape {w.shape}")
        wn = norm.wrenches(w)
        tau_pin = J.T @ w                                  # Pinocchio generalised forces
        tau = M.T @ tau_pin                                # on the screwkit joints
        ia = chain.leg.actuated_index
        act_cols = chain.actuated_columns()
        dev = 0.0
        for i in range(chain.m):
            if i != ia:
                dev = max(dev, _rel_product(wn, norm.twists(Jsk[:, i])))
        for b in chain.blocks:                             # passive S: all its Pinocchio columns
            if b.kind == "spherical" and b.idx_v not in act_cols:
                for c in range(b.idx_v, b.idx_v + 3):
                    dev = max(dev, _rel_product(wn, norm.twists(J[:, c])))
        rows.append(_row(f"{prefix}statics.passive", dev, rtol))
        if actuator_force is not None:
            Vn = norm.twists(Jsk[:, ia])
            scale = max(L * float(np.linalg.norm(wn) * np.linalg.norm(Vn)), abs(float(actuator_force)), _TINY)
            rows.append(_row(f"{prefix}statics.actuator", abs(tau[ia] - float(actuator_force)) / scale, rtol))
    return rows


def _twists_of(placed, m) -> np.ndarray:
    T = placed.twists if isinstance(placed, Leg) else np.asarray(placed, float)
    if T.shape != (m, 6):
        raise InputError(f"placed leg twists must have shape ({m}, 6), got {T.shape}")
    return T


def check_leg(home_leg: Leg, joint_values, platform_home=None, platform_pose=None, placed_leg=None,
              wrench=None, actuator_force=None, *, rtol: float = CHECK_RTOL) -> CheckReport:
    """Cross-check one serial leg with Pinocchio (checks a, b, d of the module docstring).

    Parameters
    ----------
    home_leg : Leg
        Home geometry (joint values 0).
    joint_values : array_like (m,)
        screwkit's joint values, one per equivalent joint.
    platform_home : tuple (R (3, 3), p (3,)), optional
        Platform home pose, default ``(I, home_leg.a)``.
    platform_pose : tuple (R, p), optional
        Platform pose screwkit reached; skips the closure check when None.
    placed_leg : Leg or array_like (m, 6), optional
        The leg at the pose (screwkit's current joint twists); skips b) when None.
    wrench : array_like (6,), optional
        The leg's wrench on the platform ``[f; m]`` about O; skips d) when None.
    actuator_force : float, optional
        Expected ``J_a . wrench`` on the actuated joint.
    rtol : float

    Returns
    -------
    CheckReport
    """
    lm = build_leg_model(home_leg, platform_home)
    q = np.asarray(joint_values, float).reshape(-1)
    lm.q(q)                                                # validates the shape
    rows = _leg_rows(lm.chain, lm.model, lm.model.createData(), q, platform_pose, placed_leg,
                     wrench, actuator_force, rtol, "")
    return CheckReport(tuple(rows))



# ---------------------------------------------------------------------------
# closed loops: mobility (check c) and the PM checker
# ---------------------------------------------------------------------------

@dataclass(frozen=True, eq=False)
class Mobility:
    """Mobility of a closed-loop model at a configuration.

    Attributes
    ----------
    dof : int
        Platform DOF: the rank of the platform twists ``J_p x`` over the null space
        ``x`` of the loop-closure constraint Jacobian ``J_c`` (Pinocchio only).
    locked_dof : int
        The same with the actuated joints locked (0 away from singularities).
    rank, locked_rank : int
        Ranks of the normalised ``J_c``, full and without the actuated columns.
    idle, locked_idle : int
        screwkit's count of the legs' dependent joints (all joints / passive
        joints only), ``m - rank(twists)``: ``nv - rank - idle`` is the DOF count
        of check c) in its textbook form.
    nv : int
    smallest_singular_value : float
        Smallest retained normalised singular value of ``J_c`` over the largest.
    internal, locked_internal : int
        Joint motions that leave the platform still (Pinocchio's own idle count):
        ``nv - rank - dof`` and the same with the actuators locked.
    twists : ndarray (dof, 6)
        A basis of the platform twists ``[v; w]`` about the world origin.
    """

    dof: int
    locked_dof: int
    rank: int
    locked_rank: int
    idle: int
    locked_idle: int
    nv: int
    smallest_singular_value: float
    internal: int = 0
    locked_internal: int = 0
    twists: np.ndarray = None

    @property
    def count(self) -> int:
        """``nv - rank(J_c) - idle``: the DOF from the rank of the constraint Jacobian."""
        return self.nv - self.rank - self.idle


def _svd_rank(M):
    """Rank (``RANK_RTOL`` relative to ``max(1, s_max)``), singular values and ``Vt``."""
    if M.size == 0:
        n = M.shape[1] if M.ndim == 2 else 0
        return 0, np.zeros(0), np.eye(n)
    _, s, Vt = np.linalg.svd(M, full_matrices=True)
    return int(np.sum(s > RANK_RTOL * max(1.0, float(s[0])))), s, Vt


def _constraint_state(clm: ClosedLoopModel, data, qpin):
    """Kinematics at ``qpin``, then every constraint's ``calc``: (J_c, constraint datas)."""
    import pinocchio as pin
    model = clm.model
    pin.computeJointJacobians(model, data, qpin)
    pin.updateFramePlacements(model, data)
    if not clm.constraints:
        return np.zeros((0, model.nv)), ()
    cms = pin.StdVec_RigidConstraintModel()
    cds = pin.StdVec_RigidConstraintData()
    for cm in clm.constraints:
        cd = cm.createData()
        cm.calc(model, data, cd)
        cms.append(cm)
        cds.append(cd)
    return np.array(pin.getConstraintsJacobian(model, data, cms, cds)), tuple(cds)


def constraint_jacobian(clm: ClosedLoopModel, data, qpin) -> np.ndarray:
    """``pin.getConstraintsJacobian`` at ``qpin`` (rows LOCAL to each constraint's joint1 frame;
    6 rows per ``CONTACT_6D``, 3 per ``CONTACT_3D``).

    Pinocchio 4.1 quirk: each constraint's ``calc`` must run after the kinematics,
    otherwise the Jacobian is silently computed with stale contact placements.
    """
    return _constraint_state(clm, data, qpin)[0]


def _scales(clm: ClosedLoopModel, L: float):
    """Row scale of ``J_c`` (linear rows / L) and column scale (prismatic columns * L)."""
    rows = []
    for cm in clm.constraints:
        rows.append(np.full(3, 1.0 / L))
        if cm.residualSize() == 6:
            rows.append(np.ones(3))
    colscale = np.ones(clm.model.nv)
    for ch in clm.chains:
        for b in ch.blocks:
            if b.kind == "prismatic":
                colscale[b.idx_v] = L
    return (np.concatenate(rows) if rows else np.zeros(0)), colscale


def _legs_for(clm, placed_legs):
    legs = tuple(placed_legs) if placed_legs is not None else ()
    if len(legs) != len(clm.chains) or not all(isinstance(lg, Leg) for lg in legs):
        legs = tuple(ch.leg for ch in clm.chains)
    return legs


def _mobility(clm: ClosedLoopModel, data, Jc, legs, norm: Normalisation) -> Mobility:
    import pinocchio as pin
    model = clm.model
    rowscale, colscale = _scales(clm, norm.length)
    Jn = rowscale[:, None] * Jc * colscale[None, :]
    Jp = pin.getFrameJacobian(model, data, clm.chains[clm.carrier].frame_id, pin.WORLD) * colscale
    act = sorted({c for ch in clm.chains for c in ch.actuated_columns()})
    keep = [c for c in range(model.nv) if c not in act]

    def platform_motion(cols):
        r, s, Vt = _svd_rank(Jn[:, cols]) if len(Jn) else (0, np.zeros(0), np.eye(len(cols)))
        N = Vt[r:]                                         # null space, unit in normalised joint rates
        V = norm.twists((Jp[:, cols] @ N.T).T)             # (k, 6) normalised platform twists
        d, _, Vt2 = _svd_rank(V) if len(V) else (0, None, np.eye(6))
        smin = float(s[r - 1] / s[0]) if r else 1.0
        return r, len(N), d, norm.twists_back(Vt2[:d]), smin

    rank, k, dof, twists, smin = platform_motion(list(range(model.nv)))
    locked_rank, kl, locked_dof, _, _ = platform_motion(keep)
    idle = locked_idle = 0
    for lg in legs:
        T = lg.twists
        idle += len(T) - reciprocal_system(T, lg.points).rank
        Tp = np.delete(T, lg.actuated_index, axis=0)
        locked_idle += len(Tp) - reciprocal_system(Tp, lg.points).rank
    twists.setflags(write=False)
    return Mobility(dof, locked_dof, rank, locked_rank, idle, locked_idle, model.nv, smin,
                    k - dof, kl - locked_dof, twists)


def mobility(clm: ClosedLoopModel, joint_values, placed_legs=None) -> Mobility:
    """Mobility from Pinocchio's loop-closure constraint Jacobian (check c).

    ``J_c`` is normalised before any rank decision: linear rows divided by the
    characteristic length ``L`` of the geometry, prismatic columns multiplied by
    ``L``.  The platform DOF is the rank of the (length-normalised) platform
    twists ``J_p x`` over an orthonormal basis ``x`` of the null space of ``J_c``
    (``J_p``: the carrier's platform frame Jacobian, WORLD); the locked DOF the
    same with the actuated columns removed.  screwkit's idle count (``m -
    rank(twists)`` per leg, the spin of an SPS about its line) is reported too, so
    that ``nv - rank - idle`` can be compared with the DOF.

    Parameters
    ----------
    clm : ClosedLoopModel
    joint_values : sequence of array_like (m_i,)
    placed_legs : sequence of Leg, optional
        The legs at the pose (for ``L`` and the idle count; default the home legs).

    Returns
    -------
    Mobility
    """
    data = clm.model.createData()
    Jc, _ = _constraint_state(clm, data, clm.q(joint_values))
    legs = _legs_for(clm, placed_legs)
    return _mobility(clm, data, Jc, legs, Normalisation.for_points(np.vstack([lg.points for lg in legs])))


def _per_leg(x, n, what):
    if x is None:
        return (None,) * n
    x = tuple(x)
    if len(x) != n:
        raise InputError(f"{what}: {len(x)} entries for {n} legs")
    return x


@dataclass(frozen=True, eq=False)
class PMChecker:
    """Pinocchio models of a PM's home geometry, built once and reused at every pose.

    Attributes
    ----------
    home_legs : tuple of Leg
    platform_home : tuple (R (3, 3), p (3,))
    leg_models : tuple of LegModel
        One serial model per leg, with every joint (checks a, b, d).
    closed : ClosedLoopModel
        All legs with their loop closures (``point_contacts=True``: a leg ending in
        a passive S is tied by a 3-D point contact, the others by 6-D contacts);
        checks c), the loop closure and the closed-loop virtual work.
    name : str
    """

    home_legs: tuple
    platform_home: tuple
    leg_models: tuple
    closed: ClosedLoopModel
    name: str = ""

    @classmethod
    def build(cls, home_legs, platform_home, name: str = "", *,
              point_contacts: bool = True) -> "PMChecker":
        """Build the models (Pinocchio joints placed from the home legs' geometry)."""
        legs = tuple(home_legs)
        ph = as_pose(platform_home, "platform_home")
        lms = tuple(build_leg_model(lg, ph) for lg in legs)
        clm = build_closed_loop_model(legs, ph, point_contacts=point_contacts)
        return cls(legs, ph, lms, clm, str(name))

    @classmethod
    def for_model(cls, pm_model) -> "PMChecker":
        """Build for a :class:`screwkit.pm.PMModel` (its home legs and platform home pose)."""
        return cls.build(pm_model.home_legs, pm_model.platform_home, getattr(pm_model, "name", ""))

    def check(self, joint_values, platform_pose=None, placed_legs=None, leg_wrenches=None,
              actuator_forces=None, workload=None, expected_dof=None, expected_twists=None, *,
              full_closure: bool = True, rtol: float = CHECK_RTOL) -> CheckReport:
        """Cross-check one pose (see :func:`check_closed_loop` for the parameters and rows).

        Extra parameters
        ----------------
        workload : array_like (6,), optional
            The load ``W = [F; T + o x F]`` about O balanced by the leg wrenches; with
            ``actuator_forces`` adds the closed-loop virtual-work row ``statics.work``.
        expected_twists : array_like (k, 6), optional
            screwkit's platform twist basis; adds ``mobility.twists`` (span distance).
        full_closure : bool
            Compare the whole platform pose for S-ended legs too (rows
            ``closure.position``, ``closure.orientation`` and ``closure.sphere``).
        """
        import pinocchio as pin
        n = len(self.home_legs)
        qs = tuple(np.asarray(q, float).reshape(-1) for q in _per_leg(joint_values, n, "joint_values"))
        placed = _per_leg(placed_legs, n, "placed_legs")
        ws = _per_leg(leg_wrenches, n, "leg_wrenches")
        fs = _per_leg(actuator_forces, n, "actuator_forces")
        rows = []
        for k, lm in enumerate(self.leg_models):
            lm.q(qs[k])                                    # validates the shape
            rows += _leg_rows(lm.chain, lm.model, lm.model.createData(), qs[k], platform_pose, placed[k],
                              ws[k], fs[k], rtol, f"leg{k + 1}.", full_closure)
        clm = self.closed
        model = clm.model
        data = model.createData()
        qpin = clm.q(qs)
        Jc, cds = _constraint_state(clm, data, qpin)
        legs = _legs_for(clm, placed)
        norm = Normalisation.for_points(np.vstack([lg.points for lg in legs]))
        L = norm.length
        # loop closure: the constraints' own contact placements
        dev = 0.0
        for cm, cd in zip(clm.constraints, cds):
            if cm.residualSize() == 6:
                d = pin.log6(cd.oMc1.inverse() * cd.oMc2).vector
                dev = max(dev, float(np.linalg.norm(d[:3]) / L), float(np.linalg.norm(d[3:])))
            else:
                dev = max(dev, float(np.linalg.norm(cd.oMc1.translation - cd.oMc2.translation) / L))
        rows.append(_row("loop.closure", dev, rtol))
        mob = _mobility(clm, data, Jc, legs, norm)
        if workload is not None and all(f is not None for f in fs):
            rows.append(_row("statics.work", self._work(Jc, data, qs, fs, workload, norm), rtol))
        if expected_dof is not None:
            e = int(expected_dof)
            rows.append(_row("mobility", max(abs(mob.dof - e), abs(mob.count - e)), 0))
        if expected_twists is not None:
            T = np.asarray(expected_twists, float).reshape(-1, 6)
            if len(T) and len(mob.twists):
                gap = _span_gap(norm.twists(mob.twists), norm.twists(T))
            else:
                gap = 0.0 if len(T) == len(mob.twists) else 1.0
            rows.append(_row("mobility.twists", gap, rtol))
        rows.append(_row("mobility.locked", abs(mob.locked_dof), 0))
        values = (("dof", mob.dof), ("locked_dof", mob.locked_dof), ("constraint_rank", mob.rank),
                  ("locked_rank", mob.locked_rank), ("idle", mob.idle), ("locked_idle", mob.locked_idle),
                  ("internal", mob.internal), ("nv", mob.nv),
                  ("condition", 1.0 / mob.smallest_singular_value))
        return CheckReport(tuple(rows), values)

    def _work(self, Jc, data, qs, fs, workload, norm) -> float:
        """Closed-loop virtual work: ``sum_i F_ai qdot_ai + W . V_p = 0`` for every motion
        ``qdot`` of the closed loop (null space of ``J_c``), relative to the terms' scale.
        ``data`` holds the kinematics at ``qs`` (from :func:`_constraint_state`)."""
        import pinocchio as pin
        clm = self.closed
        W = np.asarray(workload, float).reshape(-1)
        if W.shape != (6,) or not np.all(np.isfinite(W)):
            raise InputError(f"workload must be 6 finite numbers, got shape {W.shape}")
        L = norm.length
        rowscale, colscale = _scales(clm, L)
        Jn = rowscale[:, None] * Jc * colscale[None, :]
        r, _, Vt = _svd_rank(Jn) if len(Jn) else (0, None, np.eye(clm.model.nv))
        Jp = pin.getFrameJacobian(clm.model, data, clm.chains[clm.carrier].frame_id, pin.WORLD)
        F = np.array([float(f) for f in fs])
        per = np.array([1.0 if ch.leg.actuated_joint.kind == "P" else 1.0 / L for ch in clm.chains])
        scale = L * (float(np.linalg.norm(norm.wrenches(W))) + float(np.sum(np.abs(F) * per)))
        dev = 0.0
        for x in Vt[r:]:
            v = colscale * x                               # Pinocchio joint velocities
            rates = [ch.rates(q, v)[ch.leg.actuated_index] for ch, q in zip(clm.chains, qs)]
            power = float(F @ np.array(rates) + W @ (Jp @ v))
            dev = max(dev, abs(power) / max(scale, _TINY))
        return dev


def check_closed_loop(home_legs, joint_values, platform_home, platform_pose=None, placed_legs=None,
                      leg_wrenches=None, actuator_forces=None, expected_dof=None, *,
                      workload=None, expected_twists=None, full_closure: bool = False,
                      rtol: float = CHECK_RTOL) -> CheckReport:
    """Cross-check a PM at a pose with Pinocchio (builds a :class:`PMChecker`).

    Parameters
    ----------
    home_legs : sequence of Leg
        Home geometries (joint values 0).
    joint_values : sequence of array_like (m_i,)
    platform_home : tuple (R, p)
    platform_pose : tuple (R, p), optional
    placed_legs : sequence of Leg, optional
        The legs at the pose (current twists); also used to count idle motions.
    leg_wrenches : sequence of array_like (6,), optional
        Each leg's wrench on the platform, about O.
    actuator_forces : sequence of float, optional
    expected_dof : int, optional
        Adds a ``mobility`` row (deviation ``max(|dof - e|, |nv - rank - idle - e|)``,
        tolerance 0).
    workload, expected_twists, full_closure
        See :meth:`PMChecker.check` (default: S-ended legs compare their S centre only).
    rtol : float

    Returns
    -------
    CheckReport
        Rows ``leg<i>.closure.*``, ``leg<i>.twists``, ``leg<i>.twists.span.S<k>``,
        ``leg<i>.statics.*``, ``loop.closure``, ``statics.work``, ``mobility``,
        ``mobility.twists``, ``mobility.locked``; values ``dof``, ``locked_dof``,
        ``constraint_rank``, ``locked_rank``, ``idle``, ``locked_idle``, ``internal``,
        ``nv``, ``condition``.
    """
    checker = PMChecker.build(home_legs, platform_home)
    return checker.check(joint_values, platform_pose, placed_legs, leg_wrenches, actuator_forces,
                         workload, expected_dof, expected_twists, full_closure=full_closure, rtol=rtol)


def _is_analysis(x) -> bool:
    return all(hasattr(x, a) for a in ("solution", "mobility", "jacobian", "statics"))


def check_pm(solution, statics=None, *, mobility=None, expected_dof=None, checker=None,
             rtol: float = CHECK_RTOL) -> CheckReport:
    """Cross-check a :mod:`screwkit.pm` pose solution (and optionally its statics).

    Parameters
    ----------
    solution : PoseSolution or PMAnalysis
        Uses ``solution.model.home_legs``, ``solution.model.platform_home`` (or
        ``home_rotation``/``home_position``), ``solution.joint_values``,
        ``solution.legs``, ``solution.rotation``, ``solution.position``.  A
        :class:`~screwkit.pm_analysis.PMAnalysis` brings its statics and mobility.
    statics : StaticsResult, optional
        ``leg_wrenches`` (n, 6), ``active`` (n,) and ``workload`` (6,).
    mobility : screwkit.mobility.Mobility, optional
        screwkit's mobility at the pose: ``dof`` and ``twists`` are checked.
    expected_dof : int, optional
        Default: ``mobility.dof``, else ``model.stated_dof`` (or ``model.dof``).
    checker : PMChecker, optional
        Reused models (must be built for the same home geometry).
    rtol : float

    Returns
    -------
    CheckReport
        Every leg's closure (whole platform pose, and the S centre of S-ended legs),
        twists and statics rows, then ``loop.closure``, ``statics.work``,
        ``mobility``, ``mobility.twists``, ``mobility.locked``.
    """
    if _is_analysis(solution):
        statics = solution.statics if statics is None else statics
        mobility = solution.mobility if mobility is None else mobility
        solution = solution.solution
    model = solution.model
    home = getattr(model, "platform_home", None)
    if home is None:
        home = (getattr(model, "home_rotation", np.eye(3)), getattr(model, "home_position"))
    if expected_dof is None:
        expected_dof = getattr(mobility, "dof", None)
    if expected_dof is None:
        expected_dof = getattr(model, "stated_dof", getattr(model, "dof", None))
    wrenches = forces = workload = None
    if statics is not None:
        wrenches = getattr(statics, "leg_wrenches", None)
        forces = getattr(statics, "actuator_forces", None)
        if forces is None:
            forces = getattr(statics, "active", None)
        workload = getattr(statics, "workload", None)
    if checker is None:
        checker = PMChecker.build(model.home_legs, home, getattr(model, "name", ""))
    elif len(checker.home_legs) != len(solution.joint_values):
        raise InputError(f"the checker has {len(checker.home_legs)} legs, the solution "
                         f"{len(solution.joint_values)}")
    return checker.check(solution.joint_values, (solution.rotation, solution.position), solution.legs,
                         wrenches, forces, workload, expected_dof, getattr(mobility, "twists", None),
                         full_closure=True, rtol=rtol)


# ---------------------------------------------------------------------------
# PM reports: one row per check, regular poses, the whole catalog
# ---------------------------------------------------------------------------

#: The summary checks of a PM report, in order: (name, what it gathers).
SUMMARY_CHECKS = (
    ("closure", "every leg's FK reaches the platform pose (and its S centre); the loop closures"),
    ("twists", "WORLD-frame Jacobian columns = screwkit's joint twists (S: same span)"),
    ("mobility", "platform DOF from Pinocchio's closed loop = screwkit's DOF, also as nv - rank(J_c) - idle"),
    ("mobility.twists", "the platform twist spaces are the same"),
    ("locked", "no platform motion left with the actuators locked"),
    ("statics.passive", "J^T w = 0 on every passive joint of every leg"),
    ("statics.actuator", "J^T w = the actuator force on the actuated joint"),
    ("statics.work", "closed-loop virtual work: sum F_a qdot_a + W . V = 0 on every loop motion"),
)


def _group(name: str) -> str:
    base = name.split(".", 1)[1] if name.startswith("leg") and "." in name else name
    if base.startswith("closure") or base == "loop.closure":
        return "closure"
    if base.startswith("twists"):
        return "twists"
    if base == "mobility.locked":
        return "locked"
    return base


def summarize(report: CheckReport) -> tuple:
    """One :class:`CheckRow` per summary check (see :data:`SUMMARY_CHECKS`): the largest
    deviation of its detail rows, passed when every one passed."""
    out = []
    for key, _ in SUMMARY_CHECKS:
        rows = [r for r in report.rows if _group(r.name) == key]
        if rows:
            worst = max(rows, key=lambda r: (not r.passed, r.deviation / max(r.tolerance, _TINY)
                                             if r.tolerance else r.deviation))
            out.append(CheckRow(key, max(r.deviation for r in rows), worst.tolerance,
                                all(r.passed for r in rows)))
    return tuple(out)


@dataclass(frozen=True, eq=False)
class PMCheckReport(_RowLookup):
    """The Pinocchio cross-check of one PM at one pose.

    Attributes
    ----------
    pm : str
    pose : dict
        The independent pose parameters (degrees for angles, model units for lengths).
    rows : tuple of CheckRow
        One row per summary check (:data:`SUMMARY_CHECKS`).
    detail : CheckReport or None
        Every per-leg row and the measured values (DOF, ranks...).
    error : str
        Why the check could not run (empty when it ran).
    """

    pm: str
    pose: dict
    rows: tuple
    detail: object = None
    error: str = ""

    @property
    def passed(self) -> bool:
        return not self.error and bool(self.rows) and all(r.passed for r in self.rows)

    @property
    def pose_label(self) -> str:
        return ",".join(f"{k}={v:.4g}" for k, v in self.pose.items()) or "-"

    def as_dict(self) -> dict:
        out = {"pm": self.pm, "pose": dict(self.pose), "passed": self.passed,
               "rows": [{"check": r.name, "deviation": r.deviation, "tolerance": r.tolerance,
                         "passed": r.passed} for r in self.rows]}
        if self.detail is not None:
            out["detail"] = self.detail.as_dict()
        if self.error:
            out["error"] = self.error
        return out

    def __str__(self) -> str:
        head = f"{self.pm} at {self.pose_label}: {'passed' if self.passed else 'FAILED'}"
        if self.error:
            return f"{head} ({self.error})"
        return "\n".join([head] + [f"  {'ok ' if r.passed else 'BAD'} {r.name:<18} {r.deviation:.3e} "
                                   f"(tol {r.tolerance:.0e})" for r in self.rows])


def _pose_of(solution) -> dict:
    p = solution.params_degrees()
    ind = getattr(solution.model, "independent", tuple(p))
    return {k: float(p[k]) for k in ind}


def check_analysis(analysis, checker=None, *, rtol: float = CHECK_RTOL) -> PMCheckReport:
    """Cross-check a :class:`screwkit.pm_analysis.PMAnalysis` (pose, statics, mobility).

    Parameters
    ----------
    analysis : PMAnalysis
        Its statics may be None (a singular pose analysed with
        ``raise_on_singular=False``): the statics rows are then left out.
    checker : PMChecker, optional
        Models built once for the PM (:meth:`PMChecker.for_model`), reused across poses.
    rtol : float

    Returns
    -------
    PMCheckReport
    """
    if not _is_analysis(analysis):
        raise InputError(f"check_analysis needs a PMAnalysis, got {type(analysis).__name__}")
    detail = check_pm(analysis, checker=checker, rtol=rtol)
    sol = analysis.solution
    return PMCheckReport(str(getattr(analysis.model, "name", "")), _pose_of(sol), summarize(detail), detail)


def regular_analyses(pm, n: int = 10, seed: int = 0, *, centre: dict | None = None,
                     angle: float = np.radians(8.0), length_fraction: float = 0.08,
                     max_draws: int | None = None, **analyze_kwargs) -> tuple:
    """The first ``n`` regular poses drawn around a PM's default pose, analysed.

    Each independent parameter is drawn uniformly around its centre value:
    angles within ``+-angle`` (radians), lengths within ``+-length_fraction`` of
    the centre's ``|Zo|``.  Draws that are singular (:class:`SingularityError`) or
    unreachable (:class:`UnreachablePoseError`) are skipped.  The generator is
    seeded by ``seed`` and the PM's name, so each PM's draws do not depend on
    which other PMs are drawn.

    Parameters
    ----------
    pm : str or PMModel
    n : int
    seed : int
    centre : dict, optional
        Pose (radians) to draw around: its independent parameters, and ``Zo``
        for the length scale; default: the default pose (``pm.default_pose``,
        with ``Zo`` of the assembled default pose when it is dependent).
    angle, length_fraction : float
    max_draws : int, optional
        Give up after this many draws (default ``5 n + 20``).
    **analyze_kwargs
        Passed to :func:`screwkit.pm_analysis.analyze_pm` (``force``, ``torque``).

    Returns
    -------
    tuple of PMAnalysis

    Raises
    ------
    GeometryError
        Fewer than ``n`` regular poses in ``max_draws`` draws.
    """
    import zlib

    from ..engine import LENGTH_PARAMS, analyze_pm, default_full_pose, load_assembled_pm
    from ..errors import GeometryError, SingularityError, UnreachablePoseError
    from ..pm import PMModel

    model = pm if isinstance(pm, PMModel) else load_assembled_pm(pm)
    if not (isinstance(n, (int, np.integer)) and n >= 1):
        raise InputError(f"the number of poses must be a positive integer, got {n!r}")
    c = dict(model.default_pose if centre is None else centre)
    if centre is None and "Zo" not in c:
        c = default_full_pose(model)     # its |Zo| is the length scale of the draws
    zref = abs(float(c.get("Zo", 0.0))) or float(model.normalisation.length)
    rng = np.random.default_rng([int(seed), zlib.crc32(model.name.encode())])
    limit = 5 * int(n) + 20 if max_draws is None else int(max_draws)
    out = []
    for _ in range(limit):
        pose = {}
        for p in model.independent:
            span = length_fraction * zref if p in LENGTH_PARAMS else angle
            pose[p] = float(c[p]) + float(rng.uniform(-span, span))
        try:
            out.append(analyze_pm(model, pose, **analyze_kwargs))
        except (SingularityError, UnreachablePoseError):
            continue
        if len(out) == n:
            return tuple(out)
    raise GeometryError(f"{model.name}: only {len(out)} regular poses in {limit} draws around the "
                        f"default pose (wanted {n})")


def check_all(poses_per_pm: int = 3, seed: int = 0, names=None, *, rtol: float = CHECK_RTOL,
              progress=None) -> tuple:
    """Cross-check every catalog PM (or ``names``) at ``poses_per_pm`` regular poses.

    The Pinocchio models are built once per PM and reused at each pose.  A PM that
    cannot be loaded or has too few regular poses gives one failed report with
    its ``error``.

    Parameters
    ----------
    poses_per_pm : int
    seed : int
    names : sequence of str or PMModel, optional
        Default: every PM of the packaged catalog.
    rtol : float
    progress : callable, optional
        Called with each report as it is made.

    Returns
    -------
    tuple of PMCheckReport
    """
    from ..engine import load_assembled_pm
    from ..errors import ScrewkitError
    from ..pm import PMModel, pm_names

    out = []
    for name in (pm_names() if names is None else names):
        label = name.name if isinstance(name, PMModel) else str(name)
        try:
            model = name if isinstance(name, PMModel) else load_assembled_pm(name)
            checker = PMChecker.for_model(model)
            analyses = regular_analyses(model, poses_per_pm, seed)
            reps = [check_analysis(a, checker, rtol=rtol) for a in analyses]
        except ScrewkitError as exc:
            reps = [PMCheckReport(label, {}, (), None, str(exc))]
        for r in reps:
            if progress is not None:
                progress(r)
            out.append(r)
    return tuple(out)
