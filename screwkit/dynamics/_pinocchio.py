"""The inverse dynamics of a PM from Pinocchio's closed-loop model, against screwkit's.

Pinocchio side (:func:`check_dynamics`), independent of screwkit's dynamics code:

1. The closed-loop model of :func:`screwkit.interop.build_closed_loop_model` (every leg a
   branch from the universe, native S/U/R/P joints, the platform carried by the first
   leg, each other leg welded to it) gets the same inertias: each massive link on the
   Pinocchio joint it follows (the joint frames are world-oriented at home), the platform
   on the carrier's last joint, gravity in ``model.gravity``.
2. At each sample, the configuration ``q`` is screwkit's solved joint values (positions
   are cross-checked by ``screwkit check``).  The only motion input is the actuators'
   rates and accelerations.
3. Velocities: ``J_c v = 0`` (``J_c = J_1 - J_2``, the WORLD frame Jacobians of the welded
   frames), ``S v = rdot`` (``S`` selects the actuated joints), an idle motion of least
   kinetic energy (``min v^T M v``, with ``M`` from CRBA).
4. Accelerations and forces in one linear system: ``M a + h = S^T F_a + J_c^T lambda``
   (``h`` = RNEA at zero acceleration with the external workload as ``fext``),
   ``J_c a = -(a_1 - a_2)`` (the frames' WORLD spatial accelerations at ``a = 0``),
   ``S a = rddot``.  ``F_a`` are the actuator forces; ``-lambda`` is the wrench of each
   welded leg on the platform (WORLD, about ``O``); the carrier's is what balances the
   platform's RNEA wrench.

The report compares ``F_a``, the legs' wrenches on the platform and the platform twist and
acceleration with screwkit's (:class:`DynamicsCheck`).
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from ..errors import InputError

__all__ = ["DynamicsCheck", "check_dynamics", "pinocchio_model_with_inertias"]


@dataclass(frozen=True, eq=False)
class DynamicsCheck:
    """Pinocchio's inverse dynamics at the checked samples beside screwkit's.

    Attributes
    ----------
    samples : ndarray (K,) of int
    active, active_screwkit : ndarray (K, n)
    leg_wrenches, leg_wrenches_screwkit : ndarray (K, n, 6)
    twist, acceleration : ndarray (K, 6)
        Pinocchio's platform twist and spatial acceleration (about ``O``).
    errors : dict str -> float
        Largest relative differences: ``active`` (over the largest ``|F_a|`` of the
        sample), ``leg_wrenches`` (normalised wrenches), ``twist``, ``acceleration``.
    residual : float
        Largest relative residual of Pinocchio's linear systems.
    """

    samples: np.ndarray
    active: np.ndarray
    active_screwkit: np.ndarray
    leg_wrenches: np.ndarray
    leg_wrenches_screwkit: np.ndarray
    twist: np.ndarray
    acceleration: np.ndarray
    errors: dict
    residual: float

    def passed(self, rtol: float = 1e-8) -> bool:
        return all(v <= rtol for v in self.errors.values())


def pinocchio_model_with_inertias(model, params):
    """The closed-loop Pinocchio model of ``model`` with the inertias of ``params``."""
    import pinocchio as pin
    from ..interop import build_closed_loop_model

    clm = build_closed_loop_model(model.home_legs, model.platform_home)
    pm = clm.model
    R0, p0 = (np.asarray(x, float) for x in model.frame)
    for ch, ld in zip(clm.chains, params.legs):
        ends = {b.sk[-1]: b for b in ch.blocks}
        for slot, body in ld.links:
            if slot not in ends:
                raise InputError(f"leg {ch.leg.name}: the link after joint "
                                 f"{ch.leg.joints[slot].name} is inside a compound joint")
            b = ends[slot]
            bw = body.moved(R0, p0)
            origin = ch.leg.joints[b.sk[0]].point
            pm.inertias[b.joint_id] = pin.Inertia(bw.mass, bw.com - origin, bw.inertia)
        for k, b in enumerate(ch.blocks):
            if b.nv > 1 and (np.any(ld.viscous[list(b.sk)])
                                                     or np.any(ld.coulomb[list(b.sk)])):
                if b.kind != "universal":
                    raise InputError(f"leg {ch.leg.name}: friction on the joints of a "
                                     f"{b.kind} joint has no Pinocchio counterpart here")
    car = clm.chains[clm.carrier]
    Rh, oh = model.platform_home
    pb = params.platform
    origin = car.leg.joints[car.blocks[-1].sk[0]].point
    pm.inertias[car.end_joint] = pin.Inertia(pb.mass, Rh @ pb.com + oh - origin,
                                             Rh @ pb.inertia @ Rh.T)
    pm.gravity = pin.Motion(np.concatenate([R0 @ params.gravity, np.zeros(3)]))
    return clm


def _friction(clm, params, qd_sk):
    """Friction efforts on Pinocchio's velocity vector (one-dof and universal blocks)."""
    tau = np.zeros(clm.model.nv)
    for ch, ld, qd in zip(clm.chains, params.legs, qd_sk):
        for b in ch.blocks:
            if b.kind in ("spherical",):
                continue
            for k, s in enumerate(b.sk):
                tau[b.idx_v + k] += ld.viscous[s] * qd[s] + ld.coulomb[s] * np.sign(qd[s])
    return tau


def check_dynamics(model, motion=None, *, result=None, samples=None, **kwargs) -> DynamicsCheck:
    """Compare screwkit's inverse dynamics with Pinocchio's (module docstring).

    Parameters
    ----------
    model : PMModel
    motion : Motion, optional
        With ``kwargs`` (``params``, ``force``, ``torque``...) passed to :func:`dynamics`;
        or give ``result`` (a :class:`DynamicsResult`).
    samples : sequence of int, optional
        The samples to check (default: every ``ok`` sample).
    """
    import pinocchio as pin

    if result is None:
        from ._dynamics import dynamics
        result = dynamics(model, motion, **kwargs)
    res, model = result, result.model
    params = res.params
    clm = pinocchio_model_with_inertias(model, params)
    pm, data = clm.model, clm.model.createData()
    nv, n = pm.nv, model.n_legs
    idx = np.flatnonzero(res.ok) if samples is None else np.asarray(samples, int)
    car = clm.chains[clm.carrier]
    S = np.zeros((n, nv))
    for i, ch in enumerate(clm.chains):
        a = ch.leg.actuated_index
        blk = next(b for b in ch.blocks if a in b.sk)
        if blk.kind not in ("prismatic", "revolute", "helical", "universal") or \
                (blk.kind == "universal" and blk.sk[0] != a):
            raise InputError(f"leg {ch.leg.name}: its actuated joint is inside a {blk.kind} "
                             "joint whose rate Pinocchio does not give directly")
        S[i, blk.idx_v + blk.sk.index(a)] = 1.0
    jv = res.analysis.solution.joint_values
    qd_sk = res.joint_rates
    L = float(model.normalisation.length)
    out = {k: [] for k in ("F", "w", "V", "A")}
    worst = 0.0
    o_all = res.analysis.solution._platform[1]
    for k in idx:
        q = clm.q([np.asarray(v)[k] for v in jv])
        pin.computeJointJacobians(pm, data, q)
        pin.framesForwardKinematics(pm, data, q)
        Jc = np.vstack([pin.getFrameJacobian(pm, data, ch.frame_id, pin.WORLD)
                        - pin.getFrameJacobian(pm, data, car.frame_id, pin.WORLD)
                        for j, ch in enumerate(clm.chains) if j != clm.carrier])
        M = pin.crba(pm, data, q)
        M = np.triu(M) + np.triu(M, 1).T
        C = np.vstack([Jc, S])
        rd, rdd = res.actuator_rates[k], res.actuator_accelerations[k]
        # velocities of least kinetic energy: [M C^T; C 0] [v; mu] = [0; (0, rdot)]
        K = np.block([[M, C.T], [C, np.zeros((len(C), len(C)))]])
        rhs = np.concatenate([np.zeros(nv), np.zeros(len(Jc)), rd])
        v = np.linalg.lstsq(K, rhs, rcond=None)[0][:nv]
        pin.forwardKinematics(pm, data, q, v, np.zeros(nv))
        pin.updateFramePlacements(pm, data)
        gam = np.concatenate([
            pin.getFrameAcceleration(pm, data, ch.frame_id, pin.WORLD).vector
            - pin.getFrameAcceleration(pm, data, car.frame_id, pin.WORLD).vector
            for j, ch in enumerate(clm.chains) if j != clm.carrier])
        o = o_all[k]
        Wext = np.concatenate([res.force, res.torque + np.cross(o, res.force)])
        fext = [pin.Force.Zero() for _ in range(pm.njoints)]
        fext[car.end_joint] = data.oMi[car.end_joint].actInv(pin.Force(Wext))
        h = pin.rnea(pm, data, q, v, np.zeros(nv), fext) + _friction(clm, params,
                                                                    [x[k] for x in qd_sk])
        nc = len(Jc)
        # [M, -Jc^T, -S^T; Jc, 0, 0; S, 0, 0] [a; lambda; F] = [-h; -gamma; rddot]
        A = np.zeros((nv + nc + n, nv + nc + n))
        A[:nv, :nv], A[:nv, nv:nv + nc], A[:nv, nv + nc:] = M, -Jc.T, -S.T
        A[nv:nv + nc, :nv], A[nv + nc:, :nv] = Jc, S
        b = np.concatenate([-h, -gam, rdd])
        x = np.linalg.lstsq(A, b, rcond=None)[0]
        worst = max(worst, float(np.linalg.norm(A @ x - b) / max(np.linalg.norm(b), 1e-300)))
        a, lam, F = x[:nv], x[nv:nv + nc].reshape(-1, 6), x[nv + nc:]
        pin.forwardKinematics(pm, data, q, v, a)
        Vp = data.oMi[car.end_joint].act(data.v[car.end_joint]).vector
        Ap = data.oMi[car.end_joint].act(data.a[car.end_joint]).vector
        pin.rnea(pm, data, q, v, a)
        NE = data.oMi[car.end_joint].act(data.f[car.end_joint]).vector   # platform's own
        w = np.zeros((n, 6))
        others = [j for j in range(n) if j != clm.carrier]
        w[others] = -lam
        w[clm.carrier] = NE - Wext - w[others].sum(axis=0)
        out["F"].append(F)
        out["w"].append(w)
        out["V"].append(Vp)
        out["A"].append(Ap)
    F, w, V, A = (np.array(out[k]) for k in ("F", "w", "V", "A"))
    Fs, ws = res.dynamic_active[idx], res.leg_wrenches[idx]
    Vs, As = res.twist[idx], res.acceleration[idx]
    c = np.asarray(model.normalisation.centre, float)

    def nw(W):                               # normalised wrenches
        return np.concatenate([W[..., :3], (W[..., 3:] - np.cross(c, W[..., :3])) / L], axis=-1)

    def nt(T):                               # normalised twists
        return np.concatenate([(T[..., :3] - np.cross(c, T[..., 3:])) / L, T[..., 3:]], axis=-1)

    def rel(x, y, axis):
        d = np.linalg.norm(x - y, axis=axis)
        s = np.linalg.norm(y, axis=axis)
        while d.ndim > 1:
            d, s = d.max(axis=-1), s.max(axis=-1)
        return float(np.max(d / np.maximum(s, 1e-300))) if d.size else 0.0

    errors = {"active": rel(F, Fs, -1), "leg_wrenches": rel(nw(w), nw(ws), -1),
              "twist": rel(nt(V), nt(Vs), -1), "acceleration": rel(nt(A), nt(As), -1)}
    return DynamicsCheck(idx, F, Fs, w, ws, V, A, errors, worst)
