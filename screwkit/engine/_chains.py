"""What the engine keeps of a model's legs: the metadata of its unknowns (private).

A :class:`Chains` names a model's pose parametrisation and the layout of the unknowns of
its loop closures, beside the arrays the kernels take (:attr:`Chains.flat`, a
:class:`~screwkit.engine._flat.FlatModel`).  It is built once per model (:func:`chains_of`)
and never changes.  Forward kinematics (the product of exponentials of every leg) is the
kernels' (:mod:`screwkit.engine._kernels._kin`); :func:`leg_forward` runs it on one leg.
"""

from __future__ import annotations

import weakref
from dataclasses import dataclass

import numpy as np

from ..pm import LENGTH_PARAMS, PARAMS

__all__ = ["PARAMS", "LENGTH_PARAMS", "ANGLE_PARAMS", "Chains", "chains_of", "leg_forward"]

#: The three Euler angles of the platform, in this order.
ANGLE_PARAMS = ("alpha", "beta", "gamma")


@dataclass(frozen=True, eq=False)
class Chains:
    """The unknowns of a PM's loop closures (``n`` legs, ``m`` slots = the longest leg).

    Attributes
    ----------
    name : str
    n, m : int
    sizes : tuple of int
        Joints of each leg.
    q_scale : ndarray (n, m)
        The Newton unknowns are ``q / q_scale`` (``L`` for P and Pa joints, 1 otherwise).
    rotation, translation : ndarray (n, m)
        Rotation and translation per unit joint value (0 in padded slots).
    real : ndarray (n, m) of bool
        True for a real joint, False for a padded slot.
    actuated : ndarray (n,) of int
        Slot of each leg's actuated joint (a passive leg's is not an actuator: see
        :attr:`actuator_slots`).
    length : float ; centre : ndarray (3,)
        The model's normalisation.
    frame : (ndarray (3, 3), ndarray (3,))
        World <- base.
    order : str
    fixed, unknown : tuple of str
        The independent (given) and dependent (solved) pose parameters.
    x_scale : ndarray (nu,)
        Dependent lengths are solved divided by ``L``.
    home : dict
        The home pose (radians, model lengths).
    bars : ndarray (3, n, m)
        Home bar vectors of the parallelograms ``Pa`` (zero elsewhere).
    flat : FlatModel
        The arrays the kernels take.
    passive : tuple of int
        The passive legs (no actuator).
    """

    name: str
    n: int
    m: int
    sizes: tuple
    q_scale: np.ndarray
    rotation: np.ndarray
    translation: np.ndarray
    real: np.ndarray
    actuated: np.ndarray
    length: float
    centre: np.ndarray
    frame: tuple
    order: str
    fixed: tuple
    unknown: tuple
    x_scale: np.ndarray
    home: dict
    bars: np.ndarray
    flat: object
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

    def home_vector(self, N: int = 1) -> np.ndarray:
        """Unknowns at home, ``(n_unknowns, N)``."""
        X = np.zeros((self.n_unknowns, N))
        for k, u in enumerate(self.unknown):
            X[k] = self.home[u] / self.x_scale[k]
        return X

    def full_params(self, fixed: dict, N: int, out=None) -> np.ndarray:
        """``P6 (N, 6)``: the given parameters in their columns (the others 0); into
        ``out (N, 6)`` where given."""
        P6 = np.zeros((N, 6)) if out is None else out
        if out is not None:
            P6[...] = 0.0
        for p, v in fixed.items():
            P6[:, PARAMS.index(p)] = v
        return P6


_CACHE: "weakref.WeakKeyDictionary" = weakref.WeakKeyDictionary()


def chains_of(model) -> Chains:
    """The :class:`Chains` of a model (built once, cached with the model)."""
    ch = _CACHE.get(model)
    if ch is None:
        from ._flat import flatten
        from ._kernels import _layout as lay
        flat = flatten(model)
        M = flat.M
        L = float(model.normalisation.length)
        sizes = tuple(int(s) for s in M[lay.LEG][:, lay.L_SIZE])
        real = np.arange(flat.m)[None, :] < np.array(sizes)[:, None]
        unknown = flat.unknown
        ch = Chains(model.name, flat.n, flat.m, sizes, M[lay.QS], M[lay.ROT], M[lay.TRA], real,
                    M[lay.LEG][:, lay.L_ACT].copy(), L,
                    np.asarray(model.normalisation.centre, float),
                    tuple(np.asarray(x, float) for x in model.frame), model.order,
                    tuple(model.independent), unknown,
                    np.array([L if u in LENGTH_PARAMS else 1.0 for u in unknown]),
                    dict(model.home_pose), np.moveaxis(M[lay.BAR], 2, 0), flat,
                    tuple(getattr(model, "passive", ())))
        for a in (ch.real, ch.actuated, ch.x_scale, ch.bars):
            a.setflags(write=False)
        _CACHE[model] = ch
    return ch


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
    from ._flat import flatten_legs
    from ._launch import frames
    m = len(home_leg.joints)
    q = np.asarray(q, dtype=float).reshape(-1)
    if q.shape != (m,) or not np.all(np.isfinite(q)):
        raise InputError(f"leg {home_leg.name}: need {m} finite joint values, got {q.tolist()}")
    flat = flatten_legs([home_leg], None, np.zeros(3), ())
    X = np.concatenate([np.zeros(0), q / flat.M[4][0]])[None]
    fr = frames(flat, flat.Z, np.zeros((1, 6)), X, slots=True, twists=True)
    twists = fr["twists"][0, 0]
    R, t = fr["R"][0, 0, -1], fr["t"][0, 0, -1]
    if platform_home is None:
        return twists, (R, t)
    R0, p0 = (np.asarray(x, float) for x in platform_home)
    return twists, (R @ R0, R @ p0 + t)
