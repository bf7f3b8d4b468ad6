"""Check c) with Pinocchio: the mobility of a closed-loop model from its constraint Jacobian
(see :mod:`screwkit.interop._pinocchio_check`)."""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from ..legs import Leg
from ..screws import RANK_RTOL, Normalisation, reciprocal_system
from ._pinocchio_model import ClosedLoopModel

__all__ = ["Mobility", "mobility", "constraint_jacobian"]


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
    for lg, ch in zip(legs, clm.chains):
        T = lg.twists
        idle += len(T) - reciprocal_system(T, lg.points).rank
        Tp = T if ch.passive else np.delete(T, lg.actuated_index, axis=0)
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
