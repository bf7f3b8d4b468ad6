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

import weakref
from dataclasses import dataclass

import numpy as np

from ._kernels._layout import REF_MIN

__all__ = ["RowTemplate", "RowInfo", "templates_of", "labels_of", "make_labels", "REF_MIN",
           "DEFAULT_REFERENCES", "point_ref"]

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

    The decisions at home (each group's null space, the reference directions of its basis,
    the generic rule's reference wrenches, the least-norm actuation member's pitch) are made
    by the kernels' own functions on the leg at home (:mod:`screwkit.engine._kernels._probe`).

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
        from ._arrays import probe_model
        from ._kernels import compile_analysis, kernels
        self.name = leg.name
        self.names = tuple(j.name for j in leg.joints)
        self.kinds = tuple(j.kind for j in leg.joints)
        self.actuated = leg.actuated_index
        self.passive = bool(passive)
        cons = analysis.constraints
        self.k = len(cons)
        self.generic = any(c.kind == "screw" or (c.kind == "force" and not c.point_name)
                           for c in cons)
        cand = _candidates(tuple(references), self.names)
        order = []
        if not self.generic:
            for c in cons:
                key = (c.kind, c.point_name if c.kind == "force" else None)
                if key not in order:
                    order.append(key)
        prefs = [point_ref(leg, pname) for kind, pname in order if kind == "force"]
        probe, cand_ok, cand_idx, points = probe_model(leg, base_rotation, O, platform_rotation,
                                                       o, prefs, cand)
        pick = dict(zip(cand_idx.tolist(), cand_ok))
        compile_analysis()              # (a first run: the kernels compiled on two processes)
        K = kernels()
        groups = []
        if order:
            dims = np.array([sum(1 for c in cons if c.kind == kind and
                                 (kind == "couple" or c.point_name == pname))
                             for kind, pname in order], np.int64)
            gkind = np.array([int(kind == "force") for kind, _ in order], np.int64)
            gpoint = np.array([points.index(point_ref(leg, pname)) if kind == "force" else 0
                               for kind, pname in order], np.int64)
            ok = np.zeros(len(order), bool)
            chosen = np.full((len(order), 3), -1, np.int64)
            K.home_groups(*probe, gkind, gpoint, dims, cand_idx, ok, chosen)
            for g, (kind, pname) in enumerate(order):
                if not ok[g]:
                    self.generic = True
                    groups = []
                    break
                if np.any(chosen[g, :dims[g]] < 0):
                    raise ValueError("no reference directions give a basis")
                groups.append(Group(kind, pname, point_ref(leg, pname) if kind == "force"
                                    else None, int(dims[g]),
                                    tuple(pick[c] for c in chosen[g, :dims[g]])))
        self.groups = tuple(groups)
        self.generic_refs = ()
        if self.k:
            out = np.full((self.k, 3), -1, np.int64)
            K.home_generic(*probe, self.k, cand_idx, out)
            if np.any(out[:, 0] < 0):
                raise ValueError("no reference wrenches give a basis of the constraint system")
            self.generic_refs = tuple(("force" if kd == 0 else "couple", pick[c])
                                      for kd, c, _ in out)
        if self.generic:
            # what each of the generic rule's rows is at home (its own, in its order: not
            # the analysis' members, whose order and kinds its projections need not keep)
            self.member_kinds = tuple((("force", "couple", "screw")[kd], None)
                                      for kd in out[:, 2])
        else:
            self.member_kinds = tuple((g.kind, g.point) for g in self.groups for _ in range(g.dim))
        self.actuation = (Actuation("passive") if self.passive else
                          self._actuation_template(leg, analysis, probe, K))

    @property
    def active(self) -> bool:
        """The leg has an actuator (an actuation row)."""
        return not self.passive

    def _actuation_template(self, leg, analysis, probe, K):
        """The force on the line through two named points when every passive joint is
        anchored at one of them (the leg line of S-P-S, U-P-U, R-R-P-R-R...: a structural
        choice that survives any motion); otherwise the least-norm wrench."""
        act = analysis.actuation
        if act is None:
            return Actuation("none")
        from ..legs import named_points
        tol = 1e-6 * max(leg.length, float(np.linalg.norm(np.asarray(leg.a) - leg.A)))
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
        member = np.zeros(6)
        K.home_least_norm(*probe, member)
        f, m = member[:3], member[3:]
        pitch = abs(float(f @ m)) / max(float(f @ f), 1e-300)
        return Actuation("least-norm", member="force" if pitch <= 1e-9 * leg.length else "screw")


def _candidates(declared, names):
    out = list(declared)
    for r in DEFAULT_REFERENCES:
        if r == "joints":
            out += list(names)
        else:
            out.append(r)
    return out


# --------------------------------------------------------------------------- named points

def point_ref(leg, name):
    """How to find a named point of ``leg`` at any pose: ('A',), ('a',), ('joint', j) or
    ('meet', i, j)."""
    if name in ("A", "a"):
        return (name,)
    if "^" in name:
        n1, n2 = name.split("^", 1)
        return ("meet", _slot(leg, n1), _slot(leg, n2))
    for j, jt in enumerate(leg.joints):
        if jt.name == name or f"{jt.spec.origin}{jt.spec.position}" == name:
            return ("joint", j)
    raise ValueError(f"leg {leg.name}: no point named {name!r}")


def _slot(leg, name):
    for j, jt in enumerate(leg.joints):
        if jt.name == name:
            return j
    raise ValueError(f"leg {leg.name}: no joint {name!r}")


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

    @property
    def torque(self) -> bool:
        """The row's value is a torque: a couple, or the effort of a rotary actuator (an R
        or H joint of the leg's R/P chain, a U's or an S's too: its label's ``T``)."""
        return self.label.startswith("T")


_TEMPLATES: "weakref.WeakKeyDictionary" = weakref.WeakKeyDictionary()


def templates_of(model) -> tuple:
    """One :class:`~screwkit.engine._templates.RowTemplate` per leg of ``model``, decided
    at home (cached)."""
    t = _TEMPLATES.get(model)
    if t is None:
        R0, p0 = model.frame
        Rh, oh = model.platform_home
        refs = tuple(model.constraint_references) or ((),) * len(model.home_legs)
        passive = set(getattr(model, "passive", ()))
        t = tuple(RowTemplate(lg, lg.analyze(), R0, p0, Rh, oh, refs[i], passive=i in passive)
                  for i, lg in enumerate(model.home_legs))
        _TEMPLATES[model] = t
    return t


_LABELS: dict = {}


def labels_of(templates):
    """The :class:`RowInfo` of every row (memoised per templates tuple: the templates of
    a model are built once and kept, so the labels are too)."""
    key = id(templates)
    hit = _LABELS.get(key)
    if hit is not None and hit[0] is templates:
        return hit[1]
    out = make_labels(templates)
    if len(_LABELS) > 256:
        _LABELS.clear()
    _LABELS[key] = (templates, out)
    return out


def make_labels(templates):
    info_a, info_c = [], []
    for i, t in enumerate(templates):
        a = t.actuation
        if t.active:
            joint, member = t.names[t.actuated], a.member if a.kind != "none" else "none"
            # rotary: an R or H of the equivalent chain (U1a, S1b, C1r are R's: not the name)
            torque = member == "couple" or t.kinds[t.actuated] in "RH"
            info_a.append(RowInfo(i, t.name, "actuation", member, a.names[0] if a.names
                                  else None, joint, f"{'T' if torque else 'F'}_a{i + 1}"))
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
