"""The declarative catalog ``legs_catalog.yaml``: leg types, Table I, PM definitions.

Schema (``docs/catalog.md`` has the full reference)::

    version: 1
    legs:                       # accepted leg types (the paper's Fig. 2, reconstructed)
      - name: RRPRR             # unique; variants as STRING/variant ("UPU/couple")
        string: RR_PRR          # leg string, '_' before the actuated joint
        summary: one line in words
        joints: [ ... ]         # one placement rule per letter (see screwkit.legs)
        structure: [ ... ]      # checks that must hold wherever the leg is assembled
        placement: {A: [..], a: [..], o: [..]}     # optional default end points
        expect:                 # what the leg must exert, in counts and words
          forces: 1
          couples: 0
          words: "one force parallel to R2 and R4, meeting R1 and R5"
          force_lines: [{through: POINT, parallel: REF}]   # optional, each must be in the system
          couples_along: [REF]                              # optional
    table1: [UPU, UPRR, ...]    # the paper's Table I, cell by cell
    pms: { ... }                # parallel manipulators (screwkit.pm)
"""

from __future__ import annotations

import os
import re
from dataclasses import dataclass, field
from functools import lru_cache
from pathlib import Path

import numpy as np

from ..legs._guards import MAX_ENTRIES, MAX_MAGNITUDE, MAX_NAME, did_you_mean, real_vector, shorten
from ..errors import CatalogError, ScrewkitError
from ..legs import Placement, default_placement
from ..legs import LegRules, build_leg
from ..legs._rule_context import _Context

__all__ = ["LegSpec", "Catalog", "load_catalog", "default_catalog", "catalog_path",
           "leg_spec_from_mapping"]

_LEG_KEYS = {"name", "string", "summary", "joints", "structure", "placement", "expect",
             "actuation", "used_by", "note", "constraint_basis"}
#: Direction references allowed in ``constraint_basis`` (with joint names and
#: ``{perpendicular: [REF, REF]}``; a leading ``-`` reverses one).
_BASIS_REFS = {"leg", "base.X", "base.Y", "base.Z", "platform.x", "platform.y", "platform.z",
               "base.OA", "base.AO", "platform.oa", "platform.ao", "base.tangent",
               "platform.tangent"}
_EXPECT_KEYS = {"forces", "couples", "screws", "words", "force_lines", "couples_along"}
_TOP_KEYS = {"version", "units", "legs", "table1", "pms"}


@dataclass(frozen=True)
class LegSpec:
    """A catalog leg type: its rules, default placement and expected constraint wrenches."""

    rules: LegRules
    summary: str = ""
    placement: Placement | None = None
    expect: dict = field(default_factory=dict)
    used_by: tuple = ()
    note: str = ""
    basis: tuple = ()
    #: The mapping the leg type was read from (as a file's ``legs:`` holds it), to write the
    #: leg type back (``PMModel.to_mapping``).
    definition: dict | None = field(default=None, compare=False, repr=False)

    @property
    def name(self) -> str:
        return self.rules.name

    @property
    def string(self):
        return self.rules.string

    def build(self, placement: Placement | None = None, check_structure: bool = True):
        """The leg placed by its rules (default: the entry's own or the default placement)."""
        return build_leg(self.rules, placement or self.placement or default_placement(),
                         check_structure)

    def to_mapping(self) -> dict:
        """The ``legs:`` entry of this leg type (what :func:`leg_spec_from_mapping` reads
        back into an equal leg type): a model file that uses it writes it so."""
        joints = []
        for jr in self.rules.joints:
            e: dict = {}
            if jr.axis is not None:
                e["axis"] = _plain(jr.axis)
            if jr.axes:
                e["axes"] = [_plain(a) for a in jr.axes]
            if jr.at is not None:
                e["at"] = _plain(jr.at)
            if jr.to is not None:
                e["to"] = _plain(jr.to)
            if jr.pitch:
                e["pitch"] = float(jr.pitch)
            joints.append(e)
        d: dict = {"name": self.name, "string": self.string.marked}
        if self.summary:
            d["summary"] = self.summary
        d["joints"] = joints
        if self.rules.structure:
            d["structure"] = [_plain(c) for c in self.rules.structure]
        if self.placement is not None:
            pl = self.placement
            d["placement"] = {k: [float(x) for x in getattr(pl, k)] for k in ("A", "a", "O", "o")}
        if self.expect:
            d["expect"] = _plain(self.expect)
        if self.note:
            d["note"] = self.note
        if self.basis:
            d["constraint_basis"] = [_plain(b) for b in self.basis]
        return d

    def check_expectation(self, analysis) -> list:
        """Differences between the analysis and ``expect``: empty when the expectation holds.

        Counts are compared with the decomposition; each declared force line and
        couple axis is built from the rules' references (independently of the
        solver) and must be reciprocal to every joint twist.
        """
        from ..screws import span_contains
        from ..screws import couple_wrench, force_wrench

        e = self.expect
        problems = []
        for key, got in (("forces", analysis.n_forces), ("couples", analysis.n_couples),
                         ("screws", analysis.n_screws)):
            want = int(e.get(key, 0))
            if got != want:
                problems.append(f"expected {want} {key}, found {got}")
        leg = analysis.leg
        pl = self.placement or default_placement()
        if leg.A is not None:
            pl = Placement(leg.A, leg.a, pl.O, pl.o, pl.base_rotation, pl.platform_rotation) \
                if np.allclose(leg.A, pl.A) and np.allclose(leg.a, pl.a) else None
        ctx = None
        if pl is not None:
            ctx = _Context(self.rules, pl)
            for j in leg.joints:
                ctx.dirs[j.name] = j.direction
                ctx.pts[j.name] = j.point
                ctx.dirs.setdefault(f"{j.spec.origin}{j.spec.position}", j.direction)
                ctx.pts.setdefault(f"{j.spec.origin}{j.spec.position}", j.point)
        norm = analysis.system.normalisation
        W = analysis.system.wrenches
        if ctx is not None:
            for fl in e.get("force_lines", []) or []:
                p = ctx.point(fl["through"])
                d = ctx.direction_rule(fl["parallel"]) if "parallel" in fl else \
                    ctx.point(fl["toward"]) - p
                w = force_wrench(d, p).vector
                if not span_contains(W, w, norm):
                    problems.append(f"declared force line {fl} is not in the constraint system")
            for ref in e.get("couples_along", []) or []:
                w = couple_wrench(ctx.direction_rule(ref)).vector
                if not span_contains(W, w, norm):
                    problems.append(f"declared couple along {ref} is not in the constraint system")
        return problems


def _no_unknown(d: dict, known, entry, fld, source, what: str = "field", note: str = "") -> None:
    """CatalogError on the first key of ``d`` not in ``known``, with a did-you-mean."""
    bad = [k for k in d if k not in known]
    if not bad:
        return
    k = bad[0]
    where = fld or (k if isinstance(k, str) else None)
    more = f" (and {len(bad) - 1} more)" if len(bad) > 1 else ""
    raise CatalogError(f"unknown {what} {shorten(k, 40)}{did_you_mean(k, known)}{more}; "
                       f"known: {', '.join(sorted(known))}{note}", entry, where, source)


def _vec(v, entry, fld, source):
    return real_vector(v, fld, 3, bound=MAX_MAGNITUDE,
                       error=lambda m: CatalogError(m, entry, fld, source))


def leg_spec_from_mapping(d: dict, source=None, index: int | None = None) -> LegSpec:
    """Validate one ``legs`` entry (a mapping from YAML or from user code)."""
    where = d.get("name") if isinstance(d, dict) and isinstance(d.get("name"), str) \
        else f"legs[{index}]"
    if len(where) > MAX_NAME:
        where = shorten(where, 40)
    if not isinstance(d, dict):
        raise CatalogError("each leg entry must be a mapping", where, None, source)
    for req in ("name", "string", "joints"):
        if req not in d:
            raise CatalogError(f"missing required field {req!r}", where, req, source)
    _no_unknown(d, _LEG_KEYS, where, None, source)
    name = d["name"]
    if not isinstance(name, str) or not name.strip() or len(name) > MAX_NAME:
        raise CatalogError(f"must be a non-empty name of at most {MAX_NAME} characters", where,
                           "name", source)
    if not isinstance(d["string"], str):
        raise CatalogError("must be a string", name, "string", source)
    rules = LegRules.from_mapping(name, d["string"], d["joints"], d.get("structure") or (), source)
    pl = None
    if d.get("placement") is not None:
        p = d["placement"]
        if not isinstance(p, dict) or not {"A", "a"} <= set(p):
            raise CatalogError("needs at least 'A' and 'a'", name, "placement", source)
        _no_unknown(p, {"A", "a", "O", "o"}, name, "placement", source, "point")
        kw = {k: _vec(p[k], name, f"placement.{k}", source) for k in ("A", "a", "O", "o") if k in p}
        try:
            pl = Placement(**kw)
        except ScrewkitError as exc:
            raise CatalogError(str(exc), name, "placement", source) from None
    expect = d.get("expect") or {}
    if not isinstance(expect, dict):
        raise CatalogError("must be a mapping", name, "expect", source)
    _no_unknown(expect, _EXPECT_KEYS, name, "expect", source, "key")
    for k in ("forces", "couples", "screws"):
        if k in expect and not (isinstance(expect[k], int) and not isinstance(expect[k], bool)
                                and 0 <= expect[k] <= 6):
            raise CatalogError("must be an integer from 0 to 6", name, f"expect.{k}", source)
    if "words" in expect and not isinstance(expect["words"], str):
        raise CatalogError("must be a string", name, "expect.words", source)
    for k in ("force_lines", "couples_along"):
        if not isinstance(expect.get(k) or [], list):
            raise CatalogError("must be a list", name, f"expect.{k}", source)
    for i, fl in enumerate(expect.get("force_lines") or []):
        if not (isinstance(fl, dict) and "through" in fl and
                len({"parallel", "toward"} & set(fl)) == 1 and len(fl) == 2):
            raise CatalogError("each force line is {through: POINT, parallel: REF} or "
                               "{through: POINT, toward: POINT}", name, f"expect.force_lines[{i}]",
                               source)
        from ..legs._rule_check import check_reference
        eq = rules.string.equivalent
        joints = {j.name for j in eq} | {f"{j.origin}{j.position}" for j in eq}
        for k, v in fl.items():
            check_reference(v, "direction" if k == "parallel" else "point", joints, name,
                            f"expect.force_lines[{i}]", source)
    used_by = d.get("used_by") or ()
    if not (isinstance(used_by, (list, tuple)) and all(isinstance(u, str) for u in used_by)):
        raise CatalogError("must be a list of PM names", name, "used_by", source)
    for k in ("summary", "note"):
        if not isinstance(d.get(k, ""), str):
            raise CatalogError("must be a string", name, k, source)
    basis = _basis(d.get("constraint_basis") or [], rules, name, source)
    import copy
    return LegSpec(rules, str(d.get("summary", "")), pl, dict(expect), tuple(used_by),
                   str(d.get("note", "")), basis, copy.deepcopy(dict(d)))


def _basis(raw, rules, name, source) -> tuple:
    """``constraint_basis``: the ordered reference directions of the leg's constraint members
    (see :mod:`screwkit.engine._rows`), validated."""
    if not isinstance(raw, list):
        raise CatalogError("must be a list of direction references", name, "constraint_basis",
                           source)
    joints = {s.name for s in rules.string.equivalent}

    def ok(ref):
        if isinstance(ref, str):
            r = ref[1:] if ref.startswith("-") else ref
            return r in _BASIS_REFS or r in joints
        if isinstance(ref, dict) and list(ref) == ["perpendicular"]:
            v = ref["perpendicular"]
            return isinstance(v, list) and len(v) == 2 and all(map(ok, v))
        return False

    for i, ref in enumerate(raw):
        if not ok(ref):
            raise CatalogError(f"{ref!r} is not a direction reference (one of "
                               f"{', '.join(sorted(_BASIS_REFS))}, a joint name, or "
                               "{perpendicular: [REF, REF]})", name, f"constraint_basis[{i}]",
                               source)
    return tuple(_freeze(r) for r in raw)


def _plain(x):
    """A rule as plain YAML data (lists for tuples, floats for numpy numbers)."""
    if isinstance(x, dict):
        return {k: _plain(v) for k, v in x.items()}
    if isinstance(x, (list, tuple)):
        return [_plain(v) for v in x]
    if isinstance(x, np.generic):
        return x.item()
    return x


def _freeze(ref):
    if isinstance(ref, dict):
        return {"perpendicular": tuple(_freeze(x) for x in ref["perpendicular"])}
    return ref


class Catalog:
    """A loaded catalog: leg types by name, the Table I list, and raw PM definitions."""

    def __init__(self, legs: dict, table1: list, pms: dict, source: str = "<memory>"):
        self.legs = legs
        self.table1 = table1
        self.pms = pms
        self.source = source

    @classmethod
    def from_mapping(cls, data, source: str = "<memory>") -> "Catalog":
        if not isinstance(data, dict):
            raise CatalogError("the catalog must be a mapping with 'legs', 'table1' and 'pms'",
                               source=source)
        _no_unknown({k: v for k, v in data.items() if not str(k).startswith("x-")}, _TOP_KEYS,
                    None, None, source, "top-level key",
                    " (keys starting with 'x-' are free, e.g. for YAML anchors)")
        legs = {}
        raw = data.get("legs", [])
        if raw is None:
            raw = []
        if not isinstance(raw, list):
            raise CatalogError("must be a list of leg entries", None, "legs", source)
        if len(raw) > MAX_ENTRIES:
            raise CatalogError(f"{len(raw)} leg entries: a file has at most {MAX_ENTRIES}", None,
                               "legs", source)
        for i, d in enumerate(raw):
            spec = leg_spec_from_mapping(d, source, i)
            if spec.name in legs:
                raise CatalogError("duplicate leg name", spec.name, "name", source)
            legs[spec.name] = spec
        table1 = data.get("table1", []) or []
        if not isinstance(table1, list):
            raise CatalogError("must be a list of rows of leg strings", None, "table1", source)
        if sum(len(r) if isinstance(r, list) else 1 for r in table1) > MAX_ENTRIES:
            raise CatalogError(f"more than {MAX_ENTRIES} cells", None, "table1", source)
        flat = []
        for i, row in enumerate(table1):
            for s in (row if isinstance(row, list) else [row]):
                if not isinstance(s, str):
                    raise CatalogError(f"cell {s!r} is not a leg string", None, f"table1[{i}]", source)
                flat.append(s)
        table1 = flat
        pms = data.get("pms", {}) or {}
        if not isinstance(pms, dict):
            raise CatalogError("must be a mapping of PM name to definition", None, "pms", source)
        if len(pms) > MAX_ENTRIES:
            raise CatalogError(f"{len(pms)} PMs: a file has at most {MAX_ENTRIES}", None, "pms",
                               source)
        for k in pms:
            if not isinstance(k, str) or not k.strip() or len(k) > MAX_NAME:
                raise CatalogError(f"a PM name must be a non-empty name of at most {MAX_NAME} "
                                   f"characters, got {shorten(k)}", None, "pms", source)
        if data.get("units") is not None:
            # the file's units apply to each of its PMs that does not declare its own
            pms = {k: ({"units": data["units"], **v} if isinstance(v, dict) else v)
                   for k, v in pms.items()}
        return cls(legs, table1, pms, source)

    def find_leg(self, name: str) -> LegSpec | None:
        """The leg type called ``name``; a bare string matches its first variant
        (``"UPU"`` -> ``"UPU/force"``) when no entry has exactly that name."""
        if name in self.legs:
            return self.legs[name]
        name = re.sub("(Pa|[A-Za-z])\u0332", lambda m: "_" + m.group(1), name)  # (the paper's)
        for spec in self.legs.values():
            if spec.name.split("/")[0] == name or spec.string.marked == name:
                return spec
        return None

    def table1_distinct(self) -> list:
        """Table I strings without repetitions, in order of first appearance."""
        return list(dict.fromkeys(self.table1))


def catalog_path() -> Path:
    """Where the default catalog is read from: ``$SCREWKIT_CATALOG``, the packaged copy,
    or the repository's top-level ``legs_catalog.yaml``."""
    env = os.environ.get("SCREWKIT_CATALOG")
    if env:
        return Path(env)
    here = Path(__file__).resolve().parent.parent     # the screwkit package (this is pm/_catalog.py)
    for p in (here / "legs_catalog.yaml", here.parent / "legs_catalog.yaml"):
        if p.is_file():
            return p
    raise CatalogError("legs_catalog.yaml not found (set SCREWKIT_CATALOG)")


def load_catalog(path) -> Catalog:
    """Load and validate a catalog file; raise :class:`CatalogError` naming entry and field.

    The file is read strictly (:mod:`screwkit.pm._yaml`): at most 1 MiB of UTF-8 text, no
    duplicate keys, no booleans, no NaN or infinity, aliases expanding to at most 100 000
    nodes.
    """
    from ._yaml import load_yaml_file

    data, source = load_yaml_file(path, "YAML file")
    try:
        return Catalog.from_mapping(data, source)
    except CatalogError as exc:
        from ._locate import with_line_of_file
        raise with_line_of_file(exc, path) from None
    except ScrewkitError as exc:
        raise CatalogError(str(exc), source=source) from None


@lru_cache(maxsize=1)
def default_catalog() -> Catalog:
    """The catalog at :func:`catalog_path` (cached, and kept parsed on disk: `_catalog_cache`)."""
    from ._catalog_cache import kept_catalog
    return kept_catalog(catalog_path(), load_catalog, Catalog)
