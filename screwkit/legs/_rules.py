"""Declarative structure rules of a leg, and the builder that applies them.

A leg type in ``legs_catalog.yaml`` lists one entry per letter of its string.
Each entry places the joint relative to the leg line, the base, the platform
and the other joints.  The builder evaluates the entries for a
:class:`~screwkit.legs.Placement` and returns a concrete
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
literal points ``{world: [x, y, z]}``, ``{base: [x, y, z]}`` (base frame, from ``O``),
``{platform: [x, y, z]}`` (platform frame, from ``o``), in model lengths,
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

from ._guards import MAX_MAGNITUDE, MAX_STRUCTURE_CHECKS, did_you_mean, real, real_vector, shorten
from ..errors import CatalogError, ScrewkitError
from ..screws import GEOMETRY_RTOL
from ._chain import Joint, Leg
from ._parsing import JOINT_DOF, LegString, parse_leg
from ._placement import Placement
from ._rule_context import _FRAME_REFS, _POINT_NAMES, _Context, _Unresolved
from ._structure import structure_residuals
from ..screws import cross

__all__ = ["JointRule", "LegRules", "build_leg", "generic_leg"]

_JOINT_KEYS = ("axis", "axes", "at", "to", "pitch", "note")

@dataclass(frozen=True)
class JointRule:
    """Placement rule of one letter of a leg string (raw YAML mapping, validated)."""

    letter: str
    position: int
    axis: object = None          # direction rule (R, P, H, C)
    axes: tuple = ()             # direction rules (U: 2, S: 3)
    at: object = None            # point rule
    pitch: float = 0.0           # H: pitch as a fraction of the leg length per radian
    to: object = None            # Pa: point rule of its second hinge axis (bar = to - at)


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
        except ScrewkitError as exc:  # ParseError -> CatalogError with location
            raise CatalogError(str(exc), entry=name, field="string", source=source) from None
        if not isinstance(joints, (list, tuple)):
            raise CatalogError("must be a list with one entry per joint letter", name, "joints", source)
        if len(joints) != len(ls.letters):
            raise CatalogError(f"{len(joints)} entries for the {len(ls.letters)} letters of "
                               f"{ls.text!r}", name, "joints", source)
        rules = []
        for k, (letter, entry) in enumerate(zip(ls.letters, joints), start=1):
            fld = f"joints[{k - 1}] ({letter}{k})"
            if entry is None:
                entry = {}
            if not isinstance(entry, dict):
                raise CatalogError("must be a mapping with 'axis'/'axes'/'at'", name, fld, source)
            unknown = [k for k in entry if k not in _JOINT_KEYS]
            if unknown:
                raise CatalogError(f"unknown key {shorten(unknown[0], 40)}"
                                   f"{did_you_mean(unknown[0], _JOINT_KEYS)}; known: "
                                   f"{', '.join(sorted(_JOINT_KEYS))}", name, fld, source)
            axis, axes = entry.get("axis"), entry.get("axes")
            if letter == "Pa":
                missing = [k for k in ("axis", "at", "to") if entry.get(k) is None]
                if missing:
                    raise CatalogError(f"missing {missing[0]!r}: a Pa takes 'axis' (its hinges), "
                                       "'at' (a point of its first hinge) and 'to' (a point of "
                                       "its second hinge)", name, fld, source)
            elif entry.get("to") is not None:
                raise CatalogError("only a parallelogram Pa takes 'to'", name, fld, source)
            if letter in ("R", "P", "H", "C"):
                if axis is None:
                    raise CatalogError("missing 'axis'", name, fld, source)
                if letter != "P" and entry.get("at") is None:
                    raise CatalogError("missing 'at' (a point of the axis)", name, fld, source)
            if letter == "U" and (axes is None or len(axes) != 2):
                raise CatalogError("a U needs 'axes' with 2 direction rules", name, fld, source)
            if letter == "S" and axes is not None and len(axes) != 3:
                raise CatalogError("an S takes 'axes' with 3 direction rules (or none)", name, fld, source)
            if letter in ("U", "S") and entry.get("at") is None:
                raise CatalogError(f"missing 'at' (the {letter} centre)", name, fld, source)
            pitch = real(entry.get("pitch", 0.0), "pitch", bound=1e6,
                         error=lambda m: CatalogError(m, name, fld, source))
            if letter == "H" and pitch != 0 and ls.equivalent[
                    next(i for i, j in enumerate(ls.equivalent) if j.position == k)].pitch is not None:
                raise CatalogError("the pitch is given twice (in the string and in 'pitch')",
                                   name, fld, source)
            if letter != "H" and pitch != 0:
                raise CatalogError(f"only an H joint has a pitch ({letter}{k} is not helical)",
                                   name, fld, source)
            for key in ("axis", "at", "to"):
                if isinstance(entry.get(key), bool):
                    raise CatalogError(f"{key!r} must be a reference, not a boolean", name, fld,
                                       source)
            if axes is not None and not isinstance(axes, (list, tuple)):
                raise CatalogError("'axes' must be a list of direction rules", name, fld, source)
            for key in ("axis", "axes", "at", "to"):
                _check_rule_numbers(entry.get(key), f"{fld}.{key}", name, source)
            rules.append(JointRule(letter, k, axis, tuple(axes or ()), entry.get("at"), pitch,
                                   entry.get("to")))
        if not isinstance(structure, (list, tuple)):
            raise CatalogError("must be a list of checks", name, "structure", source)
        if len(structure) > MAX_STRUCTURE_CHECKS:
            raise CatalogError(f"{len(structure)} checks: a leg type has at most "
                               f"{MAX_STRUCTURE_CHECKS}", name, "structure", source)
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
        out = cls(name, ls, tuple(rules), tuple(structure))
        from ._rule_check import check_rule_references
        check_rule_references(out, source)       # unknown keys and references, by name
        return out


_VECTOR_KEYS = ("base", "platform", "world")


def _check_rule_numbers(rule, fld, name, source, depth=0):
    """The numbers of a rule (``t``, ``fraction``, explicit vectors) are finite reals, at load
    time; the rule's structure itself is read when the leg is built."""
    def err(m):
        return CatalogError(m, name, fld, source)

    if depth > 16:
        raise err("a rule nested more than 16 levels deep")
    if isinstance(rule, dict):
        for k, v in rule.items():
            if k in ("t", "fraction"):
                real(v, k, bound=1e6, error=err)
            elif k in _VECTOR_KEYS:
                real_vector(v, k, 3, bound=MAX_MAGNITUDE, error=err)
            else:
                _check_rule_numbers(v, fld, name, source, depth + 1)
    elif isinstance(rule, (list, tuple)):
        if len(rule) > 16:
            raise err(f"a list of {len(rule)} items in a rule (at most 16)")
        if len(rule) == 3 and not any(isinstance(x, (str, dict, list, tuple)) for x in rule):
            real_vector(rule, "vector", 3, bound=MAX_MAGNITUDE, error=err)
        else:
            for v in rule:
                _check_rule_numbers(v, fld, name, source, depth + 1)
    elif rule is not None and not isinstance(rule, str):
        if isinstance(rule, bool) or not isinstance(rule, (int, float)):
            raise err(f"{shorten(rule)} is not a reference")


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
        missing = {}
        for jr in pending:
            try:
                _place(jr, ctx, specs, by_pos, placed, placement)
            except _Unresolved as exc:
                left.append(jr)
                missing[f"{jr.letter}{jr.position}"] = exc.args[0] if exc.args else "?"
        if len(left) == len(pending):
            names = "; ".join(f"{k} refers to {v!r}" for k, v in missing.items())
            ctx.fail(f"unresolvable references in the rules ({names}): each names a joint that "
                     "is never placed (unknown) or placed from these ones (circular)")
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
    if jr.letter == "Pa":
        # hinges along the axis rule; the bar from the first hinge point to the second
        i, = idx
        h, p, q = ctx.direction_rule(jr.axis), ctx.point(jr.at), ctx.point(jr.to)
        bar = q - p
        nb = float(np.linalg.norm(bar))
        if nb < GEOMETRY_RTOL * L or abs(float(h @ bar)) > GEOMETRY_RTOL * nb:
            ctx.fail(f"the bar of {base_name} (from 'at' to 'to') must be non-zero and normal "
                     "to its hinges")
        d = cross(h, bar) / nb
        placed[i] = Joint(specs[i], d, p, 0.0, bar)
        for nm in (specs[i].name, base_name):
            ctx.dirs[nm], ctx.pts[nm] = d, p
        return
    if jr.letter in ("R", "P", "H", "C"):
        d = ctx.direction_rule(jr.axis)
        p = ctx.point(jr.at) if jr.at is not None else 0.5 * (pl.A + pl.a)
        for i in idx:
            # the pitch written in the string (H(2.5), model lengths per radian) or the
            # rule's (a fraction of the leg length per radian)
            h = specs[i].pitch if specs[i].pitch is not None else jr.pitch * L
            placed[i] = Joint(specs[i], d, p, h if jr.letter == "H" else 0.0)
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
    if jr.letter == "U" and np.linalg.norm(cross(*dirs)) < 1e-6:
        ctx.fail(f"the two axes of {base_name} are parallel")
    for i, d in zip(idx, dirs):
        placed[i] = Joint(specs[i], d, centre)
        ctx.dirs[specs[i].name] = d
        ctx.pts[specs[i].name] = centre
    ctx.pts[base_name] = centre


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
    n = len(ls.letters)
    joints = []
    eq = iter(ls.equivalent)
    for k, letter in enumerate(ls.letters):
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
        if letter == "Pa":
            # a random bar normal to the translation d, of a fifth of the leg's length
            b = np.cross(d, rng.standard_normal(3))
            joints.append(Joint(next(eq), d, p, 0.0, 0.2 * pl.length * b / np.linalg.norm(b)))
            continue
        for d in dirs:
            spec = next(eq)
            pitch = 0.05 * pl.length if spec.kind == "H" else 0.0
            if spec.pitch is not None:
                pitch = spec.pitch
            joints.append(Joint(spec, d, p, pitch))
    return Leg(ls, tuple(joints), pl.A, pl.a, ls.text)


def check_leg_request(name, placement, seed) -> int:
    """The arguments of :func:`screwkit.leg` checked (InputError naming the bad one); the
    seed as an int."""
    from ..errors import InputError
    from ._guards import check_seed
    if not isinstance(name, str):
        raise InputError(f"a leg is a catalog name or a leg string, got {name!r:.60}")
    if placement is not None and not isinstance(placement, Placement):
        raise InputError(f"placement must be a screwkit.legs.Placement (A, a, ...), got "
                         f"{type(placement).__name__}")
    return check_seed(seed)
