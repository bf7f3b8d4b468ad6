"""The finite motion type of a PM, from motions sampled from home.

The engine samples the motion (:func:`screwkit.engine.finite_motion`: poses solved from
home); this module classifies what it saw, from the platform rotations ``R (N, 3, 3)``,
positions ``o (N, 3)`` and pose parameters, with no solver:

* the **independent rotations** ``r``: the rank of the derivative of the platform's
  rotation (its rotation vector ``log(R R_b^T)``) with respect to the independent
  parameters, by central differences at home, with lengths divided by the characteristic
  length ``L``.  Away from home a parasitic rotation can add to that rank (the 3-RSR's
  ``gamma`` varies with ``Zo`` there): the rank at two base poses away from home is
  reported (``rotations_away``), and the rotation is named among the parasitic motions
  (where home is a representation singularity of the Euler angles, the rank is taken at
  the first base pose instead);
* ``t = dof - r`` **translations**, and the label ``"<t>T<r>R"`` (``"1T2R"`` for the 3-RPS,
  the literature's 2R1T);
* the **invariants** of the sampled displacements ``(R_i R_0^T, o_i - ...)``: a fixed
  orientation (``r = 0``); a base-fixed point (the least-squares centre of the
  displacements, as for a spherical motion); rotation axes that stay parallel to one
  base direction (``r = 1``: Schoenflies and planar motions), translations normal to it
  (planar), or translations along it proportional to the turn (a screw motion: an H
  joint's platform, labelled ``"2T1H(p=20)"`` as the instantaneous type labels it);
* the **parasitic** motions: dependent pose parameters that vary with the independent
  ones, where no fixed point explains them (the 3-RPS's ``Xo``, ``Yo``, ``gamma``).

The instantaneous classification of the twist space at one pose is another thing
(:func:`screwkit.pm.mobility`, ``instantaneous_type``).
"""

from __future__ import annotations

import weakref
from dataclasses import dataclass, field

import numpy as np

__all__ = ["FiniteMotion", "classify_finite_motion", "rotation_vectors", "FINITE_RTOL",
           "RANK_FD_RTOL", "register_finite_motion", "registered_finite_motion",
           "set_finite_motion_solver"]

#: Tolerance of the invariants, relative (rotations, radians) or to the length ``L``.
FINITE_RTOL = 1e-7
#: Relative tolerance of the rotation rank (singular values of the central-difference
#: derivative, columns in radians per radian or per ``L``).
RANK_FD_RTOL = 1e-5

_ANGLES = ("alpha", "beta", "gamma")


@dataclass(frozen=True)
class FiniteMotion:
    """The finite motion type of a PM (see the module docstring).

    Attributes
    ----------
    label : str
        ``"<t>T<r>R"``: ``"3T"``, ``"3R"``, ``"1T2R"`` (the literature's 2R1T), ``"3T1R"``;
        a screw motion ``"<t>T1H(p=...)"`` (``pitch``).
    translations, rotations : int
    dof : int
        The number of independent parameters.
    invariants : tuple of str
        What stays fixed along the sampled motion, in words.
    parasitic : tuple of str
        Dependent pose parameters that vary with the independent ones.
    independent : tuple of str
    centre : ndarray (3,) or None
        The base-fixed point of a motion that has one.
    axis : ndarray (3,) or None
        The common direction of the rotation axes (``r = 1``).
    pitch : float or None
        A screw motion's pitch (``r = 1``; model lengths per radian): the translation along
        the rotation axes proportional to the turn about them (an H joint's platform).  Its
        label then names a helical freedom, ``"2T1H(p=20)"``, as the instantaneous type
        does; it still counts as one rotation in ``rotations``.
    samples : int
        Poses solved.
    rotations_away : int
        The rank of the rotations' derivative at the base poses away from home (above
        ``rotations`` when a parasitic rotation varies with the translations there).
    notes : tuple of str
    deviation : float
        The largest deviation from the invariants named (0 without any).
    """

    label: str
    translations: int
    rotations: int
    dof: int
    invariants: tuple = ()
    parasitic: tuple = ()
    independent: tuple = ()
    centre: np.ndarray | None = field(default=None, repr=False)
    axis: np.ndarray | None = field(default=None, repr=False)
    samples: int = 0
    deviation: float = 0.0
    rotations_away: int = 0
    notes: tuple = ()
    pitch: float | None = None

    @property
    def text(self) -> str:
        """``"1T2R: independent alpha, beta, Zo; parasitic Xo, Yo, gamma (functions of
        them); ..."`` in one line."""
        out = f"{self.label}: independent {', '.join(self.independent) or 'none'}"
        if self.parasitic:
            out += f"; parasitic motion {', '.join(self.parasitic)} (functions of them)"
        else:
            out += "; no parasitic motion"
        if self.invariants:
            out += "; " + "; ".join(self.invariants)
        if self.notes:
            out += " (" + "; ".join(self.notes) + ")"
        return out

    def declared(self, independent) -> tuple:
        """``(translations, rotations)`` that the parameters ``independent`` declare."""
        t = sum(p in ("Xo", "Yo", "Zo") for p in independent)
        return t, len(tuple(independent)) - t

    def to_dict(self) -> dict:
        return {"label": self.label, "translations": self.translations,
                "rotations": self.rotations, "invariants": list(self.invariants),
                "parasitic": list(self.parasitic), "samples": self.samples}


def rotation_vectors(R) -> np.ndarray:
    """Rotation vectors ``(N, 3)`` (axis times angle, radians) of rotation matrices
    ``(N, 3, 3)``: the logarithm of SO(3) (scipy)."""
    from scipy.spatial.transform import Rotation
    return Rotation.from_matrix(np.asarray(R, float).reshape(-1, 3, 3)).as_rotvec()


def _label(t: int, r: int) -> str:
    out = (f"{t}T" if t else "") + (f"{r}R" if r else "")
    return out or "0"


def classify_finite_motion(independent, jacobians, R, o, dependent, length: float,
                           home_singular: bool = False, counts=None) -> FiniteMotion:
    """Classify sampled motions (see the module docstring).

    Parameters
    ----------
    independent : sequence of str
    jacobians : ndarray (B, 3, d)
        Central-difference derivatives of the rotation vector at ``B`` base poses (home
        first), per independent parameter (angles in radians, lengths divided by
        ``length``).
    R : ndarray (N, 3, 3)
        Platform rotations of the samples, home first.
    o : ndarray (N, 3)
        Platform positions (model lengths).
    dependent : dict
        ``{name: (N,) values}`` of the dependent pose parameters (radians, lengths).
    length : float
        Characteristic length ``L``.
    home_singular : bool
        Home is a representation singularity of the Euler angles with two of them
        independent (the XYX angles at ``beta = 0``): the parameters lose a rotation there,
        not the motion, so the rank is taken at the first base pose away from home.
    counts : (int, int), optional
        ``(translations, rotations)`` when no derivative could be sampled (the poses
        next to home are not assembled): those of the twist space at home, with a note.
    """
    ind = tuple(independent)
    d = len(ind)
    J = np.asarray(jacobians, float).reshape(-1, 3, d) if d else np.zeros((0, 3, 0))
    ranks = []
    for Jb in J:
        s = np.linalg.svd(Jb, compute_uv=False) if Jb.size else np.zeros(0)
        ranks.append(int(np.sum(s > RANK_FD_RTOL * max(1.0, float(s[0]) if s.size else 1.0))))
    r = (ranks[1] if home_singular and len(ranks) > 1 else ranks[0]) if ranks else 0
    notes = ()
    if counts is not None and not ranks:
        r = int(counts[1])
        notes = ("the poses next to home are not assembled: translations and rotations "
                 "counted in the twist space at home",)
    t = d - r
    R = np.asarray(R, float).reshape(-1, 3, 3)
    o = np.asarray(o, float).reshape(-1, 3)
    L = float(length)
    if len(R) < 2:
        return FiniteMotion(_label(t, r), t, r, d, (), (), ind, None, None, len(R), 0.0, r,
                            notes)
    Q = R @ R[0].T
    invariants, dev = [], 0.0
    centre = axis = pitch = None
    if r == 0:
        err = float(np.max(np.abs(R - R[0])))
        if err <= FINITE_RTOL:
            invariants.append("fixed orientation")
            dev = max(dev, err)
    else:
        # a base-fixed point p: o_i - p = Q_i (o_0 - p)
        A = (np.eye(3) - Q).reshape(-1, 3)
        b = (o - np.einsum("nij,j->ni", Q, o[0])).reshape(-1)
        if np.linalg.matrix_rank(A, tol=1e-9) == 3:
            p, *_ = np.linalg.lstsq(A, b, rcond=None)
            err = float(np.max(np.abs(A @ p - b))) / L
            if err <= FINITE_RTOL:
                centre = p
                invariants.append("a base-fixed point (" + ", ".join(f"{x:.6g}" for x in p) + ")")
                dev = max(dev, err)
    if r == 1:
        rv = rotation_vectors(Q)
        big = np.linalg.norm(rv, axis=1) > 1e-9
        if big.any():
            u = np.linalg.svd(rv[big])[2][0]
            u = u if u[np.argmax(np.abs(u))] > 0 else -u
            err = float(np.max(np.linalg.norm(rv[big] - np.outer(rv[big] @ u, u), axis=1)))
            if err <= FINITE_RTOL:
                axis = u
                invariants.append("rotation axes parallel to (" + ", ".join(
                    f"{x:.6g}" for x in np.where(np.abs(u) < 1e-12, 0.0, u)) + ")")
                dev = max(dev, err)
                axial = (o - o[0]) @ u
                off = float(np.max(np.abs(axial))) / L
                if t == 2 and off <= FINITE_RTOL:
                    invariants.append("planar: translations normal to the rotation axes")
                    dev = max(dev, off)
                elif off > FINITE_RTOL:
                    screw, err = _helical_pitch(rv @ u, axial, L)
                    if err <= FINITE_RTOL:
                        pitch = screw
                        invariants.append(f"helical: the turn about the axes carries a "
                                          f"translation along them of pitch {pitch:.4g} "
                                          "(length/rad)")
                        dev = max(dev, err)
    parasitic = ()
    if centre is None:
        moves = []
        for name, v in dependent.items():
            v = np.asarray(v, float)
            scale = 1.0 if name in _ANGLES else L
            if float(np.max(np.abs(v - v[0]))) > FINITE_RTOL * scale:
                moves.append(name)
        parasitic = tuple(moves)
    label = _label(t, r)
    if pitch is not None:               # (the instantaneous type's label of an H freedom)
        label = (_label(t, 0) if t else "") + f"1H(p={pitch:.4g})"
    return FiniteMotion(label, t, r, d, tuple(invariants), parasitic, ind, centre, axis,
                        len(R), dev, max(ranks[1:], default=r), notes, pitch)


def _helical_pitch(angle, axial, length: float) -> tuple:
    """``(p, err)``: the least-squares pitch of displacements ``axial (N,)`` along the
    rotation axes proportional to the signed turns ``angle (N,)`` about them (a screw
    motion: ``axial = p angle``), and the largest deviation from it over ``length``."""
    aa = float(angle @ angle)
    if aa <= 0.0:
        return 0.0, np.inf
    p = float(angle @ axial) / aa
    return p, float(np.max(np.abs(axial - p * angle))) / length


#: The finite motion of each model object the engine has classified
#: (:func:`screwkit.engine.finite_motion` fills it; :func:`screwkit.pm.mobility` reads it).
_REGISTRY: "weakref.WeakKeyDictionary" = weakref.WeakKeyDictionary()


def register_finite_motion(model, motion: FiniteMotion) -> None:
    """Remember ``motion`` as the finite motion of ``model`` (the engine computes it)."""
    _REGISTRY[model] = motion


#: The engine's ``finite_motion(model)``, installed when the engine is imported (this layer
#: never imports the engine: a solved pose comes from it, so it is there).
_SOLVER: list = []


def set_finite_motion_solver(fn) -> None:
    """Install ``fn(model) -> FiniteMotion`` (:func:`screwkit.engine.finite_motion` does it)."""
    _SOLVER[:] = [fn]


def registered_finite_motion(model, compute: bool = True) -> FiniteMotion | None:
    """The finite motion the engine computed for ``model`` (computed now with ``compute``
    when the engine is loaded), or None."""
    try:
        hit = _REGISTRY.get(model)
    except TypeError:                   # not weak-referenceable: never registered
        return None
    if hit is None and compute and _SOLVER and hasattr(model, "independent"):
        hit = _SOLVER[0](model)
    return hit
