"""The standard geometries on which candidate PMs are placed (base and platform vertices).

Each geometry is ``(label, base, platform, dimensions, home Zo, extra fields)``: a label,
the ``base:`` and ``platform:`` entries of a model file (``docs/pm_models.md``), their
dimensions (cm), the height of the platform at home and further ``pms:`` fields.  A
candidate is tried on the geometries of its kind (:func:`geometries_for`) in order.
"""

from __future__ import annotations

__all__ = ["CENTRAL_GEOMETRIES", "GEOMETRIES", "PAIR_GEOMETRIES", "PASSIVE_GEOMETRIES",
           "geometries_for"]

#: Standard geometries by number of legs: (label, base, platform, dimensions, home Zo,
#: extra fields).  Tried in order until one verifies.  The platform pentagon is irregular
#: (vertex 1 kept on the Y axis): similar pentagons in line make six-DOF legs an
#: actuation singularity at home.
GEOMETRIES = {
    3: (("triangle R=60 r=30", {"shape": "triangle", "circumradius": "R"},
         {"shape": "triangle", "circumradius": "r"}, {"R": 60, "r": 30}, "R", {}),
        ("triangle R=60 r=30, platform turned 60 deg",
         {"shape": "triangle", "circumradius": "R"},
         {"shape": "triangle", "circumradius": "r", "angles": [30, 150, 270]},
         {"R": 60, "r": 30}, "R", {"centre": [0, 0, "R/2"]}),
        ("triangle R=80 r=20, low platform", {"shape": "triangle", "circumradius": "R"},
         {"shape": "triangle", "circumradius": "r"}, {"R": 80, "r": 20}, "R/2", {})),
    4: (("square L=100, rectangle 60 x 40", {"shape": "square", "side": "L"},
         {"shape": "rectangle", "sides": ["l1", "l2"]}, {"L": 100, "l1": 60, "l2": 40},
         "0.8*L", {}),),
    5: (("pentagon R=60, irregular platform pentagon r=30",
         {"shape": "circle", "radius": "R", "angles": [90, 162, 234, 306, 18]},
         {"shape": "circle", "radius": "r", "angles": [90, 170, 240, 300, 10]},
         {"R": 60, "r": 30}, "R", {}),),
}

#: Geometries tried first for PMs with a passive leg (then :data:`GEOMETRIES`).  Four legs:
#: a square platform similar to the square base keeps every leg radial at home (a
#: platform-tangent R perpendicular to its leg, as the SPR needs; with all four legs
#: actuated, similar squares are an actuation singularity at home, the catalog's 4-UPU
#: note).  Five legs: an irregular platform pentagon turned by 30 to 40 deg from the base
#: one, so that four six-DOF legs control the rotation about the base normal (on the
#: standard pentagon, with nearly radial legs, the 4-SPS + passive PRRR has cond(J) 1.6e3
#: at home, here 30).
PASSIVE_GEOMETRIES = {
    4: (("square L=100, square l=50", {"shape": "square", "side": "L"},
         {"shape": "square", "side": "l"}, {"L": 100, "l": 50}, "0.8*L", {}),),
    5: (("pentagon R=60, turned irregular platform pentagon r=30",
         {"shape": "circle", "radius": "R", "angles": [90, 162, 234, 306, 18]},
         {"shape": "circle", "radius": "r", "angles": [130, 192, 274, 336, 58]},
         {"R": 60, "r": 30}, "R", {}),),
}


def _ring(radius: str, angles) -> list:
    """Vertices at ``angles`` (degrees) on a circle of the dimension ``radius``, as
    expressions, then the centre: a PM with a central column."""
    pts = [[f"{radius}*cos({a}*pi/180)", f"{radius}*sin({a}*pi/180)", 0] for a in angles]
    return pts + [[0, 0, 0]]


#: Geometries of PMs with a central passive column (the Tricept's), by the number of
#: actuated legs: the standard ones with the centres of base and platform added as the
#: last vertex.
CENTRAL_GEOMETRIES = {
    3: (("triangle R=60 r=30 and a central column", {"points": _ring("R", (-30, 90, 210))},
         {"points": _ring("r", (-30, 90, 210))}, {"R": 60, "r": 30}, "R", {}),
        ("triangle R=60 r=30 turned 60 deg and a central column",
         {"points": _ring("R", (-30, 90, 210))}, {"points": _ring("r", (30, 150, 270))},
         {"R": 60, "r": 30}, "R", {})),
    4: (("square L=100, rectangle 60 x 40 and a central column",
         {"points": [["L/2", "-L/2", 0], ["L/2", "L/2", 0], ["-L/2", "L/2", 0],
                     ["-L/2", "-L/2", 0], [0, 0, 0]]},
         {"points": [["l1/2", "-l2/2", 0], ["l1/2", "l2/2", 0], ["-l1/2", "l2/2", 0],
                     ["-l1/2", "-l2/2", 0], [0, 0, 0]]},
         {"L": 100, "l1": 60, "l2": 40}, "0.8*L", {}),),
}


#: Geometries of three legs where legs 1 and 2 stand at the two ends of a diameter of the
#: base (and of the platform) and leg 3 half-way round: the two legs of the same type then
#: lie in one plane through the base normal, the Exechon's (Bi and Jin 2011; Zoppi,
#: Zlatanov and Molfino 2010: two UPR legs whose U's first axes lie on one base line and
#: whose R axes are normal to the legs' plane, an SPR leg in the plane normal to it).  Used
#: for the pair compositions (:func:`~screwkit.synthesis.pair_compositions`).
PAIR_GEOMETRIES = {
    3: (("legs 1, 2 on a diameter (R=60 r=30), leg 3 between",
         {"shape": "circle", "radius": "R", "angles": [-90, 90, 180]},
         {"shape": "circle", "radius": "r", "angles": [-90, 90, 180]},
         {"R": 60, "r": 30}, "R", {}),),
}


def geometries_for(n_legs: int, passive: bool = False, central: bool = False,
                   pair: bool = False) -> tuple:
    """The standard geometries of ``n_legs`` legs, in the order they are tried (the
    :data:`PASSIVE_GEOMETRIES` first for a PM with a passive leg; with a central column,
    :data:`CENTRAL_GEOMETRIES` of ``n_legs - 1`` actuated legs; a pair composition, the
    :data:`PAIR_GEOMETRIES` only)."""
    if pair:
        return tuple(PAIR_GEOMETRIES.get(n_legs, ()))
    if central:
        return tuple(CENTRAL_GEOMETRIES.get(n_legs - 1, ()))
    return (tuple(PASSIVE_GEOMETRIES.get(n_legs, ())) if passive else ()) + tuple(
        GEOMETRIES.get(n_legs, ()))
