"""Leg and PM string parsing: names of equivalent joints, actuation marker, errors."""

import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from screwkit.errors import ParseError
from screwkit.legs import JOINT_DOF, parse_leg, parse_pm

SETTINGS = settings(max_examples=50, deadline=None)

# the expansion written out independently of the parser: letter -> (suffix, kind) parts
PARTS = {"R": [("", "R")], "P": [("", "P")], "H": [("", "H")],
         "U": [("a", "R"), ("b", "R")], "S": [("a", "R"), ("b", "R"), ("c", "R")],
         "C": [("p", "P"), ("r", "R")]}

letters_st = st.lists(st.sampled_from("RPHUSC"), min_size=1, max_size=6).map("".join)


@st.composite
def marked_strings(draw):
    s = draw(letters_st)
    k = draw(st.integers(0, len(s) - 1))
    return s, k, s[:k] + "_" + s[k:]


@SETTINGS
@given(marked_strings())
def test_marked_string_round_trip(case):
    s, k, text = case
    ls = parse_leg(text)
    assert ls.text == s and ls.marked == text and ls.explicit_actuation
    assert ls.actuated_position == k + 1
    again = parse_leg(ls.marked)
    assert again == ls                       # frozen dataclasses: field-by-field equality
    # lower case is refused with the upper-case string as a hint; the combining low line
    # (the paper's underline) means the same as '_'
    with pytest.raises(ParseError, match=f"upper case: did you mean {text!r}"):
        parse_leg(text.lower())
    assert parse_leg(s[:k + 1] + "\u0332" + s[k + 1:]).equivalent == ls.equivalent


@SETTINGS
@given(marked_strings())
def test_equivalent_chain_names(case):
    s, k, text = case
    ls = parse_leg(text)
    expected = [(f"{c}{i}{suf}", kind, c, i) for i, c in enumerate(s, 1) for suf, kind in PARTS[c]]
    got = [(j.name, j.kind, j.origin, j.position) for j in ls.equivalent]
    assert got == expected
    assert ls.dof == sum(JOINT_DOF[c] for c in s) == len(expected)
    act = [j for j in ls.equivalent if j.actuated]
    assert len(act) == 1 and act[0].position == k + 1
    # the actuated part of a compound joint: the P of a C, the first R of a U or an S
    want_suffix = {"C": "p", "U": "a", "S": "a"}.get(s[k], "")
    assert act[0].name == f"{s[k]}{k + 1}{want_suffix}"
    assert ls.actuated_name == act[0].name and ls.equivalent[ls.actuated_index] is act[0]


@SETTINGS
@given(letters_st)
def test_unmarked_default_actuation(s):
    if not any(c in "PCRUS" for c in s):          # only helical joints: must be marked
        with pytest.raises(ParseError, match="mark the actuated joint"):
            parse_leg(s)
        return
    ls = parse_leg(s)
    assert not ls.explicit_actuation
    # the rule in words: first P (or C), else first R (or U, S)
    first_p = next((i for i, c in enumerate(s) if c in "PC"), None)
    pos = first_p if first_p is not None else next(i for i, c in enumerate(s) if c in "RUS")
    assert ls.actuated_position == pos + 1
    assert ls.marked == s[:pos] + "_" + s[pos:]
    assert parse_leg(ls.marked).equivalent == ls.equivalent


@pytest.mark.parametrize("text, name, kind", [
    ("RRPRR", "P3", "linear"), ("SPR", "P2", "linear"), ("UUR", "U1a", "rotational"),
    ("RCR", "C2p", "linear"), ("SRR", "S1a", "rotational"), ("_HRR", "H1", "helical"),
    ("RR_R", "R3", "rotational"), ("US_C", "C3p", "linear"),
])
def test_actuated_joint_examples(text, name, kind):
    ls = parse_leg(text)
    assert ls.actuated_name == name and ls.actuation_type == kind


@pytest.mark.parametrize("text, position, words", [
    ("RXP", 1, "unknown joint letter 'X'"),
    ("R P", 1, "unknown joint letter ' '"),
    ("3RR+", 0, "a leg count belongs to a PM string"),
    ("RR__P", 3, "second actuation marker"),
    ("R_P_R", 3, "second actuation marker"),
    ("RRP_", 3, "not followed by a joint letter"),
    ("\u0332RR", 0, "misplaced underline"),
])
def test_leg_parse_errors_name_what_and_where(text, position, words):
    with pytest.raises(ParseError, match=words) as exc:
        parse_leg(text)
    assert exc.value.position == position
    assert f"at position {position}" in str(exc.value)


@pytest.mark.parametrize("text", ["", "   "])
def test_empty_leg_string(text):
    with pytest.raises(ParseError, match="empty leg string"):
        parse_leg(text)


def test_non_string_input():
    with pytest.raises(ParseError, match="must be a str"):
        parse_leg(["R", "P"])
    with pytest.raises(ParseError, match="must be a str"):
        parse_pm(3)


# ---------------------------------------------------------------- PM strings

@pytest.mark.parametrize("text, terms, n_legs, canonical", [
    ("3RRPRR", [(3, "RRPRR")], 3, "3RRPRR"),
    ("3-RPS", [(3, "RPS")], 3, "3RPS"),
    ("2SPS+2SPR", [(2, "SPS"), (2, "SPR")], 4, "2SPS+2SPR"),
    ("4SPS+SPR", [(4, "SPS"), (1, "SPR")], 5, "4SPS+SPR"),
    ("3SPU+UPR", [(3, "SPU"), (1, "UPR")], 4, "3SPU+UPR"),
    (" 3 - R_PS ", [(3, "RPS")], 3, "3RPS"),
])
def test_pm_strings(text, terms, n_legs, canonical):
    pm = parse_pm(text)
    assert [(t.count, t.leg.text) for t in pm.terms] == terms
    assert len(pm.legs) == n_legs and pm.canonical == canonical


def test_pm_keeps_the_marker_of_each_term():
    pm = parse_pm("2S_PS+SP_R")
    assert [lg.actuated_name for lg in pm.legs] == ["P2", "P2", "R3"]


@pytest.mark.parametrize("text, position, words", [
    ("2SPS+", 4, "no leg after it"),
    ("2SPS+2SXR", 7, "unknown joint letter 'X'"),
    ("7RPS", 0, "at most 6 legs"),
    ("0RPS", 0, "at least 1"),
    ("4SPS+3SPR", None, "7 legs in total"),
    ("3", 0, "no leg letters"),
    ("", None, "empty PM string"),
])
def test_pm_parse_errors(text, position, words):
    with pytest.raises(ParseError, match=words) as exc:
        parse_pm(text)
    assert exc.value.position == position


@SETTINGS
@given(st.lists(st.tuples(st.integers(1, 3), letters_st), min_size=1, max_size=3)
       .filter(lambda ts: sum(c for c, _ in ts) <= 6))
def test_pm_canonical_round_trip(terms):
    text = "+".join(f"{c}{s}" for c, s in terms)
    pm = parse_pm(text) if all(any(ch in "PCRUS" for ch in s) for _, s in terms) else None
    if pm is None:
        with pytest.raises(ParseError):
            parse_pm(text)
        return
    again = parse_pm(pm.canonical)
    assert [lg.marked for lg in again.legs] == [lg.marked for lg in pm.legs]
    assert len(pm.legs) == sum(c for c, _ in terms)
