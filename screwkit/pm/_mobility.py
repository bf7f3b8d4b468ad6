"""Instantaneous mobility of an assembled PM from its legs' constraint wrenches.

* ``dof = 6 - rank`` of the union of every leg's constraint-wrench system
  (length-normalised rank, :class:`screwkit.screws.Normalisation`).
* The platform twist space is the set of twists reciprocal to that union.
  ``motion_type`` is ``"<t>T<r>R"``: ``r`` is the number of independent
  rotations (the rank of the angular parts of the twist space), ``t = dof - r``
  the number of independent pure translations (twists with ``w = 0``); e.g.
  ``"1T2R"`` for the 3RRPRR, ``"3T"`` for the translational 3UPU.
* ``n_constraints`` is the sum of the legs' constraint-system dimensions,
  ``redundant = n_constraints - constraint_rank``.
* ``common`` is the dimension of the intersection of all the legs' constraint
  systems: the constraint wrenches shared by every leg (as for a planar PM,
  whose legs all exert the same three).
* ``gruebler`` is the Grubler-Kutzbach count ``6 (n_links - n_joints - 1) + sum f``
  on the graph whose nodes are the links (base, platform and each leg's
  intermediate links of the equivalent chain) and whose edges are the equivalent
  1-DOF joints; ``loops = n_joints - n_links + 1``.  It counts idle motions
  (``idle``: joint motions of a leg that move nothing, e.g. an SPS's spin) and
  ignores redundancy; ``dof = gruebler + redundant - idle`` (the modified
  Kutzbach criterion) holds at every pose and is reported when it does not.
* A parallelogram ``Pa`` is one equivalent joint of its leg (a translation) but is counted
  as the real mechanism: a planar loop of four parallel R hinges and two bars, so in the
  linkage graph it adds two links (the bars) and four 1-DOF joints instead of one (the
  Grübler count drops by 3 per Pa), and the loop's six closure equations have rank 3
  (planar), so each Pa adds 3 to ``redundant``.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from ..errors import InputError
from ._finite import registered_finite_motion
from ..screws import Normalisation, RANK_RTOL, classify_freedoms, reciprocal_system

__all__ = ["Mobility", "declared_motion", "mobility", "mobility_of_legs", "motion_type", "linkage_graph"]


@dataclass(frozen=True)
class Mobility:
    """Result of :func:`mobility`.

    Attributes
    ----------
    dof : int
    motion_type : str
        ``"1T2R"``, ``"3T"``, ``"2T2R"`` ...: the finite motion type of the PM, computed
        from motions sampled from home (:func:`screwkit.engine.finite_motion`: the
        dimension of the platform's rotations and the invariants of its displacements; it
        does not change with the pose), or, for legs without a model or a model the engine
        has not classified, the instantaneous one (with a note).  A helical freedom (a principal screw of
        the twist space with a non-zero pitch, :func:`screwkit.screws.classify_freedoms`)
        is labelled with its pitch in model lengths per radian, e.g. ``"1H(p=2.5)"`` for a
        platform on one H joint, not counted as a rotation.
    instantaneous_type : str
        The same count for the twist space at this pose (pure translations and the rank
        of the rotations): it can differ at special poses (a tilt removes the pure
        translation of a 1T2R platform whose rotations then couple with it...).
    instantaneous : str
        The twist space classified by its screws: translations (directions), rotations
        (about lines through a common point when they are), helical motions (pitch).
    finite : str
        The finite type with its independent parameters, its parasitic motions (the
        dependent parameters that vary) and its invariants, e.g. ``"1T2R: independent
        alpha, beta, Zo; parasitic motion Xo, Yo, gamma (functions of them)"`` (empty when
        not computed).
    translations, rotations : int
    constraint_rank : int
        Rank of the union of the legs' constraint wrenches.
    n_constraints : int
        Sum over legs of their constraint-system dimensions.
    redundant : int
        ``n_constraints - constraint_rank``, plus 3 per parallelogram loop.
    common : int
        Dimension of the intersection of the legs' constraint systems.
    gruebler : int
        Grubler-Kutzbach count.
    n_links, n_joints, loops : int
        Of the linkage graph (equivalent 1-DOF joints).
    idle : int
        Idle joint motions summed over legs (joints minus leg connectivity).
    leg_constraints : tuple of int
        Constraint-system dimension of each leg.
    twists : ndarray (dof, 6)
        A basis of the platform twist space ``[v; w]`` (about the world origin).
    wrenches : ndarray (constraint_rank, 6)
        A basis of the union of the constraint wrenches ``[f; m]``.
    notes : tuple of str
    freedoms : tuple of screwkit.screws.Freedom
        The twist space classified (translations, rotations about lines, helical motions
        with their pitch; :func:`screwkit.screws.classify_freedoms`).
    actuators : int
        The actuated legs (every leg but the model's passive ones): a passive leg adds its
        constraint wrenches to the count above and no actuator (a note says when the
        actuators do not match the DOF).
    passive : tuple of int
        0-based indices of the passive legs.
    """

    dof: int
    motion_type: str
    translations: int
    rotations: int
    constraint_rank: int
    n_constraints: int
    redundant: int
    common: int
    gruebler: int
    n_links: int
    n_joints: int
    loops: int
    idle: int
    leg_constraints: tuple
    twists: np.ndarray
    wrenches: np.ndarray
    notes: tuple = ()
    instantaneous: str = ""
    instantaneous_type: str = ""
    finite: str = ""
    freedoms: tuple = ()
    actuators: int = 0
    passive: tuple = ()


def declared_motion(model) -> tuple:
    """``(label, text)``: the motion type a model *declares* by its pose parametrisation.

    Each of ``Xo, Yo, Zo`` among the independent parameters counts as a translation, each
    Euler angle as a rotation (``"1T2R"`` for ``alpha, beta, Zo``).  A declaration, not a
    result: the finite motion type is computed by :func:`screwkit.engine.finite_motion`,
    and the engine checks the declaration against it when a model is loaded.
    """
    ind = tuple(model.independent)
    t = sum(p in ("Xo", "Yo", "Zo") for p in ind)
    label = motion_type(t, len(ind) - t)
    dep = tuple(getattr(model, "dependent", ()))
    text = f"{label}: independent {', '.join(ind) or 'none'}"
    text += f"; parasitic {', '.join(dep)} (functions of them)" if dep else "; no parasitic motion"
    return label, text


def linkage_graph(legs):
    """The networkx multigraph of a PM: links as nodes, equivalent joints as edges (``f = 1``)."""
    import networkx as nx

    g = nx.MultiGraph()
    g.add_nodes_from(["base", "platform"])
    for i, lg in enumerate(legs, start=1):
        prev = "base"
        m = len(lg.joints)
        for k, j in enumerate(lg.joints):
            nxt = "platform" if k == m - 1 else f"leg{i}.link{k + 1}"
            if j.spec.parallelogram:          # the real 4R loop: two bars, four hinges
                for bar in ("bar1", "bar2"):
                    b = f"leg{i}.{j.name}.{bar}"
                    g.add_edge(prev, b, joint=f"leg{i}.{j.name}.{bar}.R1", kind="R", f=1)
                    g.add_edge(b, nxt, joint=f"leg{i}.{j.name}.{bar}.R2", kind="R", f=1)
            else:
                g.add_edge(prev, nxt, joint=f"leg{i}.{j.name}", kind=j.kind, f=1)
            prev = nxt
    return g


def _rank(M, rtol=RANK_RTOL):
    if M.size == 0:
        return 0, np.zeros(0), np.eye(M.shape[1] if M.ndim == 2 else 6)
    _, s, Vt = np.linalg.svd(M, full_matrices=True)
    r = int(np.sum(s > rtol * max(1.0, float(s[0]))))
    return r, s, Vt


def motion_type(translations: int, rotations: int) -> str:
    """``"1T2R"``, ``"3T"``, ``"3R"``, ``"0"`` (rigid)."""
    out = (f"{translations}T" if translations else "") + (f"{rotations}R" if rotations else "")
    return out or "0"


def mobility_of_legs(legs, rtol: float = RANK_RTOL) -> Mobility:
    """Mobility of a platform held by ``legs`` (placed :class:`~screwkit.legs.Leg`)."""
    legs = tuple(legs)
    # no leg: a free platform (6 DOF), the normalisation of the origin
    pts = np.vstack([lg.points for lg in legs]) if legs else np.zeros((1, 3))
    norm = Normalisation.for_points(pts)
    blocks, dims, complements, idle = [], [], [], 0
    for lg in legs:
        sys = reciprocal_system(lg.twists, points=lg.points)
        idle += sys.n_twists - sys.rank
        Wn = norm.wrenches(sys.wrenches) if len(sys.wrenches) else np.zeros((0, 6))
        if len(Wn):
            Wn = Wn / np.linalg.norm(Wn, axis=1, keepdims=True)
        r, _, Vt = _rank(Wn, rtol) if len(Wn) else (0, None, np.eye(6))
        dims.append(int(len(Wn)))
        blocks.append(Wn)
        complements.append(Vt[r:])
    W = np.vstack(blocks) if blocks else np.zeros((0, 6))
    rank, _, Vt = _rank(W, rtol) if len(W) else (0, None, np.eye(6))
    Vn = Vt[rank:]                        # normalised twists reciprocal to every wrench
    twists = norm.twists_back(Vn)
    wrenches = norm.wrenches_back(Vt[:rank]) if rank else np.zeros((0, 6))
    rot = _rank(Vn[:, 3:], rtol)[0] if len(Vn) else 0
    dof = 6 - rank
    C = np.vstack(complements) if complements else np.zeros((0, 6))
    common = 0 if not legs or any(d == 0 for d in dims) else 6 - _rank(C, rtol)[0]
    # the linkage graph (linkage_graph) has base, platform and each leg's m - 1 inner links as
    # nodes and the m equivalent 1-DOF joints of each leg as edges: count it directly
    # a parallelogram is two bars and four hinges in place of its one equivalent joint
    n_pa = sum(j.spec.parallelogram for lg in legs for j in lg.joints)
    n_joints = sum(len(lg.joints) for lg in legs) + 3 * n_pa
    n_links = 2 + sum(len(lg.joints) - 1 for lg in legs) + 2 * n_pa
    f = n_joints
    gruebler = 6 * (n_links - n_joints - 1) + f
    loops = n_joints - n_links + 1
    n_con = int(sum(dims))
    redundant = n_con - rank + 3 * n_pa   # each planar 4R loop: 6 equations of rank 3
    notes = []
    if idle:
        notes.append(f"{idle} idle joint motion(s) (e.g. an S-S leg spinning about its line)")
    if n_pa:
        notes.append(f"{n_pa} parallelogram loop(s) counted as four R hinges and two bars "
                     f"each (3 redundant loop constraints each)")
    if dof != gruebler + redundant - idle:
        notes.append(f"dof {dof} differs from gruebler + redundant - idle = "
                     f"{gruebler + redundant - idle}")
    twists.setflags(write=False)
    wrenches.setflags(write=False)
    # helical freedoms (a principal screw of non-zero pitch, the platform of an H leg...)
    # are labelled with their pitch, not counted as rotations
    classified = classify_freedoms(Vn, norm) if len(Vn) else ()
    pitches = tuple(f.pitch for f in classified if f.kind == "helical")
    label = motion_type(dof - rot, rot - len(pitches)) if pitches else motion_type(dof - rot, rot)
    if pitches:
        label = (label if label != "0" else "") + \
            f"{len(pitches)}H(p={','.join(f'{h:.4g}' for h in pitches)})"
    return Mobility(dof, label, dof - rot, rot, rank, n_con, redundant,
                    common, gruebler, n_links, n_joints, loops, idle, tuple(dims), twists,
                    wrenches, tuple(notes), freedoms=tuple(classified), actuators=len(legs))


def describe_twist_space(twists, length: float, rtol: float = 1e-8) -> str:
    """Classify a basis of platform twists ``[v; w]`` (about O) by its screws.

    First the pure translations (the twists with ``w = 0``); then, for the rest, rotations
    about lines through one point when every remaining twist is one (modulo the
    translations), else the principal pitches of the remaining screw system (the
    stationary values of ``w . v / w . w``: zero for rotations, non-zero for helical
    motions), which do not depend on the basis.
    """
    T = np.asarray(twists, float).reshape(-1, 6)
    if len(T) == 0:
        return "no motion"
    W = T[:, 3:]
    _, sv, Vh = np.linalg.svd(W.T, full_matrices=True)
    k = int(np.sum(sv > rtol * max(1.0, float(sv[0]) if sv.size else 1.0)))
    trans = (Vh[k:] @ T)[:, :3]
    rot = Vh[:k] @ T                                     # twists with independent rotations
    parts = []
    Q = np.linalg.qr(trans.T)[0][:, :len(trans)] if len(trans) else np.zeros((3, 0))
    if len(trans) == 1:
        parts.append("translation along " + _fmt(_signed(Q[:, 0])))
    elif len(trans) == 2:
        parts.append("2 translations in the plane normal to " + _fmt(np.cross(Q[:, 0], Q[:, 1])))
    elif len(trans) == 3:
        parts.append("3 translations")
    if len(rot):
        Pt = np.eye(3) - Q @ Q.T                          # off the translations
        v, w = rot[:, :3] @ Pt.T, rot[:, 3:]
        n = len(rot)
        many = f"{n} rotation{'s' * (n > 1)}"
        if len(trans) == 3:
            wq = np.linalg.qr(w.T)[0][:, :n]
            parts.append(f"{many} about any line along " + (_fmt(_signed(wq[:, 0])) if n == 1 else
                         "every direction" if n == 3 else
                         "the plane normal to " + _fmt(np.cross(wq[:, 0], wq[:, 1]))))
            return " + ".join(parts)
        # principal pitches: stationary values of (w.v)/(w.w) over the combinations
        B = w @ w.T
        A = 0.5 * ((w @ v.T) + (w @ v.T).T)
        lb, Ub = np.linalg.eigh(B)
        Bm = Ub @ np.diag(lb ** -0.5) @ Ub.T
        pitches = np.linalg.eigvalsh(Bm @ A @ Bm)
        # rotations about lines through one point P: v - P x w = 0 (modulo translations)
        M = np.vstack([Pt @ _skew(wk) for wk in w])
        b = -np.concatenate(list(v))
        P, *_ = np.linalg.lstsq(M, b, rcond=None)
        res = np.linalg.norm(M @ P - b) / max(np.linalg.norm(b), length * np.sqrt(n), 1e-300)
        full = np.linalg.matrix_rank(M, tol=1e-9 * max(1.0, np.abs(M).max())) == 3
        if res <= 1e-7 and full:
            parts.append(f"{many} about lines through {_fmt(P)}")
        elif np.all(np.abs(pitches) <= 1e-7 * length):
            parts.append(f"{many} about lines that do not meet at one point")
        else:
            big = np.abs(pitches) > 1e3 * length          # w nearly 0: almost a translation
            parts.append(f"{n} screw motion{'s' * (n > 1)} of principal pitches "
                         + ", ".join(f"{h:.4g}" + (" (nearly a translation)" if g else "")
                                     for h, g in zip(pitches, big)) + " (length/rad)")
    return " + ".join(parts)


def describe_freedoms(freedoms) -> str:
    """In words, the freedoms of :func:`screwkit.screws.classify_freedoms`: the translations,
    the rotations (about lines through one point when they are concurrent) and the helical
    motions with their pitch (length/rad)."""
    tr = [f for f in freedoms if f.kind == "translation"]
    rot = [f for f in freedoms if f.kind == "rotation"]
    hel = [f for f in freedoms if f.kind == "helical"]
    parts = []
    if len(tr) == 1:
        parts.append("translation along " + _fmt(tr[0].direction))
    elif len(tr) == 2:
        parts.append("2 translations in the plane normal to "
                     + _fmt(_signed(np.cross(tr[0].direction, tr[1].direction))))
    elif len(tr) == 3:
        parts.append("3 translations")
    if len(rot) > 1 and all(np.allclose(f.point, rot[0].point, rtol=0,
                                        atol=1e-9 * max(1.0, float(np.abs(rot[0].point).max())))
                            for f in rot):
        parts.append(f"{len(rot)} rotations about lines through {_fmt(rot[0].point)}")
    else:
        parts += [f"rotation about the line through {_fmt(f.point)} along {_fmt(f.direction)}"
                  for f in rot]
    parts += [f"helical motion about the line through {_fmt(f.point)} along "
              f"{_fmt(f.direction)} of pitch {f.pitch:.4g} (length/rad)" for f in hel]
    return " + ".join(parts) or "no motion"


def _signed(d):
    """A direction with its largest component positive (a sign that does not depend on the
    basis the SVD returned)."""
    return d if d[np.argmax(np.abs(d))] >= 0 else -d


def _skew(p):
    return np.array([[0, -p[2], p[1]], [p[2], 0, -p[0]], [-p[1], p[0], 0]])


def _fmt(v):
    v = np.asarray(v, float)
    v = np.where(np.abs(v) < 5e-13, 0.0, v)
    return "(" + ", ".join(f"{x:.4g}" for x in v) + ")"


def mobility(solution, rtol: float = RANK_RTOL, finite=None) -> Mobility:
    """Mobility of a PM at a solved pose (:class:`~screwkit.engine.PoseSolution`).

    ``finite``: the model's :class:`~screwkit.pm.FiniteMotion` (default: the one the
    engine computed for it, :func:`screwkit.engine.finite_motion`).  A note is added when
    the DOF differs from the definition's stated DOF (a singular pose or a geometry that
    cannot have the stated mobility).
    """
    if not hasattr(solution, "legs"):
        raise InputError(f"mobility takes a solved pose (a PoseSolution: screwkit.solve or "
                         f"an analysis' .solution), not {type(solution).__name__}")
    res = mobility_of_legs(solution.legs, rtol)
    model = getattr(solution, "model", None)
    stated = getattr(model, "stated_dof", None)
    fields = dict(res.__dict__)
    L = float(getattr(getattr(model, "normalisation", None), "length", 1.0) or 1.0)
    fields["instantaneous"] = (describe_twist_space(res.twists, L) if res.translations == 3
                               else describe_freedoms(res.freedoms))
    fields["instantaneous_type"] = res.motion_type
    if stated is not None and stated != res.dof:
        fields["notes"] = res.notes + (
            f"the definition states {stated} DOF: this pose is singular or the geometry "
            "does not have the stated mobility",)
    passive = tuple(getattr(model, "passive", ()))
    fields["passive"] = passive
    fields["actuators"] = len(solution.legs) - len(passive)
    if passive:
        fields["notes"] = fields.get("notes", res.notes) + (
            f"passive leg{'s' * (len(passive) > 1)} "
            f"{', '.join(str(i + 1) for i in passive)}: constraint wrenches, no actuator",)
    if fields["actuators"] != res.dof:
        fields["notes"] = fields.get("notes", res.notes) + (
            f"{fields['actuators']} actuator(s) for {res.dof} DOF: "
            + ("redundantly actuated" if fields["actuators"] > res.dof else
               "the actuators do not fix every freedom"),)
    if model is not None and hasattr(model, "independent"):
        # the finite motion type is computed from sampled motions by the engine (which
        # checked it against the declaration); the twist space here may count otherwise
        # (a tilted 1T2R platform's twists are three screws of finite pitch)
        fm = finite if finite is not None else registered_finite_motion(model)
        if fm is not None:
            fields["motion_type"], fields["finite"] = fm.label, fm.text
        else:
            fields["notes"] = fields.get("notes", res.notes) + (
                "motion_type is the instantaneous count: the finite motion type is computed "
                "by screwkit.engine.finite_motion",)
    return Mobility(**fields)
