"""The outputs of a dynamics table (private): its units converted to SI, a file written,
a mass named in kg."""

from __future__ import annotations

__all__ = ["unit_converter", "write_text", "mass_in_kg"]


def unit_converter(model, units):
    """``unit -> (factor, SI unit)`` of the units of a dynamics table: products and
    quotients of the model's length and force units, seconds and angles
    (``"kN.cm/s"`` -> ``"N.m/s"``; the mass unit ``"kN.s^2/cm"`` -> ``"N.s^2/m"``, kg)."""
    from ..engine._report import output_scales
    from ..errors import InputError
    u = model.units
    _, k = output_scales(model, units)
    base = {u.length: ("m", k["length"]), u.force: ("N", k["force"])}

    def conv(unit):
        f, sides = 1.0, []
        for s, side in enumerate(str(unit).split("/")):
            parts = []
            for tok in side.split("."):
                name, _, n = tok.partition("^")
                e = int(n or 1)
                if name in base:
                    new, x = base[name]
                    f *= x ** (e if s == 0 else -e)
                    parts.append(new + (f"^{n}" if n else ""))
                elif name in ("s", "rad", "deg", "1", ""):
                    parts.append(tok)
                else:
                    raise InputError(f"a unit of the dynamics table, {unit!r}, does not "
                                     "convert to SI")
            sides.append(".".join(parts))
        return f, "/".join(sides)
    return conv


def write_text(text: str, out) -> None:
    from pathlib import Path
    from ..errors import InputError
    if hasattr(out, "write"):
        out.write(text)
        return
    try:
        Path(out).parent.mkdir(parents=True, exist_ok=True)
        Path(out).write_text(text, encoding="utf-8")
    except OSError as exc:
        raise InputError(f"cannot write {str(out)!r}: {exc}") from None


def mass_in_kg(units, mass) -> str:
    """A mass in kg when the model's units convert (pint), else in the model's unit."""
    try:
        return f"{mass / units.factor('kg', 'mass'):.4g} kg"
    except Exception:                       # no pint, or undeclared units
        return f"{mass:.4g} {units.mass}"
