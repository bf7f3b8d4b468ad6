"""The legs of a PM as arrays, and their batched forward kinematics (private).

A :class:`Chains` is what the engine keeps of a :class:`~screwkit.pm.PMModel`:
every leg's home joint axes padded to the longest leg (a padded slot is an
identity joint that never moves), the platform's home pose, the normalisation
of the model and the order of the unknowns of the loop closures.  It is built
once per model (:func:`chains_of`) and never changes.

Forward kinematics is the product of exponentials of :mod:`screwkit.engine`
(module docstring), evaluated slot by slot for every leg and every pose at once
(:func:`~screwkit.engine._poe.chain_forward`).
"""

from __future__ import annotations

import weakref
from dataclasses import dataclass

import numpy as np

from ..pm import LENGTH_PARAMS, PARAMS
from ..screws import euler_matrices
from . import _algebra as alg
from ..screws import cross
from ._poe import chain_forward

__all__ = ["PARAMS", "LENGTH_PARAMS", "ANGLE_PARAMS", "Chains", "chains_of", "Frames",
           "chain_forward", "forward", "leg_forward", "normalised_twists", "placed_bars",
           "platform_columns"]

#: The six pose parameters of the platform, in this order.
ANGLE_PARAMS = ("alpha", "beta", "gamma")


@dataclass(frozen=True, eq=False)
class Chains:
    """Constant arrays of a PM's legs (``n`` legs, ``m`` slots = the longest leg).

    Attributes
    ----------
    name : str
        The model's name (the arrays keep no reference to the model, so that the caches
        keyed by it release it).
    n, m : int
    sizes : tuple of int
        Joints of each leg.
    D, P : ndarray (3, n, m)
        Home unit axes and axis points (world); padded slots ``D = z``, ``P = 0``.
    rotation, translation : ndarray (n, m)
        Rotation per unit joint value (1 for R and H, 0 for P and padding) and
        translation along the axis per unit joint value (1 for P, the pitch for H).
    real : ndarray (n, m) of bool
        True for a real joint, False for a padded slot.
    q_scale : ndarray (n, m)
        The Newton unknowns are ``q / q_scale`` (``L`` for P joints, 1 otherwise).
    actuated : ndarray (n,) of int
        Slot of each leg's actuated joint (a passive leg's is not an actuator: see
        :attr:`actuator_slots`).
    centre, length : ndarray (3,), float
        The model's normalisation (centroid and characteristic length at home).
    platform_home : (ndarray (3, 3), ndarray (3,))
        World <- platform at home.
    frame : (ndarray (3, 3), ndarray (3,))
        World <- base.
    base_points : ndarray (n, 3)
        ``A_i`` (world).
    platform_points : ndarray (n, 3)
        ``a_i`` in the platform frame.
    order : str
    fixed : tuple of str
        The independent pose parameters (given).
    unknown : tuple of str
        The dependent ones (solved), in :data:`PARAMS` order.
    x_scale : ndarray (nu,)
        Dependent lengths are solved divided by ``L``.
    home : dict
        The home pose (radians, model lengths).
    bars : ndarray (3, n, m)
        Home bar vectors of the parallelograms ``Pa`` (zero in every other slot): a Pa's
        value is the arc length ``|b| theta`` of its bars' ends (model lengths) and it
        moves its far link along a circle (:mod:`screwkit.engine._poe`).
    """

    name: str
    n: int
    m: int
    sizes: tuple
    D: np.ndarray
    P: np.ndarray
    rotation: np.ndarray
    translation: np.ndarray
    real: np.ndarray
    q_scale: np.ndarray
    actuated: np.ndarray
    centre: np.ndarray
    length: float
    platform_home: tuple
    frame: tuple
    base_points: np.ndarray
    platform_points: np.ndarray
    order: str
    fixed: tuple
    unknown: tuple
    x_scale: np.ndarray
    home: dict
    bars: np.ndarray = None
    passive: tuple = ()

    @property
    def active(self) -> np.ndarray:
        """The actuated legs (0-based, in leg order): every leg but the passive ones."""
        return np.array([i for i in range(self.n) if i not in self.passive], int)

    @property
    def actuator_slots(self) -> tuple:
        """``(legs, slots)``: the index arrays of the actuated joints of the actuated legs,
        ``q[legs, slots]`` are the actuator values."""
        act = self.active
        return act, self.actuated[act]

    @property
    def n_unknowns(self) -> int:
        return len(self.unknown) + self.n * self.m

    @property
    def slot_rotates(self) -> np.ndarray:
        return self.rotation.any(axis=0)

    def home_vector(self, N: int = 1) -> np.ndarray:
        """Unknowns at home, ``(n_unknowns, N)``."""
        X = np.zeros((self.n_unknowns, N))
        for k, u in enumerate(self.unknown):
            X[k] = self.home[u] / self.x_scale[k]
        return X


_CACHE: "weakref.WeakKeyDictionary" = weakref.WeakKeyDictionary()


def chains_of(model) -> Chains:
    """The :class:`Chains` of a model (built once, cached with the model)."""
    ch = _CACHE.get(model)
    if ch is None:
        ch = _build(model)
        _CACHE[model] = ch
    return ch


def _build(model) -> Chains:
    legs = model.home_legs
    n = len(legs)
    sizes = tuple(len(lg.joints) for lg in legs)
    m = max(sizes)
    L = float(model.normalisation.length)
    D = np.zeros((3, n, m))
    D[2] = 1.0
    P = np.zeros((3, n, m))
    rot, tra = np.zeros((n, m)), np.zeros((n, m))
    real = np.zeros((n, m), bool)
    qs = np.ones((n, m))
    bars = np.zeros((3, n, m))
    for i, lg in enumerate(legs):
        for j, jt in enumerate(lg.joints):
            D[:, i, j], P[:, i, j], real[i, j] = jt.direction, jt.point, True
            if jt.bar is not None:
                bars[:, i, j] = jt.bar
            if jt.kind == "P":
                tra[i, j], qs[i, j] = 1.0, L
            else:
                rot[i, j] = 1.0
                tra[i, j] = jt.pitch if jt.kind == "H" else 0.0
    unknown = tuple(p for p in PARAMS if p not in model.independent)
    R0, p0 = (np.asarray(x, float) for x in model.frame)
    Rh, ph = (np.asarray(x, float) for x in model.platform_home)
    out = Chains(model.name, n, m, sizes, D, P, rot, tra, real, qs,
                 np.array([lg.actuated_index for lg in legs]),
                 np.asarray(model.normalisation.centre, float), L, (Rh, ph), (R0, p0),
                 np.asarray(model.world_base_points, float),
                 np.asarray(model.platform_points, float), model.order,
                 tuple(model.independent), unknown,
                 np.array([L if u in LENGTH_PARAMS else 1.0 for u in unknown]),
                 dict(model.home_pose), bars, tuple(getattr(model, "passive", ())))
    for a in (D, P, rot, tra, real, qs, bars):
        a.setflags(write=False)
    return out


@dataclass(frozen=True, eq=False)
class Frames:
    """Forward kinematics of every leg at ``N`` poses (arrays, pose axis last).

    Attributes
    ----------
    params : dict str -> ndarray (N,)
        The six pose parameters.
    q : ndarray (n, m, N)
        Joint values (radians for R and H, model lengths for P and for the arc ``|b| theta``
        of a Pa; 0 in padded slots).
    axes, points : ndarray (m, 3, n, N)
        Current joint axes and axis points (world).
    R_p : ndarray (3, 3, N)
        World <- platform rotation; ``o`` : ndarray (3, N) the platform centre.
    E : ndarray (3, 3, N)
        World angular Jacobian of the Euler angles.
    error : ndarray (6, n, N)
        Length-normalised closure error of each leg ``[d / L; w]``.
    """

    params: dict
    q: np.ndarray
    axes: np.ndarray
    points: np.ndarray
    R_p: np.ndarray
    o: np.ndarray
    E: np.ndarray
    error: np.ndarray

    @property
    def residual(self) -> np.ndarray:
        """Largest closure error component per pose, ``(N,)``."""
        return np.max(np.abs(self.error), axis=(0, 1))


def platform_pose(ch: Chains, params: dict):
    """World <- platform rotation ``(3, 3, N)``, centre ``(3, N)`` and Euler Jacobian."""
    Rb, E = euler_matrices(ch.order, params["alpha"], params["beta"], params["gamma"])
    R0, p0 = ch.frame
    Rp = np.einsum("ij,jk...->ik...", R0, Rb)
    E = np.einsum("ij,jk...->ik...", R0, E)
    o = np.einsum("ij,j...->i...", R0, np.stack([params["Xo"], params["Yo"], params["Zo"]]))
    return Rp, o + p0.reshape((3,) + (1,) * (o.ndim - 1)), E


def forward(ch: Chains, fixed: dict, X: np.ndarray) -> Frames:
    """Every leg's joint axes and closure error at the unknowns ``X (n_unknowns, N)``.

    ``fixed`` holds the independent parameters, each an array ``(N,)``.
    """
    nu, n, m = len(ch.unknown), ch.n, ch.m
    N = X.shape[-1]
    params = dict(fixed)
    for k, u in enumerate(ch.unknown):
        params[u] = X[k] * ch.x_scale[k]
    q = X[nu:].reshape(n, m, N) * ch.q_scale[:, :, None]
    Rp, o, E = platform_pose(ch, params)
    axes, points, R, t = chain_forward(ch.D, ch.P, ch.rotation, ch.translation, q,
                                       bars=ch.bars)
    err = closure_error(ch, Rp, o, R, t)
    return Frames(params, q, axes, points, Rp, o, E, err)


def closure_error(ch: Chains, Rp, o, R, t) -> np.ndarray:
    """Each leg's length-normalised closure error ``[d / L; w]`` ``(6, n, N)``: the twist
    carrying its end pose ``(R Rh, R ph + t)`` onto the platform pose ``(Rp (3, 3, N),
    o (3, N))``; ``R (3, 3, n, N)``, ``t (3, n, N)`` from :func:`chain_forward`."""
    Rh, ph = ch.platform_home
    RpRh = np.einsum("ij...,kj->ik...", Rp, Rh)[:, :, None]          # Rp Rh^T  (3, 3, 1, N)
    Rd = alg.matmul_t(RpRh, R)                                           # Rp (R Rh)^T
    pe = alg.matvec(R, ph.reshape(3, 1, 1)) + t
    c = ch.centre.reshape(3, 1, 1)
    d = alg.matvec(Rd, c - pe) + o[:, None] - c
    return np.concatenate([d / ch.length, alg.rotation_vector(Rd)])


def leg_forward(home_leg, q, platform_home=None):
    """Forward kinematics of one leg (the engine's product of exponentials).

    Parameters
    ----------
    home_leg : Leg
    q : array_like (m,)
        Joint values (radians for R and H, lengths for P, the arc length ``|b| theta`` of
        the bars' ends for a parallelogram Pa).
    platform_home : (ndarray (3, 3), ndarray (3,)), optional

    Returns
    -------
    twists : ndarray (m, 6)
        Current unit joint twists ``[v; w]`` about the base origin.
    end : (ndarray (3, 3), ndarray (3,))
        ``T_end(q)`` when ``platform_home`` is given, else the displacement ``G``.
    """
    from ..errors import InputError
    m = len(home_leg.joints)
    q = np.asarray(q, dtype=float).reshape(-1)
    if q.shape != (m,) or not np.all(np.isfinite(q)):
        raise InputError(f"leg {home_leg.name}: need {m} finite joint values, got {q.tolist()}")
    D = np.array([j.direction for j in home_leg.joints]).T[:, None]
    P = np.array([j.point for j in home_leg.joints]).T[:, None]
    rot = np.array([[0.0 if j.kind == "P" else 1.0 for j in home_leg.joints]])
    tra = np.array([[1.0 if j.kind == "P" else (j.pitch if j.kind == "H" else 0.0)
                     for j in home_leg.joints]])
    bars = np.array([np.zeros(3) if j.bar is None else j.bar for j in home_leg.joints]).T
    axes, points, R, t = chain_forward(D, P, rot, tra, q[None, :, None], bars=bars[:, None])
    d, p = axes[:, :, 0, 0], points[:, :, 0, 0]
    w = rot[0][:, None] * d
    twists = np.concatenate([cross(p, w) + tra[0][:, None] * d, w], axis=1)
    R, t = R[:, :, 0, 0], t[:, 0, 0]
    if platform_home is None:
        return twists, (R, t)
    R0, p0 = (np.asarray(x, float) for x in platform_home)
    return twists, (R @ R0, R @ p0 + t)


def placed_bars(ch: Chains, q: np.ndarray) -> np.ndarray:
    """The parallelograms' current bar vectors ``(m, 3, n, N)`` at the joint values ``q (n, m,
    N)`` (zero in every other slot): ``G_{j-1} Rot(h, theta) b``, from the chain's link
    rotations (a Pa does not turn its link, so ``G_j`` has the rotation of ``G_{j-1}``)."""
    axes, _, _, _, Rs, _ = chain_forward(ch.D, ch.P, ch.rotation, ch.translation, q,
                                         slots=True, bars=ch.bars)
    blen = np.sqrt(np.einsum("inm,inm->nm", ch.bars, ch.bars))             # (n, m)
    H = np.cross(ch.bars, ch.D, axis=0) / np.where(blen > 0, blen, 1.0)      # home hinges
    hinge = np.einsum("jabnN,bnj->janN", Rs, H)
    return blen.T[:, None, :, None] * np.cross(axes, hinge, axis=1)


def normalised_twists(ch: Chains, fr: Frames) -> np.ndarray:
    """Joint twists in the Newton unknowns' units, length-normalised: ``(m, 6, n, N)``.

    ``[((p - c) x d) / L + (h / L) d; d]`` for R and H, ``[d; 0]`` for P (whose
    unknown is ``q / L``); zero for padded slots.
    """
    m = ch.m
    T = np.empty((m, 6) + fr.axes.shape[2:])
    rot, trans, c = _twist_constants(ch)
    rot_l = rot / ch.length
    # every slot at once, component by component: each d[k], p[k] is a contiguous
    # (m, n, N) block of the frames (no strided passes over the whole stack)
    d = [fr.axes[:, k] for k in range(3)]
    p = [fr.points[:, k] - c[k] for k in range(3)]
    for k in range(3):
        i, j = (k + 1) % 3, (k + 2) % 3
        out = T[:, k]
        np.multiply(p[i], d[j], out=out)
        out -= p[j] * d[i]                       # ((p - c) x d)_k
        out *= rot_l
        out += trans * d[k]
        np.multiply(rot, d[k], out=T[:, 3 + k])
    return T


_TWIST_CONSTANTS: "weakref.WeakKeyDictionary" = weakref.WeakKeyDictionary()


def _twist_constants(ch: Chains):
    """Rotation and normalised translation per unit unknown ``(m, n, 1)``, and the centre
    ``(3, 1, 1, 1)`` (once per chains)."""
    k = _TWIST_CONSTANTS.get(ch)
    if k is None:
        trans = ch.translation / np.where(ch.q_scale == 1.0, ch.length, 1.0)
        k = (ch.rotation.T[:, :, None].copy(), trans.T[:, :, None].copy(),
             ch.centre.reshape(3, 1, 1, 1).copy())
        _TWIST_CONSTANTS[ch] = k
    return k


def platform_columns(ch: Chains, fr: Frames, names) -> np.ndarray:
    """Length-normalised platform twists per unit change of each parameter in ``names``,
    ``(6, len(names), N)``; a length parameter per unit of ``L`` (the unknowns' unit)."""
    N = fr.o.shape[-1]
    R0 = ch.frame[0]
    cols = []
    for u in names:
        if u in LENGTH_PARAMS:
            v = np.broadcast_to(R0[:, "XYZ".index(u[0]), None], (3, N))
            cols.append(np.concatenate([v, np.zeros((3, N))]))
        else:
            w = fr.E[:, ANGLE_PARAMS.index(u)]
            cols.append(np.concatenate([alg.cross(fr.o - ch.centre[:, None], w) / ch.length, w]))
    return np.stack(cols, axis=1) if cols else np.zeros((6, 0, N))
