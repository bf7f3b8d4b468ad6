"""One leg's velocity, acceleration and effort algebra at N poses (poses first).

A leg's joint twists ``T = [xi_1 ... xi_m]`` (about ``O``) carry the platform:
``T qdot = V`` and, differentiated, ``T qddot + b = A`` with the bias ``b = sum_j
(V_(j-1) x xi_j) qdot_j`` (``V_(j-1)`` the twist of the link that carries joint ``j``; the
screw product of :func:`~._spatial.cross_motion`).  The joints are split once, at home,
into the independent ones ``I`` and the dependent ones (``LegAnalysis.dependent_joints``:
the S-S spin's ``S3c``); the independent columns have full rank and are solved through
their Gram matrix in length-normalised, column-equilibrated coordinates.  Each dependent
joint ``d`` gives an idle motion, a null vector ``n = [T_I^+ xi_d; -1]`` of ``T``.

The leg's effort balance: with ``ID`` the joint efforts the leg's own links need (inertia,
gravity, friction; :mod:`~._newton_euler`) and ``w`` the wrench the leg applies to the
platform, every joint's effort is ``tau = ID + T^T w``: 0 at a passive joint, the
actuator's ``F_a`` at the actuated one.  The wrench ``u`` of least (normalised) norm with
``T^T u = -ID`` maps the leg's dynamics into the platform's workload (the paper's section
5.2): ``w = w_s + u`` with ``w_s`` a static leg wrench (reciprocal to the passive joints,
``xi_a . w_s = F_a``), so the unified statics (eq. 9) with the workload ``W + sum u``
gives the dynamic ``F_a`` and constraint values.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from ._parallelogram import setup_parallelograms
from ._spatial import cross_motion, normalise_twists

__all__ = ["LegSetup", "setup_legs", "LegSolver"]

#: Relative Tikhonov shift of a Gram matrix (guards an exactly singular leg only).
_SHIFT = 1e-15


@dataclass(frozen=True, eq=False)
class LegSetup:
    """Constant data of one leg: ``m`` joints, independent joints ``indep``, dependent
    ``dep`` (idle motions), ``actuated`` slot, massive links ``slots`` with their ``mass``,
    ``com (k, 3)`` and ``inertia (k, 3, 3)`` at home (world), friction ``viscous`` and
    ``coulomb (m,)``, the parallelograms ``pa`` (:class:`~._parallelogram.PaSetup`, None
    without one)."""

    m: int
    indep: np.ndarray
    dep: np.ndarray
    actuated: int
    slots: np.ndarray
    mass: np.ndarray
    com: np.ndarray
    inertia: np.ndarray
    viscous: np.ndarray
    coulomb: np.ndarray
    pa: object = None

    @property
    def massless(self) -> bool:
        return self.slots.size == 0 and (self.pa is None or self.pa.massless)

    @property
    def frictionless(self) -> bool:
        return not (self.viscous.any() or self.coulomb.any())


def setup_legs(model, params) -> tuple:
    """One :class:`LegSetup` per leg of ``model`` with the dynamics ``params`` (the link
    data moved from the base frame to the world)."""
    R0, p0 = (np.asarray(x, float) for x in model.frame)
    out = []
    for i, lg in enumerate(model.home_legs):
        m = len(lg.joints)
        dep_names = set(lg.analyze().dependent_joints)
        dep = np.array([k for k, j in enumerate(lg.joints) if j.name in dep_names], int)
        indep = np.array([k for k in range(m) if k not in set(dep.tolist())], int)
        ld = params.legs[i]
        bodies = [(s, b.moved(R0, p0)) for s, b in ld.links if not b.massless]
        out.append(LegSetup(
            m, indep, dep, int(lg.actuated_index),
            np.array([s for s, _ in bodies], int), np.array([b.mass for _, b in bodies]),
            np.array([b.com for _, b in bodies]).reshape(-1, 3),
            np.array([b.inertia for _, b in bodies]).reshape(-1, 3, 3),
            np.asarray(ld.viscous, float), np.asarray(ld.coulomb, float),
            setup_parallelograms(lg, ld, R0, p0)))
    return tuple(out)


def _solve(G, B):
    """``G X = B`` for SPD ``G (N, r, r)``, ``B (N, r[, k])`` with a tiny shift."""
    r = G.shape[-1]
    if r == 0:
        return np.zeros(B.shape)
    tr = np.einsum("nii->n", G)
    Gs = G + (_SHIFT * np.maximum(tr, 1e-300) / r)[:, None, None] * np.eye(r)
    vec = B.ndim == 2
    X = np.linalg.solve(Gs, B[..., None] if vec else B)
    return X[..., 0] if vec else X


class LegSolver:
    """The normalised Gram system of one leg's independent joints at N poses.

    Parameters
    ----------
    setup : LegSetup
    tw : ndarray (N, m, 6)
        The joint twists at the poses.
    c, L : ndarray (3,), float
        The normalisation (the model's centre and characteristic length).
    """

    def __init__(self, setup: LegSetup, tw, c, L):
        self.setup, self.tw, self.c, self.L = setup, tw, c, float(L)
        Tn = normalise_twists(tw[:, setup.indep], c, L)            # (N, r, 6)
        s = 1.0 / np.maximum(np.linalg.norm(Tn, axis=-1), 1e-300)   # column scales (N, r)
        self.s = s
        self.Th = Tn * s[..., None]                                 # (N, r, 6)
        self.G = np.einsum("nia,nja->nij", self.Th, self.Th)
        self.null = self._null()

    def _null(self):
        st = self.setup
        N, m = self.tw.shape[0], st.m
        k = st.dep.size
        out = np.zeros((N, m, k))
        if k:
            td = normalise_twists(self.tw[:, st.dep], self.c, self.L)      # (N, k, 6)
            y = _solve(self.G, np.einsum("nia,nka->nik", self.Th, td))     # (N, r, k)
            out[:, st.indep] = self.s[..., None] * y
            out[:, st.dep, np.arange(k)] = -1.0
        return out

    def particular(self, twist):
        """Joint rates ``x (N, m)`` with ``T x = twist`` (``(N, 6)``, consistent), zero at
        the dependent joints."""
        st = self.setup
        b = np.einsum("nia,na->ni", self.Th, normalise_twists(twist, self.c, self.L))
        x = np.zeros((twist.shape[0], st.m))
        x[:, st.indep] = self.s * _solve(self.G, b)
        return x

    def mapped_wrench(self, ID):
        """The wrench ``u (N, 6)`` of least normalised norm with ``T_I^T u = -ID_I``."""
        st = self.setup
        y = _solve(self.G, self.s * ID[:, st.indep])                  # (N, r)
        un = -np.einsum("nia,ni->na", self.Th, y) / self.L
        from ._spatial import denormalise_wrench
        return denormalise_wrench(un, self.c, self.L)

    def residual(self, x, twist):
        """``|T x - twist|`` normalised, relative to ``|twist|`` normalised, ``(N,)``."""
        r = normalise_twists(np.einsum("nma,nm->na", self.tw, x) - twist, self.c, self.L)
        ref = normalise_twists(twist, self.c, self.L)
        return np.linalg.norm(r, axis=-1) / np.maximum(np.linalg.norm(ref, axis=-1), 1e-300)


def cumulative_twists(tw, qd):
    """Twist of the link after each joint, ``(N, m, 6)``: ``sum_(j <= s) xi_j qdot_j``."""
    return np.cumsum(tw * qd[..., None], axis=1)


def bias_terms(tw, qd, Vc=None, curv=None):
    """Per joint ``(V_(j-1) x xi_j) qdot_j`` ``(N, m, 6)`` (the screw-product part of the
    leg's acceleration); ``Vc`` the cumulative twists; ``curv (N, m, 3)`` the own twist
    rate of the parallelograms (:func:`~._parallelogram.pa_state`): their joint twist
    also turns with their own value, adding ``[curv qdot^2; 0]``."""
    Vc = cumulative_twists(tw, qd) if Vc is None else Vc
    prev = np.concatenate([np.zeros_like(Vc[:, :1]), Vc[:, :-1]], axis=1)
    out = cross_motion(prev, tw) * qd[..., None]
    if curv is not None:
        out[..., :3] += curv * (qd * qd)[..., None]
    return out
