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
   line); with the actuated columns removed no motion is left at a regular pose;
d) **statics** - ``J_leg(q)^T w`` (``w`` the leg's wrench on the platform about O)
   vanishes on the passive joints and equals the actuator force on the actuated
   joint.

Every deviation is dimensionless (length-normalised with the geometry's
characteristic length, see :class:`screwkit.reciprocal.Normalisation`) and
compared with ``rtol`` (default :data:`CHECK_RTOL`); ranks use
:data:`screwkit.tolerance.RANK_RTOL`.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from .errors import InputError
from .legs import Leg
from .pinocchio_model import (ClosedLoopModel, LegChain, as_pose, build_closed_loop_model,
                              build_leg_model)
from .reciprocal import Normalisation, reciprocal_system
from .tolerance import RANK_RTOL

__all__ = [
    "CHECK_RTOL",
    "CheckRow",
    "CheckReport",
    "Mobility",
    "check_leg",
    "check_closed_loop",
    "check_pm",
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


@dataclass(frozen=True)
class CheckReport:
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

    @property
    def failed(self) -> tuple:
        """Names of the rows that failed."""
        return tuple(r.name for r in self.rows if not r.passed)

    def row(self, name: str) -> CheckRow:
        for r in self.rows:
            if r.name == name:
                return r
        raise InputError(f"no check row {name!r}; rows: {', '.join(r.name for r in self.rows)}")

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
              rtol, prefix) -> list:
    """Checks a), b), d) of one leg; ``model``/``data`` may hold other legs too."""
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
            rows.append(_row(f"{prefix}closure.position", np.linalg.norm(E.translation - target) / L, rtol))
        else:
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


@dataclass(frozen=True)
class Mobility:
    """Mobility of a closed-loop model at a configuration.

    Attributes
    ----------
    dof : int
        ``nv - rank - idle``.
    locked_dof : int
        The same with the actuated columns removed and the idle motions of the
        passive chains.
    rank, locked_rank : int
        Ranks of the (normalised) constraint Jacobian, full and without actuated columns.
    idle, locked_idle : int
        Dependent joints of the legs (all joints / passive joints only).
    nv : int
    smallest_singular_value : float
        Smallest retained normalised singular value over the largest (1/condition).
    """

    dof: int
    locked_dof: int
    rank: int
    locked_rank: int
    idle: int
    locked_idle: int
    nv: int
    smallest_singular_value: float


def _rank(Jn):
    if Jn.size == 0:
        return 0, 1.0
    s = np.linalg.svd(Jn, compute_uv=False)
    r = int(np.sum(s > RANK_RTOL * max(1.0, float(s[0]))))
    return r, (float(s[r - 1] / s[0]) if r else 1.0)


def constraint_jacobian(clm: ClosedLoopModel, data, qpin) -> np.ndarray:
    """``pin.getConstraintsJacobian`` at ``qpin`` (rows LOCAL to each leg's platform frame).

    Pinocchio 4.1 quirk: each constraint's ``calc`` must run after the kinematics,
    otherwise the Jacobian is silently computed with stale contact placements.
    """
    import pinocchio as pin
    model = clm.model
    pin.computeJointJacobians(model, data, qpin)
    if not clm.constraints:
        return np.zeros((0, model.nv))
    cms = pin.StdVec_RigidConstraintModel()
    cds = pin.StdVec_RigidConstraintData()
    for cm in clm.constraints:
        cd = cm.createData()
        cm.calc(model, data, cd)
        cms.append(cm)
        cds.append(cd)
    return np.array(pin.getConstraintsJacobian(model, data, cms, cds))


def mobility(clm: ClosedLoopModel, joint_values, placed_legs=None) -> Mobility:
    """Mobility from Pinocchio's loop-closure constraint Jacobian (check c).

    The Jacobian is normalised before the rank decision: linear rows divided by the
    characteristic length ``L`` of the geometry, prismatic (and helical-free
    translation) columns multiplied by ``L``.  Idle motions are counted from the
    screwkit legs: ``m - rank(twists)`` over all joints, and ``(m - 1) -
    rank(passive twists)`` for the locked count (the spin of an SPS leg about
    its line is one of each).
    """
    model = clm.model
    data = model.createData()
    qpin = clm.q(joint_values)
    Jc = constraint_jacobian(clm, data, qpin)
    legs = tuple(placed_legs) if placed_legs is not None else ()
    if len(legs) != len(clm.chains) or not all(isinstance(lg, Leg) for lg in legs):
        legs = tuple(ch.leg for ch in clm.chains)
    L = Normalisation.for_points(np.vstack([lg.points for lg in legs])).length
    rowscale = np.tile(np.r_[np.full(3, 1.0 / L), np.ones(3)], len(clm.constraints))
    colscale = np.ones(model.nv)
    act = []
    for ch in clm.chains:
        for b in ch.blocks:
            if b.kind == "prismatic":
                colscale[b.idx_v] = L
        act.extend(ch.actuated_columns())
    Jn = rowscale[:, None] * Jc * colscale[None, :]
    rank, smin = _rank(Jn)
    keep = [c for c in range(model.nv) if c not in act]
    locked_rank, _ = _rank(Jn[:, keep])
    idle = locked_idle = 0
    for lg in legs:
        T = lg.twists
        ia = lg.actuated_index
        idle += len(T) - reciprocal_system(T, lg.points).rank
        Tp = np.delete(T, ia, axis=0)
        locked_idle += len(Tp) - reciprocal_system(Tp, lg.points).rank
    return Mobility(model.nv - rank - idle, len(keep) - locked_rank - locked_idle, rank, locked_rank,
                    idle, locked_idle, model.nv, smin)


def check_closed_loop(home_legs, joint_values, platform_home, platform_pose=None, placed_legs=None,
                      leg_wrenches=None, actuator_forces=None, expected_dof=None, *,
                      rtol: float = CHECK_RTOL) -> CheckReport:
    """Cross-check a PM at a pose with one Pinocchio closed-loop model.

    Parameters
    ----------
    home_legs : sequence of Leg
        Home geometries, leg 1 first (it carries the platform in the model).
    joint_values : sequence of array_like (m_i,)
    platform_home : tuple (R, p)
    platform_pose : tuple (R, p), optional
    placed_legs : sequence of Leg, optional
        The legs at the pose (current twists); also used to count idle motions.
    leg_wrenches : sequence of array_like (6,), optional
        Each leg's wrench on the platform, about O.
    actuator_forces : sequence of float, optional
    expected_dof : int, optional
        Adds a ``mobility`` row (deviation ``|dof - expected|``, tolerance 0).
    rtol : float

    Returns
    -------
    CheckReport
        Rows ``leg<i>.closure.*``, ``leg<i>.twists``, ``leg<i>.statics.*``,
        ``loop.closure``, ``mobility``, ``mobility.locked``; values ``dof``,
        ``locked_dof``, ``constraint_rank``, ``idle``, ``nv``, ``condition``.
    """
    import pinocchio as pin
    legs = tuple(home_legs)
    n = len(legs)

    def per_leg(x, what):
        if x is None:
            return (None,) * n
        x = tuple(x)
        if len(x) != n:
            raise InputError(f"{what}: {len(x)} entries for {n} legs")
        return x

    qs = per_leg(joint_values, "joint_values")
    placed = per_leg(placed_legs, "placed_legs")
    ws = per_leg(leg_wrenches, "leg_wrenches")
    fs = per_leg(actuator_forces, "actuator_forces")
    clm = build_closed_loop_model(legs, platform_home)
    model = clm.model
    data = model.createData()
    qpin = clm.q(qs)
    rows = []
    for k, ch in enumerate(clm.chains):
        q = np.asarray(qs[k], float).reshape(-1)
        rows += _leg_rows(ch, model, data, q, platform_pose, placed[k], ws[k], fs[k], rtol, f"leg{k + 1}.")
    # loop closure inside the closed-loop model: leg i's platform frame on leg 1's
    pin.framesForwardKinematics(model, data, qpin)
    pts = [lg.points for lg in (placed if all(isinstance(x, Leg) for x in placed) else legs)]
    L = Normalisation.for_points(np.vstack(pts)).length
    P0 = data.oMf[clm.chains[0].frame_id]
    dev = 0.0
    for ch in clm.chains[1:]:
        Pi = data.oMf[ch.frame_id]
        d = pin.log6(Pi.inverse() * P0).vector
        dev = max(dev, float(np.linalg.norm(d[:3]) / L), float(np.linalg.norm(d[3:])))
    rows.append(_row("loop.closure", dev, rtol))
    mob = mobility(clm, qs, placed_legs)
    if expected_dof is not None:
        rows.append(_row("mobility", abs(mob.dof - int(expected_dof)), 0))
    rows.append(_row("mobility.locked", abs(mob.locked_dof), 0))
    values = (("dof", mob.dof), ("locked_dof", mob.locked_dof), ("constraint_rank", mob.rank),
              ("locked_rank", mob.locked_rank), ("idle", mob.idle), ("locked_idle", mob.locked_idle),
              ("nv", mob.nv), ("condition", 1.0 / mob.smallest_singular_value))
    return CheckReport(tuple(rows), values)


def check_pm(solution, statics=None, *, expected_dof=None, rtol: float = CHECK_RTOL) -> CheckReport:
    """Cross-check a :mod:`screwkit.pm` pose solution (and optionally its statics).

    Written against the PM contract: ``solution.model.home_legs``,
    ``solution.joint_values`` (one (m_i,) array per leg), ``solution.legs`` (placed),
    ``solution.rotation``, ``solution.position``; the platform home pose is
    ``solution.model.platform_home`` (or ``home_rotation``/``home_position``).
    ``statics`` (e.g. a :class:`screwkit.statics.StaticsResult`) gives ``leg_wrenches``
    (k, 6) and ``actuator_forces`` or ``active`` (k,).
    ``expected_dof`` defaults to ``solution.model.dof`` when present.
    """
    model = solution.model
    home = getattr(model, "platform_home", None)
    if home is None:
        home = (getattr(model, "home_rotation", np.eye(3)), getattr(model, "home_position"))
    if expected_dof is None:
        expected_dof = getattr(model, "dof", None)
    wrenches = forces = None
    if statics is not None:
        wrenches = getattr(statics, "leg_wrenches", None)
        forces = getattr(statics, "actuator_forces", None)
        if forces is None:
            forces = getattr(statics, "active", None)
    return check_closed_loop(model.home_legs, solution.joint_values, home,
                             (solution.rotation, solution.position), solution.legs,
                             wrenches, forces, expected_dof, rtol=rtol)
