"""From solved closures to the unified Jacobian, its conditioning and the statics (private).

Every function takes and returns arrays with the poses on the leading axis.
"""

from __future__ import annotations

import weakref
from dataclasses import dataclass

import numpy as np

from ._conditioning import (RANK_RTOL, least_norm, normalise_rows,
                            normalise_wrench, singular_values)
from ._geometry import LegGeometry, geometry_of
from ._rows import RowTemplate
from ..screws import cross

__all__ = ["RowInfo", "Rows", "templates_of", "model_rows", "legs_rows", "assemble_rows",
           "Conditioning", "condition", "default_compliance", "statics_values",
           "derived_statics", "constraint_wrenches_of", "t_r_of", "equilibrium_residual", "workload_about_origin", "COND_THRESHOLD"]

#: Largest normalised condition number of ``J`` still treated as regular.
COND_THRESHOLD = 1.0 / RANK_RTOL


@dataclass(frozen=True)
class RowInfo:
    """What a row of the unified Jacobian is (the same at every pose).

    ``leg`` (0-based), ``leg_name``, ``kind`` (``actuation``, ``force``, ``couple``,
    ``screw``), ``member`` (the geometric kind of the wrench), ``point_name`` (the
    named point of the leg on the force line, or None), ``joint`` (the actuated joint
    of an actuation row), ``label`` (``F_a1``, ``F_c2``, ``T_c3``; rotary: ``T_a1``).
    """

    leg: int
    leg_name: str
    kind: str
    member: str
    point_name: str | None
    joint: str | None
    label: str


@dataclass(frozen=True, eq=False)
class Rows:
    """The rows of ``J`` at N poses.

    Attributes
    ----------
    J : ndarray (N, m, 6)
        Actuation rows (one per leg, in leg order) then constraint rows, ``[f; m]`` about O.
    info : tuple of RowInfo
    n_actuated : int
    scale : ndarray (N, m)
        Row = scale x unit member (1 for constraint rows).
    points : ndarray (N, m, 3)
        A point of each row's line (the named point), NaN for couples.
    centre, length : ndarray (N, 3), (N,)
        The normalisation: centroid and RMS spread of every leg's points (``A``, ``a``, the
        joint points) and ``o`` (the characteristic length).
    structure_ok : ndarray (N, n) of bool
        False where a leg's constraint structure is not the one of home (the generic
        rule was used there).
    ok : ndarray (N,) of bool
        False where a row could not be formed (a dependent actuator, a degenerate basis).
    """

    J: np.ndarray
    info: tuple
    n_actuated: int
    scale: np.ndarray
    points: np.ndarray
    centre: np.ndarray
    length: np.ndarray
    structure_ok: np.ndarray
    ok: np.ndarray


_TEMPLATES: "weakref.WeakKeyDictionary" = weakref.WeakKeyDictionary()


def templates_of(model) -> tuple:
    """One :class:`RowTemplate` per leg of ``model``, built at home (cached)."""
    t = _TEMPLATES.get(model)
    if t is None:
        R0, p0 = model.frame
        Rh, oh = model.platform_home
        refs = tuple(model.constraint_references) or ((),) * len(model.home_legs)
        passive = set(getattr(model, "passive", ()))
        t = tuple(RowTemplate(lg, lg.analyze(), R0, p0, Rh, oh, refs[i], i in passive)
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
    kc = 0
    for i, t in enumerate(templates):
        a = t.actuation
        if not t.passive:          # a passive leg has no actuation row
            joint, member = t.names[t.actuated], a.member if a.kind != "none" else "none"
            torque = member == "couple" or (joint is not None and joint[0] in "RH")  # rotary
            info_a.append(RowInfo(i, t.name, "actuation", member, a.names[0] if a.names
                                  else None, joint, f"{'T' if torque else 'F'}_a{i + 1}"))
        for kind, pname in t.member_kinds:
            kc += 1
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


_LEG_CONSTANTS: "weakref.WeakKeyDictionary" = weakref.WeakKeyDictionary()


def _leg_constants(model):
    """Per leg: joints, rotation and translation per unit joint value, ``A``, ``a`` in the
    platform frame; and the base frame (built once per model)."""
    c = _LEG_CONSTANTS.get(model)
    if c is None:
        R0, p0 = model.frame
        legs = []
        for i, t in enumerate(model.home_legs):
            rot = np.array([0.0 if j.kind == "P" else 1.0 for j in t.joints])
            tra = np.array([1.0 if j.kind == "P" else (j.pitch if j.kind == "H" else 0.0)
                            for j in t.joints])
            legs.append((len(t.joints), rot, tra, np.asarray(model.world_base_points[i], float),
                         np.asarray(model.platform_points[i], float)))
        c = (tuple(legs), np.asarray(R0, float), np.asarray(p0, float))
        _LEG_CONSTANTS[model] = c
    return c


def leg_geometry(model, frames, i: int) -> LegGeometry:
    """Leg ``i`` of the model at the poses of ``frames`` (pose axis last)."""
    legs, R0, p0 = _leg_constants(model)
    m, rot, tra, A, ap = legs[i]
    a = np.einsum("ij...,j->i...", frames.R_p, ap) + frames.o
    return LegGeometry(frames.axes[:m, :, i], frames.points[:m, :, i], rot, tra, A, a, R0, p0,
                       frames.R_p, frames.o)


def model_rows(model, frames, templates=None) -> Rows:
    """The rows of ``J`` at every pose of ``frames`` (:class:`~._chains.Frames`)."""
    templates = templates_of(model) if templates is None else templates
    geos = [leg_geometry(model, frames, i) for i in range(len(templates))]
    return assemble_rows(templates, geos, frames.o)


def legs_rows(legs, o, analyses, passive=()) -> Rows:
    """The rows of ``J`` of placed legs at one pose (the base frame is the world);
    ``passive``: the indices of the legs without an actuation row."""
    o = np.asarray(o, float)
    templates, geos = [], []
    for i, (lg, an) in enumerate(zip(legs, analyses)):
        t = RowTemplate(lg, an, np.eye(3), np.zeros(3), np.eye(3), o, passive=i in passive)
        templates.append(t)
        geos.append(geometry_of(lg, np.eye(3), np.zeros(3), np.eye(3), o))
    return assemble_rows(templates, geos, o[:, None])


def assemble_rows(templates, geos, o) -> Rows:
    """Stack every leg's rows at the poses of ``geos``: the actuation rows of the actuated
    legs first (leg order; a passive leg has none), then every leg's constraint rows."""
    N = o.shape[-1]
    acts, scales_a, cons, pts_a, pts_c, struct, ok = [], [], [], [], [], [], np.ones(N, bool)
    leg_pts = []
    for t, geo in zip(templates, geos):
        act, member, scale, c, good, sok = t.rows(geo)
        if not t.passive:
            acts.append(act)
            scales_a.append(scale)
            pts_a.append(t.actuation_point(geo))
        cons.append(c)
        struct.append(sok)
        ok &= good
        pts_c.append(t.member_points(geo, c))
        leg_pts += [np.broadcast_to(geo.A[:, None], (3, N)), geo.a] + list(geo.points)
    leg_pts.append(o)
    c, L = _spread(leg_pts)
    J = np.concatenate([np.stack(acts)] + [c for c in cons if len(c)], axis=0)   # (m, 6, N)
    P = np.concatenate([np.stack(pts_a)] + [p for p in pts_c if len(p)], axis=0)
    n = len(acts)                                         # the actuation rows
    scale = np.concatenate([np.stack(scales_a), np.ones((J.shape[0] - n, N))], axis=0)
    return Rows(np.ascontiguousarray(J.transpose(2, 0, 1)), _labels(templates), n,
                scale.T.copy(), np.ascontiguousarray(P.transpose(2, 0, 1)), c, L,
                np.stack(struct, axis=1), ok)


def _spread(points):
    """Centroid ``(N, 3)`` and RMS distance ``(N,)`` of a list of point arrays ``(3, N)``
    (:func:`~._conditioning.normalisation`, without stacking them)."""
    k = len(points)
    Ps = np.stack(np.broadcast_arrays(*points))                        # (k, 3, N)
    s = Ps.sum(axis=0) / k
    q = (Ps * Ps).sum(axis=1).sum(axis=0) / k
    L2 = np.maximum(q - (s * s).sum(axis=0), 0.0)
    L = np.sqrt(L2)
    big = np.abs(Ps).max(axis=(0, 1))
    L = np.where(L <= 1e-12 * big, big, L)
    return np.ascontiguousarray(s.T), np.where(L > 0, L, 1.0)


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
        """``(Jn, d)`` of :func:`~._conditioning.normalise_rows` for these poses."""
        return normalise_rows(J, self.centre, self.length)

    def take(self, sl) -> "Conditioning":
        return Conditioning(*(getattr(self, f)[sl] for f in self.__dataclass_fields__))


def condition(J, n_actuated, c, L):
    """Conditioning of ``J (N, m, 6)`` with the normalisation ``c (N, 3)``, ``L (N,)``;
    returns ``(Conditioning, Jn, d)``."""
    N, m, _ = J.shape
    Jn, d = normalise_rows(J, c, L)
    s = singular_values(Jn)
    top = np.maximum(s[:, 0], 1e-300) if s.shape[1] else np.ones(N)
    rank = np.sum(s > RANK_RTOL * top[:, None], axis=1)
    cond = np.full(N, np.inf)
    if s.shape[1] >= 6:
        pos = s[:, 5] > 0
        cond[pos] = s[pos, 0] / s[pos, 5]
    k = max(0, 6 - n_actuated)
    Jc = Jn[:, n_actuated:]
    if Jc.shape[1]:
        sc = singular_values(Jc)
        c_rank = np.sum(sc > RANK_RTOL * np.maximum(sc[:, :1], 1e-300), axis=1)
    else:
        sc, c_rank = np.zeros((N, 0)), np.zeros(N, int)
    if k == 0:
        c_cond = np.ones(N)
    elif sc.shape[1] >= k:
        c_cond = np.full(N, np.inf)
        pos = sc[:, k - 1] > 0
        c_cond[pos] = sc[pos, 0] / sc[pos, k - 1]
    else:
        c_cond = np.full(N, np.inf)
    return Conditioning(c, L, s, rank, cond, c_rank, c_cond), Jn, d


def workload_about_origin(F, T, o):
    """``W = [F; T + o x F]`` for ``F, T (N, ..., 3)`` and ``o (N, 3)``: ``(N, ..., 6)``."""
    F, T = np.broadcast_arrays(np.asarray(F, float), np.asarray(T, float))
    osh = o.reshape((o.shape[0],) + (1,) * (F.ndim - 2) + (3,))
    return np.concatenate([F, T + cross(osh, F)], axis=-1)


def default_compliance(info, length):
    """The compliances ``(N, m)`` of the least-norm solution: 1 for a force (or a linear
    actuator), ``1 / L^2`` for a couple (or a rotary actuator), ``L`` the characteristic
    length of each pose: ``sum F^2 + sum (C / L)^2`` is minimal (unit-free, frame-free)."""
    torque = np.array([r.member == "couple" or (r.kind == "actuation" and r.joint is not None
                                                and r.joint[0] in "RH") for r in info])
    return np.where(torque[None, :], 1.0 / length[:, None] ** 2, 1.0)


def statics_values(Jn, d, s, cond: Conditioning, W, compliance=None):
    """``F_r (N, ..., m)`` with ``J^T F_r = -W`` for ``W (N, ..., 6)``.

    Square ``J``: the unique solution.  More rows than 6 (statically indeterminate): the
    one that minimises ``sum_k c_k F_k^2`` with the compliances ``c (N, m)`` (``1 /
    stiffness``; default :func:`default_compliance`); the row scaling below turns it into
    a least-norm problem.
    """
    N, m, _ = Jn.shape
    extra = W.shape[1:-1]
    Wf = W.reshape(N, -1, 6)
    K = Wf.shape[1]
    Wn = normalise_wrench(Wf, cond.centre, cond.length)
    if m > 6:
        if compliance is None:
            raise ValueError("the compliances of an indeterminate system are needed")
        g = d / np.sqrt(np.broadcast_to(compliance, (N, m)))     # u = sqrt(c) F, y = d F
        Jw = Jn * g[:, :, None]
    else:
        g, Jw = None, Jn
    if K > 1:
        Jw, s = np.repeat(Jw, K, axis=0), np.repeat(s, K, axis=0)
    y = least_norm(Jw, Wn.reshape(N * K, 6), s).reshape(N, K, m)
    F = y * (g / d)[:, None, :] if g is not None else y / d[:, None, :]
    return F.reshape((N,) + extra + (m,))


def derived_statics(J, info, n_actuated, values, W, A, a, centre, length):
    """Row wrenches, vectors, leg wrenches, constraint wrenches, ``T_r`` and the relative
    equilibrium residual from the values (all with the leading axes of ``values``)."""
    lead = values.shape[:-1]
    N, m = J.shape[0], J.shape[1]
    Jb = J.reshape((N,) + (1,) * (len(lead) - 1) + (m, 6))
    row_w = values[..., None] * Jb
    couple = np.array([r.member == "couple" for r in info])
    vectors = np.where(couple[:, None], row_w[..., 3:], row_w[..., :3])
    Pm, Pc = _leg_sums(info, n_actuated, len(A))
    leg_w = np.einsum("lm,...mj->...lj", Pm, row_w)
    con_w = np.einsum("lm,...mj->...lj", Pc, row_w)
    T_r = t_r_of(con_w, A, a)
    resid = equilibrium_residual(J, values, W, centre, length)
    return row_w, vectors, leg_w, con_w, T_r, resid


def _leg_sums(info, n_actuated, n):
    """``(n, m)`` 0/1 matrices summing the rows of each leg: all rows, and its constraint
    rows only."""
    m = len(info)
    legs = np.array([r.leg for r in info])
    Pm = np.zeros((n, m))
    Pm[legs, np.arange(m)] = 1.0
    Pc = Pm.copy()
    Pc[:, :n_actuated] = 0.0
    return Pm, Pc


def constraint_wrenches_of(J, info, n_actuated, values, n):
    """Each leg's constraint wrench about ``O``, ``(..., n, 6)``: the sum of its constraint
    rows' ``F_r J_r`` (without forming the row wrenches)."""
    lead = values.shape[:-1]
    N, m = J.shape[0], J.shape[1]
    Jb = J.reshape((N,) + (1,) * (len(lead) - 1) + (m, 6))
    Pc = _leg_sums(info, n_actuated, n)[1]
    return np.einsum("lm,...m,...mj->...lj", Pc, values, Jb)


def t_r_of(con_w, A, a):
    """``T_r (..., n)``: the moment of each leg's constraint wrench ``con_w (N, ..., n, 6)``
    about its base point ``A (n, 3)`` along ``delta = (a - A) / |a - A|``, ``a (N, n, 3)``."""
    N = con_w.shape[0]
    extra = con_w.shape[1:-2]
    ab = a.reshape((N,) + (1,) * len(extra) + a.shape[1:])
    delta = ab - A
    delta = delta / np.linalg.norm(delta, axis=-1, keepdims=True)
    moment_A = con_w[..., 3:] - cross(A, con_w[..., :3])
    return np.sum(moment_A * delta, axis=-1)


def equilibrium_residual(J, values, W, centre, length):
    """``|sum_r F_r J_r + W|`` over the largest of ``|W|`` and of the row wrenches
    ``|F_r J_r|``, all length-normalised about the centroid (unit-free, frame-free)."""
    lead = values.shape[:-1]
    N, m = J.shape[0], J.shape[1]
    Wf = W.reshape(N, -1, 6)
    K = Wf.shape[1]
    v = values.reshape(N, K, m)
    total = normalise_wrench(np.einsum("nkm,nmj->nkj", v, J) + Wf, centre, length)
    Jn = normalise_wrench(J, centre, length)
    rows = np.abs(v) * np.linalg.norm(Jn, axis=-1)[:, None, :]       # |F_r J_r| normalised
    scale = np.maximum(np.linalg.norm(normalise_wrench(Wf, centre, length), axis=-1),
                       np.max(rows, axis=-1, initial=0.0))
    return (np.linalg.norm(total, axis=-1) / np.where(scale > 0, scale, 1.0)).reshape(lead)
