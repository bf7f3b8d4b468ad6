"""Checks a), b) and d) of one leg with Pinocchio: closure of its FK, its WORLD-frame joint
twists, and the statics of its wrench (see :mod:`screwkit.interop._pinocchio_check`)."""

from __future__ import annotations

import numpy as np

from ..errors import InputError
from ..legs import Leg
from ..screws import Normalisation
from ._check_rows import _TINY, CHECK_RTOL, CheckReport, _rel_product, _row, _span_gap
from ._pinocchio_chain import LegChain, as_pose
from ._pinocchio_model import build_leg_model

__all__ = ["check_leg"]


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
        ia = None if chain.passive else chain.leg.actuated_index
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
        if actuator_force is not None and ia is not None:
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
