"""Motion patterns of a platform and the wrench systems complementary to them.

A motion pattern is the finite motion wanted of a PM's platform: ``3T`` (pure
translations), ``3R`` (rotations about a fixed point), ``1T2R`` (= ``2R1T``: a
translation along the base normal and two rotations, the 3-RPS type), ``3T1R``
(Schoenflies: translations and rotations about the base normal), ``2T3R``,
``1T3R``, ``2T2R``, ``2T1R`` (planar).  Its *complementary wrench system* is the set
of wrenches reciprocal to every twist of the motion at the home pose (about the
home position of the platform centre ``o``); the legs of a PM with that motion must
together exert a constraint system spanning it, every leg's system inside it.

The table says, for each pattern, which pose parameters are independent (the rest
are dependent and solved by the engine), how many of the complementary wrenches
are pure couples (``couples``), how many independent pure forces (zero-pitch
wrenches) it holds at most (``forces``), and the system in words, derived by hand
(`docs/synthesis.md`).  A leg whose constraint system has more forces or couples
than that cannot be a leg of such a PM.  Where the rotation axes lie (the 3-RPS
turns about lines through its S centres' plane, the 3-SPR about lines in its base
plane) depends on the legs: the counts do not, and the engine checks the rest.

Examples
--------
>>> m = motion_pattern("2R1T")
>>> m.name, m.dof, m.independent, m.forces, m.couples
('1T2R', 3, ('alpha', 'beta', 'Zo'), 3, 1)
"""

from __future__ import annotations

from dataclasses import dataclass

from ..errors import InputError

__all__ = ["MotionPattern", "MOTIONS", "motion_pattern"]


@dataclass(frozen=True)
class MotionPattern:
    """One motion pattern (see the module docstring).

    Attributes
    ----------
    name : str
        Canonical name (``"1T2R"``).
    independent : tuple of str
        The independent pose parameters of a PM with this motion (screwkit's
        ``Xo Yo Zo alpha beta gamma``, XYZ Euler angles).
    forces, couples : int
        The most independent pure forces, and the dimension of the pure couples, in the
        complementary wrench system.
    complement : str
        The complementary wrench system in words (base axes).
    translations, rotations : int
        The instantaneous count the engine's mobility gives at a general pose.
    fixed_rotation : str
        ``"all"`` when the platform does not rotate (3T), ``"z"`` when it rotates only
        about the base normal (3T1R, planar), ``""`` otherwise: a finite check.
    fixed_point : bool
        The platform turns about a base-fixed point (3R).
    """

    name: str
    independent: tuple
    forces: int
    couples: int
    complement: str
    translations: int
    rotations: int
    fixed_rotation: str = ""
    fixed_point: bool = False

    @property
    def dof(self) -> int:
        return len(self.independent)

    @property
    def constraints(self) -> int:
        """Dimension of the complementary wrench system, ``6 - dof``."""
        return 6 - self.dof

    def admits(self, forces: int, couples: int, screws: int = 0) -> bool:
        """Can a leg exerting ``forces`` pure forces, ``couples`` couples and ``screws``
        finite-pitch wrenches be a leg of a PM with this motion (counts only)?"""
        return (couples <= self.couples and forces <= self.forces and screws == 0
                and forces + couples <= self.constraints)


#: The motion patterns, by canonical name.
MOTIONS = {m.name: m for m in (
    MotionPattern("3T", ("Xo", "Yo", "Zo"), 0, 3,
                  "three couples (every couple: the platform cannot rotate)", 3, 0, "all"),
    MotionPattern("3R", ("alpha", "beta", "gamma"), 3, 0,
                  "three forces through the centre of rotation", 0, 3, fixed_point=True),
    MotionPattern("1T2R", ("alpha", "beta", "Zo"), 3, 1,
                  "three forces normal to the translation (lines in a plane for the 3-RPS, "
                  "through the base joints for the 3-SPR), a couple along it", 1, 2),
    MotionPattern("3T1R", ("Xo", "Yo", "Zo", "gamma"), 0, 2,
                  "two couples perpendicular to the base normal", 3, 1, "z"),
    MotionPattern("2T3R", ("Yo", "Zo", "alpha", "beta", "gamma"), 1, 0,
                  "one force (along X, through the platform)", 2, 3),
    MotionPattern("1T3R", ("alpha", "beta", "gamma", "Zo"), 2, 0,
                  "two forces through one point, normal to the translation", 1, 3),
    MotionPattern("2T2R", ("Xo", "Zo", "alpha", "beta"), 2, 1,
                  "forces along Y (two parallel lines at most) and a couple along Z", 2, 2),
    MotionPattern("2T1R", ("Xo", "Yo", "gamma"), 3, 2,
                  "two couples in the plane of motion and a force normal to it", 2, 1, "z"),
)}

_ALIASES = {"2R1T": "1T2R", "1R3T": "3T1R", "3R2T": "2T3R", "3R1T": "1T3R", "2R2T": "2T2R",
            "1R2T": "2T1R", "SCHOENFLIES": "3T1R", "SPHERICAL": "3R", "TRANSLATIONAL": "3T",
            "PLANAR": "2T1R"}


def motion_pattern(name) -> MotionPattern:
    """The :class:`MotionPattern` called ``name`` (``"3T"``, ``"2R1T"``, ``"schoenflies"``...).

    Raises
    ------
    InputError
        An unknown name (the message lists the known ones).
    """
    if isinstance(name, MotionPattern):
        return name
    if not isinstance(name, str) or not name.strip() or len(name) > 40:
        raise InputError(f"a motion pattern is a name such as 3T or 1T2R, got {name!r:.40}")
    key = name.strip().upper().replace("-", "").replace(" ", "")
    key = _ALIASES.get(key, key)
    if key not in MOTIONS:
        raise InputError(f"unknown motion pattern {name.strip()!r:.40}; known: "
                         f"{', '.join(MOTIONS)} (and 2R1T, schoenflies, spherical, translational)")
    return MOTIONS[key]
