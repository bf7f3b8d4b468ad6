"""A catalog with extra leg types (private; ``screwkit.extend_catalog``)."""

from __future__ import annotations

from ..errors import CatalogError
from ._catalog import Catalog, LegSpec, default_catalog

__all__ = ["catalog_with_legs"]


def catalog_with_legs(legs, catalog=None, *, replace: bool = False) -> Catalog:
    """``catalog`` (default: the packaged one, not modified) with the leg types ``legs`` (a
    :class:`LegSpec`, an iterable of them or a :class:`Catalog`) added; a name that exists
    already is a :class:`~screwkit.errors.CatalogError` unless ``replace``."""
    base = catalog if catalog is not None else default_catalog()
    if isinstance(legs, Catalog):
        extra = list(legs.legs.values())
    elif isinstance(legs, LegSpec):
        extra = [legs]
    else:
        extra = list(legs)
    merged = dict(base.legs)
    seen = set()
    for i, spec in enumerate(extra):
        if not isinstance(spec, LegSpec):
            raise CatalogError(f"expected a LegSpec (from define_leg or load_legs), got "
                               f"{type(spec).__name__}", f"legs[{i}]")
        if spec.name in seen or (spec.name in merged and not replace):
            raise CatalogError("a leg type of this name already exists (pass replace=True "
                               "to override it)", spec.name, "name")
        seen.add(spec.name)
        merged[spec.name] = spec
    return Catalog(merged, list(base.table1), dict(base.pms), base.source)
