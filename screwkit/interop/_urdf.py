"""URDF export of a closed-loop PM, its loop closures in a sidecar file, and
:func:`to_pinocchio` (the Pinocchio model and its constraint models).

A URDF describes a tree, so :func:`urdf_text` writes the *spanning tree* of the PM:
every leg is a branch from the link ``base``, its 1-DOF joints in order (an S is three
``revolute`` joints and a U two, through massless intermediate links, as screwkit's
equivalent chain; a C is a ``prismatic`` then a ``revolute`` joint on the same axis); leg 1
carries the link ``platform`` on a ``fixed`` joint.  Every joint frame sits at its joint's
home point with the base orientation, so each joint ``origin`` is a pure translation and
its ``axis`` the joint's home direction; joint values are 0 at home, as in screwkit.

A parallelogram ``Pa`` is its real four-bar: the first bar (joint ``leg<i>_Pa<k>_bar``), the
far link turning back with it (``_far``, a URDF ``mimic`` of the bar, multiplier -1, so that
it translates) and the second bar from the near link (``_twin``, a mimic of the bar).

The loops (legs 2..n meet the platform) are in a JSON sidecar (:func:`closures`): one
6-D rigid contact per leg between a frame on the leg's last joint and the same platform
frame on leg 1's last joint, and one 3-D point contact per parallelogram (the end of its
second bar on the far link; ``contact_type`` in the constraint's entry), the arguments of
``pinocchio.RigidConstraintModel``::

    import json, numpy as np, pinocchio as pin
    model = pin.buildModelFromUrdf("pm.urdf")
    loops = json.load(open("pm.closures.json"))
    se3 = lambda p: pin.SE3(np.array(p["rotation"]), np.array(p["translation"]))
    kind = lambda c: getattr(pin.ContactType, c.get("contact_type", loops["contact_type"]))
    constraints = [pin.RigidConstraintModel(kind(c), model,
                       model.getJointId(c["joint1"]), se3(c["placement1"]),
                       model.getJointId(c["joint2"]), se3(c["placement2"]),
                       pin.ReferenceFrame.LOCAL) for c in loops["constraints"]]

Visual geometry is simple: a cylinder along each link between consecutive joint points, a
sphere at each S or U centre, a thin disc for the base and for the platform (sized from
their vertices).

Units are URDF's: metres, kilograms, radians (:mod:`~._si` converts the model's, through
pint; a model that declares no units cannot be exported).  The links' ``<inertial>``
elements are the masses and inertias of the model's ``dynamics:`` block (or of the
``params`` given), each about its centre of mass in its link's frame; without one every
link is massless, and the file's header comment says so.
"""

from __future__ import annotations

import json
import math
from xml.sax.saxutils import quoteattr

import numpy as np

from ..errors import InputError

__all__ = ["urdf_text", "closures", "write_urdf", "to_pinocchio", "NO_LIMIT"]

#: The joints' effort and velocity limits (SI): a model has none, and URDF requires them
#: (0, as written before, reads as no effort and no motion allowed to tools that apply them).
NO_LIMIT = 1e12


def _f(x) -> str:
    return f"{float(x):.12g}"


def _vec(v) -> str:
    return " ".join(_f(x) for x in v)


def _rpy(R) -> tuple:
    """URDF roll-pitch-yaw (fixed X, Y, Z) of a rotation matrix."""
    from scipy.spatial.transform import Rotation
    return tuple(Rotation.from_matrix(np.asarray(R, float)).as_euler("xyz"))


def _z_to(d) -> tuple:
    """rpy of a rotation taking z to the unit vector ``d`` (a URDF cylinder lies along z)."""
    from scipy.spatial.transform import Rotation
    d = np.asarray(d, float)
    z = np.array([0.0, 0.0, 1.0])
    axis = np.cross(z, d)
    s, c = np.linalg.norm(axis), float(z @ d)
    if s < 1e-12:
        return (math.pi, 0.0, 0.0) if c < 0 else (0.0, 0.0, 0.0)
    import warnings
    with warnings.catch_warnings():      # a cylinder along +-x: any roll of it is the same
        warnings.simplefilter("ignore")
        return tuple(Rotation.from_rotvec(axis / s * math.atan2(s, c)).as_euler("xyz"))


def _cylinder(p, q, radius, origin_at) -> str:
    """A cylinder from ``p`` to ``q`` (world, home) in the frame of a link at ``origin_at``."""
    d = np.asarray(q, float) - np.asarray(p, float)
    L = float(np.linalg.norm(d))
    if L <= 0:
        return ""
    mid = 0.5 * (np.asarray(p, float) + np.asarray(q, float)) - origin_at
    return (f'    <visual><origin xyz="{_vec(mid)}" rpy="{_vec(_z_to(d / L))}"/>'
            f'<geometry><cylinder radius="{_f(radius)}" length="{_f(L)}"/></geometry></visual>\n')


def _sphere(p, radius, origin_at) -> str:
    return (f'    <visual><origin xyz="{_vec(np.asarray(p, float) - origin_at)}" rpy="0 0 0"/>'
            f'<geometry><sphere radius="{_f(radius)}"/></geometry></visual>\n')


def _disc(centre, R, radius, thickness, origin_at) -> str:
    return (f'    <visual><origin xyz="{_vec(np.asarray(centre, float) - origin_at)}" '
            f'rpy="{_vec(_rpy(R))}"/><geometry><cylinder radius="{_f(radius)}" '
            f'length="{_f(thickness)}"/></geometry></visual>\n')


def _se3(R, t) -> dict:
    return {"rotation": np.asarray(R, float).tolist(), "translation": np.asarray(t, float).tolist()}


def _joint_name(k: int, joint) -> str:
    return f"leg{k + 1}_{joint.name}"


def _tree(pm):
    """Per leg: ``[(joint, urdf joint name, point, direction, kind)]`` with checks.  A ``Pa``
    is its four-bar: the first bar (``<name>_bar``), the far link turning back with it
    (``<name>_far``, a mimic of the bar with multiplier -1) in the chain, and the second bar
    (``<name>_twin``) from the near link, listed by :func:`_twins`."""
    out = []
    for k, leg in enumerate(pm.home_legs):
        rows = []
        for j in leg.joints:
            if j.kind == "H":
                raise InputError(f"leg {k + 1} ({leg.name}): URDF has no helical joint "
                                 f"({j.name}); export a model without H joints")
            p, d = np.asarray(j.point, float), np.asarray(j.direction, float)
            if j.spec.parallelogram:
                h = np.asarray(j.hinge, float)
                rows.append((j, _joint_name(k, j) + "_bar", p, h, "revolute"))
                rows.append((j, _joint_name(k, j) + "_far", p + np.asarray(j.bar, float), h,
                             "revolute"))
                continue
            rows.append((j, _joint_name(k, j), p, d, "revolute" if j.kind == "R" else "prismatic"))
        out.append(rows)
    return out


def _twins(rows):
    """The second bars of a leg's parallelograms: ``(joint, name, parent link, parent point,
    point, hinge, bar, e)`` with ``e = h x b`` (the near link's second hinge at ``p + e``)."""
    out = []
    for r, (j, name, p, h, _) in enumerate(rows):
        if name.endswith("_bar"):
            parent = ("base", np.zeros(3)) if r == 0 else (f"{rows[r - 1][1]}_link", rows[r - 1][2])
            b = np.asarray(j.bar, float)
            e = np.cross(h, b)
            out.append((j, name[:-4] + "_twin", parent[0], parent[1], p + e, h, b, e))
    return out


def _last_rows(rows) -> list:
    """The last row of each equivalent joint in a leg's rows (the link after it)."""
    out, seen = [], []
    for r, (j, *_rest) in enumerate(rows):
        if seen and seen[-1] is j:
            out[-1] = r
        else:
            seen.append(j)
            out.append(r)
    return out


def _slot_rows(rows) -> list:
    """The row of each equivalent joint (a ``Pa``'s first bar) in a leg's rows."""
    out, seen = [], set()
    for r, (j, name, *_rest) in enumerate(rows):
        if id(j) not in seen:
            seen.add(id(j))
            out.append(r)
    return out


def _inertial(body, origin_at) -> str:
    """The ``<inertial>`` of an :class:`~._si.SIBody` in a link frame at ``origin_at`` (world
    axes; the platform's in its own frame)."""
    c = np.asarray(body.com, float) - origin_at
    I = np.asarray(body.inertia, float)
    return (f'    <inertial><origin xyz="{_vec(c)}" rpy="0 0 0"/><mass value="{_f(body.mass)}"/>'
            f'<inertia ixx="{_f(I[0, 0])}" ixy="{_f(I[0, 1])}" ixz="{_f(I[0, 2])}" '
            f'iyy="{_f(I[1, 1])}" iyz="{_f(I[1, 2])}" izz="{_f(I[2, 2])}"/></inertial>\n')


def urdf_text(pm, params=None) -> str:
    """The URDF (text) of the spanning tree of ``pm`` at its home pose, in metres and
    kilograms, with the link inertias of ``params`` (default: the model's ``dynamics:``
    block; none without one) (module docstring)."""
    from ._si import SIConversion, si_bodies

    si = SIConversion.of(pm)
    k = si.length
    bodies, note = si_bodies(pm, params)
    by_slot = {(b.leg, b.slot): b for b in bodies if b.leg is not None}
    plat_body = next((b for b in bodies if b.leg is None), None)
    R_home, o_home = pm.platform_home
    o_home = o_home * k
    scale = (float(pm.normalisation.length) or 1.0) * k
    r_link = 0.02 * scale
    base_pts = pm.world_base_points * k
    plat_pts = (R_home @ pm.platform_points.T).T * k + o_home
    R0, p0 = pm.frame
    p0 = np.asarray(p0, float) * k
    lines = [f'<?xml version="1.0"?>\n<robot name={quoteattr(pm.name)}>\n',
             f"  <!-- screwkit export of {pm.name} ({'+'.join(pm.legs)}), home pose; lengths "
             f"in m (the model's {pm.units.length} x {k:g}), masses in kg, angles in rad; "
             f"{note}; loop closures in the .closures.json sidecar; joint effort and velocity "
             f"limits are not part of the model: {NO_LIMIT:g} (none) -->\n",
             '  <link name="base">\n',
             _disc(p0, R0, float(np.max(np.linalg.norm(base_pts - p0, axis=1))) * 1.05,
                   0.02 * scale, np.zeros(3)),
             "  </link>\n"]
    trees = _tree(pm)
    for k_leg, rows in enumerate(trees):
        leg = pm.home_legs[k_leg]
        parent, parent_point = "base", np.zeros(3)
        ends = [r[2] * k for r in rows[1:]] + [np.asarray(leg.a, float) * k]
        slot_of = {r: s for s, r in enumerate(_last_rows(rows))}   # a Pa: its far link
        for row, ((j, name, p, d, kind), nxt) in enumerate(zip(rows, ends)):
            p = p * k
            child = f"{name}_link"
            big = 10.0 * scale
            lo, hi = (-math.pi, math.pi) if kind == "revolute" else (-big, big)
            lines.append(f'  <joint name="{name}" type="{kind}">\n'
                         f'    <parent link="{parent}"/><child link="{child}"/>\n'
                         f'    <origin xyz="{_vec(p - parent_point)}" rpy="0 0 0"/>'
                         f'<axis xyz="{_vec(d)}"/>\n'
                         f'    <limit lower="{_f(lo)}" upper="{_f(hi)}" effort="{NO_LIMIT:g}" '
                         f'velocity="{NO_LIMIT:g}"/>\n'
                         f"  </joint>\n")
            if name.endswith("_far"):                    # the far link translates
                lines[-1] = lines[-1].replace("  </joint>", f'    <mimic joint="{name[:-4]}_bar" '
                                              'multiplier="-1" offset="0"/>\n  </joint>')
            visual = _cylinder(p, nxt, (1.6 if kind == "prismatic" else 1.0) * r_link, p)
            if j.spec.origin in "SU" and j.name.endswith("a"):
                visual += _sphere(p, 2.0 * r_link, p)
            body = by_slot.get((k_leg, slot_of.get(row)))
            inertial = "" if body is None else _inertial(body, p)
            lines.append(f'  <link name="{child}">\n{inertial}{visual}  </link>\n')
            parent, parent_point = child, p
        for (j, name, par, par_pt, p, h, b, e) in _twins(rows):   # the parallelograms' second bars
            p, par_pt, b = p * k, par_pt * k, b * k                  # (metres)
            lines.append(f'  <joint name="{name}" type="revolute">\n'
                         f'    <parent link="{par}"/><child link="{name}_link"/>\n'
                         f'    <origin xyz="{_vec(p - par_pt)}" rpy="0 0 0"/><axis xyz="{_vec(h)}"/>\n'
                         f'    <limit lower="{_f(-math.pi)}" upper="{_f(math.pi)}" '
                         f'effort="{NO_LIMIT:g}" velocity="{NO_LIMIT:g}"/>\n'
                         f'    <mimic joint="{name[:-5]}_bar" multiplier="1" '
                         f'offset="0"/>\n  </joint>\n')
            lines.append(f'  <link name="{name}_link">\n{_cylinder(p, p + b, r_link, p)}'
                         f'  </link>\n')
        if k_leg == 0:
            lines.append(f'  <joint name="platform_fixed" type="fixed">\n'
                         f'    <parent link="{parent}"/><child link="platform"/>\n'
                         f'    <origin xyz="{_vec(o_home - parent_point)}" '
                         f'rpy="{_vec(_rpy(R_home))}"/>\n  </joint>\n')
            rad = float(np.max(np.linalg.norm(plat_pts - o_home, axis=1))) * 1.05
            lines.append('  <link name="platform">\n'
                         + ("" if plat_body is None else _inertial(plat_body, np.zeros(3)))
                         + _disc(np.zeros(3), np.eye(3), rad, 0.02 * scale, np.zeros(3))
                         + "  </link>\n")
    lines.append("</robot>\n")
    return "".join(lines)


def closures(pm, urdf_name: str = "") -> dict:
    """The loop closures of :func:`urdf_text`'s tree (JSON-ready): one ``CONTACT_6D`` per leg
    2..n, ``joint1`` its last joint, ``joint2`` leg 1's last joint, ``placement1/2`` the
    platform frame in each joint's frame (rotation (3, 3), translation (3,) in metres, as
    the URDF); and one ``CONTACT_3D`` per parallelogram (its second bar's loop)."""
    from ._si import SIConversion

    m = SIConversion.of(pm).length                  # metres per model length
    R_home, o_home = pm.platform_home
    o_home = o_home * m
    trees = [[(j, name, p * m, d, kind) for j, name, p, d, kind in rows] for rows in _tree(pm)]
    last = [rows[-1] for rows in trees]
    carrier = last[0]
    cons = []
    for i in range(1, len(trees)):
        j1 = last[i]
        cons.append({"name": f"loop{i + 1}", "leg": i + 1, "joint1": j1[1],
                     "placement1": _se3(R_home, o_home - j1[2]), "joint2": carrier[1],
                     "placement2": _se3(R_home, o_home - carrier[2])})
    for i, rows in enumerate(trees):                  # each parallelogram's own loop
        for (j, name, *_rest, b, e) in _twins(rows):
            cons.append({"name": f"{name[:-5]}_loop", "leg": i + 1, "contact_type": "CONTACT_3D",
                         "joint1": name, "placement1": _se3(np.eye(3), b * m),
                         "joint2": name[:-5] + "_far", "placement2": _se3(np.eye(3), e * m)})
    passive = tuple(getattr(pm, "passive", ()))
    actuated = [rows[_slot_rows(rows)[pm.home_legs[i].actuated_index]][1]
                for i, rows in enumerate(trees)
                if i not in passive]                  # a passive leg has no actuated joint
    return {"format": "screwkit-closures/1", "urdf": urdf_name, "pm": pm.name,
            "units": {"length": "m", "angle": "rad", "model_length": pm.units.length,
                      "metres_per_model_length": m},
            "contact_type": "CONTACT_6D", "reference_frame": "LOCAL",
            "constraints": cons, "actuated_joints": actuated,
            "passive_legs": [i + 1 for i in passive],
            "platform_frame": "platform", "carrier_leg": 1}


def write_urdf(pm, path, params=None) -> tuple:
    """Write ``path`` (URDF, SI, with the inertias of ``params`` or the model's
    ``dynamics:`` block) and ``<stem>.closures.json`` beside it; returns both paths."""
    from pathlib import Path

    from ._files import write_text
    p = Path(path)
    side = p.with_name(p.stem + ".closures.json")
    write_text(p, urdf_text(pm, params))
    write_text(side, json.dumps(closures(pm, p.name), indent=2) + "\n")
    return str(p), str(side)


def to_pinocchio(pm, *, point_contacts: bool = False):
    """The Pinocchio model of ``pm`` and its loop-closure constraint models.

    Parameters
    ----------
    pm : PMModel
    point_contacts : bool
        Tie legs ending in a passive S by a 3-D point contact instead of a 6-D one (see
        :func:`build_closed_loop_model`).

    Returns
    -------
    ClosedLoopModel
        ``.model`` (``pinocchio.Model``, joint values 0 at home), ``.constraints`` (tuple of
        ``pinocchio.RigidConstraintModel``), ``.chains``, ``.q(joint_values)``.
    """
    from ._pinocchio_model import build_closed_loop_model
    return build_closed_loop_model(pm.home_legs, pm.platform_home, point_contacts=point_contacts,
                                   passive=getattr(pm, "passive", ()))
