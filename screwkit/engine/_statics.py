"""Statics of a PM from its unified Jacobian (paper eqs. 8-9, 13d-e), for N poses at once.

A workload ``(F, T)`` applied to the platform at ``o`` (force ``F``, torque
``T`` about ``o``) is the wrench ``W = [F; T + o x F]`` about the base origin.
Virtual work, ``F_r . (J V) + W . V = 0`` for every twist ``V``, gives
``J^T F_r = -W``, i.e. ``F_r = -(J^-1)^T W`` (eq. 9) when ``J`` is square:

* ``F_r[:n]`` are the **active forces/torques** ``F_ai``, the efforts of the
  actuators conjugate to their joints' unit twists.  For a linear actuator whose
  P axis points from ``A_i`` to ``a_i``, ``F_ai > 0`` pushes the platform away
  from ``A_i``.
* ``F_r[n:]`` are the **constraint forces and couples**: the value times the
  row's unit direction is the force (couple) the leg applies to the platform, on
  the row's line.
* ``row_wrenches[r] = F_r[r] * J[r]``; a leg's **total wrench** is the sum of its
  rows (about ``O``).  Platform equilibrium: ``sum_i w_i + W = 0``.
* ``T_r[i]`` (paper eq. 13e) is the moment of leg ``i``'s constraint wrench about
  ``A_i`` along ``delta_i = (a_i - A_i) / r_i``.

With more than 6 rows (redundant constraints or actuation) the statics is
indeterminate: the result is the least-norm solution (in the normalised,
row-equilibrated unknowns); ``self_stress`` spans the solutions of
``J^T x = 0`` that may be added to it.

Examples
--------
>>> import screwkit
>>> from screwkit.engine import solve_statics
>>> from screwkit.legs import Placement
>>> A = [[100, 0, 0], [-50, 86.6, 0], [-50, -86.6, 0], [100, 20, 0], [-50, 70, 0], [-50, -100, 0]]
>>> a = [[40, 10, 80], [-30, 40, 80], [-10, -40, 80], [30, -40, 80], [-40, -10, 80], [10, 40, 80]]
>>> legs = [screwkit.leg("SPS", Placement(A[i], a[i], o=[0, 0, 80])) for i in range(6)]
>>> res = solve_statics(legs, [0, 0, 80], F=[0, 0, -100], T=[0, 0, 0])
>>> bool(res.equilibrium_residual < 1e-12)
True
"""

from __future__ import annotations

from dataclasses import dataclass, field
from functools import cached_property

import numpy as np
from numpy.typing import ArrayLike

from ._frozen import freeze_fields, kernel_array
from ._inputs import pose_index
from ._jacobian import JacobianResult
from ._statics_inputs import _finite3, _leg_points
from ._pipeline import (RANK_RTOL, leg_wrenches_of, statics_values, torque_rows,
                        workload_about_origin)
from ..screws import as_vector3, cross
from ..screws._echelon import reduced_echelon
from ..errors import MisuseError

__all__ = ["StaticsResult", "statics", "workload_wrench", "compliance_of"]


def _errors():
    from ..errors import InputError
    return InputError


def workload_wrench(F, T, o) -> np.ndarray:
    """The wrench ``[F; T + o x F]`` about the base origin of a force ``F`` at ``o`` and a
    torque ``T``; ``F, T (..., 3)`` broadcast together, ``o (3,)``."""
    F = _finite3(F, "workload force F")
    T = _finite3(T, "workload torque T")
    o = as_vector3(o, "workload point o")
    F, T = np.broadcast_arrays(F, T)
    return np.concatenate([F, T + cross(o, F)], axis=-1)


def _sq(x, single):
    return x[0] if single else x


@dataclass(frozen=True, eq=False)
class StaticsResult:
    """Active and constraint efforts balancing a workload at N poses.

    Arrays have the poses first, except for a one-pose result (``jacobian.single``);
    a batch of ``K`` workloads at one pose adds a leading ``K`` axis instead.

    Attributes
    ----------
    jacobian : JacobianResult
    F_r : ndarray (N, [K,] m)
        The values ``F_r`` (NaN where ``valid`` is False).
    W : ndarray (N, [K,] 6) or callable
        The workload about ``O`` (or a function returning it, called when first needed).
    A : ndarray (n, 3) ; a : ndarray (N, n, 3) or callable
        The legs' end points (for ``T_r``).
    valid : ndarray (N,) of bool
        False where the values are not defined (a singular or unreachable pose of a batch).
    eq : ndarray (N,), optional
        The equilibrium residuals, when the engine computed them with the values.
    amp : ndarray (N,), optional
        The force amplification of each pose (:mod:`screwkit.engine._quality`), likewise.

    Only ``F_r`` is kept for a batch; the row wrenches, vectors, leg wrenches and ``T_r``
    are formed when first read (memory linear in N with a small constant).
    """

    jacobian: JacobianResult
    F_r: np.ndarray = field(repr=False)
    W: object = field(repr=False)
    A: np.ndarray = field(repr=False)
    a: object = field(repr=False)
    valid: np.ndarray = field(repr=False)
    eq: np.ndarray | None = field(default=None, repr=False)
    amp: np.ndarray | None = field(default=None, repr=False)

    def __post_init__(self):
        freeze_fields(self, ("F_r", "A", "valid", "eq", "amp"))       # (as the Jacobian's)

    @cached_property
    def _W(self):
        return self.W() if callable(self.W) else self.W

    @cached_property
    def _a(self):
        return self.a() if callable(self.a) else self.a

    @cached_property
    def _derived(self):
        """Row wrenches, vectors, leg wrenches, constraint wrenches and ``T_r``."""
        jac = self.jacobian
        J, v = jac.matrix, self.F_r
        lead = v.shape[:-1]
        Jb = J.reshape((J.shape[0],) + (1,) * (len(lead) - 1) + J.shape[1:])
        row_w = v[..., None] * Jb
        couple = np.array([r.member == "couple" for r in jac.info])
        vectors = np.where(couple[:, None], row_w[..., 3:], row_w[..., :3])
        con_w, leg_w, T_r = leg_wrenches_of(J, jac.info, jac.n_actuated, v, self.A, self._a)
        out = (row_w, vectors, leg_w, con_w, T_r)
        for x in out:
            x.setflags(write=False)
        return out

    def _sq(self, x):
        return x[0] if self.jacobian.single else x

    @property
    def workload(self):
        """``W = [F; T + o x F]`` about ``O``."""
        return self._sq(self._W)

    @property
    def values(self):
        """``F_r``: one value per row of ``J``, ``(..., m)``."""
        return self._sq(self.F_r)

    row_wrenches = property(lambda self: self._sq(self._derived[0]),
                            doc="``values[r] * J[r]``: each row's wrench about O, (..., m, 6).")
    vectors = property(lambda self: self._sq(self._derived[1]),
                       doc="Force (couple) vector of each row on its line, (..., m, 3).")
    leg_wrenches = property(lambda self: self._sq(self._derived[2]),
                            doc="Total wrench each leg applies to the platform (about O).")
    constraint_wrenches = property(lambda self: self._sq(self._derived[3]),
                                   doc="The constraint part of each leg's wrench (about O).")

    @cached_property
    def _eq(self):
        if self.eq is not None:
            return self.eq
        from ._kernels import kernels
        jac = self.jacobian
        c = jac.conditioning
        N, m = jac.matrix.shape[:2]
        v = np.ascontiguousarray(self.F_r, float).reshape(N, -1, m)
        W = np.ascontiguousarray(np.broadcast_to(self._W, self.F_r.shape[:-1] + (6,)),
                                 float).reshape(N, -1, 6)
        out = np.empty(v.shape[:2])
        kernels().equilibrium_batch(kernel_array(jac.matrix), v, W,
                                    np.ascontiguousarray(c.centre, float),
                                    np.ascontiguousarray(c.length, float), out)
        return out.reshape(self.F_r.shape[:-1])

    @cached_property
    def _t_r(self):
        # T_r alone (a map reads it for every cell): not the row-wrench stacks of _derived
        if "_derived" in self.__dict__:
            return self._derived[4]
        jac = self.jacobian
        out = leg_wrenches_of(jac.matrix, jac.info, jac.n_actuated, self.F_r, self.A, self._a,
                              total=False)[2]
        out.setflags(write=False)
        return out

    T_r = property(lambda self: self._sq(self._t_r),
                   doc="Moment of each leg's constraint wrench about A_i along delta_i.")

    @property
    def equilibrium_residual(self):
        """``|sum_i w_i + W|`` relative to the largest of ``|W|`` and the row wrenches,
        length-normalised (max over a batch of workloads at one pose)."""
        r = self._eq
        if self.jacobian.single:
            r = r[0]
            return float(np.max(r)) if np.ndim(r) else float(r)
        return r

    def __len__(self):
        return len(self.jacobian)

    def __getitem__(self, i) -> "StaticsResult":
        if self.jacobian.single:
            raise MisuseError("a one-pose StaticsResult cannot be indexed")
        i = pose_index(i, len(self))
        sl = slice(i, i + 1) if isinstance(i, int) else i      # one pose, or a sub-batch
        return StaticsResult(self.jacobian[i], self.F_r[sl], self._W[sl], self.A, self._a[sl],
                             self.valid[sl], None if self.eq is None else self.eq[sl],
                             None if self.amp is None else self.amp[sl])

    def __repr__(self) -> str:
        if not self.jacobian.single:
            return f"StaticsResult({len(self)} poses, {int(np.sum(~self.valid))} undefined)"
        return (f"StaticsResult(values={np.array2string(np.asarray(self.values), precision=6)}, "
                f"equilibrium_residual={self.equilibrium_residual:.3g}, {self.jacobian!r})")

    @property
    def active(self) -> np.ndarray:
        """Active forces/torques ``F_ai``, ``(..., n)``."""
        return self.values[..., : self.jacobian.n_actuated]

    @property
    def constraint(self) -> np.ndarray:
        """Constraint force/couple values, ``(..., m - n)``."""
        return self.values[..., self.jacobian.n_actuated:]

    @property
    def rows(self) -> tuple:
        return self.jacobian.rows

    @property
    def points(self) -> np.ndarray:
        return self.jacobian.points

    singular = property(lambda self: self.jacobian.singular)
    singularity_kind = property(lambda self: self.jacobian.singularity_kind)
    condition_number = property(lambda self: self.jacobian.condition_number)
    indeterminacy = property(lambda self: self.jacobian.indeterminacy)
    indeterminate = property(lambda self: self.jacobian.indeterminate)

    @property
    def success(self):
        """Regular pose and equilibrium to ``sqrt(RANK_RTOL)``."""
        r = np.asarray(self._eq)
        r = r.reshape(r.shape[0], -1).max(axis=1)
        ok = ~self.jacobian.singular_mask & (r <= np.sqrt(RANK_RTOL))
        return bool(ok[0]) if self.jacobian.single else ok

    @cached_property
    def self_stress(self) -> np.ndarray:
        """Basis ``(indeterminacy, m)`` of ``{x : J^T x = 0}`` (one pose), canonical: in
        reduced row echelon form, each self-stress 1 on a row of its own (its pivot, the
        first row, in the rows' order, that the self-stresses after the earlier ones move)
        and 0 on the other self-stresses' pivots; the pivots are chosen on the normalised
        rows, so the basis does not depend on the units or the base frame (an SVD's basis
        is one of many, its signs and mixing set by the last bits of ``J``)."""
        jac = self.jacobian
        jac._one("self_stress")
        if jac.indeterminacy <= 0:
            return np.zeros((0, jac.n_rows))
        Jn, d = jac.normalised()
        Vt = np.linalg.svd(Jn[0].T, full_matrices=True)[2]
        E, piv = reduced_echelon(Vt[jac.rank:])
        N = E[:len(piv)] / d[0][None, :]
        N = N / N[np.arange(len(piv)), piv][:, None]
        N.setflags(write=False)
        return N

    @cached_property
    def determined(self) -> np.ndarray:
        """Per row: True where statics alone fixes the value, False where a self-stress can
        change it (the least-norm or compliance-weighted choice), ``(..., m)``."""
        jac = self.jacobian
        Jn, d = jac.normalised()
        N, m = Jn.shape[0], Jn.shape[1]
        out = np.ones((N, m), bool)
        ind = np.flatnonzero(np.atleast_1d(jac.n_rows - jac.conditioning.rank) > 0)
        for i in ind:
            r = int(jac.conditioning.rank[i])
            Vt = np.linalg.svd(Jn[i].T, full_matrices=True)[2]
            S = Vt[r:]                                   # self-stresses in normalised rows
            out[i] = np.max(np.abs(S), axis=0) <= 1e-9
        return out[0] if jac.single else out

    def describe(self) -> str:
        jac = self.jacobian
        jac._one("describe")
        if self.values.ndim != 1:
            return f"statics of {self.values.shape[:-1]} workloads (batched)"
        lines = [f"normalised condition number {jac.condition_number:.6g}; equilibrium residual "
                 f"{self.equilibrium_residual:.3g}"
                 + (f"; statically indeterminate of dimension {jac.indeterminacy} (least-norm "
                    "solution)" if jac.indeterminate else "")
                 + (f"; SINGULAR ({jac.singularity_kind})" if jac.singular else "")]
        for r, v, vec, det in zip(jac.rows, self.values, self.vectors, self.determined):
            lines.append(f"  {v: .6g}  {r.describe()}  -> vector "
                         f"({', '.join(f'{x:.6g}' for x in vec)})"
                         + ("" if det else "  [not determined by statics]"))
        for i, t in enumerate(self.T_r):
            lines.append(f"  leg {i} ({jac.info[jac.leg_rows(i)[0]].leg_name}): T_r = {t:.6g}")
        return "\n".join(lines)


def statics(jacobian: JacobianResult, F: ArrayLike, T: ArrayLike, o: ArrayLike | None = None, *,
            raise_on_singular: bool = True, base_points: ArrayLike | None = None,
            platform_points: ArrayLike | None = None,
            stiffness: ArrayLike | None = None) -> StaticsResult:
    """Active and constraint efforts balancing the workload ``(F, T)`` applied at ``o``.

    Parameters
    ----------
    jacobian : JacobianResult
    F, T : array_like ``(3,)``, ``(K, 3)`` (K workloads at one pose) or ``(N, 3)``
        (one per pose); force and torque about ``o``.
    o : array_like (3,) or (N, 3), optional
        Where the workload is applied; default the platform centre of each pose.
    raise_on_singular : bool
        Raise :class:`SingularityError` at a singular pose (the first one); with False
        singular poses get the least-squares values, flagged by ``singular``.
    base_points, platform_points : ndarray (n, 3), (N, n, 3), optional
        ``A_i`` and ``a_i`` (for ``T_r``); default the legs' end points.
    stiffness : array_like (m,) or (N, m), optional
        Stiffness of each row (force / length for forces and linear actuators, torque /
        radian for couples and rotary actuators, model units): a statically indeterminate
        system then takes the compliance-weighted solution, ``sum_k F_k^2 / k_k`` minimal.
        Default: the least-norm one, ``sum F^2 + sum (C / L)^2`` minimal.
    """
    InputError = _errors()
    if not isinstance(jacobian, JacobianResult):
        raise InputError(f"statics needs a JacobianResult, got {type(jacobian).__name__}")
    from ..legs._guards import flag
    if flag(raise_on_singular, "raise_on_singular"):
        jacobian.check()
    N = len(jacobian)
    F = _finite3(F, "workload force F")
    T = _finite3(T, "workload torque T")
    if o is None:
        o = jacobian.origin
    else:
        o = np.asarray(o, float)
        if o.shape == (3,):
            o = as_vector3(o, "workload point o")
        o = np.broadcast_to(_finite3(o, "workload point o"), (N, 3))
    if F.ndim > 2 or T.ndim > 2:
        raise InputError(f"workload F {F.shape} and T {T.shape} must be (3,) or (K, 3)")
    if F.ndim == 2 and T.ndim == 2 and F.shape != T.shape:
        raise InputError(f"workload F {F.shape} and T {T.shape}: give as many torques as forces")
    if jacobian.single:
        F, T = np.broadcast_arrays(F, T)
        F, T = F[None], T[None]
    else:
        for x, name in ((F, "F"), (T, "T")):
            if x.ndim == 2 and x.shape[0] != N:
                raise InputError(f"workload {name} of a batch is (3,) or ({N}, 3), one a pose, "
                                 f"got {x.shape}")
        F = np.broadcast_to(F, (N, 3)) if F.ndim == 1 else F
        T = np.broadcast_to(T, (N, 3)) if T.ndim == 1 else T
    if base_points is None and platform_points is not None:
        raise InputError("platform_points without base_points: give both (T_r needs A_i and a_i)")
    if base_points is None:
        if not jacobian.single:
            raise InputError("statics of a batch of poses needs base_points (n, 3) and "
                             "platform_points (N, n, 3); screwkit.analyze passes them")
        legs = jacobian.legs
        A = np.array([lg.A for lg in legs])
        a = np.array([[lg.a for lg in legs]])
    else:
        A, a = _leg_points(jacobian, base_points, platform_points, N)
    W = workload_about_origin(F, T, o)
    comp = None if stiffness is None else compliance_of(stiffness, jacobian.n_rows, N)
    values, eq, amp = statics_values(jacobian.matrix, jacobian.conditioning,
                                     torque_rows(jacobian.info), W, o, comp)
    for x in (W, values, eq):
        x.setflags(write=False)
    return StaticsResult(jacobian, values, W, A, a, np.ones(N, bool), eq,
                         amp if W.ndim == 2 else None)


def compliance_of(stiffness, m, N):
    """Validated compliances ``1 / k`` ``(N, m)`` of row stiffnesses ``(m,)`` or ``(N, m)``."""
    InputError = _errors()
    k = np.asarray(stiffness, dtype=float)
    if k.shape not in ((m,), (N, m)):
        raise InputError(f"stiffness must have one value per row of J ({m}), got shape {k.shape}")
    from ..legs._guards import MAX_STIFFNESS, MIN_STIFFNESS
    if not (np.all(np.isfinite(k)) and np.all(k > 0)):
        raise InputError("stiffness values must be positive and finite")
    if not np.all((k >= MIN_STIFFNESS) & (k <= MAX_STIFFNESS)):
        raise InputError(f"stiffness values must be from {MIN_STIFFNESS:g} to {MAX_STIFFNESS:g} "
                         "in the model's units")
    return np.broadcast_to(1.0 / k, (N, m))
