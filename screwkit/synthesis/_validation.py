"""Batch validation: synthesis by the observation rules, verification by the solver.

For every leg string (the paper's Table I by default) :func:`validate_string`

1. analyses a *generic* geometry (:func:`screwkit.rules.generic_leg`): connectivity,
   number of constraint wrenches ``k = 6 - rank``, dependent joints;
2. for every composition of a ``k``-system into pure forces and couples
   (``(1, 0)`` and ``(0, 1)`` when ``k = 1``; ``(2, 0)``, ``(1, 1)``, ``(0, 2)``
   when ``k = 2``...) asks :func:`screwkit.synthesis.synthesize` for a structural
   arrangement, over several random draws;
3. verifies every synthesized leg with :func:`verify`, which sees only the
   concrete :class:`~screwkit.legs.Leg` and the predicted wrenches: the
   reciprocal-screw system has the predicted dimension and contains each
   predicted wrench, the joints are independent (or the dependence was
   predicted), and the actuated joint has an actuation wrench.

:func:`validate_catalog` checks the catalog's accepted legs the same way: each
leg built by its rules must have the system its ``expect`` states, agree with the
observation rules, have an actuation wrench, and its composition must be one the
synthesis finds realizable for its string.

Examples
--------
>>> res = validate_string("SPR", draws=1)
>>> res.k, res.can_force, res.can_couple, res.ok
(1, True, False, True)
"""

from __future__ import annotations

import time
import zlib
from dataclasses import dataclass, field

import numpy as np

from ..errors import InputError
from ..legs import Leg, LegString, Placement, actuation_wrench, analyze_leg, generic_leg, parse_leg
from ..screws import independent_subset, reciprocal_system, same_span, span_contains
from ._synthesis import Synthesis, compositions, counting_rank, layouts_for, synthesize

__all__ = [
    "Verification",
    "verify",
    "DrawResult",
    "TargetResult",
    "LegValidation",
    "CatalogCheck",
    "ValidationReport",
    "validate_string",
    "validate_catalog",
    "validate_table1",
    "composition_label",
    "chain_text",
    "report_rows",
    "catalog_rows",
    "DEFAULT_DRAWS",
]

#: Random draws per target by default.
DEFAULT_DRAWS = 3


# --------------------------------------------------------------------------- verifier
@dataclass(frozen=True)
class Verification:
    """Result of :func:`verify`.

    Attributes
    ----------
    dimension : int
        Dimension of the leg's constraint system (reciprocal-screw solver).
    expected_dimension : int
        Number of predicted wrenches.
    contained : tuple of bool
        Whether each predicted wrench lies in the solver's system.
    same_span : bool
        Whether the predicted wrenches span the solver's system exactly.
    dependent_joints : tuple of str
        Joints spanned by earlier joints.
    dependence_allowed : bool
        Whether a dependence was predicted (more joints than ``6 - k``).
    actuation : bool
        Whether the actuated joint has an actuation wrench.
    residual : float
        Largest normalised ``|W . V| / (|W| |V|)`` of a predicted wrench and a joint twist.
    condition_number : float
        Of the joint twists (normalised), over the retained singular values.
    """

    dimension: int
    expected_dimension: int
    contained: tuple
    same_span: bool
    dependent_joints: tuple
    dependence_allowed: bool
    actuation: bool
    residual: float
    condition_number: float

    @property
    def problems(self) -> tuple:
        """What disagrees with the prediction (empty when verified)."""
        out = []
        if self.dimension != self.expected_dimension:
            out.append(f"constraint system has dimension {self.dimension}, predicted "
                       f"{self.expected_dimension}")
        missing = [i for i, c in enumerate(self.contained) if not c]
        if missing:
            out.append(f"predicted wrench(es) {missing} not in the constraint system")
        if not missing and self.dimension == self.expected_dimension and not self.same_span:
            out.append("predicted wrenches do not span the constraint system")
        if self.dependent_joints and not self.dependence_allowed:
            out.append(f"dependent joints {', '.join(self.dependent_joints)}")
        if self.dependence_allowed and not self.dependent_joints:
            out.append("a dependence was predicted but the joints are independent")
        if not self.actuation:
            out.append("the actuated joint has no actuation wrench (it depends on the passive joints)")
        return tuple(out)

    @property
    def ok(self) -> bool:
        return not self.problems


def verify(leg: Leg, predicted, allow_dependent: bool = False,
           actuation: str = "wrench") -> Verification:
    """Check a concrete leg against predicted constraint wrenches with the solver only.

    Parameters
    ----------
    leg : Leg
    predicted : array_like, shape (k, 6)
        Predicted constraint wrenches ``[f; m]`` (moments about O).
    allow_dependent : bool
        Whether dependent joints are expected (reported, not a failure).
    actuation : {"wrench", "rank"}
        ``"wrench"``: the actuated joint must have an actuation wrench
        (:func:`screwkit.analysis.actuation_wrench` is not None); ``"rank"``: the
        equivalent, cheaper test that the passive joints' twists have a lower rank
        than all the twists (used for repeated draws).

    Returns
    -------
    Verification
    """
    W = np.asarray(predicted, float).reshape(-1, 6)
    if not np.all(np.isfinite(W)):
        raise InputError("predicted wrenches contain NaN or infinite entries")
    T, pts = leg.twists, leg.points
    system = reciprocal_system(T, pts)
    norm = system.normalisation
    contained = tuple(bool(span_contains(system.wrenches, w, norm)) for w in W)
    same = bool(same_span(W, system.wrenches, norm)) if len(W) or system.dimension == 0 else False
    _, dep = independent_subset(T, pts)
    Tn = norm.twists(T)
    Wn = norm.wrenches(W)
    if len(W) and len(Tn):
        num = np.abs(Wn @ Tn.T)
        den = np.outer(np.linalg.norm(Wn, axis=1), np.linalg.norm(Tn, axis=1))
        residual = float(np.max(num / den))
    else:
        residual = 0.0
    if actuation == "wrench":
        act = actuation_wrench(leg, system) is not None
    elif actuation == "rank":
        ia = leg.actuated_index
        passive = np.delete(T, ia, axis=0)
        act = reciprocal_system(passive, pts, length=norm.length).rank < system.rank
    else:
        raise InputError(f"actuation must be 'wrench' or 'rank', got {actuation!r}")
    return Verification(system.dimension, len(W), contained, same,
                        tuple(leg.joints[i].name for i in dep), bool(allow_dependent), act,
                        residual, system.condition_number)


# --------------------------------------------------------------------------- results
def composition_label(comp) -> str:
    """``(2, 0)`` -> ``"2F"``, ``(1, 1)`` -> ``"1F+1C"``, ``(0, 0)`` -> ``"none"``."""
    nf, nc = comp
    parts = ([f"{nf}F"] if nf else []) + ([f"{nc}C"] if nc else [])
    return "+".join(parts) or "none"


def chain_text(ls: LegString) -> str:
    """The equivalent chain, compound joints in parentheses: ``U_PU`` -> ``(RR)-P-(RR)``."""
    expand = {"R": "R", "P": "P", "H": "H", "U": "(RR)", "S": "(RRR)", "C": "(PR)"}
    return "-".join(expand[c] for c in ls.text)


@dataclass(frozen=True)
class DrawResult:
    """One random draw of one target."""

    draw: int
    realizable: bool
    layout: str
    how: str
    reason: str
    verification: Verification | None


@dataclass(frozen=True)
class TargetResult:
    """One composition of the constraint system, over all draws.

    Attributes
    ----------
    composition : tuple (n_forces, n_couples)
    realizable : bool
        As found by the first draw.
    layout : str
        Layout realized (or the most favourable one tried).
    layout_words : str
    how : str
        Per joint, how it satisfies the rules (first draw).
    reason : str
        Why not realizable.
    proof : str
        ``"rule"``, ``"counting"`` or ``"search"``.
    draws : tuple of DrawResult
    """

    composition: tuple
    realizable: bool
    layout: str
    layout_words: str
    how: str
    reason: str
    proof: str
    draws: tuple

    @property
    def label(self) -> str:
        return composition_label(self.composition)

    @property
    def consistent(self) -> bool:
        """Every draw gives the same answer in the same layout."""
        return all(d.realizable == self.realizable and d.layout == self.layout for d in self.draws)

    @property
    def verified(self) -> bool:
        """Every realizable draw passed the solver's verification."""
        return all(d.verification is not None and d.verification.ok
                   for d in self.draws if d.realizable)

    @property
    def problems(self) -> tuple:
        out = []
        if not self.consistent:
            answers = ", ".join(f"draw {d.draw}: {'yes' if d.realizable else 'no'} ({d.layout})"
                                for d in self.draws)
            out.append(f"{self.label}: draws disagree ({answers})")
        for d in self.draws:
            if d.realizable and d.verification is not None and not d.verification.ok:
                out.append(f"{self.label} draw {d.draw}: " + "; ".join(d.verification.problems))
        return tuple(out)


@dataclass(frozen=True)
class LegValidation:
    """Validation of one leg string.

    Attributes
    ----------
    string : LegString
    connectivity : int
        Rank of the joint twists of a generic geometry.
    k : int
        Number of constraint wrenches of a generic geometry, ``6 - connectivity``.
    generic_summary : str
        The generic system in words (``"1 finite-pitch wrench"``).
    dependent_joints : tuple of str
        Of the generic geometry (non-empty: the leg always has dependent joints).
    counting : int
        The counting bound ``min(6, n_R + min(n_P, 3))`` on the rank.
    targets : tuple of TargetResult
    notes : tuple of str
        Remarks that are not disagreements (compound-joint degeneracy, k out of range).
    generic_problems : tuple of str
    """

    string: LegString
    connectivity: int
    k: int
    generic_summary: str
    dependent_joints: tuple
    counting: int
    targets: tuple
    notes: tuple = ()
    generic_problems: tuple = ()

    @property
    def can_force(self) -> bool:
        """Some realizable target contains a pure constraint force."""
        return any(t.realizable and t.composition[0] > 0 for t in self.targets)

    @property
    def can_couple(self) -> bool:
        """Some realizable target contains a pure constraint couple."""
        return any(t.realizable and t.composition[1] > 0 for t in self.targets)

    @property
    def dependent(self) -> bool:
        return bool(self.dependent_joints)

    def target(self, composition) -> TargetResult | None:
        comp = tuple(composition)
        return next((t for t in self.targets if t.composition == comp), None)

    @property
    def problems(self) -> tuple:
        return self.generic_problems + tuple(p for t in self.targets for p in t.problems)

    @property
    def ok(self) -> bool:
        return not self.problems


@dataclass(frozen=True)
class CatalogCheck:
    """Validation of one catalog leg (built by its rules at its placement)."""

    name: str
    string: str
    expected: str
    found: str
    problems: tuple

    @property
    def ok(self) -> bool:
        return not self.problems


@dataclass(frozen=True)
class ValidationReport:
    """All the results of :func:`validate_table1`."""

    legs: tuple
    catalog: tuple
    draws: int
    seed: int
    seconds: float = 0.0
    extra: dict = field(default_factory=dict)

    @property
    def counts(self) -> dict:
        """Strings that realize a force, a couple, both, neither; dependent; disagreements."""
        f = sum(v.can_force for v in self.legs)
        c = sum(v.can_couple for v in self.legs)
        b = sum(v.can_force and v.can_couple for v in self.legs)
        return {
            "strings": len(self.legs),
            "force": f,
            "couple": c,
            "both": b,
            "force_only": f - b,
            "couple_only": c - b,
            "neither": sum(not v.can_force and not v.can_couple for v in self.legs),
            "dependent": sum(v.dependent for v in self.legs),
            "synthesized_legs": sum(1 for v in self.legs for t in v.targets for d in t.draws
                                    if d.realizable),
            "catalog_legs": len(self.catalog),
            "disagreements": self.n_problems,
        }

    @property
    def n_problems(self) -> int:
        return sum(len(v.problems) for v in self.legs) + sum(len(c.problems) for c in self.catalog)

    @property
    def ok(self) -> bool:
        return self.n_problems == 0

    def summary(self) -> str:
        n = self.counts
        return (f"{n['strings']} strings: {n['force']} can exert a constraint force, "
                f"{n['couple']} a constraint couple, {n['both']} both, {n['neither']} neither; "
                f"{n['dependent']} always have dependent joints; {n['synthesized_legs']} "
                f"synthesized legs verified by the solver; catalog: {n['catalog_legs']} legs; "
                f"{n['disagreements']} disagreement{'s' * (n['disagreements'] != 1)} "
                f"({self.draws} draw{'s' * (self.draws != 1)}, seed {self.seed}, "
                f"{self.seconds:.2f} s)")


# --------------------------------------------------------------------------- drivers
def _seed_for(seed: int, text: str, *more) -> list:
    return [int(seed) & 0xFFFFFFFF, zlib.crc32(text.encode()), *more]


def validate_string(string, draws: int = DEFAULT_DRAWS, seed: int = 0,
                    placement: Placement | None = None) -> LegValidation:
    """Validate one leg string (see the module docstring).

    Parameters
    ----------
    string : str or LegString
    draws : int
        Random draws per target (each: new target geometry and new free choices).
    seed : int
    placement : Placement, optional

    Returns
    -------
    LegValidation
    """
    if int(draws) < 1:
        raise InputError(f"draws must be at least 1, got {draws}")
    ls = parse_leg(string) if isinstance(string, str) else string
    text = ls.marked
    problems = []
    notes = []
    analyses = [analyze_leg(generic_leg(ls, placement, seed=s))
                for s in np.random.default_rng(_seed_for(seed, text)).integers(0, 2**31, 2)]
    ranks = [a.connectivity for a in analyses]
    if ranks[0] != ranks[1]:
        problems.append(f"generic rank differs between two random geometries: {ranks}")
    g = analyses[0]
    r = max(ranks)
    k = 6 - r
    cnt = counting_rank(ls)
    if cnt != r:
        notes.append(f"generic rank {r} below the counting bound {cnt} (compound joints "
                     "share an idle motion)")
    targets = []
    comps = compositions(k) if k >= 1 else ()
    if k > 3:
        notes.append(f"{k} constraint wrenches: compositions with more than 3 wrenches are "
                     "not synthesized")
        comps = ()
    for ci, comp in enumerate(comps):
        if not layouts_for(comp):
            continue
        results = []
        first: Synthesis | None = None
        for d in range(int(draws)):
            rng = np.random.default_rng(_seed_for(seed, text, ci, d))
            s = synthesize(ls, comp, rng, placement)
            ver = verify(s.leg, s.predicted_wrenches, allow_dependent=s.dependent,
                         actuation="wrench" if d == 0 else "rank") if s.realizable else None
            results.append(DrawResult(d, s.realizable, s.layout.name, s.how, s.reason, ver))
            if first is None:
                first = s
        targets.append(TargetResult(comp, first.realizable, first.layout.name, first.layout.words,
                                    first.how, first.reason, first.proof, tuple(results)))
    return LegValidation(ls, r, k, g.summary(), g.dependent_joints, cnt, tuple(targets),
                         tuple(notes), tuple(problems))


def validate_catalog(catalog=None, known: dict | None = None, draws: int = 1,
                     seed: int = 0) -> tuple:
    """Check every accepted leg of the catalog (see the module docstring).

    Parameters
    ----------
    catalog : Catalog, optional
        Default :func:`screwkit.catalog.default_catalog`.
    known : dict, optional
        ``{marked string: LegValidation}`` already computed (reused for the
        composition check).
    draws, seed : int
        For strings not in ``known``.

    Returns
    -------
    tuple of CatalogCheck
    """
    from ..pm import default_catalog

    cat = catalog if catalog is not None else default_catalog()
    known = {} if known is None else known
    out = []
    for spec in cat.legs.values():
        problems = []
        e = spec.expect
        expected = composition_label((int(e.get("forces", 0)), int(e.get("couples", 0))))
        if e.get("screws"):
            expected += f"+{int(e['screws'])}W"
        try:
            leg = spec.build()
        except Exception as exc:  # a ScrewkitError or a bug in the entry: report it
            out.append(CatalogCheck(spec.name, spec.string.marked, expected, "-",
                                    (f"cannot be built: {exc}",)))
            continue
        an = leg.analyze()
        problems += list(spec.check_expectation(an))
        if not an.agrees():
            problems.append("the decomposition does not agree with the observation rules")
        if an.actuation is None:
            problems.append("the actuated joint has no actuation wrench")
        v = known.get(spec.string.marked)
        if v is None:
            v = validate_string(spec.string, draws=draws, seed=seed)
            known[spec.string.marked] = v
        comp = (an.n_forces, an.n_couples)
        if an.n_screws == 0 and sum(comp) == v.k and v.k >= 1:
            t = v.target(comp)
            if t is not None and not t.realizable:
                problems.append(f"the synthesis says {composition_label(comp)} is not realizable "
                                f"for {spec.string.text}: {t.reason}")
        found = an.summary()
        if an.dependent_joints:
            found += f" (dependent: {', '.join(an.dependent_joints)})"
        out.append(CatalogCheck(spec.name, spec.string.marked, expected, found, tuple(problems)))
    return tuple(out)


def validate_table1(draws: int = DEFAULT_DRAWS, seed: int = 0, catalog=None,
                    strings=None, check_catalog: bool = True) -> ValidationReport:
    """Validate the paper's Table I (101 distinct strings) and the catalog legs.

    Parameters
    ----------
    draws : int
    seed : int
    catalog : Catalog, optional
    strings : sequence of str, optional
        Validate these strings instead of Table I.
    check_catalog : bool
        Also run :func:`validate_catalog`.
    """
    from ..pm import default_catalog

    t0 = time.perf_counter()
    cat = catalog if catalog is not None else default_catalog()
    todo = list(dict.fromkeys(strings)) if strings is not None else cat.table1_distinct()
    legs = tuple(validate_string(s, draws=draws, seed=seed) for s in todo)
    known = {v.string.marked: v for v in legs}
    checks = validate_catalog(cat, known, draws=draws, seed=seed) if check_catalog else ()
    return ValidationReport(legs, checks, int(draws), int(seed), time.perf_counter() - t0)


# --------------------------------------------------------------------------- rows
def _target_cell(v: LegValidation, kind: int) -> str:
    """The force (kind 0) or couple (kind 1) cell: first realizable target containing one."""
    if v.k == 0:
        return "no (no constraint wrench)"
    hits = [t for t in v.targets if t.realizable and t.composition[kind] > 0]
    if hits:
        t = hits[0]
        lead = f"{t.label}" + (f" ({t.layout})" if len(layouts_for(t.composition)) > 1 else "")
        return f"yes, {lead}: {t.how}"
    misses = [t for t in v.targets if t.composition[kind] > 0]
    if not misses:
        return "no"
    t = misses[-1] if kind == 0 else misses[0]  # the pure target: all forces / all couples
    pure = [m for m in misses if m.composition[1 - kind] == 0]
    t = pure[0] if pure else t
    return f"no: {t.reason}"


def report_rows(report: ValidationReport) -> list:
    """One dict of strings per leg: the columns of the validation table."""
    rows = []
    for v in report.legs:
        conn = str(v.connectivity)
        if v.dependent:
            conn += f" (dependent: {', '.join(v.dependent_joints)})"
        combos = ", ".join(f"{t.label} {'yes' if t.realizable else 'no'}" for t in v.targets) or "-"
        nreal = sum(d.realizable for t in v.targets for d in t.draws)
        verified = "yes" if v.ok else "NO: " + "; ".join(v.problems)
        if v.ok:
            verified += f" ({nreal} legs)" if nreal else " (nothing to synthesize)"
        rows.append({
            "leg": v.string.marked,
            "chain": chain_text(v.string),
            "connectivity": conn,
            "generic": f"{v.k}: {v.generic_summary}" if v.k else "0",
            "force": _target_cell(v, 0),
            "couple": _target_cell(v, 1),
            "combinations": combos,
            "verified": verified,
        })
    return rows


def catalog_rows(report: ValidationReport) -> list:
    """One dict of strings per catalog leg."""
    return [{"leg": c.name, "string": c.string, "expected": c.expected, "found": c.found,
             "verified": "yes" if c.ok else "NO: " + "; ".join(c.problems)}
            for c in report.catalog]
