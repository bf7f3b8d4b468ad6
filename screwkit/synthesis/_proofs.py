"""Impossibility arguments of the synthesis: by the rules and by counting.

:func:`rule_reason` explains a joint with no rule-admissible placement in a layout;
:func:`rank_bound` and :func:`counting_reason` bound the rank of the joint twists
from the rules (rule 1 for the translations, rule 3 for the rotations);
:func:`counting_rank` is the plain counting bound of a string.
"""

from __future__ import annotations

import numpy as np

from ..legs import LegString, parse_leg
from ._joints import Letter, admissible
from ._layouts import Layout
from ._linalg import null_basis

__all__ = ["counting_rank", "rule_reason", "rank_bound", "counting_reason"]


def counting_rank(string: str | LegString) -> int:
    """Upper bound on the rank of a leg's twists by counting: ``min(6, n_R + min(n_P, 3))``
    (translations span at most 3 directions).  Compound joints can lower the generic
    rank further (``SS`` has an idle rotation about the line of the centres)."""
    ls = parse_leg(string) if isinstance(string, str) else string
    nr = sum(j.kind in "RH" for j in ls.equivalent)
    npr = sum(j.kind == "P" for j in ls.equivalent)
    return min(6, nr + min(npr, 3))


def rule_reason(letter: Letter, layout: Layout, rng, scale) -> str | None:
    """Why no placement of ``letter`` satisfies the rules in ``layout`` (None if one does)."""
    if letter.letter == "P":
        if layout.force_null_dimension() == 0:
            return (f"P{letter.position}: a force must be perpendicular to every P (rule 1), "
                    "and the forces span every direction")
        return None
    for locus in layout.loci:
        p = locus.sample(letter.nominal, rng, scale)
        if admissible(letter.letter, layout, p, letter.pitch, rng):
            return None
    nf, nc = layout.composition
    name = f"{letter.letter}{letter.position}"
    c_dim = layout.k - layout.force_rank          # dimension of the couples in the system
    if letter.letter == "S":
        if c_dim:
            return (f"{name}: a couple must be perpendicular to every R axis (rule 3), "
                    "and the three S axes are not coplanar")
        return (f"{name}: every force must pass through the S centre (rule 2), "
                "and the target forces have no common point")
    if letter.letter == "U":
        if c_dim >= 2:
            return (f"{name}: both U axes must be perpendicular to two couples (rule 3), "
                    "i.e. parallel to each other")
        return (f"{name}: both U axes must meet every force line and be perpendicular to "
                "every couple (rules 2, 3): no centre admits two crossed axes")
    if letter.letter == "C":
        return (f"{name}: the C axis must be perpendicular to every force (rule 1, its P), "
                "meet every force line (rule 2) and be perpendicular to every couple "
                "(rule 3, its R): no such line")
    return (f"{name}: no axis meets every force line and is perpendicular to every couple "
            "(rules 2, 3)")


def rank_bound(ls: LegString, layout: Layout) -> int:
    """Rank bound from the rules: the rotation parts of the twists are perpendicular
    to the couples of the system (rule 3), the pure translations in their span are
    perpendicular to its forces (rule 1)."""
    m = len(ls.equivalent)
    nr = sum(j.kind in "RH" for j in ls.equivalent)
    rf = layout.force_rank
    c_dim = layout.k - rf
    return min(min(nr, 3 - c_dim) + (3 - rf), m)


def counting_reason(ls: LegString, layout: Layout, target_rank: int) -> str | None:
    """Why the :func:`rank_bound` is below ``target_rank``, or why the C joints are
    necessarily dependent (None when neither)."""
    nC = ls.text.count("C")
    if nC >= 2 and len(ls.equivalent) == target_rank:
        dC = len(null_basis(np.vstack([layout.force_matrix(), layout.couple_space()])))
        if nC > dC:
            return (f"the {nC} C axes must be perpendicular to every force (rule 1, their P) "
                    "and to every couple (rule 3, their R): they span at most "
                    f"{dC} direction{'s' * (dC != 1)}, so the P parts of the C joints "
                    "are dependent")
    m = len(ls.equivalent)
    nr = sum(j.kind in "RH" for j in ls.equivalent)
    npr = m - nr
    rf = layout.force_rank
    c_dim = layout.k - rf
    rw = min(nr, 3 - c_dim)
    bound = rank_bound(ls, layout)
    if bound >= target_rank:
        return None
    parts = []
    if rf and npr > 3 - rf:
        f = "the force" if layout.k - c_dim == 1 and len(layout.force_lines) == 1 else "the forces"
        parts.append(f"the {npr} P-type joints must be perpendicular to {f} (rule 1), "
                     f"so at most {3 - rf} of them {'is' if 3 - rf == 1 else 'are'} independent")
    if c_dim and nr > 3 - c_dim:
        parts.append(f"the R axes must be perpendicular to the couple{'s' * (c_dim > 1)} "
                     f"(rule 3): at most {3 - c_dim} rotation direction{'s' * (3 - c_dim > 1)}")
    if not parts:
        parts.append(f"rotations span at most {rw} and pure translations at most {3 - rf} "
                     "directions")
    return "; ".join(parts) + f": rank <= {bound} < {target_rank}"
