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

from .errors import InputError
from .legs import Joint, Leg
from .parsing import LegString, parse_leg
from .placement import Placement, default_placement
from .reciprocal import Normalisation
from .screws import couple_wrench, force_wrench
from .tolerance import RANK_RTOL

__all__ = [
    "Locus",
    "Layout",
    "JointChoice",
    "Synthesis",
    "LAYOUTS",
    "compositions",
    "counting_rank",
    "layouts_for",
    "make_layout",
    "synthesize",
    "synthesize_composition",
]

#: Relative tolerance of the null spaces of the rule matrices (built exactly from the
#: target geometry, so only rounding separates a zero from a non-zero singular value).
NULL_RTOL = 1e-9

#: Layout names tried for each composition ``(n_forces, n_couples)``, in order.
LAYOUTS = {
    (1, 0): ("line",),
    (0, 1): ("couple",),
    (2, 0): ("concurrent", "parallel", "skew"),
    (1, 1): ("general", "perpendicular", "coaxial"),
    (0, 2): ("couples",),
    (3, 0): ("concurrent", "coplanar"),
    (2, 1): ("concurrent", "normal"),
    (1, 2): ("line", "normal"),
    (0, 3): ("couples",),
}


def compositions(k: int) -> tuple:
    """The compositions ``(n_forces, n_couples)`` of a ``k``-system, forces first."""
    return tuple((k - c, c) for c in range(k + 1))


# --------------------------------------------------------------------------- targets
@dataclass(frozen=True)
class Locus:
    """A stratum of admissible joint points of a layout.

    Attributes
    ----------
    name : str
        ``"generic"``, ``"L"``, ``"L1"``, ``"X"``, ``"pi"``, ``"N"``, ``"Pt"``.
    kind : str
        ``"space"``, ``"line"``, ``"point"`` or ``"plane"``.
    point : ndarray (3,)
        A point of the locus (unused for ``"space"``).
    direction : ndarray (3,) or None
        Line direction, or plane normal.
    """

    name: str
    kind: str
    point: np.ndarray | None = None
    direction: np.ndarray | None = None

    def sample(self, near, rng, scale: float) -> np.ndarray:
        """A random point of the locus close to ``near`` (spread ``scale``)."""
        near = np.asarray(near, float)
        if self.kind == "space":
            return near + 0.15 * scale * rng.standard_normal(3)
        if self.kind == "point":
            return np.array(self.point, float)
        d = self.direction
        if self.kind == "line":
            s = float(np.dot(near - self.point, d)) + 0.1 * scale * rng.standard_normal()
            return self.point + s * d
        # plane: project, then move inside the plane
        x = near + 0.15 * scale * rng.standard_normal(3)
        return x - np.dot(x - self.point, d) * d


@dataclass(frozen=True)
class Layout:
    """A concrete target constraint system and the strata of its admissible points.

    Attributes
    ----------
    composition : tuple (n_forces, n_couples)
    name : str
        Layout name (``"concurrent"``...; see :data:`LAYOUTS`).
    force_lines : tuple of (point, direction)
        One per target force (unit directions), named ``L`` or ``L1, L2, ...``.
    couples : tuple of ndarray (3,)
        Unit couple directions ``t`` or ``t1, t2, ...``.
    loci : tuple of Locus
        Strata of admissible points, generic first.
    words : str
        The layout in words (``"2 forces meeting at X"``).
    """

    composition: tuple
    name: str
    force_lines: tuple
    couples: tuple
    loci: tuple
    words: str

    def __post_init__(self):
        rows = [force_wrench(d, p).vector for p, d in self.force_lines]
        rows += [couple_wrench(t).vector for t in self.couples]
        W = np.array(rows, float).reshape(-1, 6)
        W.setflags(write=False)
        object.__setattr__(self, "_W", W)

    @property
    def k(self) -> int:
        return len(self.force_lines) + len(self.couples)

    @property
    def wrenches(self) -> np.ndarray:
        """The target wrenches ``[f; m]`` (moments about O), shape (k, 6): forces then couples."""
        return self._W.copy()

    @property
    def force_rank(self) -> int:
        """Rank of the force directions (the system's forces span this many directions)."""
        if not self.force_lines:
            return 0
        D = np.array([d for _, d in self.force_lines])
        s = np.linalg.svd(D, compute_uv=False)
        return int(np.sum(s > NULL_RTOL * s[0]))

    def couple_space(self) -> np.ndarray:
        """Orthonormal basis (rows) of the directions of the couples in the system's span
        (the combinations with zero force), shape (c, 3)."""
        F = self._W[:, :3]
        _, s, Vt = np.linalg.svd(F.T, full_matrices=True)
        r = int(np.sum(s > NULL_RTOL * max(1.0, float(s[0]) if s.size else 1.0)))
        M = Vt[r:] @ self._W[:, 3:]
        if len(M) == 0:
            return np.zeros((0, 3))
        return _null(_null(M))

    def force_matrix(self) -> np.ndarray:
        """``F``, shape (k, 3)."""
        return self._W[:, :3]

    def moment_matrix(self, p) -> np.ndarray:
        """``M_p``: moments of the target wrenches about ``p``, shape (k, 3)."""
        W = self._W
        return W[:, 3:] - _cross(np.asarray(p, float), W[:, :3])


def _cross(a, b):
    """``a x b`` for 3-vectors (rows of b), without numpy's generic overhead."""
    b = np.asarray(b, float)
    return np.stack([a[1] * b[..., 2] - a[2] * b[..., 1],
                     a[2] * b[..., 0] - a[0] * b[..., 2],
                     a[0] * b[..., 1] - a[1] * b[..., 0]], axis=-1)


def _unit(v):
    v = np.asarray(v, float)
    return v / np.linalg.norm(v)


def _rand_unit(rng):
    return _unit(rng.standard_normal(3))


def _perp_unit(rng, *vs):
    """A random unit vector perpendicular to every vector in ``vs``."""
    x = rng.standard_normal(3)
    for v in vs:
        v = _unit(v)
        x = x - np.dot(x, v) * v
    return _unit(x)


def make_layout(composition, name: str, rng, centre, scale: float) -> Layout:
    """Draw a target system of ``composition`` in layout ``name`` around ``centre``.

    Parameters
    ----------
    composition : tuple (n_forces, n_couples)
    name : str
        One of ``LAYOUTS[composition]``.
    rng : numpy.random.Generator
    centre : array_like (3,)
        Where the force lines pass (the middle of the leg).
    scale : float
        The leg length.
    """
    comp = tuple(int(c) for c in composition)
    if comp not in LAYOUTS or name not in LAYOUTS[comp]:
        raise InputError(f"no layout {name!r} for {comp[0]} forces and {comp[1]} couples; "
                         f"known: {LAYOUTS.get(comp, ())}")
    c0 = np.asarray(centre, float)
    near = lambda: c0 + 0.1 * scale * rng.standard_normal(3)  # noqa: E731
    generic = Locus("generic", "space")
    nf, nc = comp
    lines: list = []
    couples: list = []
    loci = [generic]
    if comp == (1, 0):
        q, c = near(), _rand_unit(rng)
        lines = [(q, c)]
        loci.append(Locus("L", "line", q, c))
        words = "1 force on a line L"
    elif comp == (0, 1):
        couples = [_rand_unit(rng)]
        words = "1 couple along t"
    elif comp == (2, 0) and name == "concurrent":
        X = near()
        c1, c2 = _rand_unit(rng), _rand_unit(rng)
        lines = [(X, c1), (X, c2)]
        loci += [Locus("X", "point", X), Locus("pi", "plane", X, _unit(np.cross(c1, c2)))]
        words = "2 forces L1, L2 meeting at X (plane pi)"
    elif comp == (2, 0) and name == "parallel":
        c = _rand_unit(rng)
        u = _perp_unit(rng, c)
        q = near()
        lines = [(q - 0.2 * scale * u, c), (q + 0.2 * scale * u, c)]
        loci.append(Locus("pi", "plane", q, _unit(np.cross(c, u))))
        words = "2 parallel forces L1, L2 (plane pi)"
    elif comp == (2, 0):  # skew
        q1, q2 = near(), near()
        c1, c2 = _rand_unit(rng), _rand_unit(rng)
        n = _unit(np.cross(c1, c2))
        # feet of the common perpendicular N
        A = np.array([[c1 @ c1, -(c1 @ c2)], [c1 @ c2, -(c2 @ c2)]])
        s, t = np.linalg.solve(A, [(q2 - q1) @ c1, (q2 - q1) @ c2])
        lines = [(q1, c1), (q2, c2)]
        loci += [Locus("L1", "line", q1, c1), Locus("L2", "line", q2, c2),
                 Locus("N", "line", q1 + s * c1, n)]
        words = "2 forces on skew lines L1, L2 (common perpendicular N)"
    elif comp == (1, 1):
        q, c = near(), _rand_unit(rng)
        if name == "general":
            t = _rand_unit(rng)
            words = "1 force on L and 1 couple along t (t oblique to L)"
        elif name == "perpendicular":
            t = _perp_unit(rng, c)
            words = "1 force on L and 1 couple along t perpendicular to L"
        else:
            t = c
            words = "1 force on L and 1 couple along L"
        lines, couples = [(q, c)], [t]
        loci.append(Locus("L", "line", q, c))
        if name == "perpendicular":
            loci.append(Locus("Pt", "plane", q, t))
    elif comp == (0, 2):
        couples = [_rand_unit(rng), _rand_unit(rng)]
        words = "2 couples t1, t2 (normal n = t1 x t2)"
    elif comp == (3, 0) and name == "concurrent":
        X = near()
        lines = [(X, _rand_unit(rng)) for _ in range(3)]
        loci.append(Locus("X", "point", X))
        words = "3 forces meeting at X"
    elif comp == (3, 0):  # coplanar
        q, nrm = near(), _rand_unit(rng)
        lines = [(q + 0.2 * scale * _perp_unit(rng, nrm), _perp_unit(rng, nrm)) for _ in range(3)]
        loci.append(Locus("pi", "plane", q, nrm))
        words = "3 forces in a plane pi"
    elif comp == (2, 1):
        X = near()
        c1, c2 = _rand_unit(rng), _rand_unit(rng)
        n = _unit(np.cross(c1, c2))
        t = _rand_unit(rng) if name == "concurrent" else n
        lines, couples = [(X, c1), (X, c2)], [t]
        loci += [Locus("X", "point", X), Locus("pi", "plane", X, n)]
        words = ("2 forces meeting at X (plane pi) and 1 couple t" if name == "concurrent" else
                 "2 forces meeting at X (plane pi) and 1 couple normal to pi")
    elif comp == (1, 2):
        q, c = near(), _rand_unit(rng)
        if name == "line":
            couples = [_rand_unit(rng), _rand_unit(rng)]
            words = "1 force on L and 2 couples t1, t2"
        else:
            couples = [_perp_unit(rng, c)]
            couples.append(_unit(np.cross(c, couples[0])))
            words = "1 force on L and 2 couples t1, t2 perpendicular to L"
        lines = [(q, c)]
        loci.append(Locus("L", "line", q, c))
    else:  # (0, 3)
        couples = [np.eye(3)[i] for i in range(3)]
        words = "3 couples (every couple)"
    assert len(lines) == nf and len(couples) == nc
    return Layout(comp, name, tuple((np.asarray(p, float), _unit(d)) for p, d in lines),
                  tuple(_unit(t) for t in couples), tuple(loci), words)


def layouts_for(composition) -> tuple:
    """Layout names tried for ``composition`` (empty when none is implemented)."""
    return LAYOUTS.get(tuple(composition), ())


# --------------------------------------------------------------------------- words
def _names(layout: Layout):
    nf = len(layout.force_lines)
    lines = ["L"] if nf == 1 else [f"L{i + 1}" for i in range(nf)]
    nc = len(layout.couples)
    ts = ["t"] if nc == 1 else [f"t{i + 1}" for i in range(nc)]
    return lines, ts


def _words(letter: str, locus: str, layout: Layout, option: str = "") -> str:
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


# --------------------------------------------------------------------------- search
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


def counting_rank(string: str | LegString) -> int:
    """Upper bound on the rank of a leg's twists by counting: ``min(6, n_R + min(n_P, 3))``
    (translations span at most 3 directions).  Compound joints can lower the generic
    rank further (``SS`` has an idle rotation about the line of the centres)."""
    ls = parse_leg(string) if isinstance(string, str) else string
    nr = sum(j.kind in "RH" for j in ls.equivalent)
    npr = sum(j.kind == "P" for j in ls.equivalent)
    return min(6, nr + min(npr, 3))


def _null(M, rtol=NULL_RTOL) -> np.ndarray:
    """Orthonormal basis (rows) of the null space of M (rows of length 3)."""
    M = np.asarray(M, float).reshape(-1, 3)
    if len(M) == 0:
        return np.eye(3)
    _, s, Vt = np.linalg.svd(M, full_matrices=True)
    scale = max(1.0, float(np.max(np.linalg.norm(M, axis=1))))
    r = int(np.sum(s > rtol * scale))
    return Vt[r:]


_NEED = {"R": 1, "H": 1, "U": 2, "S": 3, "C": 1, "P": 1}


class _Letter:
    """One letter of the string: its equivalent joints and how to place them."""

    def __init__(self, letter, position, specs, nominal, pitch):
        self.letter, self.position, self.specs = letter, position, specs
        self.nominal, self.pitch = nominal, pitch

    @property
    def dof(self):
        return len(self.specs)


def _directions(letter, layout: Layout, p, pitch: float, rng, M_p=None):
    """Random admissible directions for ``letter`` at point p, or None."""
    F = layout.force_matrix()
    Mp = layout.moment_matrix(p) if M_p is None else M_p
    if letter == "R":
        N = _null(Mp)
    elif letter == "H":
        N = _null(Mp + pitch * F)
    elif letter in ("U", "S"):
        N = _null(Mp)
    elif letter == "C":
        N = _null(np.vstack([F, Mp]))
    else:
        raise AssertionError(letter)
    if len(N) < _NEED[letter]:
        return None
    if letter == "S":
        return list(np.linalg.qr(rng.standard_normal((3, 3)))[0].T)
    if letter == "U":
        c = rng.standard_normal((2, len(N)))
        return [_unit(ci @ N) for ci in c]
    return [_unit(rng.standard_normal(len(N)) @ N)]


def _place(letter: _Letter, option, layout, rng, scale, prior_p):
    """Joints ``[(spec, direction, point, pitch)]`` for one option, or None.

    ``prior_p`` (rows) are the directions of the passive P-type joints placed
    before; option ``"span"`` puts a P in their span (a deliberate dependence, so
    that an unavoidably dependent leg keeps its actuated joint independent)."""
    if letter.letter == "P":
        N = _null(layout.force_matrix())
        if option == "span":
            if len(prior_p) == 0:
                return None
            N = _null(_null(np.asarray(prior_p)))  # orthonormal basis of their span
        d = _unit(rng.standard_normal(len(N)) @ N)
        return [(letter.specs[0], d, letter.nominal, 0.0)]
    locus = option
    p = locus.sample(letter.nominal, rng, scale)
    dirs = _directions(letter.letter, layout, p, letter.pitch, rng)
    if dirs is None:
        return None
    if letter.letter == "C":
        return [(letter.specs[0], dirs[0], p, 0.0), (letter.specs[1], dirs[0], p, 0.0)]
    return [(s, d, p, letter.pitch if s.kind == "H" else 0.0) for s, d in zip(letter.specs, dirs)]


def _twist(kind, d, p, pitch):
    if kind == "P":
        return np.concatenate([d, np.zeros(3)])
    return np.concatenate([_cross(p, d) + pitch * d, d])


class _Ranker:
    def __init__(self, norm: Normalisation, rtol=RANK_RTOL):
        self.norm, self.rtol = norm, rtol

    def __call__(self, rows) -> int:
        if not rows:
            return 0
        Tn = self.norm.twists(np.array(rows))
        s = np.linalg.svd(Tn, compute_uv=False)
        return int(np.sum(s > self.rtol * max(1.0, float(s[0]))))


def _letters(ls: LegString, placement: Placement):
    n = len(ls.text)
    out = []
    L = placement.length
    for k, letter in enumerate(ls.text):
        t = k / (n - 1) if n > 1 else 0.5
        nominal = (1 - t) * placement.A + t * placement.a
        specs = tuple(j for j in ls.equivalent if j.position == k + 1)
        out.append(_Letter(letter, k + 1, specs, nominal, 0.05 * L if letter == "H" else 0.0))
    return out


def _options(letter: _Letter, layout: Layout, dependent: bool):
    if letter.letter == "P":
        return ["free", "span"] if dependent else ["free"]
    return list(layout.loci)


def _rule_reason(letter: _Letter, layout: Layout, rng, scale) -> str | None:
    """Why no placement of ``letter`` satisfies the rules in ``layout`` (None if one does)."""
    if letter.letter == "P":
        if len(_null(layout.force_matrix())) == 0:
            return (f"P{letter.position}: a force must be perpendicular to every P (rule 1), "
                    "and the forces span every direction")
        return None
    for locus in layout.loci:
        p = locus.sample(letter.nominal, rng, scale)
        if _directions(letter.letter, layout, p, letter.pitch, rng) is not None:
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


def _bound(ls: LegString, layout: Layout) -> int:
    """Rank bound from the rules: the rotation parts of the twists are perpendicular
    to the couples of the system (rule 3), the pure translations in their span are
    perpendicular to its forces (rule 1)."""
    m = len(ls.equivalent)
    nr = sum(j.kind in "RH" for j in ls.equivalent)
    rf = layout.force_rank
    c_dim = layout.k - rf
    return min(min(nr, 3 - c_dim) + (3 - rf), m)


def _counting_reason(ls: LegString, layout: Layout, target_rank: int) -> str | None:
    """Why the :func:`_bound` is below ``target_rank``, or why the C joints are
    necessarily dependent (None when neither)."""
    nC = ls.text.count("C")
    if nC >= 2 and len(ls.equivalent) == target_rank:
        dC = len(_null(np.vstack([layout.force_matrix(), layout.couple_space()])))
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
    bound = _bound(ls, layout)
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


def _search(letters, layout, rng, scale, ranker, target_rank, actuated):
    """Depth-first search over the loci (generic first).  Returns (placed, best_rank, why)."""
    n = len(letters)
    remaining = [sum(lt.dof for lt in letters[i:]) for i in range(n + 1)]
    best = [0, ""]
    need_actuation = sum(lt.dof for lt in letters) > target_rank

    def finish(placed):
        rows = [_twist(s.kind, d, p, h) for s, d, p, h in placed]
        if ranker(rows) != target_rank:
            return False
        if need_actuation:
            passive = [r for (s, *_), r in zip(placed, rows) if s.name != actuated]
            if ranker(passive) != target_rank - 1:
                best[1] = "actuated"
                return False
        return True

    def dfs(i, placed_opts, rows):
        if i == n:
            flat = [j for js, _ in placed_opts for j in js]
            return placed_opts if finish(flat) else None
        prior = [d for js, _ in placed_opts for s, d, _p, _h in js
                 if s.kind == "P" and s.name != actuated]
        for opt in _options(letters[i], layout, need_actuation):
            js = _place(letters[i], opt, layout, rng, scale, prior)
            if js is None:
                continue
            new_rows = rows + [_twist(s.kind, d, p, h) for s, d, p, h in js]
            r = ranker(new_rows)
            best[0] = max(best[0], r)
            if r + remaining[i + 1] < target_rank:
                continue
            out = dfs(i + 1, placed_opts + [(js, opt)], new_rows)
            if out is not None:
                return out
        return None

    return dfs(0, [], []), best[0], best[1]


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
    letters = _letters(ls, pl)
    dependent = m > target_rank

    def fail(reason, proof, rank=0):
        return Synthesis(ls, comp, False, layout, None, (), rank, target_rank, dependent,
                         reason, proof)

    if m < target_rank:
        return fail(f"{m} joints cannot span the {target_rank} freedoms left by {k} "
                    "constraint wrenches", "counting", m)
    for lt in letters:
        why = _rule_reason(lt, layout, rng, scale)
        if why:
            return fail(why, "rule")
    why = _counting_reason(ls, layout, target_rank)
    if why:
        return fail(why, "counting", _bound(ls, layout))
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
        choices.append(JointChoice(lt.letter, lt.position, locus,
                                   f"{lt.letter}{lt.position}: "
                                   f"{_words(lt.letter, locus, layout, opt if isinstance(opt, str) else '')}"))
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
        End points of the leg (default :func:`screwkit.placement.default_placement`).
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

