"""The arrays of a flattened model: joints, leg layout, row templates, pose parametrisation
(private; :mod:`screwkit.engine._flat` builds them for a model or for placed legs).

:func:`build` writes the model tuple ``M`` of :mod:`screwkit.engine._kernels._layout`: the
joint kinds, axes, points, pitches and Pa links (:func:`joint_arrays`), the leg layout and
passive legs, the base and platform frames, and each leg's row template encoded as tables of
named points, reference directions (:func:`encode_direction`) and member groups.
:func:`probe_model` is the one-leg model on which a template's home decisions are made.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field

import numpy as np

from ..pm import LENGTH_PARAMS, PARAMS
from ._kernels import _layout as lay
from ._line_table import line_table

__all__ = ["FlatModel", "build", "joint_arrays", "platform_array", "encode_direction",
           "probe_model", "pack", "Packed"]

_KIND = {"R": lay.K_R, "P": lay.K_P, "H": lay.K_H}
_AXES = {"x": 0, "y": 1, "z": 2}


@dataclass(frozen=True, eq=False)
class FlatModel:
    """The arrays of a model for the kernels.

    Attributes
    ----------
    M : tuple of ndarray
        The model tuple (:mod:`screwkit.engine._kernels._layout`).
    n, m, mr, n_act : int
        Legs, slots (the longest leg), rows of ``J``, actuation rows.
    unknown, fixed : tuple of str
        The dependent and the given pose parameters.
    Z : tuple of ndarray
        The pose parametrisation without the home predictor (``C`` with no rows).
    torque : ndarray (mr,) of int
        1 for a row whose effort is a torque (a couple, a rotary actuator).
    row_leg : ndarray (mr,) of int
    """

    M: tuple
    n: int
    m: int
    mr: int
    n_act: int
    unknown: tuple
    fixed: tuple
    Z: tuple
    torque: np.ndarray
    row_leg: np.ndarray
    packed: dict = field(default_factory=dict, repr=False)

    @property
    def nu(self) -> int:
        return len(self.unknown)

    @property
    def nx(self) -> int:
        return self.nu + self.n * self.m

    def pack(self, Z) -> tuple:
        """``(M packed, Z packed)`` for the kernels' entries (each packed once)."""
        key = ("Z", id(Z))
        hit = self.packed.get(key)
        if hit is None or hit[0] is not Z:
            if "M" not in self.packed:
                self.packed["M"] = Packed.of(self.M)
            hit = self.packed[key] = (Z, Packed.of(Z))
        return self.packed["M"], hit[1]

    def with_predictor(self, C, home, span, degree) -> tuple:
        """``Z`` with the home predictor's coefficients."""
        return self.Z[:7] + (np.ascontiguousarray(C, float), np.asarray(home, float),
                             np.asarray(span, float), np.array([int(degree)]))


def encode_direction(ref, names, table: list) -> int:
    """The index in ``table`` (rows ``(type, a1, a2, negate)``, appended as needed) of the
    reference direction ``ref`` (:data:`screwkit.engine._templates.DEFAULT_REFERENCES`).
    Raises ValueError for an unknown reference."""
    if isinstance(ref, dict):
        (k, v), = ref.items()
        if k == "perpendicular":
            row = (lay.DIR_PERPENDICULAR, encode_direction(v[0], names, table),
                   encode_direction(v[1], names, table), 0)
        elif k in ("along", "parallel"):
            row = (lay.DIR_ALONG, encode_direction(v, names, table), 0, 0)
        else:
            raise ValueError(ref)
    else:
        neg = ref.startswith("-")
        r = ref[1:] if neg else ref
        if r == "leg":
            row = (lay.DIR_LEG, 0, 0, neg)
        elif r.startswith("base.") and r[5:] in ("X", "Y", "Z"):
            row = (lay.DIR_BASE, "XYZ".index(r[5]), 0, neg)
        elif r.startswith("platform.") and r[9:] in ("x", "y", "z"):
            row = (lay.DIR_PLATFORM, "xyz".index(r[9]), 0, neg)
        elif r in ("base.OA", "base.AO"):
            row = (lay.DIR_BASE_OA, 0, 0, neg != (r == "base.AO"))
        elif r in ("platform.oa", "platform.ao"):
            row = (lay.DIR_PLATFORM_OA, 0, 0, neg != (r == "platform.ao"))
        elif r == "base.tangent":
            row = (lay.DIR_BASE_TANGENT, 0, 0, neg)
        elif r == "platform.tangent":
            row = (lay.DIR_PLATFORM_TANGENT, 0, 0, neg)
        elif r in names:
            row = (lay.DIR_JOINT, names.index(r), 0, neg)
        else:
            raise ValueError(f"unknown reference direction {ref!r}")
    row = tuple(int(x) for x in row)
    if row not in table:
        table.append(row)
    return table.index(row)


def _point_code(ref) -> tuple:
    if ref[0] == "A":
        return (lay.PT_A, 0, 0)
    if ref[0] == "a":
        return (lay.PT_a, 0, 0)
    if ref[0] == "joint":
        return (lay.PT_JOINT, int(ref[1]), 0)
    return (lay.PT_MEET, int(ref[1]), int(ref[2]))


def _pad(rows_per_leg, width, fill=-1):
    k = max([len(r) for r in rows_per_leg] + [1])
    out = np.full((len(rows_per_leg), k, width), fill, np.int64)
    for i, rows in enumerate(rows_per_leg):
        for j, r in enumerate(rows):
            out[i, j, :len(r)] = r
    return out


def _templates_tables(templates, active):
    """The row templates as integer tables: PTS, DIRS, GRP, TPL, GREF, ROWS-less parts."""
    pts, dirs, grps, gref = [], [], [], []
    tpl = np.zeros((len(active), 8), np.int64)
    crow = sum(active)
    if templates is None:                 # kinematics only: no rows
        return (_pad([[]] * len(active), 3), _pad([[]] * len(active), 4),
                _pad([[]] * len(active), 6), tpl, _pad([[]] * len(active), 2), [])
    act_pts, con_pts = [], []
    for i, t in enumerate(templates):
        P, Dt, G, Gr = [], [], [], []

        def point(ref):
            code = _point_code(ref)
            if code not in P:
                P.append(code)
            return P.index(code)
        for g in t.groups:
            p = point(g.point_ref) if g.kind == "force" else 0
            refs = [encode_direction(r, t.names, Dt) for r in g.refs] + [0, 0, 0]
            G.append((lay.G_FORCE if g.kind == "force" else lay.G_COUPLE, p, g.dim, *refs[:3]))
        for kind, r in t.generic_refs:
            Gr.append((0 if kind == "force" else 1, encode_direction(r, t.names, Dt)))
        a = t.actuation
        akind = {"none": lay.A_NONE, "passive": lay.A_NONE, "line": lay.A_LINE,
                 "least-norm": lay.A_LEAST_NORM}[a.kind]
        p1 = point(a.points[0]) if a.kind == "line" else 0
        p2 = point(a.points[1]) if a.kind == "line" else 0
        tpl[i] = (int(t.generic), t.k, len(G), akind, p1, p2, crow, len(Gr))
        # the point of each row's line: a named point (>= 0), the point nearest the leg's
        # centroid (-1) or none (-2)
        if active[i]:
            act_pts.append(p1 if a.kind == "line" else -2)
        gpt = {(g.kind, g.point): G[q][1] for q, g in enumerate(t.groups)}
        for kind, pname in t.member_kinds:
            con_pts.append(-2 if kind == "couple" else
                           gpt[(kind, pname)] if pname and not t.generic else -1)
        crow += t.k
        pts.append(P)
        dirs.append(Dt)
        grps.append(G)
        gref.append(Gr)
    return _pad(pts, 3), _pad(dirs, 4), _pad(grps, 6), tpl, _pad(gref, 2), act_pts + con_pts


def joint_arrays(legs, L):
    """The joint arrays of the legs (``home_legs`` or placed legs)."""
    n = len(legs)
    sizes = [len(lg.joints) for lg in legs]
    m = max(sizes)
    D = np.zeros((n, m, 3))
    D[:, :, 2] = 1.0
    P = np.zeros((n, m, 3))
    rot, tra, qs = np.zeros((n, m)), np.zeros((n, m)), np.ones((n, m))
    bar, hinge, blen = np.zeros((n, m, 3)), np.zeros((n, m, 3)), np.zeros((n, m))
    kind = np.zeros((n, m), np.int64)
    for i, lg in enumerate(legs):
        for j, jt in enumerate(lg.joints):
            D[i, j], P[i, j] = jt.direction, jt.point
            if jt.kind == "P":
                tra[i, j], qs[i, j] = 1.0, L
                kind[i, j] = lay.K_P
                if jt.bar is not None:
                    b = np.asarray(jt.bar, float)
                    kind[i, j] = lay.K_PA
                    bar[i, j], blen[i, j] = b, np.linalg.norm(b)
                    hinge[i, j] = np.cross(b, jt.direction) / blen[i, j]
            else:
                rot[i, j] = 1.0
                tra[i, j] = jt.pitch if jt.kind == "H" else 0.0
                kind[i, j] = _KIND[jt.kind]
    trn = tra / np.where(qs == 1.0, L, 1.0)
    return sizes, m, (D, P, rot, tra, qs, trn, bar, hinge, blen, kind)


def _ball_slot(leg) -> int:
    """The slot of the leg's first S joint's first part (its three R parts follow in turn,
    as the leg string's expansion places them; ``LEG``'s ``L_BALL``), -1 without one."""
    specs = [j.spec for j in leg.joints]
    for j, sp in enumerate(specs):
        if getattr(sp, "origin", "") == "S" and sp.part == 0:
            if [(getattr(s, "origin", ""), getattr(s, "part", -1)) for s in specs[j:j + 3]] != \
                    [("S", 0), ("S", 1), ("S", 2)]:
                raise ValueError(f"{leg.name}: the parts of its S joint are not in turn")
            return j
    return -1


def platform_array(frame, platform_home, centre, L) -> np.ndarray:
    """``PLAT``: the base frame, the platform at home, the centroid and the length."""
    R0, p0 = (np.asarray(x, float) for x in frame)
    Rh, ph = (np.asarray(x, float) for x in platform_home)
    return np.concatenate([R0.ravel(), p0, Rh.ravel(), ph, np.asarray(centre, float), [L]])


def _order_code(order: str) -> np.ndarray:
    ax = [_AXES[c] for c in order.lower()]
    return np.array(ax + [int(order.isupper()), int(ax[0] == ax[2])], np.int64)


def build(legs, templates, *, L, centre, frame, platform_home, base_points, platform_points,
          order, independent, home_pose, info, passive=()) -> FlatModel:
    """The :class:`FlatModel` of legs placed at home (see :func:`flatten`)."""
    n = len(legs)
    active = [i not in passive for i in range(n)]
    sizes, m, geo = joint_arrays(legs, L)
    leg = np.zeros((n, 5), np.int64)
    k = 0
    for i, lg in enumerate(legs):
        leg[i] = (sizes[i], lg.actuated_index, int(active[i]), k if active[i] else -1,
                  _ball_slot(lg))
        k += active[i]
    plat = platform_array(frame, platform_home, centre, L)
    pts, dirs, grp, tpl, gref, row_pts = _templates_tables(templates, active)
    rows = np.zeros((len(info), 4), np.int64)
    for r, ri in enumerate(info):
        kind = {"actuation": lay.R_ACTUATION, "force": lay.R_FORCE, "couple": lay.R_COUPLE}.get(
            ri.kind, lay.R_SCREW)
        rows[r] = (ri.leg, kind, row_pts[r], int(ri.torque))
    unknown = tuple(p for p in PARAMS if p not in independent)
    rev = line_table(legs, passive, len(unknown), m, geo[lay.QS], L)
    M = tuple(np.ascontiguousarray(a) for a in geo) + (
        leg, plat, _order_code(order), np.array(base_points, float, order="C"),
        np.array(platform_points, float, order="C"), pts, dirs, grp, tpl, gref, rows, rev)
    fixed = tuple(independent)
    unk = np.array([PARAMS.index(p) for p in unknown], np.int64)
    xs = np.array([L if p in LENGTH_PARAMS else 1.0 for p in unknown])
    keep = [k for k, p in enumerate(unknown) if p not in ("alpha", "gamma")]
    pair = tuple(p for p in unknown if p in ("alpha", "gamma"))
    fix = np.array([PARAMS.index(p) for p in fixed], np.int64)
    fix2 = np.array([PARAMS.index(p) for p in fixed + pair], np.int64)
    p6home = np.array([float(home_pose[p]) for p in PARAMS])
    Z = (unk, xs, unk[keep].copy(), xs[keep].copy(), fix, fix2, p6home, np.zeros((0, 1)),
         np.zeros(0), np.zeros(0), np.array([0]))
    return FlatModel(M, n, m, len(info), int(sum(active)), unknown, fixed, Z,
                     rows[:, 3].copy(), rows[:, 0].copy())


def probe_model(leg, base_rotation, O, platform_rotation, o, point_refs, candidates):
    """A one-leg model at its reference geometry for the home decisions of a row template
    (:mod:`screwkit.engine._kernels._probe`): ``((M, fp), candidates, indices, points)``:
    the candidate reference directions that exist for this leg and their rows in ``DIRS``,
    and the named points in ``PTS`` order."""
    R0 = np.asarray(base_rotation, float)
    Rh, oh = np.asarray(platform_rotation, float), np.asarray(o, float)
    sizes, m, geo = joint_arrays([leg], 1.0)
    names = tuple(j.name for j in leg.joints)
    table, ok, idx = [], [], []
    for r in candidates:
        try:
            k = encode_direction(r, names, table)
        except ValueError:
            continue
        ok.append(r)
        idx.append(k)
    points = []
    for ref in point_refs:
        if ref not in points:
            points.append(ref)
    pts = _pad([[_point_code(p) for p in points]], 3)
    leg_row = np.array([[sizes[0], leg.actuated_index, 1, 0, _ball_slot(leg)]], np.int64)
    plat = np.concatenate([R0.ravel(), np.asarray(O, float), Rh.ravel(), oh, oh, [1.0]])
    ap = Rh.T @ (np.asarray(leg.a, float) - oh)
    empty = _pad([[]], 6)
    M = tuple(np.ascontiguousarray(a) for a in geo) + (
        leg_row, plat, _order_code("XYZ"), np.array([leg.A], float), ap[None], pts,
        _pad([table], 4), empty, np.zeros((1, 8), np.int64), np.zeros((1, 6, 2), np.int64),
        np.zeros((0, 4), np.int64), np.zeros((0, 4)))
    fp = np.zeros(27)
    fp[6:15], fp[15:18] = Rh.ravel(), oh
    return (M, fp), ok, np.array(idx, np.int64), points


class Packed:
    """Arrays packed for a kernel (:mod:`screwkit.engine._kernels._pack`): ``f`` (float64),
    ``i`` (int64) and the descriptor ``d (k, 5)``; :meth:`views` gives them back (views of
    the two buffers, each array contiguous)."""

    __slots__ = ("f", "i", "d", "shapes", "kinds", "offsets")
    _LAYOUTS: dict = {}

    def __init__(self, shapes, kinds):
        """Room for arrays of ``shapes`` (``kinds``: "f", "i" or "b" each), uninitialised."""
        key = (tuple(shapes), tuple(kinds))
        lay = self._LAYOUTS.get(key)
        if lay is None:
            lay = self._layout(shapes, kinds)
            if len(self._LAYOUTS) > 512:
                self._LAYOUTS.clear()
            self._LAYOUTS[key] = lay
        self.d, self.offsets, nf, ni = lay
        self.f, self.i = np.empty(nf), np.empty(ni, np.int64)
        self.shapes, self.kinds = shapes, kinds

    @staticmethod
    def _layout(shapes, kinds):
        rows, offsets = [], []
        nf = ni = 0
        for sh, kd in zip(shapes, kinds):
            size = math.prod(sh)
            if kd == "f":
                o, nf = nf, nf + size
            else:
                o, ni = ni, ni + size
            offsets.append((o, size))
            rows.append((int(kd != "f"), o) + tuple(sh) + (1,) * (3 - len(sh)))
        d = np.array(rows, np.int64).reshape(len(rows), 5)
        d.setflags(write=False)
        return d, offsets, nf, ni

    @classmethod
    def of(cls, arrays):
        """The arrays packed (copied): floats as float64, integers and booleans as int64."""
        arrays = [np.asarray(a) for a in arrays]
        kinds = ["f" if a.dtype.kind == "f" else ("b" if a.dtype.kind == "b" else "i")
                 for a in arrays]
        out = cls([a.shape for a in arrays], kinds)
        for v, a in zip(out.views(raw=True), arrays):
            v[...] = a
        return out

    def views(self, raw=False) -> list:
        """The arrays: views of the buffers (booleans as int64 when ``raw``, else converted)."""
        out = []
        f, i = self.f, self.i
        for sh, kd, (o, size) in zip(self.shapes, self.kinds, self.offsets):
            v = (f if kd == "f" else i)[o:o + size].reshape(sh)
            out.append(v.astype(bool) if kd == "b" and not raw else v)
        return out

    @property
    def args(self) -> tuple:
        return self.f, self.i, self.d
