"""Each leg's Jacobian rows at many poses: constraint wrenches and the actuation wrench.

The observation rules (:mod:`screwkit.legs`) decide, once per leg at a
reference geometry (home), *what* the leg's constraint wrenches are: pure
couples, forces through a named point (an S or U centre, ``A``, ``a``, the
meeting point of two axes), or finite-pitch screws.  A :class:`RowTemplate`
records that structure; :meth:`RowTemplate.rows` recomputes the members at
``N`` poses from the current joint axes, exactly, and flags the poses where
the structure no longer holds (a leg singularity, a geometry that lost its
structure) so that nothing is silently wrong.

Members of one kind are computed as a subspace, then given a canonical basis:

* couples ``[0; u]``: ``u`` is orthogonal to every rotation axis (rule 3), the
  null space of the rows ``w_j``;
* forces through a point ``X``: ``[u; X x u]`` does no work on joint ``j`` iff
  ``u . v_j(X) = 0`` with ``v_j(X) = v_j - X x w_j`` the velocity joint ``j``
  gives to ``X`` (rules 1 and 2); ``u`` spans the null space of those rows.

A subspace of dimension 1 is a direction up to sign; of dimension 2 or 3 it
needs a basis.  Both are fixed by an ordered list of *reference directions*
of the leg's own geometry (the leg line, the base normal, the joint axes in
chain order, ... or the ones the catalog entry declares): the basis is the
Gram-Schmidt orthonormalisation of the references projected on the subspace,
and a single member points along its reference.  The references are chosen at
home, where each keeps a clear projection (cosine >= :data:`REF_MIN`), and kept
for every pose: bases and signs are deterministic, covariant with the base
frame, unchanged by a change of units, and continuous along paths and maps.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from . import _algebra as alg
from ._nullspace import ZERO as _ZERO, canonical_basis as _basis, null_space as _null
from ._generic import generic_members, generic_references, subset_geometry
from ._geometry import (REF_FLAG, REF_MIN, LegGeometry, geometry_of, leg_centroid, leg_length, named_point,
                        point_ref)

__all__ = ["RowTemplate", "LegGeometry", "REF_MIN", "DEFAULT_REFERENCES"]

#: Default reference directions (tried in order): the leg line, the base normal, the
#: joint axes in chain order, the base axes.
DEFAULT_REFERENCES = ("leg", "base.Z", "joints", "base.X", "base.Y")


# --------------------------------------------------------------------------- the template

@dataclass(frozen=True)
class Group:
    """Constraint members of one kind: ``kind`` ``"couple"`` or ``"force"`` (through the
    named point ``point``), ``dim`` members along the reference directions ``refs``."""

    kind: str
    point: str | None
    point_ref: tuple | None
    dim: int
    refs: tuple


@dataclass(frozen=True)
class Actuation:
    """How the actuation member is found: ``kind`` ``"line"`` (the force on the line through
    the two named points ``names``, at ``points``), ``"least-norm"`` (the passive-reciprocal
    wrench orthogonal to the constraint system; ``member`` ``"force"`` when its pitch is
    zero at home, else ``"screw"``), ``"none"`` (the actuated joint is dependent) or
    ``"passive"`` (a passive leg: no actuation row)."""

    kind: str
    points: tuple = ()
    names: tuple = ()
    member: str = "force"


class RowTemplate:
    """The structure of one leg's rows, to recompute them at many poses.

    Parameters
    ----------
    leg : Leg
        The leg at its reference geometry (a PM's home).
    analysis : LegAnalysis
        Its analysis there (constraint members and actuation member).
    base_rotation, O : the base frame of the references (world)
    platform_rotation, o : the platform frame at the reference geometry
    references : sequence, optional
        Declared reference directions (catalog), tried before the defaults.
    passive : bool
        A leg without an actuator (:attr:`screwkit.pm.PMModel.passive`): it has no
        actuation row (``actuation.kind == "passive"``).
    """

    def __init__(self, leg, analysis, base_rotation, O, platform_rotation, o, references=(),
                 passive=False):
        self.name = leg.name
        self.passive = bool(passive)
        self.names = tuple(j.name for j in leg.joints)
        self.kinds = tuple(j.kind for j in leg.joints)
        self.actuated = leg.actuated_index
        cons = analysis.constraints
        self.k = len(cons)
        self.generic = any(c.kind == "screw" or (c.kind == "force" and not c.point_name)
                           for c in cons)
        geo = geometry_of(leg, base_rotation, O, platform_rotation, o)
        cand = _candidates(tuple(references), self.names)
        groups = []
        if not self.generic:
            order = []
            for c in cons:
                key = (c.kind, c.point_name if c.kind == "force" else None)
                if key not in order:
                    order.append(key)
            for kind, pname in order:
                dim = sum(1 for c in cons if c.kind == kind and
                          (kind == "couple" or c.point_name == pname))
                pref = point_ref(leg, pname) if kind == "force" else None
                vec, ok = self._space(geo, kind, pref, dim)
                if not ok[0]:
                    self.generic = True
                    break
                groups.append(Group(kind, pname, pref, dim,
                                    _choose_refs(geo, dim, vec, cand, self.names)))
        self.groups = tuple(groups)
        self.generic_refs = generic_references(geo, self.k, cand, self.names) if self.k else ()
        if self.generic:
            self.member_kinds = tuple((c.kind, None) for c in cons)
        else:
            self.member_kinds = tuple((g.kind, g.point) for g in self.groups for _ in range(g.dim))
        self.actuation = (Actuation("passive") if self.passive else
                          self._actuation_template(leg, analysis, geo, cand))

    # -- subspaces -------------------------------------------------------------------
    def _rows_for(self, geo, kind, pref, joints):
        L = leg_length(geo)
        rows = []
        if kind == "couple":
            for j in joints:
                if self.kinds[j] != "P":
                    rows.append(geo.axes[j])
            return rows
        X = named_point(geo, pref)
        joints = list(joints)
        if not joints:
            return rows
        V = geo.point_velocities(joints, X)                       # (3, r, N)
        size = np.array([1.0 if self.kinds[j] == "P" else np.nan for j in joints])[:, None]
        V = V / np.where(np.isnan(size), L, size)
        return list(V.transpose(1, 0, 2))

    def _space(self, geo, kind, pref, dim, joints=None):
        joints = range(len(self.names)) if joints is None else joints
        return _null(self._rows_for(geo, kind, pref, joints), dim)

    def _actuation_template(self, leg, analysis, geo, cand):
        """The force on the line through two named points when every passive joint is
        anchored at one of them (the leg line of S-P-S, U-P-U, R-R-P-R-R...: a structural
        choice that survives any motion); otherwise the least-norm wrench."""
        act = analysis.actuation
        if act is None:
            return Actuation("none")
        from ..legs import named_points
        tol = 1e-6 * max(leg.length, float(leg_length(geo)[0]))
        named = named_points(leg)
        passive = [j for j in range(len(leg.joints)) if j != leg.actuated_index]
        anchored = {nm: {j for j in passive if np.linalg.norm(leg.joints[j].point - p) <= tol
                         or (leg.joints[j].kind == "P")}
                    for nm, p in named.items()}
        names = list(named)
        for i1, n1 in enumerate(names):
            for n2 in names[i1 + 1:]:
                if np.linalg.norm(named[n1] - named[n2]) <= tol:
                    continue
                if anchored[n1] | anchored[n2] >= set(passive):
                    pts = (point_ref(leg, n1), point_ref(leg, n2))
                    d = named[n2] - named[n1]
                    if all(abs(float(d @ leg.joints[j].direction)) <= tol * np.linalg.norm(d)
                           for j in passive if leg.joints[j].kind == "P"):
                        return Actuation("line", pts, (n1, n2))
        # the least-norm member at home: a force when its pitch vanishes
        v, w = geo.twist(self.actuated)
        member, _ = self._least_norm(geo, np.concatenate([v, w]), passive, leg_length(geo))
        f, m = member[:3, 0], member[3:, 0]
        pitch = abs(float(f @ m)) / max(float(f @ f), 1e-300)
        return Actuation("least-norm", member="force" if pitch <= 1e-9 * leg.length else "screw")

    # -- evaluation ------------------------------------------------------------------
    def rows(self, geo: LegGeometry):
        """The leg's rows at ``N`` poses.

        Returns
        -------
        act : ndarray (6, N)
            Actuation row ``[f; m]`` (about ``O``), scaled so that its reciprocal product
            with the actuated joint's unit twist is 1 (0 where the actuator is dependent).
        act_member : ndarray (6, N)
            The unit member (``|f| = 1`` or ``|m| = 1``).
        act_scale : ndarray (N,)
            Its factor (``act = act_scale * act_member``).
        cons : ndarray (k, 6, N)
            Unit constraint members, group by group.
        ok : ndarray (N,) of bool
            False where a row could not be formed (a dependent actuator, a degenerate basis).
        structure_ok : ndarray (N,) of bool
            False where the home structure of the members does not hold (the generic rule
            gave them there).
        """
        N = geo.N
        ok = np.ones(N, bool)
        if self.generic:
            cons, ok = generic_members(geo, self.k, self.generic_refs, self.names)
        else:
            cons = []
            for g in self.groups:
                vec, good = self._space(geo, g.kind, g.point_ref, g.dim)
                ok &= good
                refs = [geo.direction(r, self.names) for r in g.refs]
                basis, rem = _basis(g.dim, vec, refs)
                ok &= rem > REF_FLAG
                X = None if g.kind == "couple" else named_point(geo, g.point_ref)
                for e in basis:
                    cons.append(np.concatenate([np.zeros((3, N)), e]) if X is None
                                else np.concatenate([e, alg.cross(X, e)]))
            cons = np.stack(cons) if cons else np.zeros((0, 6, N))
            structure = ok.copy()
            if self.k and not ok.all():
                # the structure of home does not hold at these poses: the generic rule there
                bad = ~ok
                gc, gok = generic_members(subset_geometry(geo, bad), self.k, self.generic_refs,
                                           self.names)
                cons[:, :, bad] = gc
                ok[bad] = gok
        if self.generic:
            structure = np.ones(N, bool)
        act, member, scale, aok = self._act_rows(geo, cons)
        return act, member, scale, cons, ok & aok, structure

    def member_points(self, geo, cons):
        """A point of each constraint member's line ``(k, 3, N)``: its named point, the
        point of the line nearest the leg's centroid otherwise; NaN for couples."""
        out = []
        c = leg_centroid(geo)
        for r, (kind, pname) in enumerate(self.member_kinds):
            f, m = cons[r, :3], cons[r, 3:]
            nf = alg.dot(f, f)
            if kind == "couple" or not np.any(nf > 0):
                out.append(np.full((3, geo.N), np.nan))
                continue
            if pname and not self.generic:
                g = next(g for g in self.groups if g.kind == "force" and g.point == pname)
                out.append(named_point(geo, g.point_ref))
                continue
            p0 = alg.cross(f, m) / np.maximum(nf, 1e-300)
            d = f / np.sqrt(np.maximum(nf, 1e-300))
            out.append(p0 + d * alg.dot(c - p0, d))
        return np.stack(out) if out else np.zeros((0, 3, geo.N))

    def actuation_point(self, geo):
        """A point of the actuation line ``(3, N)`` (NaN when it is not a force)."""
        a = self.actuation
        if a.kind == "line":
            return named_point(geo, a.points[0])
        return np.full((3, geo.N), np.nan)

    def _act_rows(self, geo, cons):
        N = geo.N
        a = self.actuation
        v, w = geo.twist(self.actuated)
        xi = np.concatenate([v, w])
        L = leg_length(geo)
        if a.kind in ("none", "passive"):
            z = np.zeros((6, N))
            return z, z, np.zeros(N), np.full(N, a.kind == "passive")
        passive = [j for j in range(len(self.names)) if j != self.actuated]
        if a.kind == "line":
            X, Y = (named_point(geo, r) for r in a.points)
            d = alg.unit(Y - X)
            member = np.concatenate([d, alg.cross(X, d)])
            if passive:
                # the passive joint whose velocity of X has the largest component along the
                # line (at its worst pose): that joint's value at every pose
                V = geo.point_velocities(passive, X)              # (3, r, N)
                P = np.array([self.kinds[j] == "P" for j in passive])[:, None]
                res_all = np.abs(alg.dot(V, d[:, None])) / np.where(P, 1.0, L)
                worst = res_all.max(axis=1).tolist()
                res = res_all[max(range(len(worst)), key=worst.__getitem__)]
            else:
                res = np.zeros(N)
            ok = res < _ZERO
        else:
            member, ok = self._least_norm(geo, xi, passive, L)
        prod = alg.dot(member[:3], xi[:3]) + alg.dot(member[3:], xi[3:])
        size = 1.0 if self.kinds[self.actuated] == "P" else L
        dependent = np.abs(prod) <= 1e-9 * np.maximum(size, 1e-300)
        flip = np.where(prod < 0, -1.0, 1.0)
        member = member * flip
        scale = np.where(dependent, 0.0, 1.0 / np.where(dependent, 1.0, np.abs(prod)))
        return member * scale, member, scale, ok & ~dependent

    def _least_norm(self, geo, xi, passive, L):
        """``P xi``: the actuated twist projected (length-normalised metric about the leg's
        centroid) on the wrenches reciprocal to the passive joints: the actuation wrench of
        least norm, orthogonal to the constraint system; a unit force when its pitch is 0."""
        c = leg_centroid(geo)
        T = []
        for j in passive:
            v, w = geo.twist(j)
            T.append(np.concatenate([(v - alg.cross(c, w)) / L, w]))
        xn = np.concatenate([(xi[:3] - alg.cross(c, xi[3:])) / L, xi[3:]])
        # as a wrench [f; m_n] the normalised twist's dual: project out the passive twists
        G = [[(T[i] * T[j]).sum(0) for j in range(i + 1)] for i in range(len(T))]
        tr = sum(G[i][i] for i in range(len(T)))
        X, piv = alg.spd_solve(G, [(T[i] * xn).sum(0) for i in range(len(T))], tr * 1e-13)
        wn = xn - sum(T[i] * X[i] for i in range(len(T)))
        f, mn = wn[:3], wn[3:]
        m = mn * L + alg.cross(c, f)
        nf = alg.norm(f)
        member = np.concatenate([f, m]) / np.maximum(nf, 1e-300)
        ok = nf > 1e-9 * alg.norm(wn)
        return member, ok

def _candidates(declared, names):
    out = list(declared)
    for r in DEFAULT_REFERENCES:
        if r == "joints":
            out += list(names)
        else:
            out.append(r)
    return out


def _choose_refs(geo, dim, vec, cand, names):
    """The first candidate references (in order) that give a clear basis at home."""
    chosen, basis = [], []
    for r in cand:
        try:
            d = geo.direction(r, names)
        except ValueError:
            continue
        if not (np.all(np.isfinite(d)) and alg.norm(d)[0] > 0.5):
            continue
        if dim == 1:
            rem = np.abs(alg.dot(vec, d))
        else:
            p = d - vec * alg.dot(vec, d) if dim == 2 else d
            for e in basis:
                p = p - e * alg.dot(e, p)
            rem = alg.norm(p)
        if rem[0] >= REF_MIN:
            chosen.append(r)
            if dim > 1:
                basis.append(p / rem)
        if len(chosen) == dim:
            return tuple(chosen)
    raise ValueError("no reference directions give a basis")


