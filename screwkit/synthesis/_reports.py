"""Result types of the batch validation, and their rows for the CLI's tables.

:class:`ValidationReport` (one :class:`LegValidation` per leg string, one
:class:`TargetResult` per composition, one :class:`DrawResult` per random draw,
one :class:`CatalogCheck` per catalog leg) is made by
:func:`screwkit.synthesis.validate_table1`; :func:`report_rows` and
:func:`catalog_rows` turn it into table rows.
"""

from __future__ import annotations

from dataclasses import dataclass, field

from ..legs import LegString
from ._synthesis import layouts_for
from ._verify import Verification

__all__ = ["DrawResult", "TargetResult", "LegValidation", "CatalogCheck", "ValidationReport",
           "composition_label", "chain_text", "report_rows", "catalog_rows"]


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
        """One line of counts. It carries no run time (that is ``seconds``), so a table
        generated with it is the same from run to run."""
        n = self.counts
        return (f"{n['strings']} strings: {n['force']} can exert a constraint force, "
                f"{n['couple']} a constraint couple, {n['both']} both, {n['neither']} neither; "
                f"{n['dependent']} always have dependent joints; {n['synthesized_legs']} "
                f"synthesized legs verified by the solver; catalog: {n['catalog_legs']} legs; "
                f"{n['disagreements']} disagreement{'s' * (n['disagreements'] != 1)} "
                f"({self.draws} draw{'s' * (self.draws != 1)}, seed {self.seed})")


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
