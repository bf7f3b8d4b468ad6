"""Enumeration of symbolic chains (:class:`~screwkit.synthesis._chains.Chain`) for a pattern.

Words of letters first (:func:`words`: R, P, H, U, S, C, Pa, with ``dof`` to ``5``
equivalent joints: a leg of six independent joints exerts no constraint), then every
assignment of the geometric conditions to their axes (:func:`assignments`), pruned by the
rules of type synthesis that make two chains the same mechanism:

* an H is parallel to an earlier axis (helical pairs of type synthesis), at most one;
* a Pa's hinges are normal to its bar and to an earlier class (the Delta's arm hinge);
* at most three classes of parallel axes, one S, one Pa, two U, two translational
  letters (P, C, Pa).

The numeric filter (the reciprocal solver on every chain at once) is
:mod:`screwkit.synthesis._leg_types`.
"""

from __future__ import annotations

from ._chains import Axis, Chain

__all__ = ["words", "default_words", "assignments", "chains_for"]

_WEIGHT = {"R": 1, "P": 1, "H": 1, "Pa": 1, "U": 2, "C": 2, "S": 3}
LETTERS = ("R", "P", "U", "S", "C", "Pa", "H")
MAX_CLASSES = 3
MAX_CONSTRAINING = 5


def words(low: int, high: int = MAX_CONSTRAINING) -> list:
    """Letter words of ``low`` to ``high`` equivalent joints, within the limits above."""
    out = []

    def grow(word, weight):
        if low <= weight <= high and word:
            out.append(tuple(word))
        for x in LETTERS:
            w = weight + _WEIGHT[x]
            if w > high:
                continue
            nxt = word + [x]
            if (nxt.count("S") > 1 or nxt.count("Pa") > 1 or nxt.count("H") > 1
                    or nxt.count("U") > 2
                    or sum(y in ("P", "C", "Pa") for y in nxt) > 2):
                continue
            grow(nxt, w)

    grow([], 0)
    return [w for w in out if w[-1] != "Pa" and w[0] != "H"]


def _actuated(word) -> int:
    """The actuated letter: the first when it is R, P, C or H; else the first P or C;
    else the first R (a U, S or Pa at the base is never actuated)."""
    if word[0] in ("R", "P", "C", "H"):
        return 0
    for want in (("P", "C"), ("R", "H")):
        for i, x in enumerate(word):
            if x in want:
                return i
    return -1


def assignments(word, codes) -> list:
    """Every admissible assignment of axis conditions to ``word``: ``[(axes, classes)]``.

    ``codes``: the direction codes a new class may take (``"c"``, through the centre, may
    start several classes).  Assignments with fewer classes come first, and earlier
    classes before new ones (parallel axes are preferred, so the first of equivalent
    chains is the most special one)."""
    out = []

    def new_codes(classes, extra=()):
        used = set(classes)
        return [c for c in tuple(codes) + tuple(extra) if c == "c" or c not in used]

    def go(i, axes, classes):
        if i == len(word):
            out.append((tuple(axes), tuple(classes)))
            return
        x = word[i]
        if x == "S":
            go(i + 1, axes + [()], classes)
            return
        options = []
        if x == "Pa":
            options = [((Axis("class", k),), classes) for k, c in enumerate(classes) if c != "c"]
        elif x == "U":
            firsts = [(k, classes) for k in range(len(classes))]
            if len(classes) < MAX_CLASSES:
                firsts += [(len(classes), classes + [c]) for c in new_codes(classes)]
            for k, cl in firsts:
                seconds = [(j, cl) for j in range(len(cl)) if j != k]
                if len(cl) < MAX_CLASSES:
                    seconds += [(len(cl), cl + [f"x{k}"])]
                    seconds += [(len(cl), cl + [c]) for c in new_codes(cl)
                                if c != cl[k] or c == "c"]
                for j, cl2 in seconds:
                    options.append(((Axis("class", k), Axis("class", j)), cl2))
        else:
            options = [((Axis("class", k),), classes) for k in range(len(classes))]
            if x != "H" and len(classes) < MAX_CLASSES:
                extra = ("l",) if x == "P" else ()
                options += [((Axis("class", len(classes)),), classes + [c])
                            for c in new_codes(classes, extra) if not (c == "c" and x == "P")]
        for ax, cl in options:
            go(i + 1, axes + [ax], list(cl))

    go(0, [], [])
    # fewer classes first (more parallel axes: the special geometry of type synthesis),
    # the enumeration order on ties
    return sorted(out, key=lambda x: len(x[1]))


def default_words(low: int, wide: bool = False) -> list:
    """The words of the default search: no H, and legs of five joints in at most three
    letters (U-P-U, R-P-S, R-U-U ...: the textbook's five-joint legs); ``wide``: every word."""
    ws = words(low)
    if wide:
        return ws
    return [w for w in ws if "H" not in w and (sum(_WEIGHT[x] for x in w) < 5 or len(w) <= 3)]


def chains_for(low: int, codes, wide: bool = False, central: bool = False, high: int = 5):
    """Every chain of ``low`` to ``high`` joints over the direction ``codes`` (a generator),
    word by word (:func:`default_words`).  ``central``: passive central columns (no
    actuator needed)."""
    for w in default_words(low, wide):
        if sum(_WEIGHT[x] for x in w) > high:
            continue
        act = _actuated(w)
        if act < 0 and not central:
            continue
        for axes, classes in assignments(w, codes):
            yield Chain(w, axes, classes, act, central)
