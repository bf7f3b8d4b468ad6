"""Leg types generated for a motion pattern: enumeration, reciprocal solver, rules, dedup.

:func:`generated_legs` is the leg half of the type synthesis of PMs.  For a
:class:`~screwkit.synthesis.MotionPattern`:

1. every symbolic chain of :mod:`screwkit.synthesis._enumerate` (``dof`` to five
   equivalent joints) is placed at :data:`SYNTHESIS_PLACEMENT` (a leg of a triangle PM at
   home) and its joint twists are stacked, all chains at once;
2. the reciprocal solver's test, batched: the twists are independent (no idle joint:
   a constraint count of ``6 - joints``, between one and ``6 - dof``), and they span
   the twists the pattern needs of every leg (:func:`pattern_twists`: the three
   translations for 3T, the rotations about ``C`` for 3R, ...).  The leg's constraint
   system is then inside the complementary one, which is the reciprocal of those twists;
3. chains that are the same up to the order of their letters and have the same twist
   system at home are one leg type (deduplicated by equivalence: the first in the
   enumeration order, the most special geometry, is kept), and a leg type equivalent to
   a catalog leg is left to the catalog's (the catalog is preferred);
4. each survivor is written as catalog rules (:func:`~screwkit.synthesis._chains.rule_entries`),
   built by the rule builder and analysed by the reciprocal-screw solver and the
   observation rules (:meth:`screwkit.legs.Leg.analyze`): it is kept when the two agree,
   its actuated joint has an actuation wrench, and its counts of forces and couples fit
   the pattern (:meth:`MotionPattern.admits`).

Whether a leg keeps its fit over a finite motion is decided by the engine on the PMs
built from it (:mod:`screwkit.design`): a leg type none of whose PMs verifies is not
listed.
"""

from __future__ import annotations

from dataclasses import dataclass
import math
from functools import lru_cache

import numpy as np

from ..legs import Placement, default_placement
from ..screws import RANK_RTOL
from ._chains import Chain, code_of, describe, elbow, located, rule_entries
from ._enumerate import chains_for
from ._motions import MotionPattern

__all__ = ["GeneratedLeg", "SYNTHESIS_PLACEMENT", "CENTRAL_PLACEMENT", "generated_legs",
           "pattern_twists",
           "pattern_codes", "twist_key"]

#: The placement where chains are screened: vertex 1 of the standard triangle (base
#: circumradius 100 at -30 deg, platform circumradius 50, height 80, ``C`` half-way up),
#: not on a base axis, so that the base axes X, Y differ from the tangent and the radial
#: direction there.
_PHI = np.radians(-30.0)
_U = np.array([np.cos(_PHI), np.sin(_PHI), 0.0])
_LENGTH = float(np.hypot(50.0, 80.0))
#: The pitch of a generated H, as a fraction of the leg length per radian (its rule's ``pitch``).
_H_PITCH = 0.1
SYNTHESIS_PLACEMENT = Placement(A=100.0 * _U, a=50.0 * _U + [0, 0, 80.0], O=np.zeros(3),
                                o=np.array([0.0, 0.0, 80.0]), C=np.array([0.0, 0.0, 40.0]))
#: The placement of a central column: from the base centre to the platform centre.
CENTRAL_PLACEMENT = Placement(A=np.zeros(3), a=np.array([0.0, 0.0, 80.0]), O=np.zeros(3),
                              o=np.array([0.0, 0.0, 80.0]), C=np.array([0.0, 0.0, 40.0]))
#: The direction codes of a central column (the tangent and the radial direction are
#: undefined at the centre).
CENTRAL_CODES = "XYn"


@dataclass(frozen=True)
class GeneratedLeg:
    """A leg type generated for a pattern.

    Attributes
    ----------
    name : str
        ``"<letters>/<code>"`` (``"RRPaR/t.t.t.t"``; :func:`~screwkit.synthesis._chains.code_of`).
    mapping : dict
        Its ``legs:`` entry (name, string, summary, joints), as a model file writes it.
    forces, couples : int
        Its constraint system, from the reciprocal-screw solver.
    """

    name: str
    mapping: dict
    forces: int
    couples: int


#: The direction codes of a new class, in the order tried (the first variants of a word use
#: the first codes): the frame of each pattern (the base normal of the Schoenflies and
#: planar motions, the centre of the spherical one, the base axes of 2T2R and 2T3R).
_CODES = {"3T": "otrn", "3R": "ctnr", "1T2R": "tnro", "3T1R": "ntro", "2T1R": "ntr",
          "2T2R": "XYntr", "2T3R": "XYntr", "1T3R": "ntro"}


def pattern_codes(motion: MotionPattern) -> str:
    """The direction codes a new class of parallel axes may take for ``motion``."""
    return _CODES.get(motion.name, "ntro")


def pattern_twists(motion: MotionPattern, placement: Placement, centre: bool = True
                   ) -> np.ndarray:
    """The twists ``[v; w]`` (about the origin) every leg of a PM with ``motion`` must allow
    at home: the pattern's pure translations, and its rotations where their axes are
    known (about ``C`` for 3R unless not ``centre``: a central column sets the centre
    itself; about the base normal for 3T1R and 2T1R)."""
    R = placement.base_rotation
    rows = []
    for p in motion.independent:
        if p in ("Xo", "Yo", "Zo"):
            rows.append(np.concatenate([R[:, "XYZ".index(p[0])], np.zeros(3)]))
    if motion.fixed_point and centre:
        C = placement.centre
        for k in range(3):
            rows.append(np.concatenate([np.cross(C, R[:, k]), R[:, k]]))
    elif motion.fixed_rotation == "z":
        rows.append(np.concatenate([np.cross(placement.o, R[:, 2]), R[:, 2]]))
    return np.array(rows).reshape(-1, 6)


def _vectors(pl: Placement, central: bool = False):
    """Direction codes and point slots evaluated at ``pl`` by the rule language itself
    (codes undefined there, the tangent at the centre, are left out)."""
    from ..errors import GeometryError
    from ..legs import LegRules
    from ..legs._rule_context import _Context
    from ._chains import DIRECTIONS

    ctx = _Context(LegRules.from_mapping("probe", "S", [{"at": "A"}]), pl)

    def tup(v):
        return tuple(float(x) for x in v)

    dirs = {}
    for c, ref in DIRECTIONS.items():
        try:
            dirs[c] = tup(ctx.direction_rule(ref))
        except GeometryError:
            continue
    pts = {"A": tup(ctx.point("A")), "a": tup(ctx.point("a"))}
    for m in range(1, 4):
        for k in range(1, m + 1):
            pts[("E", k, m)] = tup(ctx.point(elbow(k, m, central)))
            # (a chain with every axis along the base tangent moves its elbows across them)
            pts[("Et", k, m)] = tup(ctx.point(elbow(k, m, central, tangent=True)))
    return dirs, pts, tup(pl.centre)


def _cross(a, b):
    return (a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0])


def _unit(v):
    n = math.sqrt(v[0] * v[0] + v[1] * v[1] + v[2] * v[2])
    return None if n < 1e-9 else (v[0] / n, v[1] / n, v[2] / n)


def _twists(chain: Chain, dirs, pts, C, slots) -> list | None:
    """The joint twists of ``chain`` at the placement, as rows ``[v; w]`` (None: a
    degenerate axis).  Plain floats: this runs on every enumerated chain."""
    cls: dict = {}
    rows = []
    lg = dirs["l"]
    if chain.classes and all(c == "t" for c in chain.classes):      # (as rule_entries)
        slots = [("Et",) + s[1:] if isinstance(s, tuple) else s for s in slots]

    def vec(ax, p):
        k = ax.index
        if k not in cls:
            code = chain.classes[k]
            if code == "c":
                d = (C[0] - p[0], C[1] - p[1], C[2] - p[2])
            elif code.startswith("x"):
                d = _cross(cls[int(code[1:])], lg)
            else:
                d = dirs[code]
            cls[k] = _unit(d)
        return cls[k]

    def rot(d, p, h=0.0):
        v = _cross(p, d)
        return [v[0] + h * d[0], v[1] + h * d[1], v[2] + h * d[2], d[0], d[1], d[2]]

    for i, x in enumerate(chain.letters):
        p = pts[slots[i]] if slots[i] is not None else None
        if x == "S":
            rows += [rot(e, p) for e in ((1.0, 0.0, 0.0), (0.0, 1.0, 0.0), (0.0, 0.0, 1.0))]
        elif x == "Pa":
            prev = next((pts[slots[k]] for k in range(i - 1, -1, -1) if slots[k]), pts["A"])
            nxt = next((pts[slots[k]] for k in range(i + 1, len(slots)) if slots[k]), pts["a"])
            bar = (nxt[0] - prev[0], nxt[1] - prev[1], nxt[2] - prev[2])
            u = vec(chain.axes[i][0], None)
            h = _unit(_cross(u, bar)) if _unit(bar) is not None else None
            if h is None:
                return None
            d = _unit(_cross(h, bar))
            rows.append([d[0], d[1], d[2], 0.0, 0.0, 0.0])
        else:
            for ax in chain.axes[i]:
                d = vec(ax, p)
                if d is None:
                    return None
                if x == "P":
                    rows.append([d[0], d[1], d[2], 0.0, 0.0, 0.0])
                elif x == "C":
                    rows += [rot(d, p), [d[0], d[1], d[2], 0.0, 0.0, 0.0]]
                else:
                    rows.append(rot(d, p, _H_PITCH * _LENGTH if x == "H" else 0.0))
    return rows


def twist_key(letters, twists, length: float) -> tuple:
    """Equivalence key of a leg: its letters in order, the order of its axes' directions
    (each joint's direction numbered by the first earlier joint parallel to it: the order
    of a U's two axes matters over a finite motion, not at home), and its twist system
    (the orthogonal projector on the span of the length-normalised twists, rounded)."""
    T = np.array(twists, float)
    dirs: list = []
    shape = []
    for row in T:
        d = row[3:] if np.linalg.norm(row[3:]) > 1e-9 else row[:3]
        d = d / np.linalg.norm(d)
        k = next((i for i, e in enumerate(dirs) if abs(abs(float(d @ e)) - 1.0) < 1e-9), None)
        if k is None:
            k = len(dirs)
            dirs.append(d)
        shape.append(k)
    T[:, :3] /= length
    _, s, vt = np.linalg.svd(T)
    r = int(np.sum(s > RANK_RTOL * max(1.0, s[0])))
    P = vt[:r].T @ vt[:r]
    return tuple(letters), tuple(shape), np.round(P, 6).tobytes()


def _rank_filter(chains, twists, need, L) -> list:
    """Indices of the chains whose twists are independent and span ``need``."""
    keep = []
    by_size: dict = {}
    for i, T in enumerate(twists):
        if T is not None:
            by_size.setdefault(len(T), []).append(i)
    for c, idx in by_size.items():
        T = np.array([twists[i] for i in idx])
        T[:, :, :3] /= L
        s = np.linalg.svd(T, compute_uv=False)
        full = s[:, -1] > RANK_RTOL * s[:, 0]
        if len(need):
            N = np.broadcast_to(need / np.array([L] * 3 + [1] * 3), (len(idx),) + need.shape)
            s2 = np.linalg.svd(np.concatenate([T, N], axis=1), compute_uv=False)
            spans = s2[:, c] <= RANK_RTOL * s2[:, 0] if c < 6 else np.ones(len(idx), bool)
            full &= spans
        keep += [i for i, ok in zip(idx, full) if ok]
    return sorted(keep)


#: Leg types kept per word (letters in order) by default: its first twist systems in the
#: enumeration order.
VARIANTS = 2


@lru_cache(maxsize=32)
def generated_legs(motion: MotionPattern, exclude_keys: frozenset = frozenset(),
                   variants: int = VARIANTS, wide: bool = False, central: bool = False) -> tuple:
    """The leg types generated for ``motion`` (:class:`GeneratedLeg`, enumeration order).

    Parameters
    ----------
    exclude_keys : frozenset
        :func:`twist_key` of leg types already in the pool (the catalog's): an equivalent
        generated leg is left to them.
    variants : int
        Leg types kept per word (letters in order): its first ``variants`` distinct twist
        systems that pass every test.
    wide : bool
        Every word (H joints, five-joint legs of four or five letters), not only
        :func:`~screwkit.synthesis._enumerate.default_words`.
    central : bool
        Passive central columns instead (from the base centre to the platform centre, at
        :data:`CENTRAL_PLACEMENT`, direction codes :data:`CENTRAL_CODES`): legs that alone
        exert the whole complementary system (``dof`` joints), the Tricept's column for
        1T2R; they need no actuator.
    """
    from ..errors import ScrewkitError
    from ..pm import leg_spec_from_mapping

    pl = CENTRAL_PLACEMENT if central else SYNTHESIS_PLACEMENT
    L = pl.length
    dirs, pts, C = _vectors(pl, central)
    need = pattern_twists(motion, pl, centre=not central)
    codes = CENTRAL_CODES if central else pattern_codes(motion)
    if central:
        variants = 4 * variants          # few words: keep more of each
    high = motion.dof if central else 5
    chains = list(chains_for(max(motion.dof, 1), codes, wide, central, high))
    slots_of: dict = {}
    twists = []
    for ch in chains:
        if ch.letters not in slots_of:
            slots_of[ch.letters] = located(ch)
        twists.append(_twists(ch, dirs, pts, C, slots_of[ch.letters]))
    seen = set(exclude_keys)
    per_word: dict = {}
    names: set = set()
    out = []
    for i in _rank_filter(chains, twists, need, L):
        ch = chains[i]
        if 6 - ch.joints > motion.constraints or per_word.get(ch.letters, 0) >= variants:
            continue
        key = twist_key(ch.letters, twists[i], L)
        if key in seen:
            continue
        seen.add(key)
        name = base = f"{ch.text}/{'column.' if central else ''}{code_of(ch)}"
        while name in names:
            name = f"{base}~{int(name.rpartition('~')[2]) + 1 if '~' in name else 2}"
        names.add(name)
        what = "a central passive column " if central else ""
        mapping = {"name": name, "string": ch.marked,
                   "summary": f"generated for {motion.name}: {what}{describe(ch)}",
                   "joints": rule_entries(ch)}
        try:
            spec = leg_spec_from_mapping(dict(mapping), source="<generated>")
            an = spec.build(pl).analyze()
        except ScrewkitError:
            continue
        if (an.connectivity != ch.joints or not motion.admits(an.n_forces, an.n_couples, an.n_screws)
                or not an.agrees() or (an.actuation is None and not central)):
            continue
        per_word[ch.letters] = per_word.get(ch.letters, 0) + 1
        out.append(GeneratedLeg(name, mapping, an.n_forces, an.n_couples))
    return tuple(out)
