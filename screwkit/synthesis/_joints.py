"""Placement of the joints of a leg string for a target layout, and its description.

Each letter of the string is placed at a point drawn in a locus of the layout,
with directions drawn in the null space of the rule matrices there (see
:mod:`screwkit.synthesis` for the rules as linear conditions); :func:`choice_words`
says in words how the placed joint satisfies the rules.
"""

from __future__ import annotations

import numpy as np

from ..legs import LegString, Placement
from ._layouts import Layout
from ._linalg import cross, null_basis, null_dimension, unit

__all__ = ["Letter", "admissible", "admissible_directions", "place_letter", "joint_twist",
           "twist_row", "letters_of", "options_for", "choice_words"]

_NEED = {"R": 1, "H": 1, "U": 2, "S": 3, "C": 1, "P": 1}


class Letter:
    """One letter of the string: its equivalent joints and how to place them."""

    def __init__(self, letter, position, specs, nominal, pitch):
        self.letter, self.position, self.specs = letter, position, specs
        self.nominal, self.pitch = nominal, pitch

    @property
    def dof(self):
        return len(self.specs)


def _rule_matrix(letter, layout: Layout, p, pitch: float, M_p=None) -> np.ndarray:
    """The matrix whose null space holds the admissible directions of ``letter`` at p."""
    Mp = layout.moment_matrix(p) if M_p is None else M_p
    if letter in ("R", "U", "S"):
        return Mp
    if letter == "H":
        return Mp + pitch * layout.force_matrix()
    if letter == "C":
        return np.vstack([layout.force_matrix(), Mp])
    raise AssertionError(letter)


def admissible(letter, layout: Layout, p, pitch: float, rng) -> bool:
    """Whether :func:`admissible_directions` finds directions, drawing the same random
    numbers from ``rng`` (discarded) without computing a basis of the null space."""
    n = null_dimension(_rule_matrix(letter, layout, p, pitch))
    if n < _NEED[letter]:
        return False
    # the draws of admissible_directions, so that rng continues as it would after it
    rng.standard_normal((3, 3) if letter == "S" else (2, n) if letter == "U" else n)
    return True


def admissible_directions(letter, layout: Layout, p, pitch: float, rng, M_p=None):
    """Random admissible directions for ``letter`` at point p, or None."""
    N = null_basis(_rule_matrix(letter, layout, p, pitch, M_p))
    if len(N) < _NEED[letter]:
        return None
    if letter == "S":
        return list(np.linalg.qr(rng.standard_normal((3, 3)))[0].T)
    if letter == "U":
        c = rng.standard_normal((2, len(N)))
        return [unit(ci @ N) for ci in c]
    return [unit(rng.standard_normal(len(N)) @ N)]


def place_letter(letter: Letter, option, layout, rng, scale, prior_p):
    """Joints ``[(spec, direction, point, pitch)]`` for one option, or None.

    ``prior_p`` (rows) are the directions of the passive P-type joints placed
    before; option ``"span"`` puts a P in their span (a deliberate dependence, so
    that an unavoidably dependent leg keeps its actuated joint independent)."""
    if letter.letter == "P":
        N = layout.force_null()
        if option == "span":
            if len(prior_p) == 0:
                return None
            N = null_basis(null_basis(np.asarray(prior_p)))  # orthonormal basis of their span
        d = unit(rng.standard_normal(len(N)) @ N)
        return [(letter.specs[0], d, letter.nominal, 0.0)]
    locus = option
    p = locus.sample(letter.nominal, rng, scale)
    dirs = admissible_directions(letter.letter, layout, p, letter.pitch, rng)
    if dirs is None:
        return None
    if letter.letter == "C":
        return [(letter.specs[0], dirs[0], p, 0.0), (letter.specs[1], dirs[0], p, 0.0)]
    return [(s, d, p, letter.pitch if s.kind == "H" else 0.0) for s, d in zip(letter.specs, dirs)]


def joint_twist(kind, d, p, pitch):
    if kind == "P":
        return np.concatenate([d, np.zeros(3)])
    return np.concatenate([cross(p, d) + pitch * d, d])


def twist_row(kind, d, p, pitch, centre, length) -> list:
    """``Normalisation(centre, length).twists(joint_twist(kind, d, p, pitch))`` as a list of
    floats, operation for operation (so the same values, without numpy's per-call cost)."""
    d0, d1, d2 = d.tolist()
    c0, c1, c2 = centre
    if kind == "P":
        return [d0 / length, d1 / length, d2 / length, 0.0, 0.0, 0.0]
    p0, p1, p2 = p.tolist()
    v0 = (p1 * d2 - p2 * d1) + pitch * d0
    v1 = (p2 * d0 - p0 * d2) + pitch * d1
    v2 = (p0 * d1 - p1 * d0) + pitch * d2
    return [(v0 - (c1 * d2 - c2 * d1)) / length, (v1 - (c2 * d0 - c0 * d2)) / length,
            (v2 - (c0 * d1 - c1 * d0)) / length, d0, d1, d2]


#: ``{(id(string), id(placement)): (string, placement, letters)}``: both are immutable, and
#: every draw of every layout of a string places the same letters.
_LETTERS: dict = {}


def letters_of(ls: LegString, placement: Placement):
    key = (id(ls), id(placement))
    hit = _LETTERS.get(key)
    if hit is not None and hit[0] is ls and hit[1] is placement:
        return list(hit[2])
    if len(_LETTERS) >= 256:
        _LETTERS.clear()
    out = _letters_of(ls, placement)
    _LETTERS[key] = (ls, placement, tuple(out))
    return out


def _letters_of(ls: LegString, placement: Placement):
    n = len(ls.text)
    out = []
    L = placement.length
    for k, letter in enumerate(ls.text):
        t = k / (n - 1) if n > 1 else 0.5
        nominal = (1 - t) * placement.A + t * placement.a
        specs = tuple(j for j in ls.equivalent if j.position == k + 1)
        out.append(Letter(letter, k + 1, specs, nominal, 0.05 * L if letter == "H" else 0.0))
    return out


def options_for(letter: Letter, layout: Layout, dependent: bool):
    if letter.letter == "P":
        return ["free", "span"] if dependent else ["free"]
    return list(layout.loci)


# ---------------------------------------------------------------- words
def _names(layout: Layout):
    nf = len(layout.force_lines)
    lines = ["L"] if nf == 1 else [f"L{i + 1}" for i in range(nf)]
    nc = len(layout.couples)
    ts = ["t"] if nc == 1 else [f"t{i + 1}" for i in range(nc)]
    return lines, ts


def choice_words(letter: str, locus: str, layout: Layout, option: str = "") -> str:
    """How a joint of ``letter`` placed in ``locus`` satisfies the rules (short)."""
    lines, ts = _names(layout)
    nf, nc = layout.composition
    L = " and ".join(lines)
    T = ", ".join(ts)
    if letter == "P":
        if nf == 0:
            return "free direction" + (" (in the span of the earlier passive P)"
                                       if option == "span" else "")
        base = ("along the normal of pi" if nf == 2 and layout.name == "concurrent"
                else f"perpendicular to {L}")
        return base + (" (in the span of the earlier passive P)" if option == "span" else "")
    at = {"L": "on L", "L1": "on L1", "L2": "on L2", "X": "at X", "pi": "in pi",
          "N": "on N", "Pt": "in the plane through L normal to t"}.get(locus, "")
    perp = f"perpendicular to {T}" if nc else ""
    if letter in ("R", "H"):
        if nf == 0:
            return f"axis {perp}"
        if layout.name == "concurrent" and nf >= 2:
            core = "axis through X" if locus in ("generic", "X") else "axis in pi"
        elif layout.name == "parallel":
            core = f"axis parallel to {L}" if locus == "generic" else "axis in pi"
        elif layout.name == "coplanar":
            core = "axis in pi"
        elif locus == "N":
            core = "axis along the common perpendicular N"
        elif layout.composition == (1, 2) and layout.name == "normal":
            core = "axis parallel to L"
        else:
            core = f"meets {L}"
        return core + (f", {perp}" if perp else "")
    if letter == "U":
        if nf == 0:
            return f"both axes {perp}"
        if locus in ("X", "L", "L1", "L2"):
            core = f"centre {at}" + (f", plane through {'L2' if locus == 'L1' else 'L1'}"
                                     if layout.name == "skew" else "")
        elif locus == "pi":
            core = "both axes in pi"
        elif locus == "Pt":
            core = "both axes in the plane through L normal to t"
        else:
            core = f"axes in a plane through {L}"
        return core + (f", both {perp}" if perp else "")
    if letter == "S":
        return f"centre {at}" if locus != "generic" else "centre on every force line"
    # C
    if nf == 0:
        return f"axis {perp}"
    if locus == "X":
        return "axis through X along the normal of pi"
    if locus == "N":
        return "axis along the common perpendicular N"
    return f"axis meets {L} at a right angle" + (f", {perp}" if perp else "")
