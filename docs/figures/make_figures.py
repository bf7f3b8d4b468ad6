"""Regenerate the PNG figures of the documentation.

Run from the repository root::

    python docs/figures/make_figures.py

The 3-SPR example PM is symmetric: A_i on a circle of radius 100 cm at
0/120/240 deg, a_i on a circle of radius 50 cm at height 80 cm.  The wrench
values drawn on it are made up (for illustration only).
"""

from __future__ import annotations

from pathlib import Path

import numpy as np

import screwkit
from screwkit.pm import default_catalog
from screwkit.viz import draw_leg, draw_pm
from screwkit.legs import Placement

HERE = Path(__file__).resolve().parent


def three_spr_example():
    """Legs, base points, platform points, o and wrench rows of the example 3-SPR PM."""
    spec = default_catalog().find_leg("SPR")
    o = np.array([0.0, 0.0, 80.0])
    legs, B, P = [], [], []
    for k in range(3):
        th = np.radians(120.0 * k)
        A = np.array([100 * np.cos(th), 100 * np.sin(th), 0.0])
        a = np.array([50 * np.cos(th), 50 * np.sin(th), 80.0])
        legs.append(spec.build(Placement(A, a, O=np.zeros(3), o=o)))
        B.append(A)
        P.append(a)
    made_up = {"actuation": [32.0, -12.5, 21.0], "force": [-8.0, 14.0, 5.5]}
    rows = []
    for i, leg in enumerate(legs):
        res = leg.analyze()
        act = res.actuation.member
        rows.append({"kind": "actuation", "leg": i, "direction": act.direction,
                     "point": act.point, "value": made_up["actuation"][i]})
        c = res.constraints[0]
        rows.append({"kind": "force", "leg": i, "direction": c.direction, "point": c.point,
                     "value": made_up["force"][i]})
    return legs, np.array(B), np.array(P), o, rows


def main():
    for name, fname in (("RRPRR", "leg_RRPRR.png"), ("UPU/couple", "leg_UPU_couple.png"),
                        ("SPR", "leg_SPR.png")):
        leg = screwkit.leg(name)
        draw_leg(leg, leg.analyze(), out=HERE / fname)
        print(HERE / fname)
    legs, B, P, o, rows = three_spr_example()
    draw_pm(legs, B, P, o, rows, out=HERE / "pm_example.png",
            title="3-SPR at its symmetric home pose (made-up wrench values)")
    print(HERE / "pm_example.png")


if __name__ == "__main__":
    main()
