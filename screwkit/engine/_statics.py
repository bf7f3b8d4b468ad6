"""Statics of a parallel manipulator from its unified Jacobian (paper eqs. 8-9, 13d-e).

A workload ``(F, T)`` applied to the platform at ``o`` (force ``F``, torque
``T`` about ``o``) is the wrench ``W = [F; T + o x F]`` about the base origin.
Virtual work, ``F_r . (J V) + W . V = 0`` for every twist ``V``, gives
``J^T F_r = -W``, i.e. ``F_r = -(J^-1)^T W`` (eq. 9) when ``J`` is square:

* ``F_r[:n]`` are the **active forces/torques** ``F_ai``, the efforts of the
  actuators conjugate to their joints' unit twists.  For a linear actuator whose
  P axis points from ``A_i`` to ``a_i`` (every catalog leg), ``F_ai > 0`` pushes
  the platform away from ``A_i`` along ``delta_i = (a_i - A_i) / r_i``.
* ``F_r[n:]`` are the **constraint forces and couples** ``F_cj``, ``T_ck``: the
  value times the row's unit direction is the force (couple) the leg applies to
  the platform, on the row's line.  The sign of a value follows the sign of the
  row's direction, which is a convention: compare constraint forces as vectors.
* ``row_wrenches[r] = F_r[r] * J[r]``; a leg's **total wrench** is the sum of its
  rows: the wrench the leg applies to the platform (about ``O``).  It does no
  work on the leg's passive joints and its reciprocal product with the actuated
  joint's unit twist is ``F_ai``.  Platform equilibrium: ``sum_i w_i + W = 0``.
* ``T_r[i]`` (paper eq. 13e) is the moment of leg ``i``'s constraint wrench about
  ``A_i`` along ``delta_i``: the torque the leg carries about its own axis.

When ``J`` has more than 6 rows (redundant constraints or redundant actuation)
the statics is indeterminate: the result is the least-norm solution (norm of the
length-normalised, row-equilibrated unknowns, i.e. forces and couples divided by
the characteristic length, see :mod:`screwkit.engine._jacobian`), ``indeterminacy`` is
``m - rank`` and ``self_stress`` a basis of the solutions of ``J^T x = 0`` that
may be added to it.

Examples
--------
>>> import numpy as np, screwkit
>>> from screwkit.legs import Placement
>>> from screwkit.engine import solve_statics
>>> A = [[100, 0, 0], [-50, 86.6, 0], [-50, -86.6, 0], [100, 20, 0], [-50, 70, 0], [-50, -100, 0]]
>>> a = [[40, 10, 80], [-30, 40, 80], [-10, -40, 80], [30, -40, 80], [-40, -10, 80], [10, 40, 80]]
>>> legs = [screwkit.leg("SPS", Placement(A[i], a[i], o=[0, 0, 80])) for i in range(6)]
>>> res = solve_statics(legs, [0, 0, 80], F=[0, 0, -100], T=[0, 0, 0])
>>> bool(res.equilibrium_residual < 1e-12)
True
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from ..errors import InputError
from ..screws import RANK_RTOL, as_vector3
from ._jacobian import COND_THRESHOLD, JacobianResult, unified_jacobian

__all__ = ["StaticsResult", "statics", "solve_statics", "workload_wrench"]


def _finite3(x, name) -> np.ndarray:
    a = np.asarray(x, dtype=float)
    if a.ndim == 0 or a.shape[-1] != 3:
        raise InputError(f"{name} must have 3 components in its last axis, got shape {a.shape}")
    if not np.all(np.isfinite(a)):
        raise InputError(f"{name} must be finite (no NaN or inf), got {a.tolist()}")
    return a


def workload_wrench(F, T, o) -> np.ndarray:
    """The wrench about the base origin of a force ``F`` at ``o`` and a torque ``T``.

    Parameters
    ----------
    F, T : array_like, shape (..., 3)
        Force and torque (about ``o``), broadcast together.
    o : array_like, shape (3,)

    Returns
    -------
    ndarray, shape (..., 6)
        ``[F; T + o x F]``.
    """
    F = _finite3(F, "workload force F")
    T = _finite3(T, "workload torque T")
    o = as_vector3(o, "workload point o")
    F, T = np.broadcast_arrays(F, T)
    return np.concatenate([F, T + np.cross(o, F)], axis=-1)


@dataclass(frozen=True, eq=False)
class StaticsResult:
    """Active and constraint efforts balancing a workload (shapes for one workload;
    a batch of workloads of shape (..., 3) prefixes every per-load array with ``...``).

    Attributes
    ----------
    jacobian : JacobianResult
    workload : ndarray (6,)
        ``W = [F; T + o x F]`` about ``O``.
    values : ndarray (m,)
        ``F_r``, one value per row of ``J``.
    row_wrenches : ndarray (m, 6)
        ``values[r] * J[r]``: each row's wrench on the platform, about ``O``.
    vectors : ndarray (m, 3)
        Force vector (force, screw and force-type actuation rows) or couple vector
        (couple rows) of each row: value times unit direction, on the row's line.
    leg_wrenches : ndarray (n_legs, 6)
        Total wrench each leg applies to the platform, about ``O``.
    constraint_wrenches : ndarray (n_legs, 6)
        The constraint part of each leg's wrench, about ``O``.
    T_r : ndarray (n_legs,)
        Moment of each leg's constraint wrench about ``A_i`` along
        ``delta_i = (a_i - A_i)/|a_i - A_i|`` (paper eq. 13e).
    equilibrium_residual : float
        ``|sum_i w_i + W|`` over the largest of ``|W|`` and the row wrenches,
        length-normalised (relative, unit-free; max over a batch).
    singular : bool
    singularity_kind : str or None
    condition_number : float
    indeterminacy : int
        ``m - rank(J)``: dimension of the family of solutions (0 = determinate).
    self_stress : ndarray (indeterminacy, m)
        Basis of ``{x : J^T x = 0}`` (rows scaled to unit normalised norm).
    """

    jacobian: JacobianResult
    workload: np.ndarray
    values: np.ndarray
    row_wrenches: np.ndarray
    vectors: np.ndarray
    leg_wrenches: np.ndarray
    constraint_wrenches: np.ndarray
    T_r: np.ndarray
    equilibrium_residual: float
    self_stress: np.ndarray

    def __repr__(self) -> str:
        return (f"StaticsResult(values={np.array2string(np.asarray(self.values), precision=6)}, "
                f"equilibrium_residual={self.equilibrium_residual:.3g}, {self.jacobian!r})")

    @property
    def active(self) -> np.ndarray:
        """Active forces/torques ``F_ai``, shape (..., n)."""
        return self.values[..., : self.jacobian.n_actuated]

    @property
    def constraint(self) -> np.ndarray:
        """Constraint force/couple values, shape (..., m - n)."""
        return self.values[..., self.jacobian.n_actuated:]

    @property
    def rows(self) -> tuple:
        return self.jacobian.rows

    @property
    def points(self) -> np.ndarray:
        """A point of each row's line, shape (m, 3) (NaN for couples)."""
        return np.array([r.point if r.point is not None else np.full(3, np.nan)
                         for r in self.jacobian.rows])

    @property
    def singular(self) -> bool:
        return self.jacobian.singular

    @property
    def singularity_kind(self) -> str | None:
        return self.jacobian.singularity_kind

    @property
    def condition_number(self) -> float:
        return self.jacobian.condition_number

    @property
    def indeterminacy(self) -> int:
        return self.jacobian.indeterminacy

    @property
    def indeterminate(self) -> bool:
        return self.jacobian.indeterminate

    @property
    def success(self) -> bool:
        """Regular pose and equilibrium holds to ``sqrt(RANK_RTOL)``."""
        return (not self.singular) and self.equilibrium_residual <= np.sqrt(RANK_RTOL)

    def describe(self) -> str:
        jac = self.jacobian
        if self.values.ndim != 1:
            return f"statics of {self.values.shape[:-1]} workloads (batched)"
        lines = [f"normalised condition number {jac.condition_number:.6g}; equilibrium residual "
                 f"{self.equilibrium_residual:.3g}"
                 + (f"; statically indeterminate of dimension {jac.indeterminacy} (least-norm "
                    "solution)" if jac.indeterminate else "")
                 + (f"; SINGULAR ({jac.singularity_kind})" if jac.singular else "")]
        for r, v, vec in zip(jac.rows, self.values, self.vectors):
            lines.append(f"  {v: .6g}  {r.describe()}  -> vector "
                         f"({', '.join(f'{x:.6g}' for x in vec)})")
        for i, t in enumerate(self.T_r):
            lines.append(f"  leg {i} ({jac.legs[i].name}): T_r = {t:.6g}")
        return "\n".join(lines)


def statics(jacobian: JacobianResult, F, T, o=None, *, raise_on_singular: bool = True) -> StaticsResult:
    """Active and constraint efforts balancing the workload ``(F, T)`` applied at ``o``.

    Parameters
    ----------
    jacobian : JacobianResult
        From :func:`screwkit.engine.unified_jacobian`.
    F, T : array_like, shape (3,) or (..., 3)
        Force and torque about ``o`` (same units as the legs' lengths for ``T``).
    o : array_like (3,), optional
        Where the workload is applied; default the Jacobian's platform centre.
    raise_on_singular : bool
        Raise :class:`SingularityError` (``kind`` and ``condition_number``
        attributes) at a singular pose.  With False the result is returned with
        ``singular`` and ``singularity_kind`` set (for trajectories); its values are
        then the least-squares solution and ``equilibrium_residual`` says whether
        they balance the load.

    Returns
    -------
    StaticsResult
    """
    if not isinstance(jacobian, JacobianResult):
        raise InputError(f"statics needs a JacobianResult, got {type(jacobian).__name__}")
    if raise_on_singular:
        jacobian.check()
    o = jacobian.o if o is None else as_vector3(o, "workload point o")
    W = workload_wrench(F, T, o)
    jac = jacobian
    norm = jac.normalisation
    J = jac.J
    m = len(J)
    d = np.where(jac._row_norms > 0, jac._row_norms, 1.0)
    Jn = jac._Jn
    # J^T x = -W  <=>  Jn^T (d * x) = -Wn   (Wn: moments about the centroid / L)
    Wn = norm.wrenches(W)
    # least-squares / least-norm with numpy's default cut-off (machine precision), so
    # that near-singular poses give their true (large) values
    pinvT = np.linalg.pinv(Jn.T, rcond=max(m, 6) * np.finfo(float).eps)   # (m, 6)
    y = -np.einsum("mj,...j->...m", pinvT, Wn)
    values = y / d
    row_w = values[..., :, None] * J                                       # (..., m, 6)

    kinds = [r.member for r in jac.rows]
    couple = np.array([k == "couple" for k in kinds])
    vectors = np.where(couple[:, None], row_w[..., 3:], row_w[..., :3])

    n_legs = len(jac.legs)
    P = np.zeros((n_legs, m))
    P[jac.leg_of_row, np.arange(m)] = 1.0
    Pc = P.copy()
    Pc[:, : jac.n_actuated] = 0.0
    leg_w = np.einsum("lm,...mj->...lj", P, row_w)
    con_w = np.einsum("lm,...mj->...lj", Pc, row_w)
    A = np.array([leg.A for leg in jac.legs])
    delta = np.array([(leg.a - leg.A) / leg.length for leg in jac.legs])
    moment_A = con_w[..., 3:] - np.cross(A, con_w[..., :3])
    T_r = np.sum(moment_A * delta, axis=-1)

    # equilibrium, length-normalised and relative
    total = norm.wrenches(leg_w.sum(axis=-2) + W)
    scale = np.maximum(np.linalg.norm(Wn, axis=-1),
                       np.max(np.linalg.norm(norm.wrenches(row_w), axis=-1), axis=-1, initial=0.0))
    scale = np.where(scale > 0, scale, 1.0)
    resid = float(np.max(np.linalg.norm(total, axis=-1) / scale))

    if jac.indeterminacy > 0:
        # null space of Jn^T (unit rows in the normalised unknowns y = d x), back to x
        Vt = np.linalg.svd(Jn.T, full_matrices=True)[2]
        N = Vt[jac.rank:] / d[None, :]
    else:
        N = np.zeros((0, m))
    for arr in (W, values, row_w, vectors, leg_w, con_w, T_r, N):
        arr.setflags(write=False)
    return StaticsResult(jac, W, values, row_w, vectors, leg_w, con_w, T_r, resid, N)


def solve_statics(legs, o, F, T, *, analyses=None, raise_on_singular: bool = True,
                  threshold: float = COND_THRESHOLD) -> StaticsResult:
    """Shortcut: :func:`statics` of :func:`unified_jacobian` ``(legs, o)`` with the load at ``o``."""
    jac = unified_jacobian(legs, o, analyses, threshold=threshold)
    return statics(jac, F, T, o, raise_on_singular=raise_on_singular)
