"""The leg pool of a motion pattern: the catalog's leg types, the user's, and generated ones.

:func:`build_pool` gathers the leg types a PM of the pattern may use:

* every leg type of the catalog (the packaged one, or one the user extended with leg types
  of a model file, ``synthesize --model FILE``), plus the arrangements of
  :data:`EXTRA_LEGS_YAML`, analysed at their default placement;
* the leg types generated for the pattern (:func:`~screwkit.synthesis._leg_types.generated_legs`),
  except those equivalent to one of the above (the catalog is preferred);

and keeps those whose constraint systems fit the pattern's complementary wrench system
(:meth:`MotionPattern.admits`).  Every kind knows where it comes from (``origin``), so
that the ranking can prefer the catalog's and a written model carries the definition of
every leg type the packaged catalog lacks (:meth:`LegPool.definitions`).
"""

from __future__ import annotations

from dataclasses import dataclass
from functools import lru_cache

import yaml

from ._leg_types import SYNTHESIS_PLACEMENT, VARIANTS, generated_legs, twist_key
from ._motions import MotionPattern

__all__ = ["EXTRA_LEGS_YAML", "LegKind", "LegPool", "build_pool", "extra_legs", "leg_pool",
           "synthesis_catalog"]

#: Arrangements the type synthesis adds to the catalog's: the PRRR leg turned so that its
#: P and its three parallel R axes point from the base vertex towards the platform centre
#: (one leg of the translational 3-PRRR; Kong and Gosselin, Type Synthesis of Parallel
#: Mechanisms, Springer 2007, ch. 5: a PRRR leg with P parallel to the R axes exerts two
#: couples normal to them); and two planar legs, RRR and PRR with their R axes along the
#: base normal (the legs of the planar 3-RRR and 3-PRR: a force along the axes and two
#: couples normal to them, the complementary system of a planar motion).
EXTRA_LEGS_YAML = """
legs:
  - name: PRRR/translational
    string: _PRRR
    summary: "P along A->o (home), then three R axes parallel to P, not coplanar: two couples normal to them"
    joints:
      - {axis: {toward: [A, o]}}
      - {axis: {parallel: P1}, at: A}
      - {axis: {parallel: P1}, at: {offset: {between: [A, a], t: 0.5}, along: base.tangent, fraction: 0.3}}
      - {axis: {parallel: P1}, at: a}
    structure:
      - {parallel: [R2, P1]}
      - {parallel: [R4, P1]}
    expect:
      forces: 0
      couples: 2
      words: two constraint couples perpendicular to the P axis and the three parallel R axes
  - name: RRR/planar
    string: _RRR
    summary: "three R axes along the base normal (at A, at an elbow beside the leg, at a): a planar leg"
    joints:
      - {axis: base.Z, at: A}
      - {axis: base.Z, at: {offset: {between: [A, a], t: 0.5}, along: base.tangent, fraction: 0.3}}
      - {axis: base.Z, at: a}
    expect:
      forces: 1
      couples: 2
      words: a constraint force along the parallel R axes and two constraint couples perpendicular to them
  - name: PRR/planar
    string: _PRR
    summary: "P along A->O in the base plane, then two R axes along the base normal (at an elbow beside the leg, at a): a planar leg"
    joints:
      - {axis: base.AO}
      - {axis: base.Z, at: {offset: {between: [A, a], t: 0.5}, along: base.tangent, fraction: 0.3}}
      - {axis: base.Z, at: a}
    expect:
      forces: 1
      couples: 2
      words: a constraint force along the parallel R axes and two constraint couples perpendicular to them
"""


@dataclass(frozen=True)
class LegKind:
    """A leg type of the pool and its constraint system (at its default placement).

    Attributes
    ----------
    name : str
        Catalog name (``"UPU/couple"``) or generated name (``"RRPaR/t.t.t.t"``).
    string : str
        The leg string's letters (``"UPU"``).
    marked : str
        With the actuated joint marked (``"U_PU"``).
    forces, couples, screws : int
        Pure forces, pure couples and finite-pitch wrenches of its constraint system.
    joints : int
        Equivalent 1-DOF joints.
    actuated_position : int
        1-based position of the actuated letter (1: on the base).
    origin : str
        ``"catalog"`` (the packaged catalog), ``"extra"`` (:data:`EXTRA_LEGS_YAML`),
        ``"user"`` (a leg type the caller added) or ``"generated"``.
    """

    name: str
    string: str
    marked: str
    forces: int
    couples: int
    screws: int
    joints: int
    actuated_position: int
    origin: str = "catalog"

    @property
    def constraints(self) -> int:
        return self.forces + self.couples + self.screws

    @property
    def extra(self) -> bool:
        return self.origin == "extra"

    @property
    def preferred(self) -> bool:
        """A leg type of the catalog, the extra arrangements or the user's (ranked before
        an equivalent generated one)."""
        return self.origin != "generated"


@dataclass(frozen=True, eq=False)
class LegPool:
    """Result of :func:`build_pool`.

    Attributes
    ----------
    motion : MotionPattern
    kinds : tuple of LegKind
        The admitted leg types: the catalog's (and the user's, the extra ones), then the
        generated ones.
    catalog : screwkit.pm.Catalog
        Every leg type of the pool by name (and the rest of the catalog's), for building
        the candidates.
    generated : int
        Generated leg types admitted.
    columns : tuple of LegKind
        Generated central columns (from the base centre to the platform centre) that
        exert the whole complementary system: the passive legs of Tricept-like PMs.
    """

    motion: MotionPattern
    kinds: tuple
    catalog: object
    generated: int = 0
    columns: tuple = ()

    def definitions(self, names) -> list:
        """The ``legs:`` entries of the leg types among ``names`` that the packaged catalog
        lacks (extra, user and generated ones), in order: what a model file using them
        must define."""
        from ..pm import default_catalog

        packaged = default_catalog().legs
        out, seen = [], set()
        for n in names:
            spec = self.catalog.legs.get(n)
            if n in seen or spec is None or packaged.get(n) is spec:
                continue
            seen.add(n)
            out.append(_DEFINITIONS.get(id(spec)) or spec.to_mapping())
        return out


#: Raw entries of the generated and extra leg types, by ``id`` of their LegSpec (kept alive
#: by the cached pools): written as they were generated.
_DEFINITIONS: dict = {}


def extra_legs() -> dict:
    """The :data:`EXTRA_LEGS_YAML` leg types, ``{name: LegSpec}``."""
    return dict(_extra())


@lru_cache(maxsize=1)
def _extra():
    from ..pm import Catalog
    raw = yaml.safe_load(EXTRA_LEGS_YAML)
    cat = Catalog.from_mapping(raw, "<synthesis legs>")
    for entry in raw["legs"]:
        _DEFINITIONS[id(cat.legs[entry["name"]])] = entry
    return tuple(cat.legs.items())


def synthesis_catalog(catalog=None, pms: dict | None = None, legs: dict | None = None):
    """The catalog (default: the packaged one) with the extra leg types, ``legs``
    (``{name: LegSpec}``) and ``pms``."""
    from ..pm import Catalog, default_catalog
    cat = catalog if catalog is not None else default_catalog()
    return Catalog({**cat.legs, **extra_legs(), **dict(legs or {})}, cat.table1,
                   dict(pms or {}), "<synthesis>")


def _kind(name, spec, origin) -> LegKind:
    an = spec.build().analyze()
    ls = spec.string
    return LegKind(name, ls.text, ls.marked, an.n_forces, an.n_couples, an.n_screws,
                   len(ls.equivalent), ls.actuated_position, origin)


def _kinds_of(catalog) -> tuple:
    from ..pm import default_catalog
    packaged = default_catalog().legs
    extra = extra_legs()
    out = []
    for name, spec in synthesis_catalog(catalog).legs.items():
        origin = ("extra" if extra.get(name) is spec else
                  "catalog" if packaged.get(name) is spec else "user")
        out.append(_kind(name, spec, origin))
    return tuple(out)


@lru_cache(maxsize=1)
def _default_kinds() -> tuple:
    return _kinds_of(None)


def _keys_of(catalog) -> frozenset:
    """:func:`twist_key` of every leg type of ``catalog`` (and the extra ones) at the
    synthesis placement (those that cannot be built there by their rules are left out)."""
    from ..errors import ScrewkitError
    keys = set()
    for spec in synthesis_catalog(catalog).legs.values():
        try:
            leg = spec.build(SYNTHESIS_PLACEMENT)
        except ScrewkitError:
            continue
        keys.add(twist_key(spec.string.letters, leg.twists, SYNTHESIS_PLACEMENT.length))
    return frozenset(keys)


@lru_cache(maxsize=1)
def _default_keys() -> frozenset:
    return _keys_of(None)


@lru_cache(maxsize=32)
def _generated(motion, keys, variants, wide, central=False) -> tuple:
    from ..pm import leg_spec_from_mapping
    out = []
    for g in generated_legs(motion, keys, variants, wide, central):
        spec = leg_spec_from_mapping(dict(g.mapping), source="<generated>")
        _DEFINITIONS[id(spec)] = g.mapping
        ls = spec.string
        kind = LegKind(g.name, ls.text, ls.marked, g.forces, g.couples, 0, len(ls.equivalent),
                       ls.actuated_position, "generated")
        out.append((kind, spec))
    return tuple(out)


def build_pool(motion: MotionPattern, catalog=None, *, generate: bool = True,
               variants: int = VARIANTS, wide: bool = False) -> LegPool:
    """The leg pool of ``motion`` (see the module docstring).

    Parameters
    ----------
    catalog : Catalog, optional
        Leg types (default: the packaged catalog), plus the extra arrangements.
    generate : bool
        Add the leg types generated for the pattern.
    variants, wide
        Of :func:`~screwkit.synthesis._leg_types.generated_legs`.
    """
    kinds = _default_kinds() if catalog is None else _kinds_of(catalog)
    kinds = [k for k in kinds if motion.admits(k.forces, k.couples, k.screws)]
    specs = {}
    n_gen = 0
    columns = []
    if generate:
        keys = _default_keys() if catalog is None else _keys_of(catalog)
        taken = {k.name for k in kinds}
        for kind, spec in _generated(motion, keys, int(variants), bool(wide)):
            if kind.name in taken:
                continue
            kinds.append(kind)
            specs[kind.name] = spec
            n_gen += 1
        for kind, spec in _generated(motion, frozenset(), int(variants), False, True):
            columns.append(kind)
            specs[kind.name] = spec
    return LegPool(motion, tuple(kinds), synthesis_catalog(catalog, legs=specs), n_gen,
                   tuple(columns))


def leg_pool(motion: MotionPattern, catalog=None, **kwargs) -> tuple:
    """The leg types (:class:`LegKind`) whose constraint systems fit in the motion's
    complementary wrench system: the catalog's (catalog order, extra legs last), then the
    generated ones (:func:`build_pool`; ``generate=False`` for the catalog's only)."""
    return build_pool(motion, catalog, **kwargs).kinds
