"""Parsing of leg strings and PM strings, and expansion into equivalent R/P chains.

Leg strings use the upper-case letters R (revolute), P (prismatic), H (helical),
U (universal), S (spherical) and C (cylindrical), and the token ``Pa`` (a parallelogram:
a planar four-bar loop of four parallel R hinges whose far link translates along a circle,
a one-DOF curvilinear translation).  An H may carry its pitch, in model lengths per
radian: ``RH(2.5)R``.  The actuated joint is marked
by an underscore before its letter (``RR_PRR``, the ASCII form of the paper's
underline); a letter followed by the combining low line U+0332 is accepted too.
Without a marker the actuated joint is the first prismatic joint of the
equivalent chain (a P, or the P part of a C), or its first revolute joint (an R
or the first R of a U or an S) when there is none.

PM strings (``3RRPRR``, ``2SPS+2SPR``, ``3UPS+UP/passive``) are parsed by
:mod:`screwkit.legs._pm_string`.

Expansion: S -> three intersecting non-coplanar R (``S1a S1b S1c``),
U -> two crossed R (``U1a U1b``), C -> coaxial P and R (``C2p C2r``).

Examples
--------
>>> leg = parse_leg("RR_PRR")
>>> [j.name for j in leg.equivalent], leg.actuated_name
(['R1', 'R2', 'P3', 'R4', 'R5'], 'P3')
"""

from __future__ import annotations

import re
import unicodedata
from dataclasses import dataclass

from ._guards import MAX_LEG_JOINTS, MAX_LEG_LETTERS, MAX_LEG_STRING, MAX_LEGS, shorten
from ..errors import ParseError

__all__ = [
    "JOINT_LETTERS",
    "JOINT_DOF",
    "EquivalentJoint",
    "LegString",
    "parse_leg",
]

#: Joint letters and their meaning.
JOINT_LETTERS = {
    "R": "revolute",
    "P": "prismatic",
    "H": "helical",
    "U": "universal (two crossed R)",
    "S": "spherical (three intersecting non-coplanar R)",
    "C": "cylindrical (coaxial P and R)",
    "Pa": "parallelogram (a planar 4R loop: a one-DOF curvilinear translation)",
}
#: Degrees of freedom of each joint letter.
JOINT_DOF = {"R": 1, "P": 1, "H": 1, "U": 2, "S": 3, "C": 2, "Pa": 1}
_EXPANSION = {
    "R": (("R", ""),),
    "P": (("P", ""),),
    "H": (("H", ""),),
    "U": (("R", "a"), ("R", "b")),
    "S": (("R", "a"), ("R", "b"), ("R", "c")),
    "C": (("P", "p"), ("R", "r")),
    # instantaneously a translation normal to the bars and to the hinges (a P joint whose
    # direction turns with the bars); the four hinges count in the mobility
    "Pa": (("P", ""),),
}
#: Most characters of a pitch written in a leg string, ``H(...)``.
_MAX_PITCH_CHARS = 24
_COMBINING_LOW_LINE = "\u0332"
_LOWER = frozenset("rphusc")


@dataclass(frozen=True)
class EquivalentJoint:
    """One 1-DOF joint of the equivalent R/P/H chain.

    Attributes
    ----------
    name : str
        ``R1``, ``P3``, ``S1a``, ``U4b``, ``C2p`` ... (letter, 1-based position
        in the leg string, and a suffix for the parts of a compound joint).
    kind : str
        ``"R"``, ``"P"`` or ``"H"``.
    origin : str
        The letter of the leg string it comes from.
    position : int
        1-based position of that letter in the leg string.
    part : int
        Index of this joint among the parts of its letter (0 for simple joints).
    actuated : bool
    pitch : float or None
        The pitch of an H written in the string (``H(2.5)``, model lengths per radian);
        None when the string gives none.
    """

    name: str
    kind: str
    origin: str
    position: int
    part: int
    actuated: bool = False
    pitch: float | None = None

    @property
    def parallelogram(self) -> bool:
        """True for the equivalent joint of a ``Pa``."""
        return self.origin == "Pa"


@dataclass(frozen=True)
class LegString:
    """A parsed leg string.

    Attributes
    ----------
    text : str
        The letters without the actuation marker (``"RRPRR"``).
    marked : str
        The canonical string with the marker (``"RR_PRR"``).
    actuated_position : int
        1-based position of the actuated letter.
    explicit_actuation : bool
        Whether the string carried a marker.
    equivalent : tuple of EquivalentJoint
    """

    text: str
    marked: str
    actuated_position: int
    explicit_actuation: bool
    equivalent: tuple

    @property
    def letters(self) -> tuple:
        """The joint tokens of the string in order (``"RRPaR"`` -> R, R, Pa, R)."""
        return tuple(_tokens(self.text))

    @property
    def actuated_name(self) -> str:
        return next(j.name for j in self.equivalent if j.actuated)

    @property
    def actuated_index(self) -> int:
        """Index of the actuated joint in the equivalent chain."""
        return next(i for i, j in enumerate(self.equivalent) if j.actuated)

    @property
    def dof(self) -> int:
        """Sum of the joint freedoms (the length of the equivalent chain)."""
        return len(self.equivalent)

    @property
    def actuation_type(self) -> str:
        """``"linear"`` (P actuated), ``"rotational"`` (R) or ``"helical"``."""
        return {"P": "linear", "R": "rotational", "H": "helical"}[
            self.equivalent[self.actuated_index].kind]


def _tokens(text: str) -> list:
    """Joint tokens of letters without marker or pitch (``"RRPaR"`` -> R, R, Pa, R)."""
    out, i = [], 0
    while i < len(text):
        n = 2 if text.startswith("Pa", i) else 1
        out.append(text[i:i + n])
        i += n
    return out


def _expand(letters, actuated_position: int, pitches=None) -> tuple:
    joints = []
    pitches = pitches or [None] * len(letters)
    for pos, letter in enumerate(letters, start=1):
        for part, (kind, suffix) in enumerate(_EXPANSION[letter]):
            joints.append(EquivalentJoint(f"{letter}{pos}{suffix}", kind, letter, pos, part,
                                          False, pitches[pos - 1]))
    # the actuated equivalent joint of an actuated compound letter: its P part
    # for C, its first part otherwise
    cands = [i for i, j in enumerate(joints) if j.position == actuated_position]
    pick = next((i for i in cands if joints[i].kind == "P"), cands[0])
    j = joints[pick]
    joints[pick] = EquivalentJoint(j.name, j.kind, j.origin, j.position, j.part, True, j.pitch)
    return tuple(joints)


def _letter_problem(ch: str, src: str) -> str:
    """Why ``ch`` is not a joint letter, with a hint."""
    if ch in _LOWER:
        fixed = "".join(c.upper() if c in _LOWER else c for c in src)
        if "pa" in src.lower():            # the parallelogram token keeps its small a
            fixed = re.sub("P[aA]", "Pa", "".join(c.upper() if c == "p" else c for c in src))
            fixed = "".join(c.upper() if c in _LOWER and c != "a" else c for c in fixed)
        return f"joint letters are upper case: did you mean {fixed!r}?"
    if ch == "A" and "PA" in src:
        return f"unknown joint letter 'A' (a parallelogram is written Pa: did you mean " \
               f"{src.replace('PA', 'Pa')!r}?)"
    if ch == "/":
        return ("'/' is not a joint letter: it names a catalog variant of a leg (such as "
                "UPU/force; 'screwkit catalog' lists them) where a command takes one ('screwkit "
                "leg', a model file's legs), and this is none of them")
    if ch in "0123456789":
        return (f"unknown joint letter {ch!r} (a leg count belongs to a PM string such as "
                "'3RPS', not to a leg)")
    if ch.isdigit() or ch.isnumeric():
        return (f"{ch!r} (U+{ord(ch):04X}) is not an ASCII digit: a leg count is one of 1 to "
                f"{MAX_LEGS}, before the joint letters")
    if ord(ch) > 127 and (ch.upper() in _EXPANSION or
                          unicodedata.normalize("NFKC", ch).upper() in _EXPANSION):
        return (f"unknown joint letter {ch!r} (U+{ord(ch):04X}, not an ASCII letter; "
                "expected one of R, P, H, U, S, C)")
    return f"unknown joint letter {ch!r} (expected one of R, P, H, U, S, C)"


def parse_leg(text: str, offset: int = 0, source: str | None = None) -> LegString:
    """Parse a leg string such as ``"RRPRR"``, ``"RR_PRR"`` or ``"_RPS"``.

    Joint letters are upper case (``"rps"`` is refused with the hint ``did you mean
    'RPS'?``); a leg has at most :data:`MAX_LEG_LETTERS` letters and
    :data:`MAX_LEG_JOINTS` joints in its equivalent chain, and its string at most
    :data:`MAX_LEG_STRING` characters.

    Parameters
    ----------
    text : str
    offset : int
        Added to reported positions (used when the leg is part of a PM string).
    source : str, optional
        The full string, for error messages.

    Raises
    ------
    ParseError
        Naming the offending character and its 0-based position.
    """
    if not isinstance(text, str):
        raise ParseError(f"a leg string must be a str, got {type(text).__name__}")
    if len(text) > MAX_LEG_STRING:
        raise ParseError(f"a leg string of {len(text)} characters is too long (at most "
                         f"{MAX_LEG_STRING}): {shorten(text, 40)}")
    src = source if source is not None else text
    if text.strip() == "":
        raise ParseError("empty leg string: expected joint letters from R, P, H, U, S, C", src,
                         offset if source else None)
    letters: list[str] = []
    pitches: list = []
    actuated = None
    marker_pending = False
    i = 0
    while i < len(text):
        ch = text[i]
        if ch == "_":
            if actuated is not None or marker_pending:
                raise ParseError("second actuation marker '_' (a leg has one actuated joint)",
                                 src, offset + i)
            marker_pending = True
        elif ch == _COMBINING_LOW_LINE:
            if not letters or actuated is not None:
                raise ParseError("misplaced underline mark", src, offset + i)
            actuated = len(letters)
        elif ch in _EXPANSION:
            tok = "Pa" if ch == "P" and text.startswith("Pa", i) else ch
            letters.append(tok)
            pitches.append(None)
            i += len(tok) - 1
            if marker_pending:
                actuated = len(letters)
                marker_pending = False
        elif ch == "(" and letters and letters[-1] == "H" and pitches[-1] is None:
            close = text.find(")", i)
            if close < 0 or close - i - 1 > _MAX_PITCH_CHARS:
                raise ParseError("an H pitch is written H(NUMBER), e.g. RH(2.5)R (model lengths "
                                 "per radian)", src, offset + i)
            from ._guards import parse_number
            from ..errors import InputError
            try:
                pitches[-1] = parse_number(text[i + 1:close], "H pitch", bound=1e6)
            except InputError as exc:
                raise ParseError(str(exc), src, offset + i + 1) from None
            i = close
        elif ch == "(":
            raise ParseError("'(' opens a pitch and follows an H only, e.g. RH(2.5)R", src,
                             offset + i)
        else:
            raise ParseError(_letter_problem(ch, src), src, offset + i)
        i += 1
    if marker_pending:
        raise ParseError("actuation marker '_' is not followed by a joint letter", src,
                         offset + len(text) - 1)
    if not letters:
        raise ParseError("leg string has no joint letters", src, offset)
    s = "".join(letters)
    if len(letters) > MAX_LEG_LETTERS:
        raise ParseError(f"{len(s)} joint letters in leg {s!r}: a leg has at most "
                         f"{MAX_LEG_LETTERS}", src, None)
    n_joints = sum(JOINT_DOF[c] for c in letters)
    if n_joints > MAX_LEG_JOINTS:
        raise ParseError(f"leg {s!r} has {n_joints} joints in its equivalent chain: a leg has "
                         f"at most {MAX_LEG_JOINTS} (S = 3, U = C = 2)", src, None)
    explicit = actuated is not None
    if actuated is None:
        # default: first P of the equivalent chain (P or the P of a C), else its first R
        # (an R, or the first R of a U or an S); H only when marked
        actuated = next((k + 1 for k, c in enumerate(letters) if c in ("P", "C")), None)
        if actuated is None:
            actuated = next((k + 1 for k, c in enumerate(letters) if c in "RUS"), None)
        if actuated is None:
            raise ParseError(f"leg {s!r} has no P or R joint to actuate by default; "
                             "mark the actuated joint with '_'", src, None)
    shown = [t if h is None else f"{t}({h:g})" for t, h in zip(letters, pitches)]
    marked = "".join(shown[: actuated - 1]) + "_" + "".join(shown[actuated - 1:])
    return LegString(s, marked, actuated, explicit, _expand(letters, actuated, pitches))
