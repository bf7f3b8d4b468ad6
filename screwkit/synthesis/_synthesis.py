"""Synthesis of structural arrangements of a leg from the paper's three observation rules.

Given a leg string and a *target* constraint system (pure constraint forces on
chosen lines and pure constraint couples along chosen directions), place
concrete joint axes and points so that the leg's constraint system is exactly
the target: every joint does no work against every target wrench (the rules),
and the joint twists span the whole ``6 - k`` dimensional reciprocal space
(nothing more is constrained; the joints are independent whenever the leg has
``6 - k`` of them).

Rules as linear conditions
--------------------------
Let the target wrenches be ``W_i = [f_i; m_i]``, ``F`` the matrix of their force
parts (rows ``f_i``) and ``M_p`` the matrix of their moments about a point
``p`` (rows ``m_i - p x f_i``).  A unit twist does no work against every
``W_i`` when

* P along ``d``: ``F d = 0`` (rule 1: every force is perpendicular to P);
* R through ``p`` along ``d``: ``M_p d = 0`` (rule 2: the axis meets or is
  parallel to every force line; rule 3: it is perpendicular to every couple);
* H of pitch ``h``: ``(M_p + h F) d = 0``;
* U with centre ``p``: two independent directions in ``null(M_p)``; S: ``M_p = 0``
  (the centre lies on every force line and there is no couple); C: its axis in
  ``null(F)`` and in ``null(M_p)`` (its P part is perpendicular to every force, its
  R part meets every force line at a right angle and is perpendicular to every
  couple).

The size of ``null(M_p)`` depends on where ``p`` is: the admissible centres are
*strata* (a generic point, a point of a force line, the common point ``X`` of
concurrent forces, the plane ``pi`` of two forces, ...).  Each :class:`Layout`
lists the strata (:class:`Locus`) that cover every admissible line and centre
of that layout (derived by hand, see ``docs/validation.md``).  The synthesizer
draws each joint's point at random in a locus and its directions at random in
the admissible null space, and searches the loci (generic first) for an
arrangement whose twists reach rank ``6 - k``; it also requires the actuated
joint to be independent of the passive ones (else no actuation wrench exists).
A random draw inside a stratum reaches that stratum's largest rank with
probability one, so a failed exhaustive search means the target is not
realizable in that layout.  Impossibilities are explained first by the rules
(a joint with no admissible placement) and by counting (an upper bound on the
rank), then by the search.

Modules
-------
This module holds the driver (:func:`synthesize`, :func:`synthesize_composition`,
the depth-first search) and the result types (:class:`Synthesis`,
:class:`JointChoice`); the rest of the synthesis lives by concern in

* :mod:`screwkit.synthesis._layouts`: the target systems (:data:`LAYOUTS`,
  :class:`Layout`, :class:`Locus`, :func:`make_layout`), derived by hand;
* :mod:`screwkit.synthesis._joints`: placement of each letter's joints in a
  layout and the words saying how they satisfy the rules;
* :mod:`screwkit.synthesis._proofs`: the impossibility arguments (by the rules,
  by counting) and :func:`counting_rank`;
* :mod:`screwkit.synthesis._linalg`: 3-vector helpers and null spaces.

Their public names are re-exported here.

Examples
--------
>>> s = synthesize("SPR", (1, 0), seed=1)
>>> s.realizable, s.leg.string.text, [c.text for c in s.choices]
(True, 'SPR', ['S1: centre on L', 'P2: perpendicular to L', 'R3: meets L'])
>>> synthesize("SPR", (0, 1), seed=1).realizable
False
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from ..errors import InputError
from ..legs import Joint, Leg, LegString, Placement, default_placement, parse_leg
from ..screws import Normalisation, RANK_RTOL
from ..screws._svd import decided_count, small_singular_values, svd_values
from ._joints import choice_words, letters_of, options_for, place_letter, twist_row
from ._layouts import LAYOUTS, Layout, Locus, compositions, layouts_for, make_layout
from ._linalg import NULL_RTOL
from ._proofs import counting_rank, counting_reason, rank_bound, rule_reason

__all__ = [
    "Locus",
    "Layout",
    "JointChoice",
    "Synthesis",
    "LAYOUTS",
    "NULL_RTOL",
    "compositions",
    "counting_rank",
    "layouts_for",
    "make_layout",
    "synthesize",
    "synthesize_composition",
]


# --------------------------------------------------------------------------- results
@dataclass(frozen=True)
class JointChoice:
    """Where one letter of the string was placed and why it satisfies the rules."""

    letter: str
    position: int
    locus: str
    text: str


@dataclass(frozen=True)
class Synthesis:
    """Result of :func:`synthesize`.

    Attributes
    ----------
    string : LegString
    composition : tuple (n_forces, n_couples)
    realizable : bool
    layout : Layout or None
        The target system realized (or the first layout tried when not realizable).
    leg : Leg or None
        The synthesized leg when realizable.
    choices : tuple of JointChoice
    rank : int
        Rank of the joint twists reached (the best found when not realizable).
    target_rank : int
        ``6 - k``.
    dependent : bool
        Whether the leg has more joints than ``6 - k`` (dependence unavoidable).
    reason : str
        Why the composition is not realizable (empty when it is).
    proof : str
        ``"rule"``, ``"counting"`` or ``"search"`` (how the negative answer was reached).
    """

    string: LegString
    composition: tuple
    realizable: bool
    layout: Layout | None
    leg: Leg | None
    choices: tuple
    rank: int
    target_rank: int
    dependent: bool
    reason: str = ""
    proof: str = ""

    @property
    def how(self) -> str:
        """One line: the layout and, per joint, how it satisfies the rules."""
        if not self.realizable:
            return ""
        return "; ".join(c.text for c in self.choices)

    @property
    def predicted_wrenches(self) -> np.ndarray:
        """The target wrenches the synthesized leg must exert, shape (k, 6)."""
        return self.layout.wrenches if self.layout is not None else np.zeros((0, 6))


# --------------------------------------------------------------------------- search
class _Ranker:
    """Rank of normalised twist rows (lists of floats, see :func:`twist_row`)."""

    def __init__(self, norm: Normalisation, rtol=RANK_RTOL):
        self.norm, self.rtol = norm, rtol
        self.centre = np.asarray(norm.centre, float).tolist()
        self.length = float(norm.length)

    def row(self, kind, d, p, h) -> list:
        return twist_row(kind, d, p, h, self.centre, self.length)

    def __call__(self, rows) -> int:
        if not rows:
            return 0
        s = small_singular_values(rows)
        r = None if s is None else decided_count(s, self.rtol * max(1.0, s[0]))
        if r is None:
            s = svd_values(np.array(rows)).tolist()
            tol = self.rtol * max(1.0, s[0])
            r = sum(x > tol for x in s)
        return r


def _search(letters, layout, rng, scale, ranker, target_rank, actuated):
    """Depth-first search over the loci (generic first).  Returns (placed, best_rank, why)."""
    n = len(letters)
    remaining = [sum(lt.dof for lt in letters[i:]) for i in range(n + 1)]
    best = [0, ""]
    need_actuation = sum(lt.dof for lt in letters) > target_rank

    def finish(placed, rows, rank):
        # ``rank`` is the rank of ``rows``, the twists of ``placed``
        if rank != target_rank:
            return False
        if need_actuation:
            passive = [r for (s, *_), r in zip(placed, rows) if s.name != actuated]
            if ranker(passive) != target_rank - 1:
                best[1] = "actuated"
                return False
        return True

    def dfs(i, placed_opts, rows, rank):
        if i == n:
            flat = [j for js, _ in placed_opts for j in js]
            return placed_opts if finish(flat, rows, rank) else None
        prior = [d for js, _ in placed_opts for s, d, _p, _h in js
                 if s.kind == "P" and s.name != actuated]
        for opt in options_for(letters[i], layout, need_actuation):
            js = place_letter(letters[i], opt, layout, rng, scale, prior)
            if js is None:
                continue
            new_rows = rows + [ranker.row(s.kind, d, p, h) for s, d, p, h in js]
            r = ranker(new_rows)
            best[0] = max(best[0], r)
            if r + remaining[i + 1] < target_rank:
                continue
            out = dfs(i + 1, placed_opts + [(js, opt)], new_rows, r)
            if out is not None:
                return out
        return None

    return dfs(0, [], [], 0), best[0], best[1]


def synthesize_composition(string, composition, layout_name: str, rng,
                           placement: Placement | None = None,
                           n_constraints: int | None = None) -> Synthesis:
    """Synthesize ``string`` for one composition in one layout (see :func:`synthesize`)."""
    ls = parse_leg(string) if isinstance(string, str) else string
    pl = placement or default_placement()
    scale = pl.length
    comp = tuple(int(c) for c in composition)
    k = sum(comp)
    if n_constraints is not None and k != n_constraints:
        raise InputError(f"composition {comp} has {k} wrenches, expected {n_constraints}")
    target_rank = 6 - k
    m = len(ls.equivalent)
    centre = 0.5 * (pl.A + pl.a)
    layout = make_layout(comp, layout_name, rng, centre, scale)
    letters = letters_of(ls, pl)
    dependent = m > target_rank

    def fail(reason, proof, rank=0):
        return Synthesis(ls, comp, False, layout, None, (), rank, target_rank, dependent,
                         reason, proof)

    if m < target_rank:
        return fail(f"{m} joints cannot span the {target_rank} freedoms left by {k} "
                    "constraint wrenches", "counting", m)
    for lt in letters:
        why = rule_reason(lt, layout, rng, scale)
        if why:
            return fail(why, "rule")
    why = counting_reason(ls, layout, target_rank)
    if why:
        return fail(why, "counting", rank_bound(ls, layout))
    norm = Normalisation(np.asarray(centre, float), float(scale))
    ranker = _Ranker(norm)
    found, best, why = _search(letters, layout, rng, scale, ranker, target_rank,
                               ls.actuated_name)
    if found is None:
        if why == "actuated":
            return fail("every rule-admissible arrangement of rank "
                        f"{target_rank} makes the actuated joint {ls.actuated_name} dependent "
                        "on the passive joints (no actuation wrench)", "search", best)
        return fail(f"no rule-admissible arrangement in this layout reaches rank {target_rank} "
                    f"(best {best})", "search", best)
    joints, choices = [], []
    for lt, (js, opt) in zip(letters, found):
        for s, d, p, h in js:
            joints.append(Joint(s, d, p, h))
        locus = opt.name if isinstance(opt, Locus) else "-"
        words = choice_words(lt.letter, locus, layout, opt if isinstance(opt, str) else "")
        choices.append(JointChoice(lt.letter, lt.position, locus,
                                   f"{lt.letter}{lt.position}: {words}"))
    leg = Leg(ls, tuple(joints), pl.A, pl.a, f"{ls.text}[{_comp_label(comp)}]")
    return Synthesis(ls, comp, True, layout, leg, tuple(choices), target_rank, target_rank,
                     dependent)


def _comp_label(comp) -> str:
    nf, nc = comp
    parts = ([f"{nf}F"] if nf else []) + ([f"{nc}C"] if nc else [])
    return "+".join(parts) or "0"


def synthesize(string, composition, seed=0, placement: Placement | None = None,
               layouts=None) -> Synthesis:
    """Synthesize a structural arrangement of ``string`` exerting ``composition``.

    Layouts of :data:`LAYOUTS` are tried in order; the first one realized wins.

    Parameters
    ----------
    string : str or LegString
        Leg string (``"RR_PRR"``).
    composition : tuple (n_forces, n_couples)
        The target: that many pure constraint forces and couples, exactly.
    seed : int or numpy.random.Generator or sequence of int
        Seed of the random free choices (target geometry, joint points and axes).
    placement : Placement, optional
        End points of the leg (default :func:`screwkit.legs.default_placement`).
    layouts : sequence of str, optional
        Restrict the layouts tried.

    Returns
    -------
    Synthesis
        When no layout is realizable: the reason of the first layout (or every
        layout's reason when they differ).
    """
    comp = tuple(int(c) for c in composition)
    if len(comp) != 2 or min(comp) < 0 or sum(comp) == 0:
        raise InputError(f"composition must be (n_forces, n_couples) with at least one "
                         f"wrench, got {composition!r}")
    names = tuple(layouts) if layouts is not None else layouts_for(comp)
    if not names:
        raise InputError(f"no layout implemented for {comp[0]} forces and {comp[1]} couples "
                         f"(implemented: {sorted(LAYOUTS)})")
    rng = seed if isinstance(seed, np.random.Generator) else np.random.default_rng(seed)
    fails = []
    for name in names:
        s = synthesize_composition(string, comp, name, rng, placement)
        if s.realizable:
            return s
        fails.append(s)
    # report the most favourable layout (highest rank reached or bound); a search
    # failure outranks a proof only when it is the sole kind of failure
    best = max(fails, key=lambda f: (f.rank, f.proof == "search"))
    reason = best.reason
    if len(fails) > 1:
        others = ", ".join(f.layout.name for f in fails if f is not best)
        reason = f"[{best.layout.name} layout; {others} fail too] {reason}"
    proofs = {f.proof for f in fails}
    proof = "search" if "search" in proofs else ("rule" if proofs == {"rule"} else "counting")
    return Synthesis(best.string, comp, False, best.layout, None, (),
                     best.rank, best.target_rank, best.dependent, reason, proof)
