"""A PM's geometry and masses in SI (metres, kilograms, newtons), for the file formats that
define their units: URDF (:mod:`~._urdf`) and MJCF are SI.

A :class:`SIConversion` holds the factors from the model's units (:attr:`PMModel.units`,
converted through pint) and converts points, lengths, masses and inertia tensors; the
:func:`si_bodies` of a model are its massive bodies (the ``dynamics:`` block, or a given
:class:`~screwkit.pm.DynamicsParameters`) in SI, placed in the world frame at home, each
with the equivalent joint it follows.  An exporter takes these and writes them in its own
syntax; nothing in here knows a file format (the URDF writer and the MJCF writer,
:mod:`~._mjcf`'s ``si_factors``, both take their factors from here).

Examples
--------
>>> import screwkit
>>> si = SIConversion.of(screwkit.load_pm("3RRPRR"))        # the catalog's cm and kN
>>> si.length, si.force, round(si.mass, 12)                  # kN.s^2/cm = 1e5 kg
(0.01, 1000.0, 100000.0)
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from ..errors import InputError

__all__ = ["SIConversion", "SIBody", "si_bodies"]


@dataclass(frozen=True)
class SIConversion:
    """Factors from a model's units to SI: ``length`` (m per model length unit), ``force``
    (N per model force unit), ``mass`` (kg per model mass unit, force.s^2/length)."""

    length: float
    force: float

    @classmethod
    def of(cls, model) -> "SIConversion":
        """The factors of ``model`` (an :class:`InputError` when it declares no units:
        they cannot be converted)."""
        u = model.units
        if not u.declared:
            raise InputError(f"{model.name} declares no units (units: {{length: .., force: ..}}): "
                             "its lengths and masses cannot be converted to the metres and "
                             "kilograms of the file format")
        f = u.si_factors()
        return cls(float(f["length"]), float(f["force"]))

    @property
    def mass(self) -> float:
        return self.force / self.length          # (N.s^2/m per model force.s^2/length)

    @property
    def inertia(self) -> float:
        return self.mass * self.length ** 2

    def factors(self) -> dict:
        """``length`` (m), ``force`` (N), ``torque`` (N.m), ``mass`` (kg), ``inertia``
        (kg.m^2) per model unit."""
        return {"length": self.length, "force": self.force,
                "torque": self.length * self.force, "mass": self.mass,
                "inertia": self.inertia}

    def points(self, x) -> np.ndarray:
        return np.asarray(x, float) * self.length


@dataclass(frozen=True, eq=False)
class SIBody:
    """A massive body in SI: ``mass`` (kg), ``com`` (m) and ``inertia`` about the centre of
    mass (kg.m^2), in the world frame at home (``frame="world"``) for a leg link, in the
    platform frame ``{o}`` for the platform; ``leg`` and ``slot`` (0-based) name the
    equivalent joint the link follows (``leg`` None for the platform)."""

    name: str
    mass: float
    com: np.ndarray
    inertia: np.ndarray
    leg: int | None = None
    slot: int | None = None
    frame: str = "world"


def si_bodies(model, params=None) -> tuple:
    """``(bodies, note)``: the massive bodies of ``model`` in SI (:class:`SIBody`, massless
    links left out), and a note saying where they come from.

    Parameters
    ----------
    model : PMModel
    params : DynamicsParameters, optional
        Default: the model's ``dynamics:`` block; with neither, no bodies (the note says
        so).
    """
    params = model.dynamics if params is None else params
    if params is None:
        return (), (f"{model.name} declares no masses (no 'dynamics:' block): every link is "
                    "massless (no inertial elements)")
    si = SIConversion.of(model)
    R0, p0 = (np.asarray(x, float) for x in model.frame)
    out = []
    pl = params.platform
    if not pl.massless:
        out.append(SIBody("platform", pl.mass * si.mass, si.points(pl.com),
                          pl.inertia * si.inertia, None, None, "platform"))
    for i, lg in enumerate(params.legs):
        for slot, body in lg.links:
            if body.massless:
                continue
            com = R0 @ body.com + p0                       # base frame at home -> world
            out.append(SIBody(f"leg{i + 1} {body.name}".strip(), body.mass * si.mass,
                              si.points(com), R0 @ body.inertia @ R0.T * si.inertia, i, slot))
    return tuple(out), "masses and inertias of the model's dynamics: block, in kg and kg.m^2"
