"""High-level Python API (the CLI is a thin shell over these functions)."""

from __future__ import annotations

from .legs import Leg
from .placement import Placement
from .rules import generic_leg

__all__ = ["leg"]


def leg(name: str, placement: Placement | None = None, *, seed: int = 0, catalog=None) -> Leg:
    """A placed leg: a catalog variant by name (``"UPU/couple"``, ``"RRPRR"``) or, for a
    string not in the catalog, the bare string with a generic geometry.

    Parameters
    ----------
    name : str
        Catalog name or leg string (an ``_`` marks the actuated joint).
    placement : Placement, optional
        End points and frames; default :func:`screwkit.placement.default_placement`
        or the catalog entry's own placement.
    seed : int
        Seed of the generic geometry of a bare string.
    catalog : Catalog, optional
        Default: the packaged ``legs_catalog.yaml``.
    """
    from .catalog import default_catalog

    cat = catalog if catalog is not None else default_catalog()
    spec = cat.find_leg(name)
    if spec is not None:
        return spec.build(placement)
    return generic_leg(name, placement, seed)
