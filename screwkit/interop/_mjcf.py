"""MJCF export of a closed-loop PM (MuJoCo's model format): SI units, the loops closed by
weld equality constraints, the masses and inertias of the model's ``dynamics:`` block.

The tree is the URDF's (:mod:`screwkit.interop._urdf`): every leg a branch from the world
body, leg 1 carrying the platform.  Each letter of a leg string is one body, at its joint's
home point with the world's orientation, holding its joints: an R a ``hinge``, a P a
``slide``, a U two hinges (its cross), a C a slide and a hinge on one axis, an S one
``ball``, an H a hinge and a slide tied by a ``joint`` equality (slide = pitch x angle), a
Pa a bar body and its far body, each on a hinge, tied so that the far body only translates;
the bars the ``dynamics:`` block gives a Pa (``bars:``) each a body on the near body's hinge at
its offset, tied to turn with the Pa's bar (at offset 0, the Pa's bar body itself).
Joint names are the URDF's (``leg2_U1a``; an S is one ball ``leg1_S1``, the URDF's three
``leg1_S1a..c`` meeting at its centre).

The loops: legs 2..n end in a site ``leg<k>_end`` that a ``weld`` ties to the site
``platform_a<k>`` of the platform (both are the platform frame at ``a_k`` at home).  At
``qpos0`` every joint is at home (screwkit's joint values 0); keyframe 0 (``pose``) is the
exported pose solved by screwkit, so that the welds hold there too.  One ``motor`` per
actuated joint (``F_a1``...: ctrl is the actuator's force in N or torque in N.m).

Units: lengths in m, masses in kg, inertias in kg.m^2, time in s (:func:`si_factors`, the
model's declared units through pint).  Geoms (capsules along the legs, spheres at the S and
U centres, discs for the base and the platform) neither collide nor carry mass: the
inertias are the ``dynamics:`` block's, on the bodies of the links they name.  A link the
block leaves massless gets MuJoCo's ``boundmass`` (1e-6 kg) so that it can move.
"""

from __future__ import annotations

from xml.sax.saxutils import quoteattr

import numpy as np

from ..errors import InputError

__all__ = ["mjcf_text", "write_mjcf", "si_factors", "BOUND_MASS", "BOUND_INERTIA"]

#: The smallest mass (kg) and inertia (kg.m^2) of a moving body (MuJoCo's compiler bounds).
BOUND_MASS = 1e-6
BOUND_INERTIA = 1e-9


def si_factors(pm) -> dict:
    """Factors from the model's units to SI: ``length`` (m), ``mass`` (kg, the model's mass
    unit force.s^2/length), ``inertia`` (kg.m^2), ``force`` (N), ``torque`` (N.m)."""
    from ._si import SIConversion
    return SIConversion.of(pm).factors()          # the one conversion of every SI export


def _f(x) -> str:
    return f"{float(x):.12g}"


def _v(v) -> str:
    return " ".join(_f(x) for x in np.asarray(v, float).reshape(-1))


def _quat(R) -> np.ndarray:
    """(w, x, y, z) of a rotation matrix."""
    from scipy.spatial.transform import Rotation
    x, y, z, w = Rotation.from_matrix(np.asarray(R, float)).as_quat()
    return np.array([w, x, y, z])


def _rotvec_quat(axis, angle) -> np.ndarray:
    from scipy.spatial.transform import Rotation
    x, y, z, w = Rotation.from_rotvec(np.asarray(axis, float) * float(angle)).as_quat()
    return np.array([w, x, y, z])


def _inertial(body, origin, k) -> str:
    """An ``inertial`` element of a Body given in the world frame (home), in a body frame at
    ``origin`` with the world's orientation (model units in, SI out)."""
    I = np.asarray(body.inertia, float) * k["inertia"]
    full = [I[0, 0], I[1, 1], I[2, 2], I[0, 1], I[0, 2], I[1, 2]]
    return (f'<inertial pos="{_v((np.asarray(body.com) - origin) * k["length"])}" '
            f'mass="{_f(body.mass * k["mass"])}" fullinertia="{_v(full)}"/>')


class _Writer:
    """Writes the bodies of one leg and collects its joints, the keyframe's values, the
    equalities and the actuators."""

    def __init__(self, pm, k, radius):
        self.pm, self.k, self.r = pm, k, radius
        self.lines, self.eq, self.motors, self.qpos = [], [], [], []

    def add(self, depth, text):
        self.lines.append("  " * depth + text)

    def leg(self, i, leg, values, links, platform=None, bars=None):
        """Leg ``i`` (0-based) with its joint values at the exported pose (m,), its
        massive links ``{slot: Body (world)}`` and the bars of its parallelograms ``{slot:
        [(offset, Body (world))]}``."""
        k, L = self.k, self.k["length"]
        passive = tuple(getattr(self.pm, "passive", ()) or ())
        letters = leg.letters()
        ends = [js[0][1].point for _, js in letters[1:]] + [leg.a]
        parent, depth, opened = np.zeros(3), 2, 0
        for (letter, js), nxt in zip(letters, ends):
            j0 = js[0][1]
            here = np.asarray(j0.point, float)
            name = f"leg{i + 1}_{letter}{j0.spec.position}"
            own = None                            # the inertial of a bar on the Pa's own hinge
            if j0.spec.parallelogram:
                slot = js[0][0]
                own = self._bars(depth, i, j0, values[slot], parent, (bars or {}).get(slot, ()))
            self.add(depth, f'<body name={quoteattr(name)} pos="{_v((here - parent) * L)}">')
            if own is not None:
                self.add(depth + 1, _inertial(own, here, k))
            opened += 1
            slots = [s for s, _ in js]
            if j0.spec.parallelogram:             # the bar turns, the far body only translates
                theta = values[slots[0]] / np.linalg.norm(j0.bar)   # the value is the arc
                self._hinge(depth + 1, f"leg{i + 1}_{j0.name}", j0.hinge, j0, theta)
                self.add(depth + 1, f'<geom type="capsule" fromto="0 0 0 {_v(j0.bar * L)}" '
                         f'size="{_f(0.6 * self.r)}"/>')
                far = f"leg{i + 1}_{j0.name}_b"
                self.add(depth + 1, f'<body name={quoteattr(name + "_far")} '
                         f'pos="{_v(j0.bar * L)}">')
                self._hinge(depth + 2, far, j0.hinge, j0, -theta)
                self.eq.append(f'<joint name={quoteattr(far + "_tie")} joint1={quoteattr(far)} '
                               f'joint2={quoteattr(f"leg{i + 1}_{j0.name}")} '
                               'polycoef="0 -1 0 0 0"/>')
                depth += 1
                opened += 1
                here = here + j0.bar
            elif letter == "S":
                self.add(depth + 1, f'<joint name={quoteattr(name)} type="ball" pos="0 0 0"/>')
                q = np.array([1.0, 0.0, 0.0, 0.0])
                for s, j in js:                   # exp(a qa) exp(b qb) exp(c qc), home axes
                    q = _qmul(q, _rotvec_quat(j.direction, values[s]))
                self.qpos.extend(q.tolist())
                self.add(depth + 1, f'<geom type="sphere" size="{_f(2 * self.r)}"/>')
            else:
                for s, j in js:
                    jn = f"leg{i + 1}_{j.name}"
                    if j.kind == "P":
                        self.add(depth + 1, f'<joint name={quoteattr(jn)} type="slide" '
                                 f'pos="{_v((j.point - here) * L)}" axis="{_v(j.direction)}"/>')
                        self.qpos.append(values[s] * L)
                    else:
                        self._hinge(depth + 1, jn, j.direction, j, values[s], here)
                    if j.kind == "H":             # MuJoCo has no helical joint: a tied slide
                        sl = jn + "_slide"
                        self.add(depth + 1, f'<joint name={quoteattr(sl)} type="slide" '
                                 f'pos="0 0 0" axis="{_v(j.direction)}"/>')
                        self.qpos.append(j.pitch * values[s] * L)
                        self.eq.append(f'<joint name={quoteattr(sl + "_tie")} '
                                       f'joint1={quoteattr(sl)} joint2={quoteattr(jn)} '
                                       f'polycoef="0 {_f(j.pitch * L)} 0 0 0"/>')
                if letter == "U":
                    self.add(depth + 1, f'<geom type="sphere" size="{_f(1.5 * self.r)}"/>')
            d = (np.asarray(nxt, float) - here) * L
            if np.linalg.norm(d) > 1e-6 * self.r:
                self.add(depth + 1, f'<geom type="capsule" fromto="0 0 0 {_v(d)}" '
                         f'size="{_f(self.r)}"/>')
            if slots[-1] in links:
                self.add(depth + 1, _inertial(links[slots[-1]], here, k))
            for s in slots[:-1]:
                if s in links:
                    raise InputError(f"leg {i + 1} ({leg.name}): the link after joint "
                                     f"{leg.joints[s].name} is inside a compound joint")
            for s, j in js:
                if j.actuated and i not in passive:     # a passive leg drives nothing
                    if letter == "S":
                        raise InputError(f"leg {i + 1}: an actuated S has no MJCF motor")
                    self.motors.append((i, f"leg{i + 1}_{j.name}", j.kind))
            parent, depth = here, depth + 1
        self._end(depth, i, leg, parent, platform)
        for _ in range(opened):
            depth -= 1
            self.add(depth, "</body>")

    def _bars(self, depth, i, j, value, parent, bars):
        """The bars of a Pa beside its own (a body on the near link per bar off the Pa's
        hinge, at ``p + o d``, its hinge tied to the Pa's: a parallelogram's bars turn
        together); returns the body of a bar on the Pa's own hinge (offset 0), if any."""
        L, own = self.k["length"], None
        theta = value / np.linalg.norm(j.bar)
        for n, (o, body) in enumerate(bars):
            if o == 0:
                own = body
                continue
            at = np.asarray(j.point, float) + o * np.asarray(j.direction, float)
            jn = f"leg{i + 1}_{j.name}_bar{n + 1}"
            self.add(depth, f'<body name={quoteattr(jn)} pos="{_v((at - parent) * L)}">')
            self._hinge(depth + 1, jn, j.hinge, j, theta)
            self.add(depth + 1, f'<geom type="capsule" fromto="0 0 0 {_v(j.bar * L)}" '
                     f'size="{_f(0.6 * self.r)}"/>')
            self.add(depth + 1, _inertial(body, at, self.k))
            self.add(depth, "</body>")
            self.eq.append(f'<joint name={quoteattr(jn + "_tie")} joint1={quoteattr(jn)} '
                           f'joint2={quoteattr(f"leg{i + 1}_{j.name}")} polycoef="0 1 0 0 0"/>')
        return own

    def _hinge(self, depth, name, axis, joint, value, here=None):
        pos = np.zeros(3) if here is None else (np.asarray(joint.point) - here) * self.k["length"]
        self.add(depth, f'<joint name={quoteattr(name)} type="hinge" pos="{_v(pos)}" '
                 f'axis="{_v(axis)}"/>')
        self.qpos.append(float(value))

    def _end(self, depth, i, leg, here, platform):
        """The site of the leg's end (the platform frame at ``a`` at home), and, on leg 1,
        the platform body."""
        L = self.k["length"]
        R_home, o_home = self.pm.platform_home
        a = np.asarray(leg.a, float)
        self.add(depth, f'<site name="leg{i + 1}_end" pos="{_v((a - here) * L)}" '
                 f'quat="{_v(_quat(R_home))}" size="{_f(self.r)}"/>')
        if platform is None:
            return
        self.add(depth, f'<body name="platform" pos="{_v((o_home - here) * L)}" '
                 f'quat="{_v(_quat(R_home))}">')
        self.lines.extend("  " * (depth + 1) + x for x in platform)
        self.add(depth, "</body>")


def _qmul(p, q) -> np.ndarray:
    w1, x1, y1, z1 = p
    w2, x2, y2, z2 = q
    return np.array([w1 * w2 - x1 * x2 - y1 * y2 - z1 * z2, w1 * x2 + x1 * w2 + y1 * z2 - z1 * y2,
                     w1 * y2 - x1 * z2 + y1 * w2 + z1 * x2, w1 * z2 + x1 * y2 - y1 * x2 + z1 * w2])


def _parameters(pm, params, massless):
    if massless:
        if params is not None:
            raise InputError("give either masses (params / --mass) or massless, not both")
        return None
    if params is None:
        params = pm.dynamics
        if params is None:
            raise InputError(f"{pm.name} declares no masses (no 'dynamics:' block): MJCF needs "
                             "them; give a 'dynamics:' file (--mass FILE, docs/dynamics.md) or "
                             "export it massless (--massless)")
    from ..pm import DynamicsParameters, dynamics_for
    if not isinstance(params, DynamicsParameters):
        params = dynamics_for(pm, params)
    if len(params.legs) != pm.n_legs:
        raise InputError(f"the dynamics parameters have {len(params.legs)} legs, {pm.name} has "
                         f"{pm.n_legs}")
    return params


def mjcf_text(pm, joint_values=None, *, params=None, massless: bool = False,
              pose_note: str = "") -> str:
    """The MJCF (text) of ``pm`` (see the module docstring).

    Parameters
    ----------
    pm : PMModel
    joint_values : sequence of ndarray (m_i,), optional
        Every leg's joint values (0 at home, model units, radians) at the pose of keyframe
        0 (``PoseSolution.joint_values`` of one pose); default: home.
    params : DynamicsParameters, mapping or path, optional
        The masses and inertias (default: the model's ``dynamics:`` block).
    massless : bool
        Export without masses (every body at :data:`BOUND_MASS`).
    pose_note : str
        What the keyframe is (written in a comment and as the key's name's note).
    """
    k = si_factors(pm)
    params = _parameters(pm, params, massless)
    if joint_values is None:
        joint_values = [np.zeros(len(lg.joints)) for lg in pm.home_legs]
    R0, p0 = (np.asarray(x, float) for x in pm.frame)
    R_home, o_home = pm.platform_home
    scale = float(pm.normalisation.length)
    w = _Writer(pm, k, 0.02 * scale * k["length"])
    base_pts = np.asarray(pm.world_base_points, float)
    plat_pts = (np.asarray(R_home) @ np.asarray(pm.platform_points, float).T).T + o_home
    platform = [f'<geom type="cylinder" size="{_f(1.05 * np.max(np.linalg.norm(plat_pts - o_home, axis=1)) * k["length"])} {_f(0.01 * scale * k["length"])}" rgba="0.55 0.55 0.55 0.6"/>']  # noqa: E501
    if params is not None and not params.platform.massless:
        pb = params.platform
        I = np.asarray(pb.inertia, float) * k["inertia"]
        platform.append(f'<inertial pos="{_v(np.asarray(pb.com) * k["length"])}" '
                        f'mass="{_f(pb.mass * k["mass"])}" fullinertia="'
                        f'{_v([I[0, 0], I[1, 1], I[2, 2], I[0, 1], I[0, 2], I[1, 2]])}"/>')
    for n, a in enumerate(plat_pts):
        platform.append(f'<site name="platform_a{n + 1}" pos="{_v(R_home.T @ (a - o_home) * k["length"])}" '  # noqa: E501
                        f'size="{_f(w.r)}"/>')
    for i, leg in enumerate(pm.home_legs):
        links, bars = {}, {}
        if params is not None:
            links = {slot: body.moved(R0, p0) for slot, body in params.legs[i].links
                     if not body.massless}
            bars = {pair.slot: [(o, b.moved(R0, p0)) for o, b in zip(pair.offsets, pair.bodies)]
                    for pair in params.legs[i].bars}
        w.leg(i, leg, np.asarray(joint_values[i], float), links, platform if i == 0 else None,
              bars)
    # (massless: MuJoCo's default direction, standard gravity; a massless model feels none)
    g = (R0 @ params.gravity * k["length"]) if params is not None else np.array([0, 0, -9.80665])
    base_r = 1.05 * float(np.max(np.linalg.norm(base_pts - p0, axis=1))) * k["length"]
    loops = [f'<weld name="loop{i + 1}" site1="leg{i + 1}_end" site2="platform_a{i + 1}"/>'
             for i in range(1, pm.n_legs)]
    motors = [f'<motor name="{"T" if kind in "RH" else "F"}_a{i + 1}" joint={quoteattr(jn)} '
              f'gear="1"/>' for i, jn, kind in w.motors]
    out = [f'<mujoco model={quoteattr(pm.name)}>',
           f"  <!-- screwkit export of {pm.name} ({'+'.join(pm.legs)}): SI units (m, kg, s); "
           f"qpos0 = home (joint values 0); keyframe 0 = {pose_note or 'home'}; loops closed "
           "by weld equalities; masses: "
           + ("none (massless export)" if params is None else "the dynamics: block") + " -->",
           f'  <compiler angle="radian" autolimits="true" inertiafromgeom="false" '
           f'boundmass="{BOUND_MASS:g}" boundinertia="{BOUND_INERTIA:g}"/>',
           f'  <option gravity="{_v(g)}" integrator="implicitfast"/>',
           '  <default><geom contype="0" conaffinity="0" rgba="0.6 0.6 0.7 1"/></default>',
           "  <worldbody>",
           f'    <geom name="base" type="cylinder" pos="{_v(p0 * k["length"])}" '
           f'quat="{_v(_quat(R0))}" size="{_f(base_r)} {_f(0.01 * scale * k["length"])}" '
           'rgba="0.75 0.75 0.75 0.6"/>']
    out += w.lines
    out += ["  </worldbody>", "  <equality>"] + ["    " + e for e in loops + w.eq] + \
        ["  </equality>", "  <actuator>"] + ["    " + m for m in motors] + ["  </actuator>",
        "  <keyframe>", f'    <key name="pose" qpos="{_v(w.qpos)}"/>', "  </keyframe>",
        "</mujoco>", ""]
    return "\n".join(out)


def write_mjcf(pm, path, *, pose=None, degrees: bool = False, params=None,
               massless: bool = False) -> dict:
    """Write the MJCF of ``pm`` to ``path``, keyframe 0 at ``pose`` (independent pose
    parameters; default: the model's default pose), solved by the engine.

    Returns
    -------
    dict
        ``path``, ``pose`` (the six pose parameters, degrees for angles), ``joints``,
        ``equalities``, ``actuators``, ``masses`` (``dynamics:`` or ``none``).
    """
    from ..engine import solve_pose

    sol = solve_pose(pm, pose or {}, degrees=degrees)
    p = sol.params_degrees()
    note = "the pose " + ", ".join(f"{n}={float(p[n]):.6g}" for n in pm.independent)
    text = mjcf_text(pm, sol.joint_values, params=params, massless=massless, pose_note=note)
    from ._files import write_text
    out = write_text(path, text)
    ties = text.count('_tie"')
    return {"path": str(out), "pose": {n: float(v) for n, v in p.items()},
            "joints": text.count("<joint name=") - ties, "loops": text.count("<weld "),
            "ties": ties, "actuators": text.count("<motor "),
            "masses": "none" if params is None and massless else "dynamics:"}
