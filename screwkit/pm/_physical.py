"""The ``dynamics:`` block of a PM definition: masses, inertias, friction, gravity, stiffness.

::

    dynamics:
      units: {mass: kg, length: cm, force: N}   # the block's units (time in s); default kg,
                                                # the model's length unit, N
      gravity: [0, 0, -981]                     # length/s^2, base frame; default standard
                                                # gravity (9.80665 m/s^2) along -Z
      platform:
        mass: 25
        com: [0, 0, 0]                          # in {o}; default o
        inertia: [0.5, 0.5, 0.9]                # about the com, platform axes: 3 principal
                                                # moments, a 3x3 matrix, or {disc: {radius: r,
                                                # thickness: h}} (axis z of the platform)
      legs:                                     # one mapping for every leg, or a list (one per leg)
        cylinder: {mass: 3, length: 40, radius: 3}   # linear legs: the link before the actuated
        piston: {mass: 1.5, length: 40, radius: 2}   # P (from A along the leg), the link after it
                                                     # (from a back along the leg); inner_radius: tubes
        links:                                  # any leg: the link after a letter of its string
          R1: {mass: 1, com: 0.3, inertia: {rod: 20}}  # com: [x, y, z] (base frame, home) or a
                                                # fraction f (A + f (a - A) at home); inertia:
                                                # moments/3x3 in the base axes, {rod: length} or
                                                # {cylinder: {length: l, radius: r}} along the leg
        friction: {P: {viscous: 100, coulomb: 5}, R1: {viscous: 0.5}}   # by joint name or kind
        bars: {Pa3: {mass: 0.05, width: 40, inertia: {rod: 180}}}   # a parallelogram's two
                                                # bars (screwkit.pm._bars)
      stiffness:                                # one mapping for every leg, or a list
        actuator: 2.0e6                         # force/length (torque/rad for rotary actuators)
        force: 5.0e6                            # each constraint force row (force/length)
        couple: 1.0e9                           # each constraint couple row (torque/rad)
        beam: {E: 2.1e7, G: 8.1e6, area: 12, I: 40, J: 80}   # the missing ones from a beam

Every number may be an expression of the model's dimensions (``L/2``), which are in the
model's length unit.  The block is converted to the model's consistent units
(:meth:`Units.factor`, through pint) when it is read: the catalog's cm and kN make 1 kg
= 1e-5 kN.s^2/cm and 1 kg.m^2 = 0.1 kN.s^2.cm.  A model that declares no units takes the
block's numbers as they are only with ``units: model``.
"""

from __future__ import annotations

import numpy as np

from ..errors import CatalogError, InputError
from ..legs._guards import MAX_MAGNITUDE, shorten
from ..screws import GEOMETRY_RTOL
from ._bars import read_bars
from ._inertia import (NO_BODY, Body, DynamicsParameters, LegDynamics, LegStiffness,
                       check_inertia, cylinder_body)
from ._leg_stiffness import _BEAM_KEYS, _STIFF_KEYS, _per_leg, _stiffness  # noqa: F401

__all__ = ["dynamics_from_mapping", "dynamics_for", "STANDARD_GRAVITY"]

#: Standard gravity, m/s^2.
STANDARD_GRAVITY = 9.80665

_BLOCK_KEYS = {"units", "gravity", "platform", "legs", "stiffness"}
_LEG_KEYS = {"cylinder", "piston", "links", "friction", "bars"}


class _Reader:
    """Reads numbers of the block and converts them to the model's units."""

    def __init__(self, name, source, dims, factors):
        self.name, self.source, self.dims = name, source, dict(dims or {})
        self.f = factors                      # mass, length, force factors (time: s)
        self.problems = None                  # a list: collect the numbers' problems

    def err(self, msg, fld):
        return CatalogError(msg, self.name, f"dynamics.{fld}" if fld else "dynamics", self.source)

    def num(self, v, fld, *, mass=0, length=0, force=0, time=0, positive=False,
            bound=MAX_MAGNITUDE) -> float:
        """A number of the block (an expression of the dimensions, or a number), at most
        ``bound`` in magnitude as written, in the model's units; with ``problems`` a list,
        a bad number is recorded there and read as 1 (the other fields are checked on)."""
        try:
            return self._num(v, fld, mass, length, force, positive, bound)
        except CatalogError as exc:
            if self.problems is None:
                raise
            self.problems.append(exc)
            return 1.0

    def _num(self, v, fld, mass, length, force, positive, bound) -> float:
        from ._expressions import parse_expression
        if isinstance(v, bool) or not isinstance(v, (int, float, str)):
            raise self.err(f"must be a number or an expression, got {shorten(v)}", fld)
        if isinstance(v, str):
            try:
                v = parse_expression(v, tuple(self.dims))(**self.dims)
            except InputError as exc:
                raise self.err(str(exc), fld) from None
        try:
            x = float(v)
        except OverflowError:
            x = float("inf")
        if not np.isfinite(x) or (positive and x < 0):
            raise self.err(f"must be a finite{' non-negative' if positive else ''} number, "
                           f"got {shorten(v, 40) if isinstance(v, str) else format(x, 'g')}",
                           fld)
        if abs(x) > bound:
            raise self.err(f"{x:g} is beyond the limit +-{bound:g}", fld)
        fm, fl, ff = self.f
        y = x * fm ** mass * fl ** length * ff ** force
        if x != 0 and not (0 < abs(y) <= bound * 1e6):
            raise self.err(f"{x:g} is {y:g} in the model's units: out of range", fld)
        return y

    def vec(self, v, fld, **dim) -> np.ndarray:
        if not (isinstance(v, (list, tuple)) and len(v) == 3):
            raise self.err("must be a list of 3 numbers", fld)
        return np.array([self.num(x, f"{fld}[{k}]", **dim) for k, x in enumerate(v)])

    def mapping(self, v, fld, keys, required=()) -> dict:
        if not isinstance(v, dict):
            raise self.err(f"must be a mapping with keys among {', '.join(sorted(keys))}", fld)
        bad = sorted(set(v) - set(keys))
        if bad:
            raise self.err(f"unknown key(s) {bad} (allowed: {', '.join(sorted(keys))})", fld)
        for k in required:
            if k not in v:
                raise self.err(f"missing {k!r}", fld)
        return v


def _factors(raw, units, r: _Reader):
    """``(mass, length, force)`` factors from the block's ``units:`` to the model's."""
    if raw == "model":
        return (1.0, 1.0, 1.0), "in the model's consistent units (units: model)"
    block = {"mass": "kg", "length": units.length if units.declared else "m", "force": "N"}
    if raw is not None:
        r.mapping(raw, "units", ("mass", "length", "force"))
        block.update({k: str(v) for k, v in raw.items()})
    try:
        f = (units.factor(block["mass"], "mass"), units.factor(block["length"], "length"),
             units.factor(block["force"], "force"))
    except InputError as exc:
        raise r.err(f"{exc} (or write the block in the model's units with 'units: model')",
                    "units") from None
    return f, (f"converted from {block['mass']}, {block['length']}, {block['force']}, s to "
               f"{units.mass}, {units.length}, {units.force}, s")


def _inertia(v, fld, r: _Reader, mass, axis=None, length_hint=None):
    """An inertia about the centre of mass: moments, a 3x3 matrix, {disc: ...},
    {rod: l}, {cylinder: {length, radius}} (the last two along ``axis``)."""
    if v is None:
        return np.zeros((3, 3))
    if isinstance(v, dict):
        kind, spec = next(iter(v.items())) if len(v) == 1 else (None, None)
        if kind == "disc":
            s = r.mapping(spec, f"{fld}.disc", ("radius", "thickness"), ("radius",))
            rad = r.num(s["radius"], f"{fld}.disc.radius", length=1, positive=True)
            h = r.num(s.get("thickness", 0), f"{fld}.disc.thickness", length=1, positive=True)
            return cylinder_body(mass, np.zeros(3), [0, 0, 1], length=h, radius=rad).inertia
        if kind in ("rod", "cylinder") and axis is not None:
            if kind == "rod":
                ln, rad = r.num(spec, f"{fld}.rod", length=1, positive=True), 0.0
            else:
                s = r.mapping(spec, f"{fld}.cylinder", ("length", "radius"), ("length",))
                ln = r.num(s["length"], f"{fld}.cylinder.length", length=1, positive=True)
                rad = r.num(s.get("radius", 0), f"{fld}.cylinder.radius", length=1, positive=True)
            return cylinder_body(mass, np.zeros(3), axis, length=ln, radius=rad).inertia
        raise r.err("must be 3 principal moments, a 3x3 matrix or "
                    + ("{disc: {radius, thickness}}" if axis is None else
                       "{rod: length} or {cylinder: {length, radius}}"), fld)
    a = np.asarray(v, dtype=object)
    if a.shape == (3,):
        I = np.diag([r.num(x, f"{fld}[{k}]", mass=1, length=2) for k, x in enumerate(v)])
    elif a.shape == (3, 3):
        I = np.array([[r.num(x, f"{fld}[{i}][{j}]", mass=1, length=2) for j, x in enumerate(row)]
                      for i, row in enumerate(v)])
    else:
        raise r.err("must be 3 principal moments or a 3x3 matrix", fld)
    try:
        return check_inertia(I, mass, "", shown=self_factor(r))
    except InputError as exc:
        raise r.err(str(exc).lstrip(": "), fld) from None


def self_factor(r: _Reader) -> float:
    """The factor from an inertia as the block writes it to the model's units."""
    fm, fl, _ = r.f
    return fm * fl ** 2


def _platform(v, r: _Reader) -> Body:
    if v is None:
        return NO_BODY
    s = r.mapping(v, "platform", ("mass", "com", "inertia"), ("mass",))
    m = r.num(s["mass"], "platform.mass", mass=1, positive=True)
    com = r.vec(s["com"], "platform.com", length=1) if s.get("com") is not None else np.zeros(3)
    I = _inertia(s.get("inertia"), "platform.inertia", r, m)
    return Body(m, com, I, "platform")


def _letters(leg):
    """``{letter name: last slot}`` of a leg (``R1``, ``U2``, ``S3``, ``P3``...)."""
    return {f"{letter}{js[0][1].spec.position}": js[-1][0] for letter, js in leg.letters()}


def _linear_link(spec, fld, r, leg, which) -> tuple:
    """The default cylinder (link before the actuated P, from A) or piston (after it, from
    a) of a linear leg, as ``(slot, Body)`` or None when it is the base or the platform."""
    act = leg.actuated_index
    j = leg.joints[act]
    u = leg.a - leg.A
    L = float(np.linalg.norm(u))
    u = u / L
    if j.kind != "P" or j.spec.origin != "P" or abs(abs(float(u @ j.direction)) - 1) > \
            10 * GEOMETRY_RTOL:
        raise r.err(f"leg {leg.name}: '{which}' needs an actuated P joint along the leg line "
                    "A -> a; give its links with 'links:'", fld)
    s = r.mapping(spec, fld, ("mass", "length", "radius", "inner_radius"), ("mass", "length"))
    m = r.num(s["mass"], f"{fld}.mass", mass=1, positive=True)
    ln = r.num(s["length"], f"{fld}.length", length=1, positive=True)
    rad = r.num(s.get("radius", 0), f"{fld}.radius", length=1, positive=True)
    rin = r.num(s.get("inner_radius", 0), f"{fld}.inner_radius", length=1, positive=True)
    if rin > rad:
        raise r.err("inner_radius is larger than radius", fld)
    if which == "cylinder":
        slot, com = act - 1, leg.A + 0.5 * ln * u
    else:
        slot, com = act, leg.a - 0.5 * ln * u
    if slot < 0 or slot >= len(leg.joints) - 1:
        return None, f"leg {leg.name}: the {which} is part of the {'base' if slot < 0 else 'platform'}"
    return (slot, cylinder_body(m, com, u, length=ln, radius=rad, inner_radius=rin,
                                name=which)), None


def _links(v, fld, r, leg) -> dict:
    letters = _letters(leg)
    r.mapping(v, fld, tuple(letters))
    out = {}
    last = len(leg.joints) - 1
    u = (leg.a - leg.A) / max(np.linalg.norm(leg.a - leg.A), 1e-300)
    for name, spec in v.items():
        f = f"{fld}.{name}"
        slot = letters[name]
        if slot == last:
            raise r.err(f"the link after the last joint {name} is the platform (give it under "
                        "'platform')", f)
        s = r.mapping(spec, f, ("mass", "com", "inertia"), ("mass",))
        m = r.num(s["mass"], f"{f}.mass", mass=1, positive=True)
        c = s.get("com", 0.5)
        if isinstance(c, (list, tuple)):
            com = r.vec(c, f"{f}.com", length=1)
        else:
            frac = r.num(c, f"{f}.com")
            com = leg.A + frac * (leg.a - leg.A)
        out[slot] = Body(m, com, _inertia(s.get("inertia"), f"{f}.inertia", r, m, axis=u),
                         f"after {name}")
    return out


def _friction(v, fld, r, leg):
    m = len(leg.joints)
    visc, coul = np.zeros(m), np.zeros(m)
    if v is None:
        return visc, coul
    names = [j.name for j in leg.joints]
    kinds = sorted({j.kind for j in leg.joints})
    r.mapping(v, fld, names + kinds)
    order = sorted(v, key=lambda k: k in names)          # kinds first, joint names override
    for key in order:
        f = f"{fld}.{key}"
        s = r.mapping(v[key], f, ("viscous", "coulomb"))
        for k, j in enumerate(leg.joints):
            if key not in (j.name, j.kind):
                continue
            lin = j.kind == "P"           # P: force; R, H: torque (per rad)
            if "viscous" in s:
                visc[k] = r.num(s["viscous"], f"{f}.viscous", force=1, time=1,
                                length=-1 if lin else 1, positive=True)
            if "coulomb" in s:
                coul[k] = r.num(s["coulomb"], f"{f}.coulomb", force=1, length=0 if lin else 1,
                                positive=True)
    return visc, coul


def _leg(v, fld, r, leg, stiff) -> LegDynamics:
    m = len(leg.joints)
    if v is None:
        return LegDynamics((), np.zeros(m), np.zeros(m), stiff)
    s = r.mapping(v, fld, _LEG_KEYS)
    links, notes = {}, []
    for which in ("cylinder", "piston"):
        if s.get(which) is not None:
            link, note = _linear_link(s[which], f"{fld}.{which}", r, leg, which)
            if link is not None:
                links[link[0]] = link[1]
            if note:
                notes.append(note)
    if s.get("links") is not None:
        for slot, body in _links(s["links"], f"{fld}.links", r, leg).items():
            if slot in links:
                raise r.err(f"leg {leg.name}: the link after joint {leg.joints[slot].name} is "
                            "given twice (cylinder/piston and links)", f"{fld}.links")
            links[slot] = body
    visc, coul = _friction(s.get("friction"), f"{fld}.friction", r, leg)
    bars = () if s.get("bars") is None else read_bars(s["bars"], f"{fld}.bars", r, leg, _inertia)
    return LegDynamics(tuple(sorted(links.items(), key=lambda x: x[0])), visc, coul, stiff,
                       tuple(notes), bars)


def dynamics_from_mapping(raw, name, source, dimensions, home_legs, units):
    """Read a ``dynamics:`` block (module docstring) into :class:`DynamicsParameters`.

    Parameters
    ----------
    raw : mapping or None
    name, source : str
        The PM and its file, for messages.
    dimensions : dict
        The model's dimensions (names usable in expressions, model length unit).
    home_legs : sequence of Leg
        The legs at home (base frame).
    units : Units
        The model's units.

    Returns
    -------
    DynamicsParameters or None
        None when ``raw`` is None.

    Raises
    ------
    CatalogError
        Naming the PM and the field (``dynamics.legs[1].piston.mass``).
    """
    if raw is None:
        return None
    r = _Reader(name, source, dimensions, (1.0, 1.0, 1.0))
    r.mapping(raw, "", _BLOCK_KEYS)
    if not units.declared and raw.get("units") != "model":
        raise r.err("the model declares no units: declare them (units: {length: .., force: ..})"
                    " or write the block in the model's consistent units with 'units: model'",
                    "units")
    r.f, how = _factors(raw.get("units"), units, r)
    notes = [f"dynamics parameters {how}"]
    if raw.get("gravity") is None:
        g = np.array([0.0, 0.0, -STANDARD_GRAVITY * (units.factor("m", "length")
                                                    if units.declared else 1.0)])
        notes.append(f"gravity: standard gravity {STANDARD_GRAVITY} m/s^2 along -Z of the base")
    else:
        g = r.vec(raw["gravity"], "gravity", length=1, time=-2)
    n = len(home_legs)
    stiff = [_stiffness(v, f, r, lg) for (v, f), lg in
             zip(_per_leg(raw.get("stiffness"), "stiffness", r, n), home_legs)]
    legs = [_leg(v, f, r, lg, st) for (v, f), lg, st in
            zip(_per_leg(raw.get("legs"), "legs", r, n), home_legs, stiff)]
    for lg in legs:
        notes.extend(lg.notes)
    return DynamicsParameters(_platform(raw.get("platform"), r), tuple(legs), g,
                              units.mass, tuple(notes))


def dynamics_for(model, raw) -> DynamicsParameters:
    """A ``dynamics:`` block (a mapping, or a YAML file holding one under ``dynamics:``)
    read for ``model`` (:func:`dynamics_from_mapping` with the model's legs, dimensions and
    units); the model itself is not changed."""
    from pathlib import Path
    source = model.source
    if isinstance(raw, (str, Path)):
        from ..legs._guards import MAX_MODEL_BYTES, decode_utf8, read_limited
        from ._yaml import load_yaml_text
        source = str(raw)
        what = f"the dynamics file {source[:200]!r}"
        # (bounded like a model file: /dev/zero or a huge file is refused, not read whole)
        text = decode_utf8(read_limited(source, MAX_MODEL_BYTES, what), what)
        doc = load_yaml_text(text, source)
        if not (isinstance(doc, dict) and isinstance(doc.get("dynamics"), dict)):
            raise CatalogError("the file has no 'dynamics:' mapping", source=source)
        raw = doc["dynamics"]
    R0, p0 = (np.asarray(x, float) for x in model.frame)
    legs = tuple(lg.moved(R0.T, -R0.T @ p0) for lg in model.home_legs)   # world -> base
    return dynamics_from_mapping(raw, model.name, source, model.dimensions, legs, model.units)
