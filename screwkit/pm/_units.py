"""The units a model declares (``units: {length: cm, force: kN}``), and conversions to SI.

Every number screwkit computes is in the model's own consistent units: lengths in its
length unit, forces in its force unit, couples and rotary actuators' torques in force x
length, angles in radians in the Python API (degrees at the command line).  The catalog
declares the paper's cm and kN.  A conversion (``--units SI``) scales the outputs through
pint, imported only when one is asked for.

Examples
--------
>>> u = Units("cm", "kN")
>>> u.torque, u.of("torque"), u.of("force"), u.of("angle")
('kN.cm', 'kN.cm', 'kN', 'deg')
"""

from __future__ import annotations

from dataclasses import dataclass

from ..errors import CatalogError, InputError

__all__ = ["Units", "LENGTH_UNITS", "FORCE_UNITS", "units_from_mapping", "UNDECLARED"]

#: Length and force units a model may declare.
LENGTH_UNITS = ("mm", "cm", "dm", "m", "in", "ft")
FORCE_UNITS = ("N", "kN", "MN", "lbf")


@dataclass(frozen=True)
class Units:
    """A model's units: ``length`` and ``force`` (``torque`` is force.length).

    ``declared`` is False for a model that declares none: its numbers are in whatever
    consistent units its dimensions were written in, and are labelled with the dimensions
    ``[L]`` (its length unit) and ``[F]`` (its force unit): torques ``[F.L]``, stiffnesses
    ``[F/L]``, masses ``[F.s^2/L]``.
    """

    length: str = "cm"
    force: str = "kN"
    declared: bool = True

    @property
    def torque(self) -> str:
        return f"{self.force}.{self.length}" if self.declared else "[F.L]"

    @property
    def mass(self) -> str:
        """The consistent mass unit, force.s^2/length (time in seconds): ``kN.s^2/cm`` is
        1e5 kg, so that mass x acceleration is a force in the model's unit."""
        return f"{self.force}.s^2/{self.length}" if self.declared else "[F.s^2/L]"

    def of(self, quantity: str) -> str:
        """The unit of a quantity: ``length``, ``force``, ``torque``, ``angle`` (degrees at the
        command line), ``stiffness`` (force/length), ``angular stiffness`` (torque/rad)."""
        table = {"length": self.length, "force": self.force, "torque": self.torque,
                 "angle": "deg", "stiffness": f"{self.force}/{self.length}" if self.declared
                 else "[F/L]", "angular stiffness": f"{self.torque}/rad", "mass": self.mass,
                 "time": "s", "": ""}
        try:
            return table[quantity]
        except KeyError:
            raise InputError(f"unknown quantity {quantity!r}") from None

    def as_dict(self) -> dict:
        return {"length": self.length, "force": self.force, "torque": self.torque,
                "angle": "deg", "declared": self.declared}

    def si_factors(self) -> dict:
        """Factors to metres, newtons and newton metres (through pint)."""
        try:
            import pint
        except ImportError:
            raise InputError("unit conversions need the 'pint' package "
                             "(pip install 'screwkit[units]')") from None
        ureg = _registry(pint)
        lf = float(ureg.Quantity(1.0, self.length).to("m").magnitude)
        ff = float(ureg.Quantity(1.0, self.force).to("N").magnitude)
        return {"length": lf, "force": ff, "torque": lf * ff, "angle": 1.0}


    def factor(self, unit: str, dimension: str) -> float:
        """How many of the model's units of ``dimension`` (``length``, ``force``, ``mass``,
        ``time``) make one ``unit`` (a pint unit: ``kg``, ``m``, ``N``, ``s``), through pint;
        e.g. ``Units("cm", "kN").factor("kg", "mass") == 1e-5``."""
        target = {"length": self.length, "force": self.force, "time": "s",
                  "mass": f"{self.force}*s**2/{self.length}"}.get(dimension)
        if target is None:
            raise InputError(f"unknown dimension {dimension!r} (length, force, mass, time)")
        if not self.declared:
            raise InputError("the model declares no units (units: {length: ..., force: ...}): "
                             f"{unit} cannot be converted")
        try:
            import pint
        except ImportError:
            raise InputError("unit conversions need the 'pint' package "
                             "(pip install 'screwkit[units]')") from None
        if not isinstance(unit, str) or not unit.strip() or len(unit) > 100:
            raise InputError(f"{str(unit)[:100]!r} is not a unit name (kg, m, N, s ...)")
        ureg = _registry(pint)
        try:
            return float(ureg.Quantity(1.0, unit).to(target).magnitude)
        except Exception as exc:          # pint's parser fails on a bad name in many ways
            # (PintError, ValueError, an AssertionError on '{}'): every one is a bad unit
            why = f"{type(exc).__name__}: {exc}" if str(exc) else "not a unit pint reads"
            raise InputError(f"cannot convert {unit!r} to a {dimension} ({why})") from None


_REG = []


def _registry(pint):
    if not _REG:
        _REG.append(pint.UnitRegistry())
    return _REG[0]


#: The units of a model that declares none: labelled with their dimensions, ``[L]`` and
#: ``[F]`` (the model's own, undeclared, length and force units).
UNDECLARED = Units("[L]", "[F]", False)


def units_from_mapping(raw, where: str = "", source=None, default: Units | None = None) -> Units:
    """Validate a ``units:`` mapping (``{length: cm, force: kN}``)."""
    if raw is None:
        return default if default is not None else UNDECLARED
    if not isinstance(raw, dict) or set(raw) - {"length", "force"} or not raw:
        raise CatalogError("must be a mapping {length: UNIT, force: UNIT}", where, "units",
                           source)
    length, force = raw.get("length"), raw.get("force")
    if length is not None and length not in LENGTH_UNITS:
        raise CatalogError(f"unknown length unit {length!r} (one of {', '.join(LENGTH_UNITS)})",
                           where, "units.length", source)
    if force is not None and force not in FORCE_UNITS:
        raise CatalogError(f"unknown force unit {force!r} (one of {', '.join(FORCE_UNITS)})",
                           where, "units.force", source)
    if default is None and (length is None or force is None):
        # (no silent default: a model in mm with its forces assumed in kN)
        raise CatalogError(f"give both units, {{length: {length or 'UNIT'}, force: "
                           f"{force or 'UNIT'}}}: the {'force' if force is None else 'length'} "
                           "unit is not assumed", where, "units", source)
    length = length if length is not None else default.length
    force = force if force is not None else default.force
    if length not in LENGTH_UNITS:
        raise CatalogError(f"unknown length unit {length!r} (one of {', '.join(LENGTH_UNITS)})",
                           where, "units.length", source)
    if force not in FORCE_UNITS:
        raise CatalogError(f"unknown force unit {force!r} (one of {', '.join(FORCE_UNITS)})",
                           where, "units.force", source)
    return Units(length, force, True)
