"""Workspace measures of a map: reachable, singularity-free and good-transmission volumes.

The task box is the map's box: the extent ``[first, last]`` of each grid parameter (or the
``--samples`` box), its volume the product of the extents in the parameters' units
(``cm.deg^2`` for ``alpha``, ``beta``, ``Zo`` in degrees and cm).  Each region is a set of
cells; its fraction is the share of the cells (the grid's nodes, or the random samples)
that lie in it and its volume that fraction of the box volume (for samples, a Monte Carlo
estimate with its standard error ``sqrt(f (1 - f) / N)`` times the box volume).

* ``reachable``: assembled from home and within the model's limits (where it declares
  some);
* ``singularity_free``: the reachable cells that are not singular and have ``det J`` of the
  home sign (square ``J``), *connected to home* through faces of the grid: the connected
  component that holds the cell nearest the home pose (a compiled flood fill from that
  cell, ``engine/_kernels/_extra.face_component``: ``scipy.ndimage.label`` gave the same
  cells, but its import took a quarter of a second of a ``map`` command).  Random samples
  have no neighbours: there, every non-singular sample of the home assembly mode counts
  (``method`` says which);
* ``good_transmission``: the reachable cells with ``LTI >= threshold`` (0.7 by default, the
  usual bound of a good motion/force transmission).

Examples
--------
>>> import screwkit
>>> ds = screwkit.map("3RRPRR", {"alpha": (-10, 10, 5), "Zo": (70, 90, 3)}, fix={"beta": 0},
...                   degrees=True)
>>> ws = screwkit.maps.workspace(ds)
>>> ws.units, ws.box_volume, ws.regions["reachable"]["fraction"]
('cm.deg', 400.0, 1.0)
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from ..errors import InputError

__all__ = ["Workspace", "workspace", "GOOD_TRANSMISSION"]

#: The default LTI threshold of the good-transmission workspace.
GOOD_TRANSMISSION = 0.7


@dataclass(frozen=True)
class Workspace:
    """Workspace measures of a map (module docstring).

    Attributes
    ----------
    box : dict str -> (float, float)
        The task box: each varied parameter's extent, in the map's units.
    units : str
        The unit of a volume (the product of the parameters' units).
    box_volume : float
    cells : int
    regions : dict str -> dict
        ``reachable``, ``singularity_free``, ``good_transmission``: each with ``cells``,
        ``fraction`` of the box, ``volume`` (in ``units``), ``stderr`` (samples; else None)
        and its definition.
    threshold : float
        The LTI bound of ``good_transmission``.
    method : str
        How ``singularity_free`` was found (connected to home on the grid, or the home
        assembly mode for samples), and where home lies.
    """

    box: dict
    units: str
    box_volume: float
    cells: int
    regions: dict
    threshold: float
    method: str

    def to_dict(self) -> dict:
        return {"box": {k: list(v) for k, v in self.box.items()}, "units": self.units,
                "box_volume": self.box_volume, "cells": self.cells, "regions": self.regions,
                "lti_threshold": self.threshold, "singularity_free_method": self.method}


def _unit_product(ds, params) -> str:
    counts = {}
    for p in params:
        u = str(ds[p].attrs.get("units", ""))
        counts[u] = counts.get(u, 0) + 1
    order = sorted(counts, key=lambda u: (u in ("deg", "rad"), u))    # lengths first
    return ".".join(u if n == 1 else f"{u}^{n}" for u, n in ((u, counts[u]) for u in order))


def _home_cell(ds, model_home, dims):
    """The flat index of the grid node nearest the home pose (each parameter scaled by its
    extent), and whether home lies in the box and on the map's slice."""
    deg = ds.attrs.get("units_angle") == "deg"

    def value(p):
        v = float(model_home[p])
        return np.degrees(v) if deg and p not in ("Xo", "Yo", "Zo") else v
    idx, inside = [], True
    for d in dims:
        x = ds[d].values
        h = value(d)
        inside &= bool(min(x[0], x[-1]) - 1e-9 <= h <= max(x[0], x[-1]) + 1e-9)
        idx.append(int(np.argmin(np.abs(x - h))))
    on_slice = all(np.isclose(float(ds[k].values), value(k), atol=1e-9)
                   for k in ds.coords if ds[k].ndim == 0 and k in model_home)
    return int(np.ravel_multi_index(idx, tuple(ds.sizes[d] for d in dims))), inside, on_slice


def workspace(ds, threshold: float = GOOD_TRANSMISSION, home=None) -> Workspace:
    """The workspace measures of a map (see the module docstring).

    Parameters
    ----------
    ds : xarray.Dataset
        A map of :func:`screwkit.map` (a grid or random samples).
    threshold : float
        The LTI bound of the good-transmission region, in (0, 1].
    home : mapping, optional
        The home pose (radians, model lengths; default: the one the map records in its
        ``home_pose_*`` attributes).
    """
    if isinstance(threshold, bool) or not isinstance(threshold, (int, float, np.number)) \
            or not 0 < float(threshold) <= 1:
        raise InputError(f"the LTI threshold must be a number in (0, 1], got {threshold!r:.40}")
    dims = ds["ok"].dims
    samples = dims == ("sample",)
    params = [k for k in ds.coords if k != "sample" and ds[k].ndim == 1]
    box = {p: tuple(float(x) for x in ds.attrs[f"box_{p}"]) if f"box_{p}" in ds.attrs else
           (float(np.min(ds[p].values)), float(np.max(ds[p].values))) for p in params}
    vol = float(np.prod([hi - lo for lo, hi in box.values()]))
    reach = ds["reachable"].values.copy()
    if "within_limits" in ds:
        reach &= ds["within_limits"].values
    level = ds["level"].values
    regular = reach & (level < 3)
    hs = int(ds.attrs.get("home_det_sign", 0))
    det = ds["det_sign"].values
    if hs != 0:
        regular &= det == hs
    home = home if home is not None else _attr_home(ds)
    if samples:
        free = regular
        method = "samples: every non-singular sample of home's assembly mode (det J sign)"
    else:
        from ..engine._kernels import kernels
        seed, inside, on_slice = _home_cell(ds, home, dims)
        free = np.zeros(regular.size, bool)
        kernels().face_component(np.ascontiguousarray(regular, bool).reshape(-1),
                                 np.array(regular.shape, np.int64), int(seed), free)
        free = free.reshape(regular.shape)
        where = ("home lies in the box" if inside and on_slice else
                 "home lies outside the box or off its slice: the component of the node "
                 "nearest home")
        method = (f"grid: the face-connected component of non-singular cells of home's det J sign "
                  f"that holds the node nearest home ({where})")
    lti = ds["lti"].values if "lti" in ds else np.full(reach.shape, np.nan)
    with np.errstate(invalid="ignore"):
        good = reach & (lti >= float(threshold))
    n = reach.size
    regions = {}
    for name, mask, what in (
            ("reachable", reach, "assembled from home" + (", within the limits"
                                                          if "within_limits" in ds else "")),
            ("singularity_free", free, "not singular, connected to home"),
            ("good_transmission", good, f"reachable with LTI >= {float(threshold):g}")):
        c = int(np.sum(mask))
        f = c / n if n else 0.0
        regions[name] = {"cells": c, "fraction": f, "volume": f * vol,
                         "stderr": float(np.sqrt(f * (1 - f) / n) * vol) if samples and n
                         else None, "definition": what}
    return Workspace(box, _unit_product(ds, params), vol, int(n), regions, float(threshold),
                     method)


def _attr_home(ds) -> dict:
    names = [k[len("home_pose_"):] for k in ds.attrs if k.startswith("home_pose_")]
    if not names:
        raise InputError("the map does not record its home pose: pass home= (radians, model "
                         "lengths)")
    return {k: float(ds.attrs[f"home_pose_{k}"]) for k in names}
