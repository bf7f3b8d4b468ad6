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
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from ..screws import Normalisation, RANK_RTOL, reciprocal_system

__all__ = ["Mobility", "mobility", "mobility_of_legs", "motion_type", "linkage_graph"]


@dataclass(frozen=True)
class Mobility:
    """Result of :func:`mobility`.

    Attributes
    ----------
    dof : int
    motion_type : str
        ``"1T2R"``, ``"3T"``, ``"2T2R"`` ...
    translations, rotations : int
    constraint_rank : int
        Rank of the union of the legs' constraint wrenches.
    n_constraints : int
        Sum over legs of their constraint-system dimensions.
    redundant : int
        ``n_constraints - constraint_rank``.
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
    pts = np.vstack([lg.points for lg in legs])
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
    C = np.vstack(complements)
    common = 0 if any(d == 0 for d in dims) else 6 - _rank(C, rtol)[0]
    # the linkage graph (linkage_graph) has base, platform and each leg's m - 1 inner links as
    # nodes and the m equivalent 1-DOF joints of each leg as edges: count it directly
    n_joints = sum(len(lg.joints) for lg in legs)
    n_links = 2 + sum(len(lg.joints) - 1 for lg in legs)
    f = n_joints
    gruebler = 6 * (n_links - n_joints - 1) + f
    loops = n_joints - n_links + 1
    n_con = int(sum(dims))
    notes = []
    if idle:
        notes.append(f"{idle} idle joint motion(s) (e.g. an S-S leg spinning about its line)")
    if dof != gruebler + (n_con - rank) - idle:
        notes.append(f"dof {dof} differs from gruebler + redundant - idle = "
                     f"{gruebler + n_con - rank - idle}")
    twists.setflags(write=False)
    wrenches.setflags(write=False)
    return Mobility(dof, motion_type(dof - rot, rot), dof - rot, rot, rank, n_con, n_con - rank,
                    common, gruebler, n_links, n_joints, loops, idle, tuple(dims), twists,
                    wrenches, tuple(notes))


def mobility(solution, rtol: float = RANK_RTOL) -> Mobility:
    """Mobility of a PM at a solved pose (:class:`~screwkit.engine.PoseSolution`).

    A note is added when the DOF differs from the definition's stated DOF (a
    singular pose or a geometry that cannot have the stated mobility).
    """
    res = mobility_of_legs(solution.legs, rtol)
    stated = getattr(getattr(solution, "model", None), "stated_dof", None)
    if stated is not None and stated != res.dof:
        res = Mobility(**{**res.__dict__, "notes": res.notes + (
            f"the definition states {stated} DOF: this pose is singular or the geometry "
            "does not have the stated mobility",)})
    return res
