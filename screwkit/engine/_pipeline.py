"""What the rows of the unified Jacobian are, and the statics of given Jacobians by the
kernels (private).

Every function takes and returns arrays with the poses on the leading axis.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from ._frozen import kernel_array
from ._kernels._layout import RANK_RTOL
from ._templates import RowInfo, templates_of

__all__ = ["RowInfo", "templates_of", "Conditioning", "COND_THRESHOLD", "RANK_RTOL",
           "statics_values", "leg_wrenches_of", "workload_about_origin", "normalise_rows",
           "amplification_of", "conditioning_of"]

#: Largest normalised condition number of ``J`` still treated as regular.
COND_THRESHOLD = 1.0 / RANK_RTOL


def torque_rows(info) -> np.ndarray:
    """1 for a row whose effort is a torque (a couple, a rotary actuator), else 0."""
    return np.array([int(r.torque) for r in info], np.int64)


@dataclass(frozen=True, eq=False)
class Conditioning:
    """Rank and conditioning of N Jacobians (arrays with the poses first).

    ``centre (N, 3)``, ``length (N,)``: the normalisation (centroid and characteristic
    length of the legs' points and ``o``); ``singular_values (N, min(m, 6))`` of the
    normalised, row-equilibrated ``J``; ``rank``; ``condition_number``;
    ``constraint_rank``; ``constraint_condition_number``.
    """

    centre: np.ndarray
    length: np.ndarray
    singular_values: np.ndarray
    rank: np.ndarray
    condition_number: np.ndarray
    constraint_rank: np.ndarray
    constraint_condition_number: np.ndarray

    def normalised(self, J):
        """``(Jn, d)``: the rows of ``J (N, m, 6)`` about the centroid, moments over the
        length, unit; and their norms."""
        return normalise_rows(J, self.centre, self.length)

    def take(self, sl) -> "Conditioning":
        return Conditioning(*(getattr(self, f)[sl] for f in self.__dataclass_fields__))


def normalise_rows(J, centre, length):
    """``(Jn (N, m, 6), d (N, m))`` by the kernel (see :class:`Conditioning`)."""
    from ._kernels import kernels
    J = kernel_array(J)                 # (a result's read-only rows: the same kernel)
    Jn, d = np.empty(J.shape), np.empty(J.shape[:2])
    kernels().normalise_batch(J, kernel_array(centre), kernel_array(length), Jn, d)
    return Jn, d


def conditioning_of(J, n_actuated, centre, length) -> Conditioning:
    """The :class:`Conditioning` of given rows ``J (N, m, 6)`` (the first ``n_actuated``
    the actuation rows) with the normalisation ``centre (N, 3)``, ``length (N,)``."""
    from ._kernels import kernels
    J = kernel_array(J)
    N, m = J.shape[:2]
    sv = np.empty((N, min(m, 6)))
    rank, crank = np.empty(N, np.int64), np.empty(N, np.int64)
    cond, ccond = np.empty(N), np.empty(N)
    kernels().conditioning_batch(J, kernel_array(centre), kernel_array(length),
                                 int(n_actuated), sv, rank, cond, crank, ccond)
    return Conditioning(np.asarray(centre, float), np.asarray(length, float), sv, rank, cond,
                        crank, ccond)


def workload_about_origin(F, T, o):
    """``W = [F; T + o x F]`` for ``F, T (N, ..., 3)`` and ``o (N, 3)``: ``(N, ..., 6)``
    (the statics kernels' own arithmetic, ``_kernels._extra.workload_batch``: the same bits
    as a workload given to the analysis)."""
    from ._kernels import kernels
    from ._launch import kernel_input
    F, T = np.broadcast_arrays(np.asarray(F, float), np.asarray(T, float))
    N, K = F.shape[0], int(np.prod(F.shape[1:-1], dtype=np.int64))
    W = np.empty((N, K, 6))
    # (read-only inputs whatever the caller's: one compiled version of the kernel)
    kernels().workload_batch(kernel_input(F.reshape(N, K, 3)), kernel_input(T.reshape(N, K, 3)),
                             kernel_input(np.reshape(o, (N, 3))), W)
    return W.reshape(F.shape[:-1] + (6,))


def statics_values(J, cond: Conditioning, torque, W, o, compliance=None, workers=None):
    """``(F_r, equilibrium, amplification)`` of ``J (N, m, 6)`` under ``W (N, [K,] 6)``
    about O (the kernel: ``J^T F_r = -W``, the least-norm or compliance-weighted solution of
    an indeterminate system); shapes ``(N, [K,] m)``, ``(N, [K])``."""
    from ._launch import statics_of
    N = J.shape[0]
    extra = W.shape[1:-1]
    Wf = np.asarray(W, float).reshape(N, -1, 6)
    comp = None if compliance is None else np.broadcast_to(np.asarray(compliance, float),
                                                           (N, J.shape[1]))
    v, eq, amp = statics_of(J, cond.centre, cond.length, cond.singular_values, torque, Wf, o,
                            compliance=comp, workers=workers)
    return (v.reshape((N,) + extra + (J.shape[1],)), eq.reshape((N,) + extra),
            amp.reshape((N,) + extra))


def amplification_of(values, torque, W, o, L):
    """The force amplification ``(N, [K])`` of efforts ``values (N, [K,] m)`` under ``W``."""
    from ._kernels import kernels
    from ._launch import kernel_input
    N = values.shape[0]
    extra = values.shape[1:-1]
    v = kernel_input(np.reshape(values, (N, -1, values.shape[-1])))
    Wf = kernel_input(np.reshape(np.broadcast_to(W, (N,) + W.shape[1:]), (N, -1, 6)))
    out = np.empty(v.shape[:2])
    # (the inputs read-only whatever the caller's: one compiled version of the kernel)
    kernels().amplification_batch(v, kernel_input(torque, np.int64), Wf, kernel_input(o),
                                  kernel_input(L), out)
    return out.reshape((N,) + extra)


def leg_wrenches_of(J, info, n_actuated, values, A, a, total=True):
    """Each leg's constraint wrench and (``total``) total wrench about O ``(N, [K,] n, 6)``
    and ``T_r (N, [K,] n)`` from the values ``(N, [K,] m)`` (the kernel)."""
    from ._launch import leg_wrenches
    N, m = J.shape[0], J.shape[1]
    extra = values.shape[1:-1]
    v = np.asarray(values, float).reshape(N, -1, m)
    rl = np.array([r.leg for r in info], np.int64)
    A = np.asarray(A, float)
    a = np.broadcast_to(np.asarray(a, float), (N,) + A.shape)
    con, leg, tr = leg_wrenches(J, v, rl, n_actuated, A, a, total=total)
    n = len(A)
    return (con.reshape((N,) + extra + (n, 6)),
            leg.reshape((N,) + extra + (n, 6)) if total else None,
            tr.reshape((N,) + extra + (n,)))
