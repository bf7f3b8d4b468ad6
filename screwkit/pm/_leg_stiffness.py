"""The ``stiffness:`` of a ``dynamics:`` block: each leg's row stiffnesses (private, for
:mod:`screwkit.pm._physical`, whose reader converts the numbers to the model's units), and
the per-leg lists of the block."""

from __future__ import annotations

from ..legs._guards import MAX_STIFFNESS, MIN_STIFFNESS
from ._inertia import LegStiffness

__all__ = ["_stiffness", "_per_leg"]

_STIFF_KEYS = {"actuator", "force", "couple", "beam"}
_BEAM_KEYS = {"E", "G", "area", "I", "J"}


def _stiffness(v, fld, r, leg) -> LegStiffness:
    if v is None:
        return LegStiffness()
    s = r.mapping(v, fld, _STIFF_KEYS)
    rot = leg.actuated_joint.kind != "P"
    out = {}
    if s.get("actuator") is not None:
        out["actuator"] = r.num(s["actuator"], f"{fld}.actuator", force=1,
                                length=1 if rot else -1, positive=True, bound=MAX_STIFFNESS)
    if s.get("force") is not None:
        out["force"] = r.num(s["force"], f"{fld}.force", force=1, length=-1, positive=True,
                             bound=MAX_STIFFNESS)
    if s.get("couple") is not None:
        out["couple"] = r.num(s["couple"], f"{fld}.couple", force=1, length=1, positive=True,
                              bound=MAX_STIFFNESS)
    if s.get("beam") is not None:
        b = r.mapping(s["beam"], f"{fld}.beam", _BEAM_KEYS, tuple(sorted(_BEAM_KEYS)))
        dims = {"E": (1, -2), "G": (1, -2), "area": (0, 2), "I": (0, 4), "J": (0, 4)}
        out["beam"] = {k: r.num(x, f"{fld}.beam.{k}", force=dims[k][0], length=dims[k][1],
                                positive=True) for k, x in b.items()}
    for k, x in out.items():
        if k != "beam" and not MIN_STIFFNESS <= x <= MAX_STIFFNESS:
            raise r.err(f"a stiffness must be from {MIN_STIFFNESS:g} to {MAX_STIFFNESS:g} in "
                        f"the model's units, got {x:g} (leave it out for a rigid row)",
                        f"{fld}.{k}")
        if k == "beam" and not all(v > 0 for v in x.values()):
            raise r.err("E, G, area, I and J of a beam must be positive", f"{fld}.{k}")
    return LegStiffness(**out)


def _per_leg(v, fld, r, n):
    if isinstance(v, list):
        if len(v) != n:
            raise r.err(f"{len(v)} entries for {n} legs (one mapping for every leg, or a list "
                        "with one per leg)", fld)
        return [(x, f"{fld}[{i}]") for i, x in enumerate(v)]
    return [(v, fld)] * n
