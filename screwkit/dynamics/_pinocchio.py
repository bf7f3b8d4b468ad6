"""The inverse dynamics of a PM from Pinocchio's closed-loop model, against screwkit's.

Pinocchio side (:func:`check_dynamics`), independent of screwkit's dynamics code:

1. The closed-loop model of :func:`screwkit.interop.build_closed_loop_model` (every leg a
   branch from the universe, native S/U/R/P joints, the platform carried by the first
   leg, each other leg welded to it) gets the same inertias: each massive link on the
   Pinocchio joint it follows (the joint frames are world-oriented at home), the platform
   on the carrier's last joint, gravity in ``model.gravity``; a parallelogram is its real
   four-bar, a bar per offset of the ``bars:`` block, each with its mass, closed on the
   far link by a point contact (:mod:`~._pinocchio_model`).
2. At each sample, the configuration ``q`` is screwkit's solved joint values; that it
   closes every loop (the welded frames coincide) and puts the platform at the solved pose
   is checked with Pinocchio's own forward kinematics (``DynamicsCheck.residual``).  The
   motion input is the path's own: the independent pose parameters' rates and
   accelerations (``Motion``, exact derivatives of the expressions), nothing of screwkit's
   velocity or acceleration solution.
3. Velocities: ``J_c v = 0`` (``J_c = J_1 - J_2``, the WORLD frame Jacobians of the welded
   frames, and the in-plane rows of the parallelograms' point contacts; where closures
   repeat constraints, their independent combinations) and ``P_ind J_p v = theta_dot_ind``, with ``J_p`` the platform frame's
   LOCAL_WORLD_ALIGNED Jacobian (velocity of ``o``, angular velocity) and ``P =
   diag(R0^T, E^-1 R0^T)`` its map to the pose parameters' rates (``E`` the Euler angles'
   columns, built here from scipy's elemental rotations); an idle motion of least kinetic
   energy (``min v^T M v``, with ``M`` from CRBA).
4. Accelerations and forces in one linear system: ``M a + h = S^T F_a + J_c^T lambda``
   (``h`` = RNEA at zero acceleration with the external workload as ``fext``, plus the
   joint friction at Pinocchio's ``v``; ``S`` selects the actuated joints),
   ``J_c a = -(a_1 - a_2)`` (the frames' WORLD spatial accelerations at ``a = 0``) and
   ``P_ind (J_p a + d) - [0; E^-1 Edot theta_dot]_ind = theta_ddot_ind`` (``d`` the platform
   frame's classical acceleration at ``a = 0``).  ``F_a`` are the actuator forces;
   ``-lambda`` is the wrench of each welded leg on the platform (WORLD, about ``O``); the
   carrier's is what balances the platform's RNEA wrench.

The report compares ``F_a``, the legs' wrenches on the platform (up to the self-stresses of
a statically indeterminate PM), the platform twist and acceleration, the actuator rates
``S v`` and the kinetic and potential energies with screwkit's (:class:`DynamicsCheck`).
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from ..engine import PARAMS
from ..errors import InputError
from ._pinocchio_model import (friction_efforts, independent_rows, parallelogram_frames,
                               parallelogram_rows, pinocchio_model_with_inertias, self_stresses)

__all__ = ["DynamicsCheck", "check_dynamics", "pinocchio_model_with_inertias"]

# (the model with screwkit's masses, the friction, the parallelograms' loops and the
# self-stresses of an indeterminate PM: ._pinocchio_model)


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
        sample), ``leg_wrenches`` (normalised wrenches), ``twist``, ``acceleration``,
        ``actuator_rates``, ``energy`` (the kinetic energy ``v^T M v / 2`` and Pinocchio's
        potential energy, up to its constant).
    residual : float
        Largest relative residual of Pinocchio's linear systems, and largest gap of the
        loop closures at the configuration (``log6`` of each welded frame relative to the
        carrier's, translation over the characteristic length).
    euler_condition : ndarray (K,)
        Condition number of the Euler angles' columns ``E`` at each sample (large near a
        representation singularity, where the ``path`` drive loses digits).
    drive : str
        ``path`` or ``actuators`` (:func:`check_dynamics`).
    self_stress : ndarray (K,) of int
        The number of independent self-stresses at each sample (leg wrenches that load
        nothing: 0 for a PM whose legs' wrenches are determined, 3 for the Delta's couples);
        ``leg_wrenches`` compares the wrenches up to them.
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
    euler_condition: np.ndarray = None
    drive: str = "path"
    self_stress: np.ndarray = None

    def passed(self, rtol: float = 1e-8) -> bool:
        return all(v <= rtol for v in self.errors.values())


def _euler_columns(order, angles, rates=None):
    """The Euler angles' columns ``E`` (``w = E theta_dot``, base frame), ``Edot theta_dot``
    and the rotation, from scipy's elemental rotations (independent of screwkit's Euler code).

    Intrinsic (upper case) ``R = R_1 R_2 R_3``: ``w = sum_k theta_dot_k R_<k e_k``; an
    extrinsic order is the intrinsic one reversed.  ``d/dt (R_<k e_k) = w_<k x (R_<k e_k)``.
    """
    from scipy.spatial.transform import Rotation
    seq = list(range(3)) if order.isupper() else [2, 1, 0]
    E, Rc = np.zeros((3, 3)), np.eye(3)
    wsum, bias = np.zeros(3), np.zeros(3)
    for k in seq:
        ax = order[k].upper()
        u = Rc @ np.eye(3)["XYZ".index(ax)]
        E[:, k] = u
        if rates is not None:
            bias += rates[k] * np.cross(wsum, u)
            wsum = wsum + rates[k] * u
        Rc = Rc @ Rotation.from_euler(ax, angles[k]).as_matrix()
    return E, bias, Rc


def _energy_error(T, U, Ts, Us) -> float:
    """Largest difference of the kinetic energies and of the potential energies (up to
    their constant, compared from the first checked sample), over the energy's scale."""
    if not len(T):
        return 0.0
    scale = max(np.abs(Ts).max(), np.ptp(Us), np.abs(Us).max() * 1e-12, 1e-300)
    d = max(np.abs(T - Ts).max(), np.abs((U - U[0]) - (Us - Us[0])).max())
    return float(d / scale)


def _solve(A, b):
    """Least-squares solution of ``A x = b`` with rows and columns equilibrated first (the
    masses, the lengths and the Euler rows near a representation singularity differ by
    orders of magnitude; scaling changes no solution, only the rounding)."""
    r = 1.0 / np.maximum(np.linalg.norm(A, axis=1), 1e-300)
    A1 = A * r[:, None]
    c = 1.0 / np.maximum(np.linalg.norm(A1, axis=0), 1e-300)
    y = np.linalg.lstsq(A1 * c, b * r, rcond=None)[0]
    return c * y


def check_dynamics(model, motion=None, *, result=None, samples=None, drive: str = "path",
                   **kwargs) -> DynamicsCheck:
    """Compare screwkit's inverse dynamics with Pinocchio's (module docstring).

    Parameters
    ----------
    model : PMModel
    motion : Motion, optional
        With ``kwargs`` (``params``, ``force``, ``torque``...) passed to :func:`dynamics`;
        or give ``result`` (a :class:`DynamicsResult`).
    samples : sequence of int, optional
        The samples to check (default: every ``ok`` sample).
    drive : {"path", "actuators"}
        What moves Pinocchio's model: the path's independent pose parameters (default; a
        second computation of the kinematics too), or screwkit's actuator rates and
        accelerations (``S v = rdot``, ``S a = rddot``: the forces only).  Near a
        representation singularity of the Euler angles the path drive is ill-conditioned
        (``E^-1`` grows like ``1 / sin(beta)``; ``DynamicsCheck.euler_condition``).
    """
    import pinocchio as pin

    if drive not in ("path", "actuators"):
        raise InputError(f"drive must be 'path' or 'actuators', not {drive!r}")

    if result is None:
        from ._dynamics import dynamics
        result = dynamics(model, motion, **kwargs)
    res, model = result, result.model
    params = res.params
    clm = pinocchio_model_with_inertias(model, params)
    pa_frames = parallelogram_frames(clm)
    pm, data = clm.model, clm.model.createData()
    nv, n = pm.nv, model.n_legs
    active = list(model.active)                    # a passive leg has no actuator
    na = len(active)
    idx = np.flatnonzero(res.ok) if samples is None else np.asarray(samples, int)
    car = clm.chains[clm.carrier]
    S = np.zeros((na, nv))
    for i, ch in enumerate(clm.chains[k] for k in active):
        a = ch.leg.actuated_index
        blk = next(b for b in ch.blocks if a in b.sk)
        if blk.kind not in ("prismatic", "revolute", "helical", "universal") or \
                (blk.kind == "universal" and blk.sk[0] != a):
            raise InputError(f"leg {ch.leg.name}: its actuated joint is inside a {blk.kind} "
                             "joint whose rate Pinocchio does not give directly")
        S[i, blk.idx_v + blk.sk.index(a)] = 1.0
    jv = res.analysis.solution.joint_values
    L = float(model.normalisation.length)
    out = {k: [] for k in ("F", "w", "wn", "V", "A", "r", "T", "U")}
    worst, cond, n_self = 0.0, [], []
    motion = res.motion
    R0, p0 = (np.asarray(x, float) for x in model.frame)
    ind = [PARAMS.index(p) for p in model.independent]
    c = np.asarray(model.normalisation.centre, float)

    def nw(W):                               # normalised wrenches
        return np.concatenate([W[..., :3], (W[..., 3:] - np.cross(c, W[..., :3])) / L], axis=-1)

    for k in idx:
        q = clm.q([np.asarray(v)[k] for v in jv])
        pin.computeJointJacobians(pm, data, q)
        pin.framesForwardKinematics(pm, data, q)
        # the configuration closes the loops: every welded frame is at the carrier's
        Mc = data.oMf[car.frame_id]
        for j, ch in enumerate(clm.chains):
            if j != clm.carrier:
                gap = pin.log6(Mc.actInv(data.oMf[ch.frame_id])).vector
                worst = max(worst, float(np.linalg.norm(
                    np.concatenate([gap[:3] / L, gap[3:]]))))
        for f1, f2, _, _ in pa_frames:      # and every parallelogram's second bar
            worst = max(worst, float(np.linalg.norm(data.oMf[f1].translation
                                                    - data.oMf[f2].translation)) / L)
        Jc = np.vstack([pin.getFrameJacobian(pm, data, ch.frame_id, pin.WORLD)
                        - pin.getFrameJacobian(pm, data, car.frame_id, pin.WORLD)
                        for j, ch in enumerate(clm.chains) if j != clm.carrier]
                       + [np.zeros((0, nv))])
        n_leg_rows = len(Jc)
        Jc = np.vstack([Jc, parallelogram_rows(pm, data, pa_frames)[0]])
        Q = independent_rows(Jc)          # repeated closures (the Delta's): their combinations
        Jr = Jc if Q is None else Q.T @ Jc
        M = pin.crba(pm, data, q)
        M = np.triu(M) + np.triu(M, 1).T
        # the independent pose parameters' rows: P maps the platform frame's twist
        # (LOCAL_WORLD_ALIGNED: velocity of o, angular velocity) to the six rates
        Jp = pin.getFrameJacobian(pm, data, car.frame_id, pin.LOCAL_WORLD_ALIGNED)
        angles = [float(np.asarray(res.params_values[p])[k]) for p in ("alpha", "beta", "gamma")]
        E, _, Rb = _euler_columns(model.order, angles)
        xyz = np.array([float(np.asarray(res.params_values[p])[k]) for p in ("Xo", "Yo", "Zo")])
        worst = max(worst, float(np.linalg.norm(Mc.rotation - R0 @ Rb)),
                    float(np.linalg.norm(Mc.translation - R0 @ xyz - p0)) / L)
        Einv = np.linalg.pinv(E)
        P = np.zeros((6, 6))
        P[:3, :3], P[3:, 3:] = R0.T, Einv @ R0.T
        cond.append(float(np.linalg.cond(E)))
        if drive == "path":
            D = P[ind] @ Jp
            rd = np.array([motion.rates[p][k] for p in model.independent])
            rdd = np.array([motion.accelerations[p][k] for p in model.independent])
        else:
            D, rd, rdd = S, res.actuator_rates[k], res.actuator_accelerations[k]
        C = np.vstack([Jr, D])
        # velocities of least kinetic energy: [M C^T; C 0] [v; mu] = [0; (0, theta_dot)]
        K = np.block([[M, C.T], [C, np.zeros((len(C), len(C)))]])
        rhs = np.concatenate([np.zeros(nv), np.zeros(len(Jr)), rd])
        v = _solve(K, rhs)[:nv]
        pin.forwardKinematics(pm, data, q, v, np.zeros(nv))
        pin.updateFramePlacements(pm, data)
        gam = np.concatenate([
            pin.getFrameAcceleration(pm, data, ch.frame_id, pin.WORLD).vector
            - pin.getFrameAcceleration(pm, data, car.frame_id, pin.WORLD).vector
            for j, ch in enumerate(clm.chains) if j != clm.carrier]
            + [parallelogram_rows(pm, data, pa_frames)[1]])
        gam = gam if Q is None else Q.T @ gam
        # theta_ddot = P (J_p a + drift) - [0; E^-1 Edot theta_dot]
        drift = pin.getFrameClassicalAcceleration(pm, data, car.frame_id,
                                                  pin.LOCAL_WORLD_ALIGNED).vector
        th_ang = (P @ (Jp @ v))[3:]
        bias = np.concatenate([np.zeros(3), Einv @ _euler_columns(model.order, angles,
                                                                  th_ang)[1]])
        gp = (P @ drift - bias)[ind] if drive == "path" else np.zeros(na)
        o = Mc.translation
        Wext = np.concatenate([res.force, res.torque + np.cross(o, res.force)])
        fext = [pin.Force.Zero() for _ in range(pm.njoints)]
        fext[car.end_joint] = data.oMi[car.end_joint].actInv(pin.Force(Wext))
        h = pin.rnea(pm, data, q, v, np.zeros(nv), fext) + friction_efforts(clm, params, v)
        nc = len(Jr)
        # [M, -Jc^T, -S^T; Jc, 0, 0; D, 0, 0] [a; lambda; F] = [-h; -gamma; rddot - gp]
        A = np.zeros((nv + nc + na, nv + nc + na))
        A[:nv, :nv], A[:nv, nv:nv + nc], A[:nv, nv + nc:] = M, -Jr.T, -S.T
        A[nv:nv + nc, :nv], A[nv + nc:, :nv] = Jr, D
        b = np.concatenate([-h, -gam, rdd - gp])
        x = _solve(A, b)
        worst = max(worst, float(np.linalg.norm(A @ x - b) / max(np.linalg.norm(b), 1e-300)))
        lam = x[nv:nv + nc] if Q is None else Q @ x[nv:nv + nc]
        a, lam, F = x[:nv], lam[:n_leg_rows].reshape(-1, 6), x[nv + nc:]
        pin.forwardKinematics(pm, data, q, v, a)
        Vp = data.oMi[car.end_joint].act(data.v[car.end_joint]).vector
        Ap = data.oMi[car.end_joint].act(data.a[car.end_joint]).vector
        pin.rnea(pm, data, q, v, a)
        NE = data.oMi[car.end_joint].act(data.f[car.end_joint]).vector   # platform's own
        w = np.zeros((n, 6))
        others = [j for j in range(n) if j != clm.carrier]
        w[others] = -lam
        w[clm.carrier] = NE - Wext - w[others].sum(axis=0)
        # up to the leg wrenches that load nothing (an indeterminate PM): the difference
        # from screwkit's without its part along them
        Sb = self_stresses(Jc, n_leg_rows, n, clm.carrier, nw)
        n_self.append(len(Sb))
        ws = nw(res.leg_wrenches[k]).reshape(-1)
        dn = nw(w).reshape(-1) - ws
        out["wn"].append((ws + dn - Sb.T @ (Sb @ dn)).reshape(n, 6))
        out["F"].append(F)
        out["r"].append(S @ v)
        out["T"].append(0.5 * v @ M @ v)                       # kinetic energy
        out["U"].append(pin.computePotentialEnergy(pm, data, q))
        out["w"].append(w)
        out["V"].append(Vp)
        out["A"].append(Ap)
    F, w, V, A, r, T, U = (np.array(out[k]) for k in ("F", "w", "V", "A", "r", "T", "U"))
    Fs, ws = res.dynamic_active[idx], res.leg_wrenches[idx]
    Vs, As = res.twist[idx], res.acceleration[idx]

    def nt(T):                               # normalised twists
        return np.concatenate([(T[..., :3] - np.cross(c, T[..., 3:])) / L, T[..., 3:]], axis=-1)

    def rel(x, y, axis):
        d = np.linalg.norm(x - y, axis=axis)
        s = np.linalg.norm(y, axis=axis)
        while d.ndim > 1:
            d, s = d.max(axis=-1), s.max(axis=-1)
        return float(np.max(d / np.maximum(s, 1e-300))) if d.size else 0.0

    wn = np.array(out["wn"]).reshape(len(idx), n, 6)
    errors = {"active": rel(F, Fs, -1), "leg_wrenches": rel(wn, nw(ws), -1),
              "twist": rel(nt(V), nt(Vs), -1), "acceleration": rel(nt(A), nt(As), -1),
              "actuator_rates": rel(r, res.actuator_rates[idx], -1),
              "energy": _energy_error(T, U, res.kinetic_energy[idx],
                                      res.potential_energy[idx])}
    return DynamicsCheck(idx, F, Fs, w, ws, V, A, errors, worst, np.array(cond), drive,
                         np.array(n_self, int))
