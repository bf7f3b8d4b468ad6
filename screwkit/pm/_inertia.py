"""The constant physical parameters of a PM: masses, inertias, friction, gravity, stiffness.

A :class:`DynamicsParameters` is attached to a :class:`~screwkit.pm.PMModel` (its
``dynamics`` field, read from the definition's ``dynamics:`` block by
:func:`screwkit.pm.dynamics_from_mapping`) or passed on its own to
:func:`screwkit.dynamics.dynamics`.  It is a constant description like the model: the
dynamics layer takes it and never changes it.  Every number is in the model's consistent
units (the block's own units are converted when it is read): lengths and forces in the
model's units, time in seconds, so that masses are in force.s^2/length (``kN.s^2/cm`` =
1e5 kg for the catalog's cm and kN, :attr:`Units.mass`).

Frames.  The platform's centre of mass and inertia are given in the platform frame
``{o}``.  A leg link's are given in the **base frame at the home pose** (joint values 0,
:attr:`PMModel.home_legs`); the link then moves with the product of exponentials of the
joints before it.

Examples
--------
>>> b = cylinder_body(2.0, [0, 0, 0], [0, 0, 1], length=0.5, radius=0.1)
>>> [round(float(x), 6) for x in np.diag(b.inertia)]     # m (3 r^2 + l^2) / 12, m r^2 / 2
[0.046667, 0.046667, 0.01]
"""

from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np

from ..errors import InputError

__all__ = ["Body", "BarPair", "LegDynamics", "LegStiffness", "DynamicsParameters",
           "cylinder_body", "check_inertia", "NO_BODY"]


@dataclass(frozen=True, eq=False)
class Body:
    """A rigid body: ``mass``, centre of mass ``com (3,)`` and the inertia tensor about the
    centre of mass ``inertia (3, 3)``, in the frame its owner says (model units)."""

    mass: float
    com: np.ndarray
    inertia: np.ndarray
    name: str = ""

    def __post_init__(self):
        c = np.array(self.com, float).reshape(3)
        inertia = np.array(self.inertia, float).reshape(3, 3)
        for a in (c, inertia):
            a.setflags(write=False)
        object.__setattr__(self, "com", c)
        object.__setattr__(self, "inertia", inertia)
        object.__setattr__(self, "mass", float(self.mass))

    @property
    def massless(self) -> bool:
        return self.mass == 0.0 and not self.inertia.any()

    def moved(self, R, p) -> "Body":
        """The body after ``x -> R x + p``."""
        R = np.asarray(R, float)
        return Body(self.mass, R @ self.com + p, R @ self.inertia @ R.T, self.name)


#: A massless body.
NO_BODY = Body(0.0, np.zeros(3), np.zeros((3, 3)), "massless")


def check_inertia(I, mass: float, where: str = "inertia", rtol: float = 1e-9,
                  shown: float = 1.0) -> np.ndarray:
    """Validate an inertia tensor about a centre of mass: symmetric, its principal moments
    non-negative and each at most the sum of the other two (a real mass distribution),
    zero for a zero mass.  Returns it symmetrised.  Messages quote moments divided by
    ``shown`` (the factor from the units they were written in)."""
    I = np.asarray(I, float)
    if I.shape != (3, 3) or not np.all(np.isfinite(I)):
        raise InputError(f"{where}: must be 3 principal moments or a 3x3 matrix of finite numbers")
    scale = max(float(np.abs(I).max()), 1e-300)
    if np.abs(I - I.T).max() > rtol * scale:
        raise InputError(f"{where}: the inertia matrix is not symmetric")
    I = 0.5 * (I + I.T)
    ev = np.linalg.eigvalsh(I)
    if ev[0] < -rtol * scale:
        raise InputError(f"{where}: a principal moment is negative ({ev[0] / shown:.6g}, in the "
                         "units given)")
    if ev[2] > ev[0] + ev[1] + rtol * scale:
        raise InputError(f"{where}: the principal moments "
                         f"{', '.join(f'{x / shown:.6g}' for x in ev)} (in the units given) "
                         "violate the triangle inequality (I3 <= I1 + I2): no mass has them")
    if mass == 0 and scale > 1e-300 and I.any():
        raise InputError(f"{where}: a massless body cannot have an inertia")
    return I


def cylinder_body(mass: float, com, axis, *, length: float, radius: float = 0.0,
                  inner_radius: float = 0.0, name: str = "") -> Body:
    """A homogeneous cylinder (or tube) of axis ``axis`` centred at ``com``.

    Inertia about the centre: ``m (r^2 + r_i^2) / 2`` about the axis and
    ``m (3 (r^2 + r_i^2) + l^2) / 12`` about every perpendicular line (a thin rod for
    ``radius = 0``).
    """
    if not (length >= 0 and radius >= 0 and 0 <= inner_radius <= radius):
        raise InputError(f"{name or 'cylinder'}: need length >= 0 and 0 <= inner_radius <= "
                         f"radius (got {length}, {inner_radius}, {radius})")
    u = np.asarray(axis, float)
    u = u / np.linalg.norm(u)
    r2 = radius ** 2 + inner_radius ** 2
    ia = mass * r2 / 2.0
    it = mass * (3.0 * r2 + length ** 2) / 12.0
    uu = np.outer(u, u)
    return Body(mass, com, ia * uu + it * (np.eye(3) - uu), name)


@dataclass(frozen=True, eq=False)
class LegStiffness:
    """How stiff a leg is, per row of the unified Jacobian (model units).

    ``actuator``: the actuation row (force/length for a linear actuator, torque/rad for
    a rotary one); ``force``, ``couple``: each constraint force row (force/length) and
    couple row (torque/rad).  ``beam`` (``E, G, area, I, J``) derives the missing ones
    from a uniform beam of the current leg length ``l = |a_i - A_i|`` clamped at ``A_i``
    and loaded at ``a_i`` (:func:`screwkit.dynamics.row_stiffness`): ``EA/l`` along
    the leg, ``3EI/l^3`` across it, ``GJ/l`` for a couple about it, ``EI/l`` for a couple
    across it.  ``None``: not given (a row without a stiffness is rigid).
    """

    actuator: float | None = None
    force: float | None = None
    couple: float | None = None
    beam: dict | None = None

    @property
    def given(self) -> bool:
        return any(v is not None for v in (self.actuator, self.force, self.couple, self.beam))


@dataclass(frozen=True, eq=False)
class BarPair:
    """The two bars of a parallelogram ``Pa`` (its four-bar loop's moving sides).

    A Pa's equivalent joint is its first hinge axis and its bar vector ``b``; the real
    bars are parallel to ``b``, each on a hinge of the near link at ``p + o d_0`` (``p`` the
    Pa's point, ``d_0`` its translation direction at home, in the four-bar's plane, ``o``
    the bar's offset) and turning by the Pa's angle ``theta = s / |b|`` relative to that
    link; their far ends hinge on the far link (the link after the Pa, which only
    translates).

    Attributes
    ----------
    slot : int
        The Pa's equivalent joint (0-based).
    offsets : tuple of float
        Each bar's offset ``o`` along ``d_0`` (model lengths).
    bodies : tuple of Body
        Each bar's mass, centre and inertia (base frame at home), in the order of
        ``offsets``.
    """

    slot: int
    offsets: tuple
    bodies: tuple

    @property
    def massless(self) -> bool:
        return all(b.massless for b in self.bodies)


@dataclass(frozen=True, eq=False)
class LegDynamics:
    """The massive links and the joint friction of one leg.

    Attributes
    ----------
    links : tuple of (int, Body)
        ``(slot, body)``: the link that follows equivalent joint ``slot`` (0-based; the
        last joint of its letter), in the base frame at home.  Links not listed are
        massless; the link after the last joint is the platform.
    viscous, coulomb : ndarray (m,)
        Friction of each equivalent joint: effort ``viscous * qdot + coulomb *
        sign(qdot)`` resisting the motion (force or torque; model units, seconds).
    stiffness : LegStiffness
    notes : tuple of str
    bars : tuple of BarPair
        The bars of the leg's parallelograms ``Pa`` that have a mass.
    """

    links: tuple
    viscous: np.ndarray
    coulomb: np.ndarray
    stiffness: LegStiffness = field(default_factory=LegStiffness)
    notes: tuple = ()
    bars: tuple = ()

    @property
    def massless(self) -> bool:
        return all(b.massless for _, b in self.links) and all(p.massless for p in self.bars)

    @property
    def frictionless(self) -> bool:
        return not (np.any(self.viscous) or np.any(self.coulomb))


@dataclass(frozen=True, eq=False)
class DynamicsParameters:
    """Masses, inertias, friction, gravity and stiffness of a PM (model units, seconds).

    Attributes
    ----------
    platform : Body
        In the platform frame ``{o}`` (centre of mass relative to ``o``).
    legs : tuple of LegDynamics
        One per leg, links in the base frame at home.
    gravity : ndarray (3,)
        Acceleration of gravity in the base frame (length/s^2).
    mass_unit : str
        The model's mass unit (:attr:`Units.mass`), for reports.
    notes : tuple of str
        What was assumed (the default gravity...) and how the block's units were converted.
    """

    platform: Body
    legs: tuple
    gravity: np.ndarray
    mass_unit: str = ""
    notes: tuple = ()

    def __post_init__(self):
        g = np.array(self.gravity, float).reshape(3)
        g.setflags(write=False)
        object.__setattr__(self, "gravity", g)

    @property
    def massless_legs(self) -> bool:
        return all(lg.massless for lg in self.legs)

    @property
    def frictionless(self) -> bool:
        return all(lg.frictionless for lg in self.legs)

    @property
    def has_stiffness(self) -> bool:
        return any(lg.stiffness.given for lg in self.legs)

    def with_gravity(self, gravity) -> "DynamicsParameters":
        """The same parameters under another gravity (base frame, model units); its note
        replaces the one of the gravity they had."""
        g = np.asarray(gravity, float).reshape(3)
        notes = tuple(n for n in self.notes if not n.startswith("gravity")) + (
            f"gravity: ({', '.join(f'{x:.6g}' for x in g)}) model length/s^2 in the base "
            "frame, as given",)
        return DynamicsParameters(self.platform, self.legs, g, self.mass_unit, notes)

    def total_mass(self) -> float:
        return self.platform.mass + sum(b.mass for lg in self.legs for _, b in lg.links) + \
            sum(b.mass for lg in self.legs for p in lg.bars for b in p.bodies)
