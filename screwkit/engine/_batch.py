"""Vectorised (over path samples) kinematics, Jacobian rows and statics of a PM.

The per-pose pipeline (:func:`screwkit.solve`, :meth:`Leg.analyze`,
:func:`~screwkit.engine.unified_jacobian`, :func:`~screwkit.engine.statics`)
costs ~35 ms a pose, most of it in the observation-rule decomposition of every
leg (named points, rule explanations).  Along a path the *structure* of that
decomposition does not change, only the geometry; this module evaluates the
same quantities for N samples at once with numpy:

* :func:`newton_batch` - the loop closures of :mod:`screwkit.engine._kinematics`
  (same unknowns, same length-normalised closure error, same minimum-norm
  Gauss-Newton step) for N samples simultaneously;
* :class:`LegTemplate` - what a leg's analysis chose at a reference pose (its
  constraint row is the leg's unique reciprocal wrench, its actuation row is
  the unit force on the line through two named points); :meth:`LegTemplate.rows`
  recomputes both at N poses and flags every sample where one of the analysis'
  decisions (rank, kind, orientation, choice of line) is not clear-cut;
* :func:`jacobian_statics_batch` - conditioning and statics with the formulas of
  :mod:`screwkit.engine._jacobian` and :mod:`screwkit.engine._statics`.

Flagged samples are recomputed by the caller (:mod:`screwkit.paths._trajectory`) with
the per-pose pipeline, so the results agree with ``screwkit analyze`` at every
sample (``tests/test_trajectory.py`` checks it).
"""

from __future__ import annotations

from dataclasses import dataclass
from itertools import combinations

import numpy as np
from scipy.spatial.transform import Rotation

from ..screws import GEOMETRY_RTOL, RANK_RTOL
from ._jacobian import COND_THRESHOLD
from ._kinematics import CONVERGED, LENGTH_PARAMS

__all__ = ["LegArrays", "leg_arrays", "forward_batch", "twists_batch", "KinematicsBatch",
           "BatchProblem", "newton_batch", "assemble_batch", "LegTemplate",
           "jacobian_statics_batch", "BatchStatics"]

_AX = {"x": 0, "y": 1, "z": 2}
#: Safety factor: a decision is "clear-cut" when its test quantity is this far from the threshold.
_MARGIN = 1e3
#: Step halvings tried by :func:`newton_batch` before giving a sample up.
_HALVINGS = 6


# ----------------------------------------------------------------------------- small batched algebra

def _mv(R, v):
    """(N, 3, 3) @ (N, 3) -> (N, 3)."""
    return np.einsum("nij,nj->ni", R, v)


def _rot(d, th):
    """Rodrigues, batched: rotations by ``th`` (N,) about unit ``d`` (N, 3)."""
    x, y, z = d[:, 0], d[:, 1], d[:, 2]
    c, s = np.cos(th), np.sin(th)
    v = 1.0 - c
    R = np.empty((len(th), 3, 3))
    R[:, 0, 0] = c + x * x * v
    R[:, 0, 1] = x * y * v - z * s
    R[:, 0, 2] = x * z * v + y * s
    R[:, 1, 0] = y * x * v + z * s
    R[:, 1, 1] = c + y * y * v
    R[:, 1, 2] = y * z * v - x * s
    R[:, 2, 0] = z * x * v - y * s
    R[:, 2, 1] = z * y * v + x * s
    R[:, 2, 2] = c + z * z * v
    return R


def _axis_rot(axis, ang):
    """Batched :func:`screwkit.screws.axis_rotation`."""
    c, s = np.cos(ang), np.sin(ang)
    j, k = (axis + 1) % 3, (axis + 2) % 3
    R = np.zeros((len(ang), 3, 3))
    R[:, axis, axis] = 1.0
    R[:, j, j] = R[:, k, k] = c
    R[:, k, j], R[:, j, k] = s, -s
    return R


def _rotvec(R):
    """Batched rotation vectors (the formula of ``kinematics._rotvec``)."""
    w = 0.5 * np.stack([R[:, 2, 1] - R[:, 1, 2], R[:, 0, 2] - R[:, 2, 0],
                        R[:, 1, 0] - R[:, 0, 1]], axis=1)
    c = 0.5 * (np.trace(R, axis1=1, axis2=2) - 1.0)
    s = np.linalg.norm(w, axis=1)
    th = np.arctan2(s, c)
    out = np.where((s > 1e-12)[:, None], w * (th / np.where(s > 0, s, 1.0))[:, None], w)
    far = c < -0.9
    if np.any(far):
        out[far] = Rotation.from_matrix(R[far]).as_rotvec()
    return out


def _char_length(P):
    """Batched :func:`screwkit.screws.characteristic_length` for (N, p, 3) points
    (RMS spread about the centroid); returns (centre (N, 3), length (N,), ok (N,))."""
    c = P.mean(axis=1)
    L = np.sqrt(np.mean(np.sum((P - c[:, None, :]) ** 2, axis=2), axis=1))
    ok = L > 1e-9 * np.max(np.abs(P), axis=(1, 2))
    return c, np.where(ok, L, 1.0), ok


def _norm_wrenches(W, c, L):
    """``Normalisation(c, L).wrenches`` batched: W (N, ..., 6), c (N, 3), L (N,)."""
    sh = (-1,) + (1,) * (W.ndim - 2) + (3,)
    f = W[..., :3]
    m = (W[..., 3:] - np.cross(c.reshape(sh), f)) / L.reshape(sh[:-1] + (1,))
    return np.concatenate([f, m], axis=-1)


def _norm_twists(T, c, L):
    sh = (-1,) + (1,) * (T.ndim - 2) + (3,)
    w = T[..., 3:]
    v = (T[..., :3] - np.cross(c.reshape(sh), w)) / L.reshape(sh[:-1] + (1,))
    return np.concatenate([v, w], axis=-1)


# ----------------------------------------------------------------------------- legs

@dataclass(frozen=True)
class LegArrays:
    """A home leg as arrays: joint kinds (m,), home directions and points (m, 3), pitches."""

    kinds: tuple
    D: np.ndarray
    P: np.ndarray
    H: np.ndarray


def leg_arrays(leg) -> LegArrays:
    return LegArrays(tuple(j.kind for j in leg.joints), np.array([j.direction for j in leg.joints]),
                     np.array([j.point for j in leg.joints]), np.array([j.pitch for j in leg.joints]))


def forward_batch(arr: LegArrays, q):
    """Batched product of exponentials (``kinematics._forward``).

    Parameters
    ----------
    arr : LegArrays
    q : ndarray (N, m)

    Returns
    -------
    Dc, Pc : ndarray (N, m, 3)
        Current joint directions and points.
    R : ndarray (N, 3, 3)
    t : ndarray (N, 3)
        The displacement ``G = prod exp(xi_i q_i)`` as ``x -> R x + t``.
    """
    N, m = q.shape
    R = np.broadcast_to(np.eye(3), (N, 3, 3)).copy()
    t = np.zeros((N, 3))
    Dc, Pc = np.empty((N, m, 3)), np.empty((N, m, 3))
    for i, k in enumerate(arr.kinds):
        d, p = R @ arr.D[i], R @ arr.P[i] + t
        Dc[:, i], Pc[:, i] = d, p
        if k == "P":
            t = t + q[:, i, None] * d
        else:
            Ri = _rot(d, q[:, i])
            t = _mv(Ri, t - p) + p
            if k == "H":
                t = t + (arr.H[i] * q[:, i])[:, None] * d
            R = Ri @ R
    return Dc, Pc, R, t


def twists_batch(kinds, H, Dc, Pc):
    """Joint twists (N, m, 6) ``[v; w]`` from current directions and points."""
    T = np.zeros(Dc.shape[:2] + (6,))
    for i, k in enumerate(kinds):
        if k == "P":
            T[:, i, :3] = Dc[:, i]
        else:
            T[:, i, :3] = np.cross(Pc[:, i], Dc[:, i]) + (H[i] * Dc[:, i] if k == "H" else 0.0)
            T[:, i, 3:] = Dc[:, i]
    return T


# ----------------------------------------------------------------------------- kinematics

@dataclass(frozen=True, eq=False)
class KinematicsBatch:
    """N assembled poses.

    Attributes
    ----------
    params : dict str -> ndarray (N,)
        The six pose parameters (radians, model units).
    q : list of ndarray (N, m_i)
        Joint values of each leg.
    Dc, Pc : list of ndarray (N, m_i, 3)
        Current joint directions and points of each leg (world).
    A : ndarray (n, 3)
        Base points (world).
    a : ndarray (N, n, 3)
        Platform points (world).
    o : ndarray (N, 3)
    residual : ndarray (N,)
        Largest length-normalised closure error.
    """

    params: dict
    q: list
    Dc: list
    Pc: list
    A: np.ndarray
    a: np.ndarray
    o: np.ndarray
    residual: np.ndarray


class BatchProblem:
    """``kinematics._Problem`` for N samples: unknowns = dependent pose parameters, then
    every leg's joint values (same order, same scaling)."""

    def __init__(self, model, fixed: dict):
        self.model = model
        self.fixed = {k: np.asarray(v, float) for k, v in fixed.items()}
        self.unknown = tuple(p for p in ("Xo", "Yo", "Zo", "alpha", "beta", "gamma")
                             if p not in fixed)
        self.arrays = [leg_arrays(lg) for lg in model.home_legs]
        self.sizes = [len(a.kinds) for a in self.arrays]
        self.c, self.L = model.normalisation.centre, model.normalisation.length
        self.Rh, self.ph = model.platform_home
        self.R0, self.p0 = model.frame
        sc = [self.L if n in LENGTH_PARAMS else 1.0 for n in self.unknown]
        for a in self.arrays:
            sc += [self.L if k == "P" else 1.0 for k in a.kinds]
        self.scale = np.array(sc)

    @property
    def n_unknowns(self) -> int:
        return len(self.scale)

    def split(self, X, rows=slice(None)):
        pose = {k: v[rows] for k, v in self.fixed.items()}
        nu = len(self.unknown)
        for j, n in enumerate(self.unknown):
            pose[n] = X[:, j]
        qs, k = [], nu
        for m in self.sizes:
            qs.append(X[:, k:k + m])
            k += m
        return pose, qs

    def pose_matrix(self, pose):
        ang = np.stack([pose["alpha"], pose["beta"], pose["gamma"]], axis=1)
        R = self.R0 @ Rotation.from_euler(self.model.order, ang).as_matrix()
        o = np.stack([pose["Xo"], pose["Yo"], pose["Zo"]], axis=1) @ self.R0.T + self.p0
        return R, o

    def _angular_jacobian(self, pose):
        order = self.model.order
        ax = [_AX[c] for c in order.lower()]
        a, b, g = pose["alpha"], pose["beta"], pose["gamma"]
        e = np.eye(3)
        N = len(a)
        if order.isupper():
            R1 = _axis_rot(ax[0], a)
            R12 = R1 @ _axis_rot(ax[1], b)
            cols = [np.broadcast_to(e[ax[0]], (N, 3)), R1 @ e[ax[1]], R12 @ e[ax[2]]]
        else:
            R3 = _axis_rot(ax[2], g)
            R32 = R3 @ _axis_rot(ax[1], b)
            cols = [R32 @ e[ax[0]], R3 @ e[ax[1]], np.broadcast_to(e[ax[2]], (N, 3))]
        return np.einsum("ij,njk->nik", self.R0, np.stack(cols, axis=2))

    def _model_norm(self, T):
        w = T[..., 3:]
        v = T[..., :3] + np.cross(w, self.c)
        return np.concatenate([v / self.L, w], axis=-1)

    def evaluate(self, X, rows=slice(None), jac=True, geometry=False):
        pose, qs = self.split(X, rows)
        N = len(X)
        Rp, pp = self.pose_matrix(pose)
        nu, n = len(self.unknown), X.shape[1]
        e = np.zeros((N, 6 * len(qs)))
        J = np.zeros((N, 6 * len(qs), n)) if jac else None
        if jac:
            E = self._angular_jacobian(pose) if any(u not in LENGTH_PARAMS for u in self.unknown) \
                else None
            Pt = np.zeros((N, nu, 6))
            for j, u in enumerate(self.unknown):
                if u in LENGTH_PARAMS:
                    Pt[:, j, :3] = self.R0[:, "XYZ".index(u[0])]
                else:
                    w = E[:, :, ("alpha", "beta", "gamma").index(u)]
                    Pt[:, j, :3] = np.cross(pp, w)
                    Pt[:, j, 3:] = w
            Pt = self._model_norm(Pt)
        geo = []
        k = nu
        for i, (arr, q) in enumerate(zip(self.arrays, qs)):
            Dc, Pc, R, t = forward_batch(arr, q)
            Re = R @ self.Rh
            pe = _mv(R, np.broadcast_to(self.ph, (N, 3))) + t
            Rd = Rp @ np.transpose(Re, (0, 2, 1))
            w = _rotvec(Rd)
            d = _mv(Rd, self.c - pe) + pp - self.c
            e[:, 6 * i:6 * i + 3] = d / self.L
            e[:, 6 * i + 3:6 * i + 6] = w
            if jac:
                J[:, 6 * i:6 * i + 6, :nu] = np.transpose(Pt, (0, 2, 1))
                T = twists_batch(arr.kinds, arr.H, Dc, Pc)
                J[:, 6 * i:6 * i + 6, k:k + q.shape[1]] = -np.transpose(self._model_norm(T), (0, 2, 1))
            if geometry:
                geo.append((Dc, Pc))
            k += q.shape[1]
        if jac:
            J = J * self.scale[None, None, :]
        return e, J, (pose, qs, Rp, pp, geo)


def _min_norm_solve(J, e):
    """Minimum-norm solutions of ``J x = e`` (N, r, c): LU when J is square or has full row
    rank (``x = J^T (J J^T)^-1 e``), the pseudo-inverse (``lstsq``'s ``rcond=1e-12``) when
    a matrix is singular or badly conditioned."""
    N, r, c = J.shape
    try:
        if r == c:
            x = np.linalg.solve(J, e[..., None])[..., 0]
        elif r < c:
            x = np.einsum("nji,nj->ni", J, np.linalg.solve(J @ np.transpose(J, (0, 2, 1)),
                                                             e[..., None])[..., 0])
        else:
            raise np.linalg.LinAlgError
    except np.linalg.LinAlgError:
        return np.einsum("nij,nj->ni", np.linalg.pinv(J, rcond=1e-12), e)
    # accuracy check: where the solve lost the residual (ill-conditioned), use the pseudo-inverse
    bad = ~(np.linalg.norm(np.einsum("nij,nj->ni", J, x) - e, axis=1)
            <= 1e-8 * np.maximum(np.linalg.norm(e, axis=1), 1e-300))
    if np.any(bad):
        x[bad] = np.einsum("nij,nj->ni", np.linalg.pinv(J[bad], rcond=1e-12), e[bad])
    return x


def newton_batch(model, fixed: dict, X0, max_iter: int = 12):
    """Minimum-norm Gauss-Newton on the loop closures of N samples at once.

    Parameters
    ----------
    model : PMModel
    fixed : dict str -> ndarray (N,)
        The independent pose parameters (radians, model units).
    X0 : ndarray (N, n_unknowns)
        Initial guesses (dependent parameters, then joint values leg by leg).
    max_iter : int

    Returns
    -------
    X : ndarray (N, n_unknowns)
    residual : ndarray (N,)
        Largest normalised closure error (``inf`` where an iteration failed to
        decrease it: those samples stop at their last good value).
    problem : BatchProblem
    """
    prob = BatchProblem(model, fixed)
    X = np.array(X0, float)
    N = len(X)
    e, J, _ = prob.evaluate(X)
    f = np.max(np.abs(e), axis=1)
    failed = ~np.isfinite(f)
    keep = np.isfinite(f) & (f > CONVERGED * 1e-2)
    active, e, J = np.flatnonzero(keep), e[keep], J[keep]   # e, J: rows of the active samples
    for _ in range(max_iter):
        if active.size == 0:
            break
        step = -_min_norm_solve(J, e) * prob.scale
        Xn = X[active] + step
        en, Jn, _ = prob.evaluate(Xn, rows=active)
        ne = np.linalg.norm(e, axis=1)
        good = np.isfinite(en).all(axis=1) & (np.linalg.norm(en, axis=1) < ne)
        for _ in range(_HALVINGS):     # backtracking for the samples whose full step failed
            retry = np.flatnonzero(~good)
            if retry.size == 0:
                break
            step[retry] *= 0.5
            Xr = X[active[retry]] + step[retry]
            er, Jr, _ = prob.evaluate(Xr, rows=active[retry])
            ok = np.isfinite(er).all(axis=1) & (np.linalg.norm(er, axis=1) < ne[retry])
            Xn[retry[ok]], en[retry[ok]], Jn[retry[ok]] = Xr[ok], er[ok], Jr[ok]
            good[retry[ok]] = True
        fn = np.max(np.abs(en), axis=1)
        idx = active[good]
        X[idx], f[idx] = Xn[good], fn[good]
        failed[active[~good]] = True
        keep = good & (fn > CONVERGED * 1e-2)
        active, e, J = active[keep], en[keep], Jn[keep]
    res = np.where(failed & (f > CONVERGED), np.inf, f)
    return X, res, prob


def assemble_batch(model, prob: BatchProblem, X, rows=slice(None)) -> KinematicsBatch:
    """Geometry of converged samples (joint axes, points, o, a_i); ``rows`` selects the
    samples of ``prob``'s fixed parameters that the rows of ``X`` belong to."""
    e, _, (pose, qs, Rp, pp, geo) = prob.evaluate(X, rows=rows, jac=False, geometry=True)
    R0, p0 = model.frame
    A = model.base_points @ R0.T + p0
    a = np.einsum("nij,kj->nki", Rp, model.platform_points) + pp[:, None, :]
    params = {k: np.asarray(pose[k], float) for k in ("Xo", "Yo", "Zo", "alpha", "beta", "gamma")}
    return KinematicsBatch(params, qs, [g[0] for g in geo], [g[1] for g in geo], A, a, pp,
                           np.max(np.abs(e), axis=1))


# ----------------------------------------------------------------------------- leg rows

class LegTemplate:
    """The structure of a leg's analysis, to recompute its rows at many poses.

    Built from the :class:`~screwkit.legs.LegAnalysis` of the leg at a
    reference pose.  It is *trackable* when the leg has at most one constraint
    wrench (a pure force or a pure couple, unique up to its sign, which
    ``observation._orientation_sign`` fixes) and its actuation member is the unit
    force on the line through the first pair of its named points (S/U centres,
    ``A``, ``a``) that ``analysis.actuation_wrench`` tries.  At each sample
    :meth:`rows` reproduces those decisions with margins and flags the samples
    where one is not clear-cut.
    """

    def __init__(self, leg, analysis):
        self.leg = leg
        self.name = leg.name
        self.arr = leg_arrays(leg)
        self.ia = leg.actuated_index
        cons = analysis.constraints
        self.k = len(cons)
        self.kinds = tuple(c.kind for c in cons)
        self.reason = ""
        # named points in the order of observation.named_points: S/U centres, A, a
        names, where = [], []
        for i, j in enumerate(leg.joints):
            if j.spec.origin in "SU":
                nm = f"{j.spec.origin}{j.spec.position}"
                if nm not in names:
                    names.append(nm)
                    where.append(i)
        for nm in ("A", "a"):
            if nm not in names:
                names.append(nm)
                where.append(nm)
        self.point_names, self.point_where = tuple(names), tuple(where)
        self.pair = None
        if self.k > 1:
            self.reason = f"{self.k} constraint wrenches (the choice of basis is not tracked)"
        elif self.k == 1 and self.kinds[0] not in ("force", "couple"):
            self.reason = f"its constraint wrench is a {self.kinds[0]}"
        act = analysis.actuation
        if act is None or act.member.kind != "force":
            self.reason = self.reason or "its actuation member is not a force on a line"
        if not self.reason:
            self.pair = self._find_pair(leg, act.member)
            if self.pair is None:
                self.reason = "its actuation line is not the first line through two named points"

    @property
    def trackable(self) -> bool:
        return not self.reason

    def _named(self, Pc, A, a):
        """Named points (N, p, 3) at the samples."""
        out = []
        for w in self.point_where:
            if w == "A":
                out.append(np.broadcast_to(A, (len(a), 3)))
            elif w == "a":
                out.append(a)
            else:
                out.append(Pc[:, w])
        return np.stack(out, axis=1)

    def _tol(self, points, a, A):
        """``actuation_wrench``'s distance tolerance: GEOMETRY_RTOL * 10 * max(|a - A|, L)."""
        _, L, _ = _char_length(points)
        return GEOMETRY_RTOL * 10 * np.maximum(np.linalg.norm(a - A, axis=-1), L)

    def _find_pair(self, leg, member):
        pts = self._named(np.array([[j.point for j in leg.joints]]), leg.A, leg.a[None])[0]
        tol = self._tol(leg.points[None], leg.a[None], leg.A)[0]
        for i1, i2 in combinations(range(len(pts)), 2):
            if np.linalg.norm(pts[i2] - pts[i1]) <= tol:
                continue
            d = (pts[i2] - pts[i1]) / np.linalg.norm(pts[i2] - pts[i1])
            same_dir = abs(abs(float(d @ member.direction)) - 1.0) < 1e-9
            off = pts[i1] - member.point
            dist = np.linalg.norm(off - (off @ member.direction) * member.direction)
            # only the first pair tried is tracked (an earlier one would be re-chosen)
            return (i1, i2) if same_dir and dist <= tol else None
        return None

    def rows(self, Dc, Pc, A, a):
        """Actuation row and constraint row of the leg at N samples.

        Parameters
        ----------
        Dc, Pc : ndarray (N, m, 3)
        A : ndarray (3,)
        a : ndarray (N, 3)

        Returns
        -------
        act : ndarray (N, 6)
            Unit force on the actuation line scaled to unit reciprocal product
            with the actuated joint's unit twist.
        act_dir : ndarray (N, 3)
            Its direction, oriented so that the scale is positive.
        cons : ndarray (N, k, 6)
            Unit constraint force / couple, oriented as ``observation`` does.
        ok : ndarray (N,) of bool
            False where a decision is not clear-cut (recompute with the full analysis).
        """
        N = len(a)
        T = twists_batch(self.arr.kinds, self.arr.H, Dc, Pc)
        pts = np.concatenate([np.broadcast_to(A, (N, 1, 3)), a[:, None, :], Pc], axis=1)
        c, L, ok = _char_length(pts)
        # -- the constraint system: null space of the unit-row normalised twists
        Tn = _norm_twists(T, c, L)
        Tu = Tn / np.maximum(np.linalg.norm(Tn, axis=2, keepdims=True), 1e-300)
        _, s, Vt = np.linalg.svd(Tu, full_matrices=True)
        tol = RANK_RTOL * np.maximum(1.0, s[:, 0])
        rank = 6 - self.k
        if rank > s.shape[1]:
            ok[:] = False
        else:
            ok &= s[:, rank - 1] > _MARGIN * tol
            if s.shape[1] > rank:
                ok &= s[:, rank] < tol / _MARGIN
        cons = np.zeros((N, self.k, 6))
        if self.k == 1:
            wn = Vt[:, 5]
            f = wn[:, :3]
            m = wn[:, 3:] * L[:, None] + np.cross(c, f)
            nf = np.linalg.norm(f, axis=1)
            if self.kinds[0] == "couple":       # observation.decompose: |f| <= 1e-9 (unit wn)
                ok &= nf < 1e-9 / _MARGIN
                part = m / np.linalg.norm(m, axis=1, keepdims=True)
                w = np.concatenate([np.zeros((N, 3)), part], axis=1)
            else:                               # a force: f != 0 and zero pitch
                ok &= nf > 1e-9 * _MARGIN
                ok &= np.abs(np.sum(wn[:, :3] * wn[:, 3:], axis=1)) <= 1e-9 * nf / _MARGIN
                nf = np.where(nf > 0, nf, 1.0)
                w = np.concatenate([f, m], axis=1) / nf[:, None]
                part = w[:, :3]
            sgn, sok = self._orientation(part, Dc, A, a)
            ok &= sok
            cons[:, 0] = w * sgn[:, None]
        # -- the actuation row
        named = self._named(Pc, A, a)
        ttol = GEOMETRY_RTOL * 10 * np.maximum(np.linalg.norm(a - A, axis=1), L)
        i1, i2 = self.pair
        for j in range(1, i2):     # earlier pairs (i1 = 0 only: see _find_pair) must coincide
            dist = np.linalg.norm(named[:, j] - named[:, 0], axis=1)
            ok &= dist < ttol / _MARGIN
        p, q = named[:, i1], named[:, i2]
        dq = np.linalg.norm(q - p, axis=1)
        ok &= dq > ttol * _MARGIN
        d = (q - p) / np.where(dq > 0, dq, 1.0)[:, None]
        w = np.concatenate([d, np.cross(p, d)], axis=1)
        xi = T[:, self.ia]
        passive = [i for i in range(T.shape[1]) if i != self.ia]
        wn = _norm_wrenches(w, c, L)
        Tp = _norm_twists(T[:, passive], c, L)
        recip = np.abs(np.einsum("npj,nj->np", Tp, wn)) / (
            np.linalg.norm(Tp, axis=2) * np.linalg.norm(wn, axis=1)[:, None])
        ok &= np.max(recip, axis=1, initial=0.0) < 1e-8 / _MARGIN
        prod = np.sum(w * xi, axis=1)
        scale_ref = np.linalg.norm(_norm_twists(xi, c, L), axis=1) * L
        ok &= np.abs(prod) > 1e-6 * _MARGIN * np.linalg.norm(wn, axis=1) * scale_ref
        prod = np.where(prod != 0, prod, 1.0)
        act = w / prod[:, None]
        act_dir = d * np.sign(prod)[:, None]
        ok &= np.all(np.isfinite(act), axis=1) & np.all(np.isfinite(cons), axis=(1, 2))
        return act, act_dir, cons, ok

    def _orientation(self, part, Dc, A, a):
        """Batched ``observation._orientation_sign``: +1/-1 along ``a - A`` or else the
        first joint axis it is not perpendicular to (|cos| > 1e-6)."""
        refs = np.concatenate([(a - A)[:, None, :], Dc], axis=1)
        cos = np.einsum("nj,nrj->nr", part, refs) / np.maximum(np.linalg.norm(refs, axis=2), 1e-300)
        big = np.abs(cos) > 1e-6
        first = np.argmax(big, axis=1)
        rows = np.arange(len(part))
        sgn = np.where(big[rows, first], np.sign(cos[rows, first]), 1.0)
        # clear-cut: no reference up to the chosen one has |cos| near the 1e-6 threshold
        near = (np.abs(cos) > 1e-6 / _MARGIN) & (np.abs(cos) < 1e-6 * _MARGIN)
        upto = np.arange(refs.shape[1])[None, :] <= first[:, None]
        ok = ~np.any(near & upto, axis=1) & np.any(big, axis=1)
        return sgn, ok


# ----------------------------------------------------------------------------- Jacobian and statics

@dataclass(frozen=True, eq=False)
class BatchStatics:
    """Conditioning and statics of N samples (``NaN`` where singular).

    Attributes
    ----------
    condition_number : ndarray (N,)
    singular : ndarray (N,) of bool
    kind : ndarray (N,) of str
        ``""``, ``"actuation"`` or ``"constraint"``.
    values : ndarray (N, m)
    leg_wrenches : ndarray (N, n, 6)
    T_r : ndarray (N, n)
    equilibrium_residual : ndarray (N,)
    """

    condition_number: np.ndarray
    singular: np.ndarray
    kind: np.ndarray
    values: np.ndarray
    leg_wrenches: np.ndarray
    T_r: np.ndarray
    equilibrium_residual: np.ndarray


def jacobian_statics_batch(J, leg_of_row, n_act, points, A, a, o, F, T,
                           threshold: float = COND_THRESHOLD) -> BatchStatics:
    """The conditioning of ``unified_jacobian`` and the statics of ``statics.statics``, batched.

    Parameters
    ----------
    J : ndarray (N, m, 6)
        Rows about the base origin: actuation rows then constraint rows.
    leg_of_row : ndarray (m,) of int
    n_act : int
    points : ndarray (N, p, 3)
        Every leg's points (``Leg.points``, leg by leg) and ``o`` last: they set
        the Jacobian's normalisation.
    A : ndarray (n, 3)
    a, : ndarray (N, n, 3)
    o : ndarray (N, 3)
    F, T : ndarray (3,)
        Workload at ``o``.
    """
    N, m, _ = J.shape
    n_legs = len(A)
    c, L, _ = _char_length(points)
    Jn = _norm_wrenches(J, c, L)
    d = np.linalg.norm(Jn, axis=2)
    d = np.where(d > 0, d, 1.0)
    Jn = Jn / d[:, :, None]
    s = np.linalg.svd(Jn, compute_uv=False)
    cond = np.full(N, np.inf)
    if s.shape[1] >= 6:
        pos = s[:, 5] > 0
        cond[pos] = s[pos, 0] / s[pos, 5]
    k = max(0, 6 - n_act)
    if k == 0:
        c_cond = np.ones(N)
    elif m - n_act >= k:
        sc = np.linalg.svd(Jn[:, n_act:], compute_uv=False)
        c_cond = np.full(N, np.inf)
        pos = sc[:, k - 1] > 0
        c_cond[pos] = sc[pos, 0] / sc[pos, k - 1]
    else:
        c_cond = np.full(N, np.inf)
    singular = ~(cond <= threshold)
    kind = np.where(~singular, "", np.where((k > 0) & ~(c_cond <= threshold), "constraint",
                                            "actuation"))
    W = np.concatenate([np.broadcast_to(F, (N, 3)), T + np.cross(o, F)], axis=1)
    Wn = _norm_wrenches(W, c, L)
    pinvT = np.linalg.pinv(np.transpose(Jn, (0, 2, 1)), rcond=max(m, 6) * np.finfo(float).eps)
    values = -np.einsum("nmj,nj->nm", pinvT, Wn) / d
    row_w = values[:, :, None] * J
    P = np.zeros((n_legs, m))
    P[leg_of_row, np.arange(m)] = 1.0
    Pc = P.copy()
    Pc[:, :n_act] = 0.0
    leg_w = np.einsum("lm,nmj->nlj", P, row_w)
    con_w = np.einsum("lm,nmj->nlj", Pc, row_w)
    delta = a - A[None]
    delta = delta / np.linalg.norm(delta, axis=2, keepdims=True)
    moment_A = con_w[..., 3:] - np.cross(A[None], con_w[..., :3])
    T_r = np.sum(moment_A * delta, axis=2)
    total = _norm_wrenches(leg_w.sum(axis=1) + W, c, L)
    scale = np.maximum(np.linalg.norm(Wn, axis=1),
                       np.max(np.linalg.norm(_norm_wrenches(row_w, c, L), axis=2), axis=1))
    scale = np.where(scale > 0, scale, 1.0)
    resid = np.linalg.norm(total, axis=1) / scale
    bad = singular
    values[bad] = np.nan
    leg_w[bad] = np.nan
    T_r[bad] = np.nan
    resid[bad] = np.nan
    return BatchStatics(cond, singular, kind, values, leg_w, T_r, resid)
