"""Declarative structure rules of a leg, and the builder that applies them.

A leg type in ``legs_catalog.yaml`` lists one entry per letter of its string.
Each entry places the joint relative to the leg line, the base, the platform
and the other joints.  The builder evaluates the entries for a
:class:`~screwkit.placement.Placement` and returns a concrete
:class:`~screwkit.legs.Leg`.

Direction references (``REF``)
------------------------------
``leg``
    unit vector from ``A`` to ``a``.
``base.X``, ``base.Y``, ``base.Z``; ``platform.x``, ``platform.y``, ``platform.z``
    frame axes.
``base.AO`` / ``base.OA``; ``platform.ao`` / ``platform.oa``
    radial directions (from ``A`` to ``O`` ...).
``base.tangent`` / ``platform.tangent``
    ``Z x (A - O)`` and ``z x (a - o)``, normalised.
a joint name (``R1``, ``S1a``, ``C2``)
    that joint's axis.
``{toward: [P, Q]}``
    unit vector from point P to point Q.
``{base: [x, y, z]}``, ``{platform: [x, y, z]}``, ``{world: [x, y, z]}``
    explicit vectors.

Direction rules
---------------
``REF`` (shorthand for ``{along: REF}``), ``{along: REF}``, ``{parallel: REF}``,
``{perpendicular: [REF1, REF2]}`` (the common perpendicular ``REF1 x REF2``).

Point references
----------------
``A``, ``a``, ``O``, ``o``, ``C`` (the placement's centre of rotation), a joint name (its point; ``S1``/``U1`` its centre),
``{between: [P, Q], t: 0.5}``, ``{meet: [J1, J2]}`` (where two joint axes meet),
``{offset: P, along: REF, fraction: f}`` (``P + f |a - A| REF``).

Structure checks (residuals that must vanish)
---------------------------------------------
``{perpendicular: [REF1, REF2]}``, ``{parallel: [REF1, REF2]}``,
``{meets: [J1, J2]}`` (axes intersect or are parallel),
``{through: [J, P]}`` (the axis of J passes through point P).
Each check takes exactly two references; names (``R3``, ``U1a``, ``leg``, ``a``...)
are validated when the catalog is loaded.
"""

from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np

from ..errors import CatalogError, GeometryError
from ..screws import GEOMETRY_RTOL, Line
from ._chain import Joint, Leg
from ._parsing import JOINT_DOF, LegString, parse_leg
from ._placement import Placement

__all__ = ["JointRule", "LegRules", "build_leg", "generic_leg", "structure_residuals"]

_FRAME_REFS = {"base.X", "base.Y", "base.Z", "platform.x", "platform.y", "platform.z",
               "base.AO", "base.OA", "platform.ao", "platform.oa", "base.tangent",
               "platform.tangent", "leg"}
_POINT_NAMES = {"A", "a", "O", "o"}  # and C, the placement's centre of rotation


@dataclass(frozen=True)
class JointRule:
    """Placement rule of one letter of a leg string (raw YAML mapping, validated)."""

    letter: str
    position: int
    axis: object = None          # direction rule (R, P, H, C)
    axes: tuple = ()             # direction rules (U: 2, S: 3)
    at: object = None            # point rule
    pitch: float = 0.0           # H: pitch as a fraction of the leg length per radian


@dataclass(frozen=True)
class LegRules:
    """All the rules of one leg type.

    Attributes
    ----------
    name : str
        ``"RRPRR"`` or ``"UPU/couple"``.
    string : LegString
    joints : tuple of JointRule
    structure : tuple of dict
        Checks that must hold (residual 0) wherever the leg is assembled.
    """

    name: str
    string: LegString
    joints: tuple
    structure: tuple = field(default_factory=tuple)

    @classmethod
    def from_mapping(cls, name: str, string: str, joints, structure=(), source=None) -> "LegRules":
        """Validate raw catalog data; raise :class:`CatalogError` naming the field at fault."""
        try:
            ls = parse_leg(string)
        except Exception as exc:  # ParseError -> CatalogError with location
            raise CatalogError(str(exc), entry=name, field="string", source=source) from None
        if not isinstance(joints, (list, tuple)):
            raise CatalogError("must be a list with one entry per joint letter", name, "joints", source)
        if len(joints) != len(ls.text):
            raise CatalogError(f"{len(joints)} entries for the {len(ls.text)} letters of "
                               f"{ls.text!r}", name, "joints", source)
        rules = []
        for k, (letter, entry) in enumerate(zip(ls.text, joints), start=1):
            fld = f"joints[{k - 1}] ({letter}{k})"
            if entry is None:
                entry = {}
            if not isinstance(entry, dict):
                raise CatalogError("must be a mapping with 'axis'/'axes'/'at'", name, fld, source)
            unknown = set(entry) - {"axis", "axes", "at", "pitch", "note"}
            if unknown:
                raise CatalogError(f"unknown keys {sorted(unknown)}", name, fld, source)
            axis, axes = entry.get("axis"), entry.get("axes")
            if letter in "RPHC":
                if axis is None:
                    raise CatalogError("missing 'axis'", name, fld, source)
                if letter != "P" and entry.get("at") is None:
                    raise CatalogError("missing 'at' (a point of the axis)", name, fld, source)
            if letter == "U" and (axes is None or len(axes) != 2):
                raise CatalogError("a U needs 'axes' with 2 direction rules", name, fld, source)
            if letter == "S" and axes is not None and len(axes) != 3:
                raise CatalogError("an S takes 'axes' with 3 direction rules (or none)", name, fld, source)
            if letter in "US" and entry.get("at") is None:
                raise CatalogError(f"missing 'at' (the {letter} centre)", name, fld, source)
            pitch = entry.get("pitch", 0.0)
            if letter == "H" and not isinstance(pitch, (int, float)):
                raise CatalogError("pitch must be a number", name, fld, source)
            rules.append(JointRule(letter, k, axis, tuple(axes or ()), entry.get("at"), float(pitch or 0.0)))
        if not isinstance(structure, (list, tuple)):
            raise CatalogError("must be a list of checks", name, "structure", source)
        # names a check may use: frame references, end points, joints and S/U/C groups
        known = _FRAME_REFS | _POINT_NAMES | {"C"} | {j.name for j in ls.equivalent} | \
            {f"{j.origin}{j.position}" for j in ls.equivalent}
        for i, chk in enumerate(structure):
            ok = (isinstance(chk, dict) and len(chk) == 1 and
                  next(iter(chk)) in ("perpendicular", "parallel", "meets", "through"))
            pair = next(iter(chk.values())) if ok else None
            if not (ok and isinstance(pair, (list, tuple)) and len(pair) == 2):
                raise CatalogError("each check is one of perpendicular/parallel/meets/through "
                                   "with a pair of references", name, f"structure[{i}]", source)
            bad = [r for r in pair if isinstance(r, str) and r.lstrip("-") not in known]
            if bad:
                raise CatalogError(f"unknown reference {bad[0]!r} (not a frame reference, end "
                                   f"point or joint of {ls.text!r})", name, f"structure[{i}]", source)
        return cls(name, ls, tuple(rules), tuple(structure))


class _Context:
    """Evaluates references for one placement while the joints are being built."""

    def __init__(self, rules: LegRules, pl: Placement):
        self.rules, self.pl = rules, pl
        self.dirs: dict[str, np.ndarray] = {}
        self.pts: dict[str, np.ndarray] = {}
        self.where = rules.name

    def fail(self, msg):
        raise GeometryError(f"leg {self.where}: {msg}")

    def _unit(self, v, what):
        n = np.linalg.norm(v)
        if n < 1e-12:
            self.fail(f"{what} is undefined here (zero vector)")
        return v / n

    def frame_dir(self, ref: str) -> np.ndarray:
        pl = self.pl
        Rb, Rp = pl.base_rotation, pl.platform_rotation
        if ref == "leg":
            return self._unit(pl.a - pl.A, "the leg line")
        if ref.startswith("base.") and ref[5:] in "XYZ" and len(ref) == 6:
            return Rb[:, "XYZ".index(ref[5])]
        if ref.startswith("platform.") and ref[9:] in "xyz" and len(ref) == 10:
            return Rp[:, "xyz".index(ref[9])]
        if ref == "base.AO":
            return self._unit(pl.O - pl.A, "base.AO (A is at the base centre)")
        if ref == "base.OA":
            return -self.frame_dir("base.AO")
        if ref == "platform.ao":
            return self._unit(pl.o - pl.a, "platform.ao (a is at the platform centre)")
        if ref == "platform.oa":
            return -self.frame_dir("platform.ao")
        if ref == "base.tangent":
            return self._unit(np.cross(Rb[:, 2], pl.A - pl.O), "base.tangent")
        if ref == "platform.tangent":
            return self._unit(np.cross(Rp[:, 2], pl.a - pl.o), "platform.tangent")
        raise KeyError(ref)

    def direction(self, ref) -> np.ndarray:
        """A direction reference (not a rule)."""
        if isinstance(ref, str):
            neg = ref.startswith("-")
            r = ref[1:] if neg else ref
            if r in _FRAME_REFS:
                d = self.frame_dir(r)
            elif r in self.dirs:
                d = self.dirs[r]
            else:
                raise _Unresolved(r)
            return -d if neg else d
        if isinstance(ref, dict) and len(ref) == 1 and "toward" in ref:
            p, q = (self.point(x) for x in ref["toward"])
            return self._unit(q - p, f"direction toward {ref['toward']}")
        if isinstance(ref, dict) and len(ref) == 1:
            (k, v), = ref.items()
            try:
                v = np.asarray(v, float)
            except (TypeError, ValueError):
                self.fail(f"cannot read direction reference {ref!r} (a direction rule such as "
                          "'perpendicular' is not allowed here)")
            if v.shape == (3,):
                if k == "base":
                    return self._unit(self.pl.base_rotation @ v, "explicit base vector")
                if k == "platform":
                    return self._unit(self.pl.platform_rotation @ v, "explicit platform vector")
                if k == "world":
                    return self._unit(v, "explicit world vector")
        if isinstance(ref, (list, tuple)) and len(ref) == 3:
            return self._unit(np.asarray(ref, float), "explicit vector")
        self.fail(f"cannot read direction reference {ref!r}")

    def direction_rule(self, rule) -> np.ndarray:
        if isinstance(rule, dict) and len(rule) == 1:
            (k, v), = rule.items()
            if k in ("along", "parallel"):
                return self.direction(v)
            if k == "perpendicular":
                if not (isinstance(v, (list, tuple)) and len(v) == 2):
                    self.fail(f"'perpendicular' needs two references, got {v!r}")
                d1, d2 = self.direction(v[0]), self.direction(v[1])
                c = np.cross(d1, d2)
                if np.linalg.norm(c) < 1e-9:
                    self.fail(f"{v[0]} and {v[1]} are parallel here: their common perpendicular "
                              "is undefined")
                return c / np.linalg.norm(c)
        return self.direction(rule)

    def point(self, ref) -> np.ndarray:
        pl = self.pl
        if isinstance(ref, str):
            if ref in _POINT_NAMES:
                return {"A": pl.A, "a": pl.a, "O": pl.O, "o": pl.o}[ref]
            if ref == "C":
                return pl.centre
            if ref in self.pts:
                return self.pts[ref]
            raise _Unresolved(ref)
        if isinstance(ref, dict):
            if "between" in ref:
                p, q = (self.point(x) for x in ref["between"])
                t = float(ref.get("t", 0.5))
                return (1 - t) * p + t * q
            if "meet" in ref:
                j1, j2 = ref["meet"]
                l1 = Line.through(self.point(j1), self.direction(j1))
                l2 = Line.through(self.point(j2), self.direction(j2))
                if l1.is_parallel(l2):
                    self.fail(f"{j1} and {j2} are parallel: they do not meet at a point")
                x1, x2 = l1.closest_points(l2)
                if np.linalg.norm(x1 - x2) > GEOMETRY_RTOL * max(pl.length, 1e-300) * 10:
                    self.fail(f"{j1} and {j2} do not meet (distance {np.linalg.norm(x1 - x2):.3g})")
                return 0.5 * (x1 + x2)
            if "offset" in ref:
                p = self.point(ref["offset"])
                d = self.direction(ref.get("along", "leg"))
                return p + float(ref.get("fraction", 0.0)) * pl.length * d
        self.fail(f"cannot read point reference {ref!r}")


class _Unresolved(Exception):
    """A reference to a joint not yet placed (resolved on a later pass)."""


def build_leg(rules: LegRules, placement: Placement, check_structure: bool = True) -> Leg:
    """Place the joints of a leg type for ``placement``.

    Joints may refer to joints later in the chain; references are resolved in
    as many passes as needed.

    Raises
    ------
    GeometryError
        A rule cannot be evaluated here (parallel vectors, circular references),
        or a structure check fails when ``check_structure`` is true.
    """
    ctx = _Context(rules, placement)
    specs = rules.string.equivalent
    by_pos: dict[int, list] = {}
    for i, s in enumerate(specs):
        by_pos.setdefault(s.position, []).append(i)
    placed: dict[int, Joint] = {}
    pending = list(rules.joints)
    for _ in range(len(pending) + 1):
        if not pending:
            break
        left = []
        for jr in pending:
            try:
                _place(jr, ctx, specs, by_pos, placed, placement)
            except _Unresolved:
                left.append(jr)
        if len(left) == len(pending):
            names = ", ".join(f"{r.letter}{r.position}" for r in left)
            ctx.fail(f"unresolvable (circular or unknown) references in the rules of {names}")
        pending = left
    leg = Leg(rules.string, tuple(placed[i] for i in range(len(specs))), placement.A, placement.a,
              rules.name)
    if check_structure:
        bad = [(c, r) for c, r in structure_residuals(rules, placement, leg) if abs(r) > GEOMETRY_RTOL]
        if bad:
            c, r = bad[0]
            ctx.fail(f"structure check {c} fails here (residual {r:.3g})")
    return leg


def _place(jr: JointRule, ctx: _Context, specs, by_pos, placed, pl: Placement):
    idx = by_pos[jr.position]
    base_name = f"{jr.letter}{jr.position}"
    L = pl.length
    if jr.letter in "RPHC":
        d = ctx.direction_rule(jr.axis)
        p = ctx.point(jr.at) if jr.at is not None else 0.5 * (pl.A + pl.a)
        for i in idx:
            placed[i] = Joint(specs[i], d, p, jr.pitch * L if jr.letter == "H" else 0.0)
            ctx.dirs[specs[i].name] = d
            ctx.pts[specs[i].name] = p
        ctx.dirs[base_name] = d
        ctx.pts[base_name] = p
        return
    centre = ctx.point(jr.at)
    if jr.letter == "S" and not jr.axes:
        dirs = [pl.base_rotation[:, k] for k in range(3)]
    else:
        # axes in order, each registered at once so that U1b may refer to U1a
        dirs = []
        for i, r in zip(idx, jr.axes):
            d = ctx.direction_rule(r)
            dirs.append(d)
            ctx.dirs[specs[i].name] = d
            ctx.pts[specs[i].name] = centre
    M = np.array(dirs)
    if jr.letter == "S" and abs(np.linalg.det(M)) < 1e-6:
        ctx.fail(f"the three axes of {base_name} are coplanar")
    if jr.letter == "U" and np.linalg.norm(np.cross(*dirs)) < 1e-6:
        ctx.fail(f"the two axes of {base_name} are parallel")
    for i, d in zip(idx, dirs):
        placed[i] = Joint(specs[i], d, centre)
        ctx.dirs[specs[i].name] = d
        ctx.pts[specs[i].name] = centre
    ctx.pts[base_name] = centre


def structure_residuals(rules: LegRules, placement: Placement, leg: Leg) -> list:
    """Dimensionless residuals of the structure checks, ``[(check, value), ...]``.

    ``perpendicular``: ``d1 . d2``; ``parallel``: ``|d1 x d2|``; ``meets``: the
    distance between the axes (0 when parallel is not allowed... parallel axes
    count as meeting at infinity) divided by the leg length; ``through``: the
    distance from the point to the axis divided by the leg length.
    """
    ctx = _Context(rules, placement)
    for j in leg.joints:
        ctx.dirs[j.name] = j.direction
        ctx.pts[j.name] = j.point
        ctx.dirs.setdefault(f"{j.spec.origin}{j.spec.position}", j.direction)
        ctx.pts.setdefault(f"{j.spec.origin}{j.spec.position}", j.point)
    L = max(placement.length, 1e-300)
    out = []
    for chk in rules.structure:
        (k, v), = chk.items()
        label = f"{k}: {v}"
        try:
            if k == "perpendicular":
                r = float(np.dot(ctx.direction(v[0]), ctx.direction(v[1])))
            elif k == "parallel":
                r = float(np.linalg.norm(np.cross(ctx.direction(v[0]), ctx.direction(v[1]))))
            elif k == "meets":
                l1 = Line.through(ctx.point(v[0]), ctx.direction(v[0]))
                l2 = Line.through(ctx.point(v[1]), ctx.direction(v[1]))
                r = 0.0 if l1.is_parallel(l2) else l1.distance_to_line(l2) / L
            else:  # through
                r = Line.through(ctx.point(v[0]), ctx.direction(v[0])).distance_to_point(ctx.point(v[1])) / L
        except _Unresolved as exc:
            raise GeometryError(f"leg {rules.name}: structure check {label} names unknown "
                                f"reference {exc.args[0]!r}") from None
        out.append((label, r))
    return out


def generic_leg(string: str | LegString, placement: Placement | None = None, seed: int = 0) -> Leg:
    """A leg with *generic* geometry: joints spread along ``A -> a`` with random axes.

    Used for bare strings that are not in the catalog: it exhibits the
    constraint count that holds for almost every geometry.

    Parameters
    ----------
    string : str or LegString
    placement : Placement, optional
    seed : int
        Seed of the random axis directions.
    """
    from ._placement import default_placement

    ls = parse_leg(string) if isinstance(string, str) else string
    pl = placement or default_placement()
    rng = np.random.default_rng(seed)
    n = len(ls.text)
    joints = []
    eq = iter(ls.equivalent)
    for k, letter in enumerate(ls.text):
        t = k / (n - 1) if n > 1 else 0.5
        # points off the straight line too, so that no accidental alignment occurs
        p = (1 - t) * pl.A + t * pl.a + 0.15 * pl.length * rng.standard_normal(3) * (0 < k < n - 1)
        if letter == "S":
            dirs = list(np.linalg.qr(rng.standard_normal((3, 3)))[0].T)
        elif letter == "U":
            q = np.linalg.qr(rng.standard_normal((3, 3)))[0].T
            dirs = [q[0], q[1]]
        else:
            d = rng.standard_normal(3)
            dirs = [d / np.linalg.norm(d)] * JOINT_DOF[letter]
        for d in dirs:
            spec = next(eq)
            pitch = 0.05 * pl.length if spec.kind == "H" else 0.0
            joints.append(Joint(spec, d, p, pitch))
    return Leg(ls, tuple(joints), pl.A, pl.a, ls.text)
