"""Pinocchio's side of the dynamics check: the closed-loop model with screwkit's masses, the
joint friction on Pinocchio's velocities, the parallelograms' own loops as rows of the
constraint Jacobian, and the self-stresses of a statically indeterminate PM.

* **Inertias** (:func:`pinocchio_model_with_inertias`): each massive link on the Pinocchio
  joint it follows (a link after a ``Pa`` on the far link's hinge ``bar_far``), the
  platform on the carrier's last joint; every bar of a parallelogram on its own hinge of
  the near link, at its offset (:func:`screwkit.interop.build_closed_loop_model` with
  ``bar_offsets``), closed on the far link by a point contact.
* **Friction** (:func:`friction_efforts`): on one-dof and universal blocks; a ``Pa``'s
  (screwkit's force along the arc ``s``) on its first bar's hinge, whose rate is ``s_dot /
  |b|``: the torque ``F |b|`` does the same work.
* **Parallelogram loops** (:func:`parallelogram_rows`): the end of each second bar and the
  same point of the far link move together; the two components in the four-bar's plane
  (normal to the hinges; the one along them holds identically) of ``J_1 - J_2`` (the
  points' LOCAL_WORLD_ALIGNED Jacobians) and of their classical accelerations at zero
  joint acceleration.
* **Redundant closures** (:func:`independent_rows`): a PM whose loops repeat constraints
  (the Delta's legs all forbid rotations) has a constraint Jacobian of deficient row rank;
  its independent combinations ``Q^T J_c`` make the accelerations' system regular (the
  solution is the same; the multipliers ``lambda = Q mu`` are one of the many).
* **Self-stresses** (:func:`self_stresses`): where the legs' wrenches on the platform are
  not determined by the mechanics (the Delta's legs' couples: 9 rows of rank 6), the
  multipliers ``lambda`` with ``J_c^T lambda = 0`` give the sets of leg wrenches that load
  nothing; two correct solutions differ by one of them.
"""

from __future__ import annotations

import numpy as np

from ..errors import InputError
from ..screws import RANK_RTOL

__all__ = ["pinocchio_model_with_inertias", "friction_efforts", "parallelogram_frames",
           "parallelogram_rows", "self_stresses", "independent_rows"]


def _bar_block(ch, slot, point):
    """The block of the bar of the Pa ``slot`` whose near hinge is at ``point``."""
    for b in ch.blocks:
        if b.sk == (slot,) and b.kind in ("bar", "bar_twin"):
            at = ch.leg.joints[slot].point if b.origin is None else b.origin
            if np.linalg.norm(np.asarray(at) - point) <= 1e-9 * max(1.0, ch.leg.length):
                return b
    raise InputError(f"leg {ch.leg.name}: no bar of {ch.leg.joints[slot].name} at "
                     f"{np.asarray(point).tolist()}")


def _add_inertia(pm, jid, body, origin):
    import pinocchio as pin
    pm.inertias[jid] = pm.inertias[jid] + pin.Inertia(body.mass, body.com - origin, body.inertia)


def pinocchio_model_with_inertias(model, params):
    """The closed-loop Pinocchio model of ``model`` with the inertias of ``params``."""
    import pinocchio as pin
    from ..interop import build_closed_loop_model

    offsets = {(i, pair.slot): tuple(pair.offsets)
               for i, ld in enumerate(params.legs) for pair in ld.bars}
    clm = build_closed_loop_model(model.home_legs, model.platform_home,
                                  passive=getattr(model, "passive", ()), bar_offsets=offsets)
    pm = clm.model
    R0, p0 = (np.asarray(x, float) for x in model.frame)
    for ch, ld in zip(clm.chains, params.legs):
        # the joint each link follows (the link after a Pa is its far link, on "bar_far")
        ends = {b.sk[-1]: b for b in ch.blocks if b.kind not in ("bar", "bar_twin")}
        for slot, body in ld.links:
            if slot not in ends:
                raise InputError(f"leg {ch.leg.name}: the link after joint "
                                 f"{ch.leg.joints[slot].name} is inside a compound joint")
            b = ends[slot]
            origin = ch.leg.joints[b.sk[0]].point if b.origin is None else b.origin
            _add_inertia(pm, b.joint_id, body.moved(R0, p0), origin)
        for pair in ld.bars:
            j = ch.leg.joints[pair.slot]
            for o, body in zip(pair.offsets, pair.bodies):
                at = np.asarray(j.point, float) + o * np.asarray(j.direction, float)
                _add_inertia(pm, _bar_block(ch, pair.slot, at).joint_id, body.moved(R0, p0), at)
        for b in ch.blocks:
            if b.nv > 1 and (np.any(ld.viscous[list(b.sk)]) or np.any(ld.coulomb[list(b.sk)])):
                if b.kind != "universal":
                    raise InputError(f"leg {ch.leg.name}: friction on the joints of a "
                                     f"{b.kind} joint has no Pinocchio counterpart here")
    car = clm.chains[clm.carrier]
    Rh, oh = model.platform_home
    pb = params.platform
    last = next(b for b in car.blocks if b.joint_id == car.end_joint)
    origin = car.leg.joints[last.sk[0]].point if last.origin is None else last.origin
    pm.inertias[car.end_joint] = pin.Inertia(pb.mass, Rh @ pb.com + oh - origin,
                                             Rh @ pb.inertia @ Rh.T)
    pm.gravity = pin.Motion(np.concatenate([R0 @ params.gravity, np.zeros(3)]))
    return clm


def friction_efforts(clm, params, v):
    """Friction efforts on Pinocchio's velocity vector ``v`` (one-dof and universal blocks,
    whose velocity components are the joint rates themselves, and a Pa's first bar)."""
    tau = np.zeros(clm.model.nv)
    for ch, ld in zip(clm.chains, params.legs):
        for b in ch.blocks:
            if b.kind in ("spherical", "bar_far", "bar_twin"):
                continue
            for k, s in enumerate(b.sk):
                qd = v[b.idx_v + k] / b.scale                 # screwkit's rate
                tau[b.idx_v + k] += (ld.viscous[s] * qd + ld.coulomb[s] * np.sign(qd)) / b.scale
    return tau


def parallelogram_frames(clm) -> list:
    """Add a frame at each end of every parallelogram loop; ``[(frame1, frame2, joint1,
    hinge)]`` (the second bar's end, the far link's point, the bar's joint and its home
    hinge)."""
    import pinocchio as pin
    pm = clm.model
    out = []
    for k, ch in enumerate(clm.chains):
        for n, (j1, p1, j2, p2) in enumerate(ch.loops):
            blk = next(b for b in ch.blocks if b.joint_id == j1)
            f1 = pm.addFrame(pin.Frame(f"leg{k + 1}.pa{n + 1}.bar_end", j1,
                                       pin.SE3(np.eye(3), p1), pin.FrameType.OP_FRAME))
            f2 = pm.addFrame(pin.Frame(f"leg{k + 1}.pa{n + 1}.far_point", j2,
                                       pin.SE3(np.eye(3), p2), pin.FrameType.OP_FRAME))
            out.append((f1, f2, j1, np.asarray(blk.axes[0], float)))
    return out


def _plane(h):
    """Two unit vectors normal to ``h`` and to each other."""
    a = np.eye(3)[int(np.argmin(np.abs(h)))]
    u = np.cross(h, a)
    u /= np.linalg.norm(u)
    return np.vstack([u, np.cross(h, u)])


def parallelogram_rows(pm, data, frames):
    """The parallelogram loops' rows ``(2 k, nv)`` of the constraint Jacobian and their drift
    ``(2 k,)`` (the classical accelerations at zero joint acceleration: call after
    ``forwardKinematics(q, v, 0)``); the Jacobians need ``computeJointJacobians(q)``."""
    import pinocchio as pin
    rows, drift = [], []
    for f1, f2, j1, h0 in frames:
        U = _plane(data.oMi[j1].rotation @ h0)
        lwa = pin.LOCAL_WORLD_ALIGNED
        rows.append(U @ (pin.getFrameJacobian(pm, data, f1, lwa)[:3]
                         - pin.getFrameJacobian(pm, data, f2, lwa)[:3]))
        drift.append(U @ (pin.getFrameClassicalAcceleration(pm, data, f1, lwa).linear
                          - pin.getFrameClassicalAcceleration(pm, data, f2, lwa).linear))
    nv = pm.nv
    return (np.vstack(rows) if rows else np.zeros((0, nv)),
            np.concatenate(drift) if drift else np.zeros(0))


def self_stresses(Jc, n_leg_rows, n_legs, carrier, normalise):
    """The leg-wrench sets that load nothing, as orthonormal rows ``(k, 6 n)`` of normalised
    wrenches (``normalise`` maps ``(..., 6)`` wrenches about ``O`` to normalised ones).

    ``lambda`` with ``J_c^T lambda = 0`` (rank decided on the equilibrated matrix,
    relative to its largest singular value) gives ``-lambda`` to the welded legs (the
    first ``n_leg_rows`` rows, 6 per leg) and their opposite sum to the carrier."""
    if not len(Jc):
        return np.zeros((0, 6 * n_legs))
    r, U, rank = _equilibrated_svd(Jc)
    lam = U[:, rank:].T * r                          # back from the scaled rows
    others = [j for j in range(n_legs) if j != carrier]
    out = []
    for x in lam:
        w = np.zeros((n_legs, 6))
        w[others] = -x[:n_leg_rows].reshape(-1, 6)
        w[carrier] = -w[others].sum(axis=0)
        out.append(normalise(w).reshape(-1))
    if not out:
        return np.zeros((0, 6 * n_legs))
    U, sv, Wt = np.linalg.svd(np.array(out), full_matrices=False)
    keep = sv > RANK_RTOL * max(sv[0], 1e-300)
    return Wt[keep]


def _equilibrated_svd(Jc):
    """Row scales ``r`` and the SVD of ``J_c`` with rows, then columns, of unit norm."""
    r = 1.0 / np.maximum(np.linalg.norm(Jc, axis=1), 1e-300)
    A = Jc * r[:, None]
    A = A / np.maximum(np.linalg.norm(A, axis=0), 1e-300)
    U, s, Vt = np.linalg.svd(A, full_matrices=True)
    rank = int(np.sum(s > RANK_RTOL * max(s[0], 1e-300))) if s.size else 0
    return r, U, rank


def independent_rows(Jc):
    """``Q (nc, r)``: the independent combinations of the rows of ``J_c`` (``Q^T J_c`` of
    full row rank, the same null space), rank decided on the equilibrated matrix relative
    to its largest singular value; ``None`` when the rows are independent already."""
    if not len(Jc):
        return None
    r, U, rank = _equilibrated_svd(Jc)
    if rank == len(Jc):
        return None
    return U[:, :rank] * r[:, None]
