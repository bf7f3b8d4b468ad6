"""Leg kinematics (product of exponentials) and the unified inverse displacement of a PM.

Each leg of a :class:`~screwkit.pm.PMModel` has a *home* geometry (a
:class:`~screwkit.legs.Leg` built by its catalog rules at the home pose) and
joint values ``q`` (one per equivalent joint, 0 at home).  Its end pose is the
product of exponentials in the world frame::

    T_end(q) = exp(xi_1 q_1) ... exp(xi_m q_m) T_end_home

with ``T_end_home`` the platform pose at home (the platform is rigidly attached
to the last link) and ``xi_i`` the home unit twists ``[v; w]``.  The *current*
twists are ``xi_i(q) = Ad(exp(xi_1 q_1) ... exp(xi_{i-1} q_{i-1})) xi_i``.  A P
joint translates by ``q u``; an H joint rotates by ``q`` and translates by
``pitch q`` along its axis.

Inverse displacement: given the independent pose parameters, the dependent
ones and every leg's joint values solve the loop closures ``T_end_i(q_i) =
T_platform(pose)`` by damped Gauss-Newton with minimum-norm steps (legs with
idle motions, e.g. the spin of an SPS, keep the smallest joint motion).  The
closure error of a leg is the length-normalised twist that carries its end
pose onto the platform pose, measured at the PM's centroid: ``[d / L; w]``
with ``w`` the rotation vector and ``d`` the displacement of the platform point
at the centroid (see :class:`screwkit.screws.Normalisation`); the reported
``residual`` is its largest component.
"""

from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np
from scipy.spatial.transform import Rotation

from ..errors import InputError, UnreachablePoseError
from ..legs import Joint, Leg, structure_vector
from ..pm import LENGTH_PARAMS, PARAMS     # the pose parametrisation of the models
from ..screws import angular_jacobian, is_singular, rotation_matrix

__all__ = ["PARAMS", "LENGTH_PARAMS", "PoseSolution", "leg_forward", "placed_leg",
           "solve_pose", "solve_path", "structure_vector", "CONVERGED", "ACCEPTED"]

#: Normalised closure residual regarded as converged (success).
CONVERGED = 1e-10
#: Largest normalised residual returned without raising UnreachablePoseError.
ACCEPTED = 1e-6
#: Largest structure-check residual regarded as satisfied (dimensionless).
STRUCTURE_TOL = 1e-7
_MAX_ITER = 60
_SING_STEP = 1e-4   # beta offset (radians) of the one-sided limits at a representation singularity


@dataclass(frozen=True, eq=False)
class PoseSolution:
    """The PM assembled at one pose.

    Attributes
    ----------
    model : PMModel
    params : dict
        ``Xo Yo Zo alpha beta gamma`` (lengths in model units, angles in radians).
    rotation : ndarray (3, 3)
        World <- platform rotation.
    position : ndarray (3,)
        The platform centre ``o`` (world).
    legs : tuple of Leg
        Each leg placed at the pose: joints on their current axes, names as at
        home, ``A = A_i`` and ``a = a_i`` (world).
    joint_values : tuple of ndarray (m_i,)
        Joint values (0 at home): radians for R and H, lengths for P.
    extensions : ndarray (n,)
        ``r_i = |a_i - A_i|``.
    actuator_values : ndarray (n,)
        Value of each leg's actuated joint (displacement from home).
    residual : float
        Largest length-normalised loop-closure error.
    success : bool
        ``residual <= CONVERGED``.
    notes : tuple of str
        Representation singularity and how it was resolved, defaults used...
    iterations : int
    """

    model: object
    params: dict
    rotation: np.ndarray
    position: np.ndarray
    legs: tuple
    joint_values: tuple
    extensions: np.ndarray
    actuator_values: np.ndarray
    residual: float
    success: bool
    notes: tuple = ()
    iterations: int = 0

    @property
    def platform_points(self) -> np.ndarray:
        """The platform vertices ``a_i`` (world), shape (n, 3)."""
        return np.array([lg.a for lg in self.legs])

    @property
    def base_points(self) -> np.ndarray:
        """The base vertices ``A_i`` (world), shape (n, 3)."""
        return np.array([lg.A for lg in self.legs])

    def __repr__(self) -> str:
        p = ", ".join(f"{k}={v:.6g}" for k, v in self.params_degrees().items())
        return (f"PoseSolution({getattr(self.model, 'name', '?')}: {p}; residual "
                f"{self.residual:.2g}, {'ok' if self.success else 'NOT converged'})")

    def params_degrees(self) -> dict:
        """``params`` with the angles in degrees."""
        return {k: (np.degrees(v) if k not in LENGTH_PARAMS else v) for k, v in self.params.items()}


# ---------------------------------------------------------------------------
# product of exponentials
# ---------------------------------------------------------------------------

def _cross(a, b):
    return np.array([a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0]])


def _rot(d, th):
    """Rodrigues: rotation by ``th`` about the unit vector ``d``."""
    x, y, z = d
    c, s = np.cos(th), np.sin(th)
    v = 1.0 - c
    return np.array([[c + x * x * v, x * y * v - z * s, x * z * v + y * s],
                     [y * x * v + z * s, c + y * y * v, y * z * v - x * s],
                     [z * x * v - y * s, z * y * v + x * s, c + z * z * v]])


def _rotvec(R):
    """Rotation vector of a rotation matrix (scipy's robust path near pi)."""
    w = 0.5 * np.array([R[2, 1] - R[1, 2], R[0, 2] - R[2, 0], R[1, 0] - R[0, 1]])
    c = 0.5 * (R[0, 0] + R[1, 1] + R[2, 2] - 1.0)
    if c < -0.9:
        return Rotation.from_matrix(R).as_rotvec()
    s = np.sqrt(w @ w)
    th = np.arctan2(s, c)
    return w * (th / s) if s > 1e-12 else w


def _leg_arrays(leg: Leg):
    kinds = tuple(j.kind for j in leg.joints)
    D = np.array([j.direction for j in leg.joints])
    P = np.array([j.point for j in leg.joints])
    H = np.array([j.pitch for j in leg.joints])
    return kinds, D, P, H


def _forward(arrays, q):
    """Current axes and the displacement ``G = prod exp(xi_i q_i)`` as (R, t)."""
    kinds, D, P, H = arrays
    R, t = np.eye(3), np.zeros(3)
    Dc, Pc = np.empty_like(D), np.empty_like(P)
    for i, k in enumerate(kinds):
        d, p = R @ D[i], R @ P[i] + t
        Dc[i], Pc[i] = d, p
        if k == "P":
            t = t + q[i] * d
        else:
            Ri = _rot(d, q[i])
            t = Ri @ t + p - Ri @ p + (H[i] * q[i] * d if k == "H" else 0.0)
            R = Ri @ R
    return Dc, Pc, R, t


def _twists(kinds, D, P, H):
    T = np.zeros((len(kinds), 6))
    for i, k in enumerate(kinds):
        if k == "P":
            T[i, :3] = D[i]
        else:
            T[i, :3] = _cross(P[i], D[i]) + (H[i] * D[i] if k == "H" else 0.0)
            T[i, 3:] = D[i]
    return T


def leg_forward(home_leg: Leg, q, platform_home=None):
    """Forward kinematics of one leg.

    Parameters
    ----------
    home_leg : Leg
    q : array_like (m,)
    platform_home : tuple (R (3, 3), p (3,)), optional

    Returns
    -------
    twists : ndarray (m, 6)
        Current joint twists.
    end : tuple (R, p)
        ``T_end(q)`` when ``platform_home`` is given, else the displacement ``G``.
    """
    arr = _leg_arrays(home_leg)
    q = _as_q(q, len(arr[0]), home_leg.name)
    Dc, Pc, R, t = _forward(arr, q)
    if platform_home is None:
        return _twists(arr[0], Dc, Pc, arr[3]), (R, t)
    R0, p0 = platform_home
    return _twists(arr[0], Dc, Pc, arr[3]), (R @ np.asarray(R0, float), R @ np.asarray(p0, float) + t)


def placed_leg(home_leg: Leg, q, A=None, a=None) -> Leg:
    """The leg with every joint on its current axis after joint values ``q``."""
    arr = _leg_arrays(home_leg)
    q = _as_q(q, len(arr[0]), home_leg.name)
    Dc, Pc, R, t = _forward(arr, q)
    joints = tuple(Joint(j.spec, Dc[i], Pc[i], j.pitch) for i, j in enumerate(home_leg.joints))
    A = home_leg.A if A is None else A
    a = (R @ home_leg.a + t) if a is None else a
    return Leg(home_leg.string, joints, A, a, home_leg.name)


def _as_q(q, m, name):
    q = np.asarray(q, dtype=float).reshape(-1)
    if q.shape != (m,):
        raise InputError(f"leg {name}: {q.size} joint values for {m} joints")
    if not np.all(np.isfinite(q)):
        raise InputError(f"leg {name}: joint values must be finite")
    return q


# ---------------------------------------------------------------------------
# the loop-closure solver
# ---------------------------------------------------------------------------

def _platform_twists(model, pose, names):
    """World twists of the platform per unit change of each pose parameter in ``names``."""
    R0, p0 = model.frame
    R, o = model.pose_matrix(pose)
    E = R0 @ angular_jacobian(model.order, pose["alpha"], pose["beta"], pose["gamma"])
    cols = []
    for n in names:
        if n in LENGTH_PARAMS:
            cols.append(np.concatenate([R0[:, "XYZ".index(n[0])], np.zeros(3)]))
        else:
            w = E[:, ("alpha", "beta", "gamma").index(n)]
            cols.append(np.concatenate([_cross(o, w), w]))
    return np.array(cols).reshape(len(names), 6)


def _closure_error(Rp, pp, Re, pe, c, L):
    Rd = Rp @ Re.T
    w = _rotvec(Rd)
    d = Rd @ (c - pe) + pp - c
    return np.concatenate([d / L, w])


class _Problem:
    """Unknowns: the dependent pose parameters, then every leg's joint values."""

    def __init__(self, model, fixed: dict, unknown_params):
        self.model = model
        self.fixed = dict(fixed)
        self.unknown = tuple(unknown_params)
        self.arrays = [_leg_arrays(lg) for lg in model.home_legs]
        self.sizes = [len(a[0]) for a in self.arrays]
        norm = model.normalisation
        self.c, self.L = norm.centre, norm.length
        Rh, ph = model.platform_home
        self.Rh, self.ph = Rh, ph
        # scale of each unknown: lengths are divided by L
        sc = [self.L if n in LENGTH_PARAMS else 1.0 for n in self.unknown]
        for a in self.arrays:
            sc += [self.L if k == "P" else 1.0 for k in a[0]]
        self.scale = np.array(sc)

    def split(self, x):
        pose = dict(self.fixed)
        pose.update(zip(self.unknown, x[:len(self.unknown)]))
        qs, k = [], len(self.unknown)
        for m in self.sizes:
            qs.append(x[k:k + m])
            k += m
        return pose, qs

    def evaluate(self, x, jac=True):
        pose, qs = self.split(x)
        Rp, pp = self.model.pose_matrix(pose)
        nu, n = len(self.unknown), len(x)
        e = np.zeros(6 * len(qs))
        J = np.zeros((6 * len(qs), n)) if jac else None
        Pt = self.model_norm_twists(_platform_twists(self.model, pose, self.unknown)) if jac else None
        k = nu
        for i, (arr, q) in enumerate(zip(self.arrays, qs)):
            Dc, Pc, R, t = _forward(arr, q)
            e[6 * i:6 * i + 6] = _closure_error(Rp, pp, R @ self.Rh, R @ self.ph + t, self.c, self.L)
            if jac:
                J[6 * i:6 * i + 6, :nu] = Pt.T
                J[6 * i:6 * i + 6, k:k + len(q)] = -self.model_norm_twists(
                    _twists(arr[0], Dc, Pc, arr[3])).T
            k += len(q)
        if jac:
            J = J * self.scale[None, :]
        return e, J

    def model_norm_twists(self, T):
        T = np.asarray(T, float)
        w = T[:, 3:]
        c = self.c
        v = T[:, :3] + np.column_stack([w[:, 1] * c[2] - w[:, 2] * c[1], w[:, 2] * c[0] - w[:, 0] * c[2],
                                        w[:, 0] * c[1] - w[:, 1] * c[0]])
        return np.concatenate([v / self.L, w], axis=1)


def _newton(prob: _Problem, x0, tol=CONVERGED * 1e-2, max_iter=_MAX_ITER):
    x = np.array(x0, dtype=float)
    e, J = prob.evaluate(x)
    f = float(np.max(np.abs(e)))
    it = 0
    lam = 0.0
    while f > tol and it < max_iter:
        it += 1
        if lam:
            A = np.vstack([J, np.sqrt(lam) * np.eye(J.shape[1])])
            rhs = np.concatenate([-e, np.zeros(J.shape[1])])
            dx = np.linalg.lstsq(A, rhs, rcond=None)[0]
        else:
            dx = np.linalg.lstsq(J, -e, rcond=1e-12)[0]
        step = dx * prob.scale
        accepted = False
        for k in range(8):
            xn = x + step
            en, Jn = prob.evaluate(xn, jac=(k == 0))
            if np.all(np.isfinite(en)) and np.linalg.norm(en) < np.linalg.norm(e):
                accepted = True
                break
            step = 0.5 * step
        if not accepted:
            if lam > 1e6:
                break
            lam = max(1e-6, 10 * lam)
            continue
        lam = lam / 10 if lam > 1e-9 else 0.0
        x, e = xn, en
        J = Jn if Jn is not None else prob.evaluate(x)[1]
        f = float(np.max(np.abs(e)))
    return x, f, it


def _validate(model, independent, degrees):
    if not isinstance(independent, dict):
        raise InputError(f"{model.name}: the independent pose parameters must be a mapping "
                         f"name -> value of {', '.join(model.independent)}")
    notes = []
    vals = {}
    for k, v in independent.items():
        if k not in PARAMS:
            raise InputError(f"{model.name}: unknown pose parameter {k!r} (one of {', '.join(PARAMS)})")
        if k not in model.independent:
            raise InputError(f"{model.name}: {k} is a dependent pose parameter; give "
                             f"{', '.join(model.independent)}")
        try:
            v = float(v)
        except (TypeError, ValueError):
            raise InputError(f"{model.name}: pose parameter {k} must be a number, got {v!r}") from None
        if not np.isfinite(v):
            raise InputError(f"{model.name}: pose parameter {k} is {v} (must be finite)")
        vals[k] = np.radians(v) if (degrees and k not in LENGTH_PARAMS) else v
    missing = [k for k in model.independent if k not in vals]
    if missing:
        for k in missing:
            vals[k] = model.default_pose[k]
        notes.append(f"{', '.join(missing)} taken from the default pose")
    return vals, notes


def _start(model, guess):
    """Full pose and joint values to start from: the guess (a PoseSolution or a dict) or home."""
    pose = dict(model.home_pose)
    qs = [np.zeros(len(lg.joints)) for lg in model.home_legs]
    if guess is None:
        return pose, qs
    if isinstance(guess, PoseSolution):
        gq = [np.array(q, float) for q in guess.joint_values]
        if [len(q) for q in gq] != [len(q) for q in qs]:
            raise InputError(f"{model.name}: the guess is a solution of another PM")
        return dict(guess.params), gq
    if isinstance(guess, dict):
        for k, v in guess.items():
            if k not in PARAMS or not np.isfinite(float(v)):
                raise InputError(f"{model.name}: bad guess entry {k}={v!r}")
            pose[k] = float(v)
        return pose, qs
    raise InputError(f"{model.name}: guess must be a PoseSolution or a dict of pose parameters")


def _solve_fixed(model, fixed, start_pose, start_q):
    """Newton from the start, then by continuation from the start pose if that fails."""
    unknown = tuple(p for p in PARAMS if p not in fixed)
    prob = _Problem(model, fixed, unknown)
    x0 = np.concatenate([[start_pose[p] for p in unknown]] + list(start_q))
    x, f, it = _newton(prob, x0)
    total = it
    if f <= CONVERGED:
        return prob, x, f, total
    # continuation: move the fixed parameters from the start pose in k steps
    for k in (4, 16, 64):
        xs, ok = x0.copy(), True
        for s in range(1, k + 1):
            fx = {p: start_pose[p] + (fixed[p] - start_pose[p]) * s / k for p in fixed}
            pr = _Problem(model, fx, unknown)
            xs, fs, it = _newton(pr, xs, tol=CONVERGED if s == k else 1e-6)
            total += it
            if fs > 1e-4:
                ok = False
                break
        if ok:
            x, f = xs, fs
            if f <= CONVERGED:
                break
    return prob, x, f, total


def solve_pose(model, independent: dict, guess=None, degrees: bool = False) -> PoseSolution:
    """Unified inverse displacement: see the module docstring and :func:`screwkit.solve`."""
    fixed, notes = _validate(model, independent, degrees)
    pose0, q0 = _start(model, guess)
    pair = [p for p in ("alpha", "gamma") if p not in fixed]
    beta_fixed = "beta" in fixed
    if beta_fixed and pair and is_singular(model.order, fixed["beta"]):
        fixed, extra = _resolve_singularity(model, fixed, pose0, q0, pair, guess)
        notes += extra
    elif beta_fixed and is_singular(model.order, fixed["beta"]):
        notes.append(f"beta = {np.degrees(fixed['beta']):.6g} deg is a representation singularity "
                     f"of {model.order}: alpha and gamma turn about the same axis (both given)")
    prob, x, f, it = _solve_fixed(model, fixed, pose0, q0)
    pose, qs = prob.split(x)
    if not np.isfinite(f) or f > ACCEPTED:
        given = ", ".join(f"{k}={_fmt(k, v)}" for k, v in fixed.items() if k in model.independent)
        raise UnreachablePoseError(
            f"{model.name}: pose {given} is unreachable from the home assembly: the loop "
            f"closures stop at a length-normalised residual {f:.3g} (> {ACCEPTED:g})", residual=f)
    if not beta_fixed and pair and is_singular(model.order, pose["beta"]):
        notes.append(f"beta = {np.degrees(pose['beta']):.6g} deg is a representation singularity of "
                     f"{model.order}: the split of {' and '.join(pair)} kept the warm start's value "
                     "(minimum-norm step)")
    return _assemble(model, pose, qs, f, tuple(notes), it)


def _fmt(k, v):
    return f"{v:.6g}" if k in LENGTH_PARAMS else f"{np.degrees(v):.6g} deg"


def _resolve_singularity(model, fixed, pose0, q0, pair, guess):
    """At a representation singularity the dependent angle(s) of the pair (alpha, gamma) are
    undetermined; take their limit as beta -> beta0 (one-sided from the warm start's side,
    Richardson-extrapolated, else the two-sided average)."""
    b0 = fixed["beta"]
    side = 0.0
    if guess is not None and abs(pose0["beta"] - b0) > _SING_STEP:
        side = np.sign(pose0["beta"] - b0)
    vals = {}
    offsets = (side * _SING_STEP, 2 * side * _SING_STEP) if side else (_SING_STEP, -_SING_STEP)
    for db in offsets:
        fx = dict(fixed, beta=b0 + db)
        prob, x, f, _ = _solve_fixed(model, fx, pose0, q0)
        if f > ACCEPTED:
            raise UnreachablePoseError(
                f"{model.name}: beta = {np.degrees(b0):.6g} deg is a representation singularity "
                f"of {model.order} and the neighbouring poses are unreachable (residual {f:.3g})",
                residual=f)
        pose, _ = prob.split(x)
        vals[db] = {p: pose[p] for p in pair}
    d1, d2 = offsets
    out = dict(fixed)
    if side:   # g(0) ~ 2 g(d) - g(2d)
        lim = {p: 2 * vals[d1][p] - vals[d2][p] for p in pair}
        how = f"the one-sided limit from beta {'>' if side > 0 else '<'} {np.degrees(b0):.6g} deg (warm start's side)"
        jump = 0.0
    else:
        lim = {p: 0.5 * (vals[d1][p] + vals[d2][p]) for p in pair}
        jump = max(abs(vals[d1][p] - vals[d2][p]) for p in pair)
        how = "the limit beta -> " + f"{np.degrees(b0):.6g} deg (average of both sides)"
    out.update(lim)
    txt = ", ".join(f"{p} = {np.degrees(v):.6g} deg" for p, v in lim.items())
    notes = [f"beta = {np.degrees(b0):.6g} deg is a representation singularity of {model.order} "
             f"(alpha and gamma turn about the same axis): {' and '.join(pair)} resolved by "
             f"continuity as {how}: {txt}"]
    if jump > 1e-3:
        notes.append(f"the one-sided limits differ by {np.degrees(jump):.3g} deg: the pose "
                     "parametrisation is discontinuous here")
    return out, notes


def _structure_notes(model, pose, legs):
    out = []
    for i, (r, lg) in enumerate(zip(model.leg_rules, legs)):
        if not r.structure:
            continue
        v = structure_vector(r, model.placement(i, pose), lg)
        if v.size and float(np.max(np.abs(v))) > STRUCTURE_TOL:
            out.append(f"leg {i + 1} ({r.name}): its structure checks do not hold here (residual "
                       f"{float(np.max(np.abs(v))):.3g}); its constraint wrenches are those of "
                       "the actual geometry")
    return out


def _assemble(model, pose, qs, f, notes, it) -> PoseSolution:
    Rp, pp = model.pose_matrix(pose)
    A = model.world_base_points
    a = (Rp @ model.platform_points.T).T + pp
    legs = tuple(placed_leg(h, q, A[i], a[i]) for i, (h, q) in enumerate(zip(model.home_legs, qs)))
    notes = tuple(notes) + tuple(_structure_notes(model, pose, legs))
    ext = np.linalg.norm(a - A, axis=1)
    act = np.array([q[h.actuated_index] for h, q in zip(model.home_legs, qs)])
    params = {p: float(pose[p]) for p in PARAMS}
    jv = tuple(np.array(q, float) for q in qs)
    for arr in (Rp, pp, ext, act, *jv):
        arr.setflags(write=False)
    return PoseSolution(model, params, Rp, pp, legs, jv, ext, act, float(f), bool(f <= CONVERGED),
                        notes, it)


def solve_path(model, poses, guess=None, degrees: bool = False) -> tuple:
    """Solve a sequence of poses, each warm-started from the previous solution."""
    out = []
    prev = guess
    for k, ind in enumerate(poses):
        try:
            sol = solve_pose(model, ind, prev, degrees)
        except UnreachablePoseError as exc:
            raise UnreachablePoseError(f"path sample {k}: {exc}", residual=exc.residual) from None
        out.append(sol)
        prev = sol
    return tuple(out)
