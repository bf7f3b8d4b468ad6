"""Pinocchio models of screwkit legs and closed-loop PMs (for cross-checking).

A screwkit leg is an equivalent chain of 1-DOF joints (S -> 3 R, U -> 2 R,
C -> P + R) whose forward kinematics is the product of exponentials in the
world frame::

    T_end(q) = exp(xi_1 q_1) ... exp(xi_m q_m) T_end_home

with ``xi_i`` the home unit twists ``[v; w]`` about the world origin.  This
module rebuilds the same leg with Pinocchio's *native* joints:

=======  ==============================================================
letter   Pinocchio joint
=======  ==============================================================
S        ``JointModelSpherical`` (nq = 4 quaternion ``x y z w``, nv = 3)
U        ``JointModelUniversal(axis1, axis2)`` (nq = nv = 2)
R        ``JointModelRevoluteUnaligned(axis)``
P        ``JointModelPrismaticUnaligned(axis)``
H        ``JointModelHelicalUnaligned(axis, pitch)`` (translation pitch*q)
C        ``PrismaticUnaligned`` + ``RevoluteUnaligned`` on the same axis
         (pin 4.1 has no unaligned cylindrical joint)
=======  ==============================================================

Every joint frame sits at its joint's home point with the *world* orientation
at home, so each joint placement relative to its parent is a pure translation;
then Pinocchio's FK equals the POE above (checked when a model is built, with
``model.check(data)``).  An operational frame ``platform`` on the last joint
sits at the platform's home pose.

A closed-loop model (:func:`build_closed_loop_model`) holds every leg as a
branch from the universe, added depth first; one *carrier* leg carries the
platform and every other leg is tied to it by a ``RigidConstraintModel``:
``CONTACT_6D``, or with ``point_contacts`` a ``CONTACT_3D`` at the centre of a
leg's last (passive) S, which is then left out of the model.  Pinocchio is
imported lazily, inside the functions.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from ..errors import GeometryError, InputError
from ..legs import Leg
from ._pinocchio_chain import JointBlock, LegChain, as_pose

__all__ = ["LegModel", "ClosedLoopModel", "build_leg_model", "build_closed_loop_model"]

#: Tolerance of the build-time self-check (Pinocchio FK at home == joint points).
_HOME_RTOL = 1e-10


@dataclass(frozen=True, eq=False)
class LegModel:
    """A Pinocchio model of one serial leg (see :func:`build_leg_model`).

    Attributes
    ----------
    model : pinocchio.Model
    chain : LegChain
    platform_home : tuple (R (3, 3), p (3,))
    """

    model: object
    chain: LegChain
    platform_home: tuple

    def q(self, joint_values) -> np.ndarray:
        """Pinocchio configuration (nq,) of screwkit joint values (m,)."""
        import pinocchio as pin
        out = pin.neutral(self.model)
        self.chain.fill_q(_values(joint_values, self.chain), out)
        return out

    def joint_values(self, qpin, hint=None) -> np.ndarray:
        """Screwkit joint values (m,) of a Pinocchio configuration."""
        return self.chain.read_q(np.asarray(qpin, float), hint)

    def velocity_map(self, joint_values) -> np.ndarray:
        """``M`` (nv, m) with ``v_pin = M qdot`` (see :meth:`LegChain.velocity_map`)."""
        return self.chain.velocity_map(_values(joint_values, self.chain), self.model.nv)


@dataclass(frozen=True, eq=False)
class ClosedLoopModel:
    """All legs of a PM in one Pinocchio model plus loop-closure constraints.

    Attributes
    ----------
    model : pinocchio.Model
    chains : tuple of LegChain
        In leg order; the last link of ``chains[carrier]`` carries the platform.
    constraints : tuple of pinocchio.RigidConstraintModel
        One per leg other than the carrier (in leg order, see ``constraint_legs``):
        ``CONTACT_6D`` between the leg's platform frame (joint1) and the carrier's
        (joint2), or ``CONTACT_3D`` between the centre of the leg's dropped last S
        (joint1, ``LegChain.truncated``) and the same point of the platform on the
        carrier (joint2); reference frame ``LOCAL`` (of joint1's contact).
    platform_home : tuple (R, p)
    carrier : int
        Index of the leg whose last link carries the platform.
    constraint_legs : tuple of int
        The leg of each constraint.
    """

    model: object
    chains: tuple
    constraints: tuple
    platform_home: tuple
    carrier: int = 0
    constraint_legs: tuple = ()

    def q(self, joint_values) -> np.ndarray:
        """Pinocchio configuration of the per-leg screwkit joint values."""
        import pinocchio as pin
        if len(joint_values) != len(self.chains):
            raise InputError(f"{len(joint_values)} joint-value vectors for {len(self.chains)} legs")
        out = pin.neutral(self.model)
        for ch, qv in zip(self.chains, joint_values):
            ch.fill_q(_values(qv, ch), out)
        return out

    def velocity_map(self, joint_values) -> np.ndarray:
        """``M`` (nv, sum m) mapping stacked screwkit joint rates to Pinocchio velocities."""
        return np.hstack([ch.velocity_map(_values(qv, ch), self.model.nv)
                          for ch, qv in zip(self.chains, joint_values)])


def _values(q, chain: LegChain) -> np.ndarray:
    q = np.asarray(q, float).reshape(-1)
    if q.shape != (chain.m,) or not np.all(np.isfinite(q)):
        raise InputError(f"leg {chain.leg.name}: expected {chain.m} finite joint values "
                         f"({', '.join(j.name for j in chain.leg.joints)}), got shape {q.shape}")
    return q


def _add_chain(model, leg: Leg, platform_home, prefix: str, point_contact: bool = False,
               passive: bool = False, bar_offsets=None) -> LegChain:
    """Append ``leg`` to ``model`` as a branch from the universe (depth first).

    With ``point_contact`` a passive last S is left out: the chain ends at the link
    before it, with frames ``contact`` at the S centre (see :class:`LegChain`).
    ``bar_offsets`` ``{slot: offsets}`` places a parallelogram's bars (see
    :func:`build_closed_loop_model`)."""
    import pinocchio as pin
    R_home, o_home = platform_home
    joints = leg.joints
    groups, i = [], 0
    while i < len(joints):
        j = joints[i]
        if j.spec.origin in "SU":
            n = 3 if j.spec.origin == "S" else 2
            grp = list(range(i, i + n))
            pts = np.array([joints[k].point for k in grp])
            if any(joints[k].spec.position != j.spec.position for k in grp) or \
                    np.abs(pts - pts[0]).max() > 1e-9 * max(1.0, leg.length):
                raise GeometryError(f"leg {leg.name}: the parts of {j.spec.origin}{j.spec.position} "
                                    "do not share one centre")
            groups.append(("spherical" if n == 3 else "universal", tuple(grp)))
            i += n
        elif j.spec.parallelogram:
            groups.append(("parallelogram", (i,)))
            i += 1
        else:
            groups.append(({"R": "revolute", "P": "prismatic", "H": "helical"}[j.kind], (i,)))
            i += 1
    truncated = bool(point_contact and groups[-1][0] == "spherical"
                     and (passive or leg.actuated_index not in groups[-1][1]))
    if truncated:
        groups = groups[:-1]
    parent, parent_point = 0, np.zeros(3)
    blocks, twins = [], []
    for kind, grp in groups:
        j0 = joints[grp[0]]
        if kind == "parallelogram":
            parent, parent_point = _add_parallelogram(model, j0, grp[0], parent, parent_point,
                                                      prefix, blocks, twins,
                                                      (bar_offsets or {}).get(grp[0]))
            continue
        axes = np.array([joints[k].direction for k in grp])
        if kind == "spherical":
            jm = pin.JointModelSpherical()
        elif kind == "universal":
            jm = pin.JointModelUniversal(axes[0], axes[1])
        elif kind == "revolute":
            jm = pin.JointModelRevoluteUnaligned(axes[0])
        elif kind == "prismatic":
            jm = pin.JointModelPrismaticUnaligned(axes[0])
        else:
            jm = pin.JointModelHelicalUnaligned(axes[0], float(j0.pitch))
        placement = pin.SE3(np.eye(3), j0.point - parent_point)   # pure translation
        name = f"{prefix}{'+'.join(joints[k].name for k in grp)}"
        jid = model.addJoint(parent, jm, placement, name)
        jmod = model.joints[jid]
        axes.setflags(write=False)
        blocks.append(JointBlock(kind, jid, grp, jmod.idx_q, jmod.nq, jmod.idx_v, jmod.nv, axes))
        parent, parent_point = jid, j0.point
    # the second bars after the main branch: depth first, the near link's subtree through
    # the first bar comes before the second bar
    loops = [_add_twin(model, prefix, blocks, *t) for t in twins]
    if truncated:
        c = np.asarray(joints[-1].point, float)
        fid = model.addFrame(pin.Frame(f"{prefix}contact", parent, pin.SE3(np.eye(3), c - parent_point),
                                       pin.FrameType.OP_FRAME))
        return LegChain(leg, tuple(blocks), parent, fid, fid, (R_home, o_home), True, passive,
                        tuple(loops))
    fid = model.addFrame(pin.Frame(f"{prefix}platform", parent, pin.SE3(R_home, o_home - parent_point),
                                   pin.FrameType.OP_FRAME))
    eid = model.addFrame(pin.Frame(f"{prefix}end", parent, pin.SE3.Identity(), pin.FrameType.OP_FRAME))
    return LegChain(leg, tuple(blocks), parent, fid, eid, (R_home, o_home), False, passive,
                    tuple(loops))


def _add_parallelogram(model, j, slot, parent, parent_point, prefix, blocks, twins,
                       offsets=None):
    """A ``Pa`` as its real four-bar: the first bar on a hinge at the Pa's point ``p``, the
    far link on a hinge at the bar's end ``p + b`` (turning back by the bar's angle, so that
    it translates); the second bar (added by :func:`_add_twin` once the leg's main branch is
    in) on a hinge at ``p + e`` of the near link, its end tied to the far link's
    ``p + e + b`` (``e = h x b``, normal to the hinges and the bar, ``|e| = |b|``).  With
    ``offsets`` (the bars' offsets ``o`` along the Pa's translation direction ``d``), one
    such bar at ``e = o d`` for each non-zero offset (a zero offset is the first bar).
    Returns the far link's joint and home point."""
    import pinocchio as pin
    h = np.asarray(j.hinge, float)
    p, b = np.asarray(j.point, float), np.asarray(j.bar, float)
    nb = float(np.linalg.norm(b))
    axes = h[None, :].copy()
    axes.setflags(write=False)
    ids = []
    for kind, par, at, rel, scale in (("bar", parent, p, p - parent_point, 1.0 / nb),
                                      ("bar_far", None, p + b, b, -1.0 / nb)):
        jid = model.addJoint(ids[0] if par is None else par, pin.JointModelRevoluteUnaligned(h),
                             pin.SE3(np.eye(3), rel), f"{prefix}{j.name}.{kind}")
        jm = model.joints[jid]
        ids.append(jid)
        blocks.append(JointBlock(kind, jid, (slot,), jm.idx_q, jm.nq, jm.idx_v, jm.nv, axes,
                                 scale, np.array(at, float)))
    d = np.asarray(j.direction, float)
    places = [np.cross(h, b)] if offsets is None else [o * d for o in offsets if o != 0]
    for n, e in enumerate(places):
        twins.append((j.name, slot, parent, parent_point, p, b, h, ids[1], axes, 1.0 / nb, e,
                      "" if n == 0 else str(n + 1)))
    return ids[1], p + b


def _add_twin(model, prefix, blocks, name, slot, parent, parent_point, p, b, h, far, axes,
              scale, e, suffix=""):
    """A second bar of a ``Pa`` at ``p + e`` (see :func:`_add_parallelogram`); returns its
    loop ``(twin joint, b, far joint, e)``: the same point ``p + e + b`` in each joint's
    frame."""
    import pinocchio as pin
    jid = model.addJoint(parent, pin.JointModelRevoluteUnaligned(h),
                         pin.SE3(np.eye(3), p + e - parent_point),
                         f"{prefix}{name}.bar_twin{suffix}")
    jm = model.joints[jid]
    blocks.append(JointBlock("bar_twin", jid, (slot,), jm.idx_q, jm.nq, jm.idx_v, jm.nv, axes,
                             scale, np.array(p + e, float)))
    return jid, b, far, e


def _check_home(model, chains, platform_home) -> None:
    """Pinocchio FK at the neutral configuration: each joint frame = (I, home point),
    each platform frame = the platform's home pose (the POE at q = 0)."""
    import pinocchio as pin
    data = model.createData()
    if not model.check(data):
        raise GeometryError("Pinocchio model/data consistency check failed")
    pin.framesForwardKinematics(model, data, pin.neutral(model))
    R_home, o_home = platform_home
    for ch in chains:
        L = max(ch.leg.length, 1e-300)
        for b in ch.blocks:
            M = data.oMi[b.joint_id]
            p = ch.leg.joints[b.sk[0]].point if b.origin is None else b.origin
            if np.abs(M.rotation - np.eye(3)).max() > _HOME_RTOL or \
                    np.linalg.norm(M.translation - p) > _HOME_RTOL * max(L, np.linalg.norm(p)):
                raise GeometryError(f"leg {ch.leg.name}: Pinocchio joint {b.joint_id} is not at its home point")
        F = data.oMf[ch.frame_id]
        R_f, p_f = (np.eye(3), ch.sphere_centre) if ch.truncated else (R_home, o_home)
        if np.abs(F.rotation - R_f).max() > _HOME_RTOL or \
                np.linalg.norm(F.translation - p_f) > _HOME_RTOL * max(L, np.linalg.norm(p_f)):
            raise GeometryError(f"leg {ch.leg.name}: Pinocchio platform frame is not at the home pose")


def build_leg_model(home_leg: Leg, platform_home=None, *, passive: bool = False) -> LegModel:
    """Pinocchio model of one serial leg with native joints (see module docstring).

    Parameters
    ----------
    home_leg : Leg
        The leg at its home geometry (joint values 0).
    platform_home : tuple (R (3, 3), p (3,)), optional
        Platform home pose; default ``(I, home_leg.a)``.
    passive : bool
        A leg without an actuator (every joint passive).

    Returns
    -------
    LegModel
    """
    import pinocchio as pin
    ph = as_pose(platform_home if platform_home is not None else (np.eye(3), home_leg.a), "platform_home")
    model = pin.Model()
    model.name = home_leg.name
    chain = _add_chain(model, home_leg, ph, "", passive=passive)
    _check_home(model, [chain], ph)
    return LegModel(model, chain, ph)


def build_closed_loop_model(home_legs, platform_home, *, point_contacts: bool = False,
                            passive=(), bar_offsets=None) -> ClosedLoopModel:
    """One Pinocchio model with every leg (depth first) and its loop closures.

    Every leg is a branch from the universe, added depth first in leg order.  The
    *carrier* leg's last link carries the platform: leg 1, or with
    ``point_contacts`` the first leg that does not end in an S (leg 1 if they all
    do).  Each other leg is tied to the platform on the carrier by a
    ``RigidConstraintModel`` (frame ``LOCAL`` of joint1):

    * ``CONTACT_6D`` between its platform frame and the carrier's;
    * with ``point_contacts``, a leg ending in a passive S loses that S and gets a
      ``CONTACT_3D`` between the S centre on its previous link and the same point
      of the platform (the S only makes the two coincide).

    Without ``point_contacts`` (the default) S-ended legs keep their S and get a 6-D
    closure: the S's rotations then show up in the Jacobian and its idle spin as a
    dependent joint (see :func:`screwkit.interop.mobility`).  Both models
    give the same platform mobility.

    Parameters
    ----------
    home_legs : sequence of Leg
    platform_home : tuple (R (3, 3), p (3,))
    point_contacts : bool
    passive : sequence of int
        0-based indices of the passive legs (no actuated joint).
    bar_offsets : mapping, optional
        ``{(leg, slot): offsets}`` (0-based): where a parallelogram's real bars are, each
        offset ``o`` a bar on the near link's hinge at ``p + o d`` (``p`` the Pa's point,
        ``d`` its translation direction at home; 0 is the chain's own bar), each other bar
        closed on the far link by a point contact (the bars' masses go on them, see
        :func:`screwkit.dynamics.check_dynamics`).  Default: one second bar at ``|b| d``.

    Returns
    -------
    ClosedLoopModel
    """
    import pinocchio as pin
    legs = tuple(home_legs)
    if len(legs) < 1:
        raise InputError("a closed-loop model needs at least one leg")
    ph = as_pose(platform_home, "platform_home")
    o_h = ph[1]

    def s_ended(lg):
        return lg.joints[-1].spec.origin == "S"

    carrier = 0
    if point_contacts:
        carrier = next((k for k, lg in enumerate(legs) if not s_ended(lg)), 0)
    model = pin.Model()
    passive = set(passive)
    offs = dict(bar_offsets or {})
    chains = tuple(_add_chain(model, lg, ph, f"leg{k + 1}.", point_contacts and k != carrier,
                              k in passive, {s: o for (i, s), o in offs.items() if i == k})
                   for k, lg in enumerate(legs))
    _check_home(model, chains, ph)
    c0 = chains[carrier]
    p0 = model.frames[c0.frame_id].placement          # platform frame in the carrier's end joint
    cons, owners = [], []
    for k, ch in enumerate(chains):
        if k == carrier:
            continue
        pk = model.frames[ch.frame_id].placement
        if ch.truncated:
            # the S centre as a point of the platform: home offset from the carrier's end joint
            # (the carrier's end-joint frame is world-oriented at home: c - p_end = c - o_h + p0.t)
            c_on_platform = pin.SE3(np.eye(3), ch.sphere_centre - o_h + p0.translation)
            cm = pin.RigidConstraintModel(pin.ContactType.CONTACT_3D, model, ch.end_joint, pk,
                                          c0.end_joint, c_on_platform, pin.ReferenceFrame.LOCAL)
        else:
            cm = pin.RigidConstraintModel(pin.ContactType.CONTACT_6D, model, ch.end_joint, pk,
                                          c0.end_joint, p0, pin.ReferenceFrame.LOCAL)
        cm.name = f"loop{k + 1}"
        cons.append(cm)
        owners.append(k)
    for k, ch in enumerate(chains):                     # the parallelograms' own loops
        for n, (j1, p1, j2, p2) in enumerate(ch.loops):
            cm = pin.RigidConstraintModel(pin.ContactType.CONTACT_3D, model, j1,
                                          pin.SE3(np.eye(3), p1), j2, pin.SE3(np.eye(3), p2),
                                          pin.ReferenceFrame.LOCAL)
            cm.name = f"leg{k + 1}.parallelogram{n + 1}"
            cons.append(cm)
            owners.append(k)
    return ClosedLoopModel(model, chains, tuple(cons), ph, carrier, tuple(owners))
