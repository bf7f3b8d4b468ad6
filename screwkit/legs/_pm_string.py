"""PM strings: ``3RRPRR``, ``3-RPS``, ``2SPS+2SPR``, ``4SPS+SPR``, ``3SPU+UPR``.

A term is an optional leg count (one ASCII digit, 1 to 6), an optional dash and a leg string
(:func:`~screwkit.legs.parse_leg`); terms are joined by ``+``.  A term followed by
``/passive`` is a passive leg: no actuator, it adds its constraint wrenches to the PM and no
actuation (the Tricept ``3UPS+UP/passive``).

Examples
--------
>>> [(t.count, t.leg.text) for t in parse_pm("2SPS+2SPR").terms]
[(2, 'SPS'), (2, 'SPR')]
>>> pm = parse_pm("3UPS+UP/passive")
>>> pm.canonical, pm.passive
('3UPS+UP/passive', (3,))
"""

from __future__ import annotations

import re
from dataclasses import dataclass

from ._guards import MAX_LEGS, MAX_PM_STRING, shorten
from ._parsing import LegString, parse_leg
from ..errors import ParseError

__all__ = ["PMTerm", "PMString", "parse_pm", "PASSIVE_SUFFIX"]

#: The suffix of a passive leg's term in a PM string (``3UPS+UP/passive``).
PASSIVE_SUFFIX = "/passive"
# spaces (ASCII only) may surround the count and the dash: "3 - RPS + 2 SPR"
_TERM = re.compile(r" *([0-9]*) *(-?) *([^+]*)")


@dataclass(frozen=True)
class PMTerm:
    """``count`` legs of one type; ``passive`` when the term carries ``/passive`` (legs
    without an actuator)."""

    count: int
    leg: LegString
    passive: bool = False

    @property
    def text(self) -> str:
        """The term as the canonical PM string writes it (``3UPS``, ``UP/passive``)."""
        return ((str(self.count) if self.count > 1 else "") + self.leg.text
                + (PASSIVE_SUFFIX if self.passive else ""))


@dataclass(frozen=True)
class PMString:
    """A parsed PM string: ``terms`` in order, e.g. ``2SPS+2SPR`` -> (2, SPS), (2, SPR)."""

    text: str
    terms: tuple

    @property
    def legs(self) -> tuple:
        """One LegString per leg, in order (``2SPS+SPR`` -> SPS, SPS, SPR)."""
        return tuple(t.leg for t in self.terms for _ in range(t.count))

    @property
    def passive(self) -> tuple:
        """0-based indices (in :attr:`legs` order) of the passive legs."""
        out: list[int] = []
        k = 0
        for t in self.terms:
            if t.passive:
                out += range(k, k + t.count)
            k += t.count
        return tuple(out)

    @property
    def canonical(self) -> str:
        """``3UPS+UP/passive``: counts, leg letters without markers, passive terms marked."""
        return "+".join(t.text for t in self.terms)


def parse_pm(text: str) -> PMString:
    """Parse a PM string such as ``"3RRPRR"``, ``"3-RPS"``, ``"2SPS+2SPR"`` or
    ``"3UPS+UP/passive"`` (``/passive`` after a term: its legs have no actuator).

    A leg count is one ASCII digit from 1 to 6, a PM has at most :data:`MAX_LEGS`
    legs and its string at most :data:`MAX_PM_STRING` characters.

    Raises
    ------
    ParseError
        Naming the offending character and its 0-based position.
    """
    if not isinstance(text, str):
        raise ParseError(f"a PM string must be a str, got {type(text).__name__}")
    if len(text) > MAX_PM_STRING:
        raise ParseError(f"a PM string of {len(text)} characters is too long (at most "
                         f"{MAX_PM_STRING}): {shorten(text, 40)}")
    if text.strip() == "":
        raise ParseError("empty PM string: expected e.g. '3RRPRR' or '2SPS+2SPR'", text, None)
    terms = []
    pos = 0
    for chunk in text.split("+"):
        start = pos
        m = _TERM.fullmatch(chunk)
        if m is None:                 # _TERM matches any chunk; a guard for the type checker
            raise ParseError("not a PM term", text, start)
        count_txt, dash, leg_txt = m.group(1), m.group(2), m.group(3)
        leg_start = start + m.start(3)
        if leg_txt.strip(" ") == "":
            where = start + len(chunk) - 1 if chunk else start
            what = "a '+' with no leg after it" if not chunk.strip(" ") else \
                "a term with no leg letters"
            raise ParseError(f"{what}", text, max(0, min(where, len(text) - 1)))
        if len(count_txt) > 1:
            raise ParseError(f"leg count {shorten(count_txt, 20)}: a PM has 1 to {MAX_LEGS} "
                             "legs of one type", text, start + m.start(1))
        count = int(count_txt) if count_txt else 1
        if count < 1:
            raise ParseError("leg count must be at least 1", text, start + m.start(1))
        if count > MAX_LEGS:
            raise ParseError(f"{count} legs of one type: a PM has at most {MAX_LEGS} legs", text,
                             start + m.start(1))
        stripped = leg_txt.rstrip(" ")
        passive = False
        slash = stripped.find("/")
        if slash >= 0:
            suffix = stripped[slash:].strip(" ")
            if suffix != PASSIVE_SUFFIX:
                raise ParseError(f"unknown leg suffix {shorten(suffix, 20)}: the only suffix of "
                                 f"a PM term is {PASSIVE_SUFFIX!r} (a leg without an actuator, "
                                 "e.g. '3UPS+UP/passive')", text, leg_start + slash)
            passive, stripped = True, stripped[:slash].rstrip(" ")
            if not stripped:
                raise ParseError("'/passive' follows a leg, e.g. 'UP/passive'", text,
                                 leg_start + slash)
        terms.append(PMTerm(count, parse_leg(stripped, offset=leg_start, source=text), passive))
        pos = start + len(chunk) + 1
    pm = PMString(text, tuple(terms))
    n_legs = sum(t.count for t in terms)
    if n_legs > MAX_LEGS:
        raise ParseError(f"{n_legs} legs in total: a PM has at most {MAX_LEGS} legs", text, None)
    return pm
