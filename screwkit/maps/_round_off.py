"""Round-off in the extremes of a map: a row zero by its structure reads 0 in every unit."""

from __future__ import annotations

import numpy as np


#: A row's largest |value| at most this share of the largest effort of the map (forces
#: times the PM's length beside torques) is round-off: zero at every usable cell.
ROUND_OFF = 1e-12


def zero_round_off(rows, ds) -> None:
    """Rows of :func:`extremes` whose largest ``|value|`` is round-off beside the map's
    largest effort (a leg's ``T_r`` that is zero by its structure, computed as 1e-12 in one
    unit and 1e-13 in another) set to exactly 0, with no pose (zero at every usable cell):
    the same in any unit, where an absolute cut would not be."""
    for r in rows:
        r["round_off"] = False
    L = float(ds.attrs.get("normalisation_length", np.nan))
    torque = ds.attrs.get("units_torque")
    big = [r["max_abs"] * (1.0 if r["unit"] == torque else L) for r in rows
           if r["max_abs"] is not None]
    if not big or not np.isfinite(L):
        return
    ref = max(big)
    for r in rows:
        if r["max_abs"] is not None and \
                r["max_abs"] * (1.0 if r["unit"] == torque else L) <= ROUND_OFF * ref:
            r.update(max_abs=0.0, value=0.0, pose=None, level=None, conditioning=None,
                     workload=None, round_off=True)
