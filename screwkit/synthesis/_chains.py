"""Symbolic joint chains of type synthesis: letters, geometric conditions, rule entries.

A *chain* is a leg string (letters R, P, H, U, S, C, Pa; at most ``MAX_JOINTS`` equivalent
one-DOF joints) with, for every axis, one of the geometric conditions of type synthesis:

* parallel to an earlier axis (a *class* of parallel axes: ``{parallel: R1}``), or the
  first axis of a new class along a direction of the pattern's frame: the base normal
  (``n``), the tangent of the base circle at the vertex (``t``), the radial direction
  towards the base centre (``r``), the direction from the base vertex towards the platform
  centre (``o``), or the base axes ``X``, ``Y`` (for the patterns defined on them);
* through the centre ``C`` of the pattern (``c``: the axes of a spherical leg meet there);
* a U's second axis normal to its first and to the leg line (``x``), or parallel to an
  earlier class;
* a P along the leg line (``l``) or along a class;
* a Pa (parallelogram) whose hinges are normal to its bar and to a class direction.

Joints sit, in order, at the base vertex ``A``, at elbow points off the line ``A -> a``
(:func:`elbow`), and at the platform vertex ``a`` (the first located letter at ``A``, the
last at ``a``); a composite letter (U, S: axes meeting at a point; C: an R and a P
coaxial) is one located letter.  :func:`rule_entries` writes a chain as the ``joints:``
list of a leg type (``docs/catalog.md``), so that every generated leg is a leg type like
the catalog's, placed by its rules at every vertex of a PM.
"""

from __future__ import annotations

from dataclasses import dataclass

__all__ = ["Axis", "Chain", "DIRECTIONS", "MAX_JOINTS", "elbow", "rule_entries", "code_of"]

#: Largest number of equivalent one-DOF joints of a generated leg (a leg of six
#: independent joints exerts no constraint: the unconstrained legs are the catalog's).
MAX_JOINTS = 6

#: The concrete first directions of a class, as rule references.
DIRECTIONS = {
    "n": "base.Z",
    "t": "base.tangent",
    "r": "base.AO",
    "o": {"toward": ["A", "o"]},
    "X": {"base": [1, 0, 0]},
    "Y": {"base": [0, 1, 0]},
    "l": "leg",
}

#: Words for the codes (docs and summaries).
WORDS = {"n": "the base normal", "t": "the base tangent", "r": "the radial direction",
         "o": "the line from the base vertex to the platform centre", "X": "the base X axis",
         "Y": "the base Y axis", "l": "the leg line", "c": "through the centre C",
         "x": "normal to the previous axis and the leg line"}


@dataclass(frozen=True)
class Axis:
    """One axis of a chain: ``kind`` ``"class"`` (parallel to class ``index``, whose first
    member sets its direction ``code``) or ``"c"`` (through the centre ``C``)."""

    kind: str
    index: int = -1


@dataclass(frozen=True)
class Chain:
    """A symbolic leg: letters, one tuple of :class:`Axis` per letter, class directions.

    Attributes
    ----------
    letters : tuple of str
    axes : tuple of tuple of Axis
        Per letter: R, H, C, P one axis; U two; S none (default axes); Pa one (the class
        its hinges are normal to, with the bar).
    classes : tuple of str
        The direction code of each class (``"t"``, ``"x0"``: normal to class 0 and the leg).
    actuated : int
        Index of the actuated letter (-1: none, a passive column).
    central : bool
        A central column (from the base centre ``O`` to the platform centre ``o``): its
        elbows are moved off the line along the base X axis (the tangent is undefined
        at the centre).
    """

    letters: tuple
    axes: tuple
    classes: tuple
    actuated: int = 0
    central: bool = False

    @property
    def text(self) -> str:
        return "".join(self.letters)

    @property
    def marked(self) -> str:
        act = max(self.actuated, 0)
        return "".join(("_" if i == act else "") + x for i, x in enumerate(self.letters))

    @property
    def joints(self) -> int:
        return sum({"U": 2, "S": 3, "C": 2}.get(x, 1) for x in self.letters)


def located(chain: Chain) -> list:
    """Per letter: its point slot (``"A"``, ``"a"``, ``("E", k, m)``) or None (P, Pa)."""
    idx = [i for i, x in enumerate(chain.letters) if x not in ("P", "Pa")]
    out = [None] * len(chain.letters)
    if len(idx) == 1:
        out[idx[0]] = "A" if idx[0] == 0 else "a"
        return out
    m = len(idx) - 2
    for k, i in enumerate(idx):
        out[i] = "A" if k == 0 else "a" if k == len(idx) - 1 else ("E", k, m)
    return out


def elbow(k: int, m: int, central: bool = False, tangent: bool = False) -> dict:
    """The ``k``-th of ``m`` elbow points (1-based): on ``A -> a`` at ``k / (m + 1)``, moved
    off the line along the base tangent (the base X axis for a central column; alternating
    sides) and the base normal, so that parallel axes through ``A``, the elbows and ``a``
    are never coplanar.  A chain whose axes all lie along the base tangent (a Delta leg)
    moves its elbows across them instead, outwards along ``A -> O``'s opposite: moved along
    its own axes an elbow stays on the line ``A -> a`` seen along them, and the leg is
    stretched (singular) at home."""
    side = 0.3 if k % 2 else -0.25
    inner = {"offset": {"between": ["A", "a"], "t": round(k / (m + 1), 6)},
             "along": "base.X" if central else ("base.AO" if tangent else "base.tangent"),
             "fraction": -0.3 if tangent else side}
    return {"offset": inner, "along": "base.Z", "fraction": 0.15}


def _point_ref(slot, central=False, tangent=False):
    if slot is None:
        return None
    if isinstance(slot, tuple):
        return elbow(slot[1], slot[2], central, tangent)
    return slot


def _names(chain: Chain) -> list:
    """Per letter, the equivalent-joint names of its axes (as :func:`parse_leg` names them)."""
    out = []
    for i, x in enumerate(chain.letters, start=1):
        out.append({"U": [f"U{i}a", f"U{i}b"], "C": [f"C{i}r"], "S": [], "Pa": [f"Pa{i}"]}
                   .get(x, [f"{x}{i}"]))
    return out


def rule_entries(chain: Chain) -> list:
    """The ``joints:`` rules of ``chain`` (one mapping per letter)."""
    names = _names(chain)
    slots = located(chain)
    first: dict = {}                        # class index -> name of its first axis
    entries = []

    def direction(ax: Axis, point, name):
        if ax.index in first:
            return {"parallel": first[ax.index]}
        code = chain.classes[ax.index]
        first[ax.index] = name
        if code == "c":
            return {"toward": [point, "C"]}
        if code.startswith("x"):
            return {"perpendicular": [first[int(code[1:])], "leg"]}
        return DIRECTIONS[code]

    tangent = bool(chain.classes) and all(c == "t" for c in chain.classes)
    for i, x in enumerate(chain.letters):
        pt = _point_ref(slots[i], chain.central, tangent)
        e: dict = {}
        if x == "S":
            e["at"] = pt
        elif x == "U":
            e["at"] = pt
            e["axes"] = [direction(ax, pt, nm) for ax, nm in zip(chain.axes[i], names[i])]
        elif x == "Pa":
            c = chain.central
            prev = next((_point_ref(slots[k], c, tangent) for k in range(i - 1, -1, -1)
                         if slots[k]), "A")
            nxt = next((_point_ref(slots[k], c, tangent) for k in range(i + 1, len(slots))
                        if slots[k]), "a")
            ax = chain.axes[i][0]
            ref = first[ax.index] if ax.index in first else DIRECTIONS[chain.classes[ax.index]]
            e = {"axis": {"perpendicular": [ref, {"toward": [prev, nxt]}]}, "at": prev, "to": nxt}
        else:
            e["axis"] = direction(chain.axes[i][0], pt, names[i][0])
            if pt is not None:
                e["at"] = pt
            if x == "H":
                e["pitch"] = 0.1
        entries.append(e)
    return entries


def code_of(chain: Chain) -> str:
    """A short code of the geometric conditions: per letter, the direction codes of its
    axes (``c`` through the centre, ``-`` an S), joined by ``.`` (``t.t.t.t`` for a Delta
    leg whose axes are all along the base tangent)."""
    parts = []
    for x, axes in zip(chain.letters, chain.axes):
        if x == "S":
            parts.append("-")
            continue
        codes = []
        for ax in axes:
            c = "c" if ax.kind == "c" else chain.classes[ax.index]
            codes.append("x" if c.startswith("x") else c)
        parts.append("".join(codes))
    return ".".join(parts)


def describe(chain: Chain) -> str:
    """The geometric conditions in words (the summary of a generated leg type)."""
    parts = []
    names = _names(chain)
    slots = located(chain)
    where = {"A": "at the base vertex", "a": "at the platform vertex"}
    for i, (x, axes) in enumerate(zip(chain.letters, chain.axes)):
        at = where.get(slots[i], "at an elbow") if slots[i] is not None else ""
        if x == "S":
            parts.append(f"S{i + 1} {at}")
            continue
        codes = []
        for ax in axes:
            c = "c" if ax.kind == "c" else chain.classes[ax.index]
            codes.append(WORDS["x" if c.startswith("x") else c] if c != "c" else WORDS["c"])
        label = f"{x}{i + 1}" if x != "U" else f"U{i + 1} ({names[i][0]}, {names[i][1]})"
        if x == "Pa":
            parts.append(f"{label} with hinges normal to its bar and to {codes[0]}")
        else:
            parts.append(f"{label} {' and '.join(dict.fromkeys(codes))} {at}".rstrip())
    return "; ".join(parts)
