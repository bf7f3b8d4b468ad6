"""A workload at the platform centre ``o``, and the default one a model declares.

Workloads are stated, never assumed: a model that has one declares it in its definition,
with its units, and every output says which workload it used and where it came from::

    workload:                      # the default workload at o (base axes)
      force: [-20, -30, -60]
      torque: [-30, -30, 100]
      units: {force: kN, length: cm}   # torque in kN.cm; 'model': the model's own units
      source: the paper's workload, section 5.1   # optional: where it comes from

A model without ``workload:`` has none: its statics need one given (``force=``/``torque=``
in the Python API, ``--force``/``--torque`` at the command line), while its kinematics,
mobility and Jacobian do not.  The declared values are converted to the model's units
(through pint) when the model is read.

Examples
--------
>>> w = Workload([0, 0, -10], [0, 0, 0], "given")
>>> w.describe("kN", "kN.cm")
'F = (0, 0, -10) kN, T = (0, 0, 0) kN.cm at o (given)'
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from ..errors import CatalogError, InputError

__all__ = ["Workload", "workload_from_mapping", "WORKLOAD_KEYS"]

#: Keys of a ``workload:`` block.
WORKLOAD_KEYS = ("force", "torque", "units", "source")


@dataclass(frozen=True, eq=False)
class Workload:
    """A force and a torque applied at the platform centre ``o`` (model units).

    Attributes
    ----------
    force, torque : ndarray (3,)
        In the model's force and torque (force.length) units, world axes.
    source : str
        Where the workload comes from: ``"declared default"`` (the model's ``workload:``),
        ``"given"`` (the caller's ``force=``/``torque=``), ``"command line"``, or a file.
    note : str
        What the model's definition says about it (its ``source:``), or "".
    """

    force: np.ndarray
    torque: np.ndarray
    source: str = "given"
    note: str = ""

    def __post_init__(self):
        for name in ("force", "torque"):
            v = np.array(getattr(self, name), float).reshape(3)
            v.setflags(write=False)
            object.__setattr__(self, name, v)

    def moved(self, rotation) -> "Workload":
        """The workload after the base frame turns by ``rotation`` (vectors turn with it)."""
        R = np.asarray(rotation, float)
        return Workload(R @ self.force, R @ self.torque, self.source, self.note)

    def with_source(self, source: str) -> "Workload":
        return Workload(self.force, self.torque, source, self.note)

    @property
    def origin(self) -> str:
        """``source`` with its note: ``"declared default (the paper's workload, section 5.1)"``."""
        return f"{self.source} ({self.note})" if self.note else self.source

    def describe(self, force_unit: str, torque_unit: str, kf: float = 1.0,
                 kt: float = 1.0) -> str:
        """One line: the force and torque with their units, and where they come from."""
        def vec(v):
            c = np.asarray(v, float)
            top = float(np.abs(c).max()) if c.size else 0.0
            return "(" + ", ".join("0" if abs(x) <= 1e-12 * top or x == 0 else f"{x:.6g}"
                                   for x in c) + ")"
        return (f"F = {vec(self.force * kf)} {force_unit}, T = {vec(self.torque * kt)} "
                f"{torque_unit} at o ({self.origin})")

    def as_dict(self) -> dict:
        return {"force": self.force, "torque": self.torque, "applied_at": "o",
                "source": self.source, "note": self.note}


def workload_from_mapping(raw, name: str, source, units, dims=None) -> Workload | None:
    """Read a model's ``workload:`` block (module docstring) in the model's units.

    Parameters
    ----------
    raw : mapping or None
    name, source : str
        The PM and its file, for messages.
    units : Units
        The model's units (the block's are converted to them).
    dims : dict, optional
        The model's dimensions (names usable in expressions).

    Raises
    ------
    CatalogError
        Naming the PM and the field (``workload.force[2]``).
    """
    from ..legs._guards import MAX_LOAD, real, shorten
    from ._expressions import parse_expression

    if raw is None:
        return None

    def err(msg, fld=""):
        return CatalogError(msg, name, f"workload.{fld}" if fld else "workload", source)

    if not isinstance(raw, dict):
        raise err("must be a mapping {force: [Fx, Fy, Fz], torque: [Tx, Ty, Tz], units: "
                  "{force: .., length: ..}}")
    bad = sorted(str(k) for k in raw if k not in WORKLOAD_KEYS)
    if bad:
        raise err(f"unknown key {shorten(bad[0], 40)} (allowed: {', '.join(WORKLOAD_KEYS)})")
    if "force" not in raw and "torque" not in raw:
        raise err("give 'force' and/or 'torque' (the missing one is zero)")
    kf, kt = _factors(raw.get("units"), units, err)
    dims = dict(dims or {})

    def vec(fld, factor):
        v = raw.get(fld)
        if v is None:
            return np.zeros(3)
        if not (isinstance(v, (list, tuple)) and len(v) == 3):
            raise err("must be a list of 3 numbers", fld)
        out = []
        for k, x in enumerate(v):
            where = f"{fld}[{k}]"
            if isinstance(x, str):
                try:
                    x = float(parse_expression(x, tuple(dims))(**dims))
                except InputError as exc:
                    raise err(str(exc), where) from None
            x = real(x, where, bound=MAX_LOAD, error=lambda m, w=where: err(m, w))
            y = x * factor
            if not abs(y) <= MAX_LOAD:
                raise err(f"{x:g} is {y:g} in the model's units, beyond the limit "
                          f"+-{MAX_LOAD:g}", where)
            out.append(y)
        return np.array(out)

    note = raw.get("source", "")
    if not isinstance(note, str) or len(note) > 500:
        raise err("must be a text of at most 500 characters", "source")
    return Workload(vec("force", kf), vec("torque", kt), "declared default", note)


def _factors(raw, units, err):
    """The factors from the block's ``units:`` to the model's force and torque units."""
    if raw is None:
        raise err("missing 'units': say the units of the workload ({force: kN, length: cm}: "
                  "torque in kN.cm; or 'model': the model's own units)", "units")
    if raw == "model":
        return 1.0, 1.0
    if not isinstance(raw, dict) or set(raw) - {"force", "length"} or \
            not {"force", "length"} <= set(raw):
        raise err("must be {force: UNIT, length: UNIT} (torque in force.length) or 'model'",
                  "units")
    if not units.declared:
        raise err("the model declares no units: declare them (units: {length: .., force: ..}) "
                  "or write the workload in the model's own units with 'units: model'", "units")
    for key in ("force", "length"):
        if not isinstance(raw[key], str):
            raise err(f"must be a unit name (kN, cm ...), not {str(raw[key])[:40]!r}",
                      f"units.{key}")
    try:
        ff = units.factor(raw["force"], "force")
        fl = units.factor(raw["length"], "length")
    except InputError as exc:
        raise err(str(exc), "units") from None
    return ff, ff * fl
