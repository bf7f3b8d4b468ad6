"""Cross-check of screwkit's kinematics and statics with Pinocchio.

Given what screwkit computed for a leg or a PM at a pose (joint values, the
legs placed at the pose, leg wrenches, actuator forces), rebuild the
mechanism in Pinocchio (:mod:`screwkit.interop._pinocchio_model`) and compare:

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
solution or a :class:`~screwkit.engine.PMAnalysis`) gives the detailed
rows, :func:`check_analysis` a :class:`PMCheckReport` with one row per check
(:data:`SUMMARY_CHECKS`), :func:`regular_analyses` draws regular poses around a
PM's default pose and :func:`check_all` runs the whole catalog
(``screwkit check``).

Every deviation is dimensionless (length-normalised with the geometry's
characteristic length, see :class:`screwkit.screws.Normalisation`) and
compared with ``rtol`` (default :data:`CHECK_RTOL`); ranks use
:data:`screwkit.screws.RANK_RTOL`.

This module holds the PM checker and :func:`check_pm`; the rows and reports are
in :mod:`screwkit.interop._check_rows`, the checks of one leg (a, b, d) in
:mod:`screwkit.interop._check_leg`, the mobility (c) in
:mod:`screwkit.interop._check_mobility` and the PM reports, regular poses and
catalog run in :mod:`screwkit.interop._check_catalog`; all are re-exported by
:mod:`screwkit.interop`.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from ..errors import InputError
from ..screws import Normalisation
from ._check_leg import _leg_rows
from ._check_mobility import _constraint_state, _legs_for, _mobility, _scales, _svd_rank
from ._check_rows import _TINY, CHECK_RTOL, CheckReport, _row, _span_gap
from ._pinocchio_chain import as_pose
from ._pinocchio_model import ClosedLoopModel, build_closed_loop_model, build_leg_model

__all__ = ["PMChecker", "check_closed_loop", "check_pm"]

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
    passive : tuple of int
        0-based indices of the passive legs: no actuated joint (``J^T w`` vanishes on all
        their joints; the actuator forces are the actuated legs' only).
    """

    home_legs: tuple
    platform_home: tuple
    leg_models: tuple
    closed: ClosedLoopModel
    name: str = ""
    passive: tuple = ()

    @classmethod
    def build(cls, home_legs, platform_home, name: str = "", *,
              point_contacts: bool = True, passive=()) -> "PMChecker":
        """Build the models (Pinocchio joints placed from the home legs' geometry)."""
        legs = tuple(home_legs)
        passive = tuple(sorted(set(int(i) for i in passive)))
        ph = as_pose(platform_home, "platform_home")
        lms = tuple(build_leg_model(lg, ph, passive=k in passive) for k, lg in enumerate(legs))
        clm = build_closed_loop_model(legs, ph, point_contacts=point_contacts, passive=passive)
        return cls(legs, ph, lms, clm, str(name), passive)

    @classmethod
    def for_model(cls, pm_model) -> "PMChecker":
        """Build for a :class:`screwkit.pm.PMModel` (its home legs, platform home pose and
        passive legs)."""
        return cls.build(pm_model.home_legs, pm_model.platform_home, getattr(pm_model, "name", ""),
                         passive=getattr(pm_model, "passive", ()))

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
        active = [k for k in range(n) if k not in self.passive]
        fa = _per_leg(actuator_forces, len(active), "actuator_forces (one per actuated leg)")
        fs = [None] * n
        for k, f in zip(active, fa):
            fs[k] = f
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
        if workload is not None and all(fs[k] is not None for k in active):
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
        act = [ch for ch in clm.chains if not ch.passive]
        F = np.array([float(f) for f in fs if f is not None])
        per = np.array([1.0 if ch.leg.actuated_joint.kind == "P" else 1.0 / L for ch in act])
        scale = L * (float(np.linalg.norm(norm.wrenches(W))) + float(np.sum(np.abs(F) * per)))
        dev = 0.0
        for x in Vt[r:]:
            v = colscale * x                               # Pinocchio joint velocities
            rates = [ch.rates(q, v)[ch.leg.actuated_index] for ch, q in zip(clm.chains, qs)
                     if not ch.passive]
            power = float(F @ np.array(rates) + W @ (Jp @ v))
            dev = max(dev, abs(power) / max(scale, _TINY))
        return dev


def check_closed_loop(home_legs, joint_values, platform_home, platform_pose=None, placed_legs=None,
                      leg_wrenches=None, actuator_forces=None, expected_dof=None, *,
                      workload=None, expected_twists=None, full_closure: bool = False,
                      rtol: float = CHECK_RTOL, passive=()) -> CheckReport:
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
        One per actuated leg (every leg but the ``passive`` ones), in leg order.
    expected_dof : int, optional
        Adds a ``mobility`` row (deviation ``max(|dof - e|, |nv - rank - idle - e|)``,
        tolerance 0).
    workload, expected_twists, full_closure
        See :meth:`PMChecker.check` (default: S-ended legs compare their S centre only).
    rtol : float
    passive : sequence of int
        0-based indices of the passive legs.

    Returns
    -------
    CheckReport
        Rows ``leg<i>.closure.*``, ``leg<i>.twists``, ``leg<i>.twists.span.S<k>``,
        ``leg<i>.statics.*``, ``loop.closure``, ``statics.work``, ``mobility``,
        ``mobility.twists``, ``mobility.locked``; values ``dof``, ``locked_dof``,
        ``constraint_rank``, ``locked_rank``, ``idle``, ``locked_idle``, ``internal``,
        ``nv``, ``condition``.
    """
    checker = PMChecker.build(home_legs, platform_home, passive=passive)
    return checker.check(joint_values, platform_pose, placed_legs, leg_wrenches, actuator_forces,
                         workload, expected_dof, expected_twists, full_closure=full_closure, rtol=rtol)


def _is_analysis(x) -> bool:
    return all(hasattr(x, a) for a in ("solution", "mobility", "jacobian", "statics"))


def check_pm(solution, statics=None, *, mobility=None, expected_dof=None, checker=None,
             rtol: float = CHECK_RTOL) -> CheckReport:
    """Cross-check a :class:`screwkit.engine.PoseSolution` (and optionally its statics).

    Parameters
    ----------
    solution : PoseSolution or PMAnalysis
        Uses ``solution.model.home_legs``, ``solution.model.platform_home`` (or
        ``home_rotation``/``home_position``), ``solution.joint_values``,
        ``solution.legs``, ``solution.rotation``, ``solution.position``.  A
        :class:`~screwkit.engine.PMAnalysis` brings its statics and mobility.
    statics : StaticsResult, optional
        ``leg_wrenches`` (n, 6), ``active`` (n,) and ``workload`` (6,).
    mobility : screwkit.pm.Mobility, optional
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
        if statics is None and getattr(solution, "has_workload", True):
            statics = solution.statics           # (none without a workload: kinematics only)
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
        checker = PMChecker.build(model.home_legs, home, getattr(model, "name", ""),
                                  passive=getattr(model, "passive", ()))
    elif len(checker.home_legs) != len(solution.joint_values):
        raise InputError(f"the checker has {len(checker.home_legs)} legs, the solution "
                         f"{len(solution.joint_values)}")
    return checker.check(solution.joint_values, (solution.rotation, solution.position), solution.legs,
                         wrenches, forces, workload, expected_dof, getattr(mobility, "twists", None),
                         full_closure=True, rtol=rtol)
