"""What the rows of the unified Jacobian are, and the statics of given Jacobians by the
kernels (private).

Every function takes and returns arrays with the poses on the leading axis.
"""

from __future__ import annotations

import weakref
from dataclasses import dataclass

import numpy as np

from ..screws import cross
from ._kernels._layout import RANK_RTOL

__all__ = ["RowInfo", "templates_of", "Conditioning", "COND_THRESHOLD", "RANK_RTOL",
           "statics_values", "leg_wrenches_of", "workload_about_origin", "normalise_rows",
           "amplification_of"]

#: Largest normalised condition number of ``J`` still treated as regular.
COND_THRESHOLD = 1.0 / RANK_RTOL


@dataclass(frozen=True)
class RowInfo:
    """What a row of the unified Jacobian is (the same at every pose).

    ``leg`` (0-based), ``leg_name``, ``kind`` (``actuation``, ``force``, ``couple``,
    ``screw``), ``member`` (the geometric kind of the wrench), ``point_name`` (the
    named point of the leg on the force line, or None), ``joint`` (the actuated joint
    of an actuation row), ``label`` (``F_a1``, ``F_c2``, ``T_c3``...).
    """

    leg: int
    leg_name: str
    kind: str
    member: str
    point_name: str | None
    joint: str | None
    label: str


_TEMPLATES: "weakref.WeakKeyDictionary" = weakref.WeakKeyDictionary()


def templates_of(model) -> tuple:
    """One :class:`~screwkit.engine._templates.RowTemplate` per leg of ``model``, decided
    at home (cached)."""
    t = _TEMPLATES.get(model)
    if t is None:
        from ._templates import RowTemplate
        R0, p0 = model.frame
        Rh, oh = model.platform_home
        refs = tuple(model.constraint_references) or ((),) * len(model.home_legs)
        passive = set(getattr(model, "passive", ()))
        t = tuple(RowTemplate(lg, lg.analyze(), R0, p0, Rh, oh, refs[i],
                              active=i not in passive)
                  for i, lg in enumerate(model.home_legs))
        _TEMPLATES[model] = t
    return t


_LABELS: dict = {}


def _labels(templates):
    """The :class:`RowInfo` of every row (memoised per templates tuple: the templates of
    a model are built once and kept, so the labels are too)."""
    key = id(templates)
    hit = _LABELS.get(key)
    if hit is not None and hit[0] is templates:
        return hit[1]
    out = _make_labels(templates)
    if len(_LABELS) > 256:
        _LABELS.clear()
    _LABELS[key] = (templates, out)
    return out


def _make_labels(templates):
    info_a, info_c = [], []
    for i, t in enumerate(templates):
        a = t.actuation
        if t.active:
            info_a.append(RowInfo(i, t.name, "actuation",
                                  a.member if a.kind != "none" else "none",
                                  a.names[0] if a.names else None, t.names[t.actuated],
                                  f"F_a{i + 1}"))
        for kind, pname in t.member_kinds:
            sym = {"force": "F_c", "couple": "T_c"}.get(kind, "W_c")
            info_c.append(RowInfo(i, t.name, kind, kind, pname, None, f"{sym}{i + 1}"))
    # number repeated labels of one leg: F_c1.1, F_c1.2
    counts = {}
    for r in info_c:
        counts[r.label] = counts.get(r.label, 0) + 1
    seen = {}
    final = list(info_a)
    for r in info_c:
        if counts[r.label] > 1:
            seen[r.label] = seen.get(r.label, 0) + 1
            r = RowInfo(r.leg, r.leg_name, r.kind, r.member, r.point_name, r.joint,
                        f"{r.label}.{seen[r.label]}")
        final.append(r)
    return tuple(final)


def torque_rows(info) -> np.ndarray:
    """1 for a row whose effort is a torque (a couple, a rotary actuator), else 0."""
    return np.array([int(r.member == "couple" or (r.kind == "actuation" and r.joint is not None
                                                 and r.joint[0] in "RH")) for r in info],
                    np.int64)


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
    J = np.ascontiguousarray(J, float)
    Jn, d = np.empty_like(J), np.empty(J.shape[:2])
    kernels().normalise_batch(J, np.ascontiguousarray(centre, float),
                              np.ascontiguousarray(length, float), Jn, d)
    return Jn, d


def workload_about_origin(F, T, o):
    """``W = [F; T + o x F]`` for ``F, T (N, ..., 3)`` and ``o (N, 3)``: ``(N, ..., 6)``."""
    F, T = np.broadcast_arrays(np.asarray(F, float), np.asarray(T, float))
    osh = o.reshape((o.shape[0],) + (1,) * (F.ndim - 2) + (3,))
    return np.concatenate([F, T + cross(osh, F)], axis=-1)


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
    N = values.shape[0]
    extra = values.shape[1:-1]
    v = np.ascontiguousarray(values, float).reshape(N, -1, values.shape[-1])
    Wf = np.ascontiguousarray(np.broadcast_to(W, (N,) + W.shape[1:]), float).reshape(N, -1, 6)
    out = np.empty(v.shape[:2])
    kernels().amplification_batch(v, np.ascontiguousarray(torque, np.int64), Wf,
                                  np.ascontiguousarray(o, float),
                                  np.ascontiguousarray(L, float), out)
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
