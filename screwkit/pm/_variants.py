"""The same PM with other dimensions, and its definition as a model file (private).

A model loaded by :func:`screwkit.pm.load_pm` keeps its :class:`Definition`: the ``pms:``
entry as read, the catalog its legs come from and the overrides it was loaded with.
:func:`with_dimensions` evaluates that entry again with other dimension values (the
geometry, the home assembly and the legs built by their rules): no file is read or parsed
again, and the model equals ``load_pm(name, overrides)`` with the same values bit for bit
(the same code on the same numbers).  Dimensional synthesis (``screwkit optimize``) builds
every candidate this way.  :func:`definition_yaml` writes a model (a chosen design) as a
model file that ``load_pm`` reads back.
"""

from __future__ import annotations

from dataclasses import dataclass

from ..errors import CatalogError, GeometryError, InputError

__all__ = ["Definition", "with_dimensions", "definition_yaml"]


@dataclass(frozen=True, eq=False)
class Definition:
    """How a model was defined (see the module docstring).

    Attributes
    ----------
    name : str
        The key of the ``pms:`` entry.
    raw : dict
        The entry as read (dimensions as declared).
    catalog : Catalog
        The catalog of its legs (the packaged one, or it merged with a user file's).
    overrides : dict
        The dimension values the model was loaded with.
    build : callable
        The loader's ``build(name, raw, catalog, overrides) -> PMModel``.
    mapping : dict
        The entry self-contained, as ``PMModel.to_mapping`` returns it: leg types not of the
        packaged catalog written inline, the overrides applied to its dimensions.
    """

    name: str
    raw: dict
    catalog: object
    overrides: dict
    build: object
    mapping: dict

    def rebuild(self, model, values) -> "PMModel":  # noqa: F821
        """:func:`with_dimensions` of ``model`` (built from this definition)."""
        return with_dimensions(model, values)


def with_dimensions(model, values) -> "PMModel":  # noqa: F821
    """The model with the dimensions ``values`` (``{name: positive length}``, model units)
    instead of its own; the others stay as the model has them.

    Raises
    ------
    InputError
        The model has no definition (it was not loaded from a catalog or file), or a name
        is not one of its dimensions, or a value is not a positive length.
    CatalogError
        The geometry cannot be built with these dimensions.
    """
    d = model.definition
    if d is None:
        raise InputError(f"model {model.name}: no definition to rebuild it from (load it with "
                         "screwkit.load_pm)")
    if not isinstance(values, dict):
        raise InputError(f"{model.name}: the dimensions must be a mapping name -> value")
    try:
        return d.build(d.name, d.raw, d.catalog, {**d.overrides, **values})
    except GeometryError as exc:
        raise CatalogError(f"the geometry cannot be built: {exc}", d.name, None,
                           d.catalog.source) from None


def definition_yaml(model, note: str = "") -> str:
    """The model as a model file (YAML text): its self-contained ``pms:`` entry
    (``PMModel.to_mapping``: leg types not of the packaged catalog written inline) with the
    model's dimensions.  ``note`` goes into the entry's ``source`` field."""
    import yaml

    if model.definition is None:
        raise InputError(f"model {model.name}: no definition to write (load it with "
                         "screwkit.load_pm)")
    entry = model.to_mapping()
    entry["dimensions"] = {k: float(v) for k, v in model.dimensions.items()}
    if note:
        entry["source"] = note
    return yaml.safe_dump({"pms": {model.name: entry}}, sort_keys=False, allow_unicode=True,
                          width=100)
