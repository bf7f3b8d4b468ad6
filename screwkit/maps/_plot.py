"""The picture of a map: heatmaps of chosen quantities, drawn by :mod:`screwkit.viz`.

:func:`plot_map` takes a map's Dataset, picks a 1-D or 2-D slice (a 3-D map is cut at
``at``, by default the middle of its last grid parameter), and passes plain arrays to
:func:`screwkit.viz.plot_heatmaps`: the quantities (a variable name, or ``conditioning``,
``forces`` for every actuator), the unreachable cells and the cells outside the limits
(hatched), and the refined singular crossings of the slice (points, by kind).
"""

from __future__ import annotations

import numpy as np

from ..errors import InputError

__all__ = ["plot_map", "quantity_names"]

_LOG = {"condition_number", "constraint_condition_number", "amplification", "residual"}
#: Indices drawn on their whole range [0, 1].
_UNIT_RANGE = {"iti", "oti", "lti", "cti"}


def quantity_names(ds, quantity: str) -> list:
    """The variables a ``--quantity`` names: a variable, ``forces`` (every actuator),
    ``constraints`` (every constraint row), ``conditioning`` (condition number)."""
    cell = ds["ok"].dims
    rows = [k for k, v in ds.data_vars.items() if "row" in v.attrs]
    if quantity == "forces":
        return [k for k in rows if ds[k].attrs.get("kind") == "actuation"]
    if quantity == "constraints":
        return [k for k in rows if ds[k].attrs.get("kind") != "actuation"]
    if quantity == "conditioning":
        return ["condition_number"]
    if quantity == "transmission":
        return [k for k in ("iti", "oti", "lti", "cti") if k in ds.data_vars
                and np.isfinite(ds[k].values).any()]
    if quantity not in ds.data_vars or ds[quantity].dims != cell:
        names = [k for k, v in ds.data_vars.items() if v.dims == cell]
        raise InputError(f"no quantity {quantity!r} in the map; one of forces, constraints, "
                         f"conditioning, transmission, {', '.join(names)}")
    return [quantity]


def _label(ds, name):
    unit = ds[name].attrs.get("units", "1")
    if unit in ("", "1"):
        return f"{name.replace('_', ' ')} [–]"          # dimensionless
    return f"{name} [{unit}]"


def _codes(v):
    """``[(value, meaning)]`` of a flag variable (CF ``flag_meanings``) or a boolean one;
    empty for a quantity."""
    if "flag_meanings" in v.attrs:
        return list(zip(np.asarray(v.attrs["flag_values"]).tolist(),
                        str(v.attrs["flag_meanings"]).split()))
    if v.dtype == bool:
        return [(0, "no"), (1, "yes")]
    if v.name == "det_sign":
        return [(-1, "negative"), (0, "none"), (1, "positive")]
    return []


def plot_map(ds, out, quantities=("conditioning",), at=None, title=None):
    """Draw heatmaps of ``quantities`` of a map to ``out`` (PNG); returns the figure.

    ``at``: ``{parameter: value}`` picks the slice of a 3-D map (nearest grid value)."""
    from ..viz import plot_heatmaps
    from ._locus import LOCUS_KINDS
    dims = ds["ok"].dims
    if dims == ("sample",):
        raise InputError("random samples have no grid to draw: plot a map made with --grid")
    names = [n for q in quantities for n in quantity_names(ds, q)]
    if not names and "transmission" in quantities:
        raise InputError("nothing to plot: the transmission indices are defined at no cell of "
                         "the map (none reachable and regular)")
    sel, note = {}, []
    at = dict(at or {})
    for d in list(at):
        if d not in dims:
            raise InputError(f"--at {d}: not a grid parameter of the map ({', '.join(dims)})")
    if at and len(dims) < 3:
        raise InputError(f"--at picks the slice of a 3-D map; this map has {len(dims)} grid "
                         f"parameter(s) ({', '.join(dims)}): drop --at")
    if len(at) > 1:
        raise InputError(f"--at: give one grid parameter to cut the 3-D map at, got "
                         f"{', '.join(at)}")
    if len(dims) == 3:
        d = next((d for d in dims if d in at), dims[-1])
        v = at.get(d, float(ds[d].values[len(ds[d]) // 2]))
        grid = ds[d].values
        step = float(np.max(np.abs(np.diff(grid)))) if len(grid) > 1 else 0.0
        if d in at and not grid.min() - step / 2 <= v <= grid.max() + step / 2:
            unit = ds[d].attrs.get("units", "")
            raise InputError(f"--at {d}={v:g}: outside the map's {d} ({grid.min():g} .. "
                             f"{grid.max():g}{' ' + unit if unit else ''})")
        k = int(np.argmin(np.abs(grid - v)))
        sel[d] = k
        note.append(f"{d} = {float(ds[d].values[k]):.6g} {ds[d].attrs.get('units', '')}")
    sub = ds.isel(sel)
    free = [d for d in dims if d not in sel]
    x = sub[free[0]].values
    y = sub[free[1]].values if len(free) > 1 else None

    def arr(name):
        a = sub[name].transpose(*free).values
        return a.astype(float)

    lev = sub["level"].transpose(*free).values
    calm = lev <= 1       # the colour range: ok and ill-conditioned cells (arrows: some beyond)
    panels = [{"z": arr(n), "label": _label(ds, n), "log": n in _LOG,
               "limits": (0.0, 1.0) if n in _UNIT_RANGE else None,
               "title": f"{n}: {ds[n].attrs['long_name']}" if "long_name" in ds[n].attrs
               else _label(ds, n),
               "limits_from": None if n in _LOG else calm,
               # the rows of J are signed: one symmetric scale per kind across the legs
               "signed": "row" in ds[n].attrs, "group": ds[n].attrs.get("kind")
               if "row" in ds[n].attrs else None} for n in names]
    for pan, n in zip(panels, names):
        codes = _codes(ds[n])
        if codes:            # a flag or a boolean: every value in range, the codes named
            pan.update(label=f"{n} (code)", log=False, signed=False, group=None,
                       title=pan["title"] + "\n" + ", ".join(f"{k} {m}" for k, m in codes),
                       limits_from=np.ones(pan["z"].shape, bool))
    masks = [(~sub["reachable"].transpose(*free).values, "unreachable")]
    loaded = bool(np.all(np.isfinite(np.asarray(ds.attrs.get("force", [np.nan]), float))))
    masks.append(((lev == 2) | (lev == 3), "near-singular (efforts > 5x the load, or "
                  "condition > 1e3)" if loaded else "near-singular (condition > 1e3)"))
    if "within_limits" in sub:
        masks.append(((~sub["within_limits"] & sub["reachable"]).transpose(*free).values,
                      "outside the limits"))
    points = []
    if "locus_kind" in ds:
        kind = ds["locus_kind"].values
        keep = np.ones(kind.size, bool)
        for d, k in sel.items():              # crossings in the drawn slice
            keep &= np.isclose(ds[f"locus_{d}"].values, float(ds[d].values[k]))
        for j, name in enumerate(LOCUS_KINDS[:2]):
            m = keep & (kind == j)
            xs = ds[f"locus_{free[0]}"].values[m]
            ys = ds[f"locus_{free[1]}"].values[m] if y is not None else np.zeros(m.sum())
            points.append((xs, ys, f"{name} singularity (det J = 0, refined crossings)"))
    fixed = [f"{k} = {float(ds[k].values):.6g} {ds[k].attrs.get('units', '')}"
             for k in ds.coords if ds[k].ndim == 0]
    if title is None:
        title = f"{ds.attrs.get('pm', '')}: " + ", ".join(fixed + note)
        F = np.asarray(ds.attrs.get("force", []), float).round(6).tolist()
        T = np.asarray(ds.attrs.get("torque", []), float).round(6).tolist()
        title += (f"\nload F = {F} {ds.attrs.get('units_force', '')}, T = {T} "
                  f"{ds.attrs.get('units_torque', '')} at o" if loaded else
                  "\nno workload (the conditioning and transmission do not depend on one)")
    return plot_heatmaps(out, x, y, panels, xlabel=_label(ds, free[0]),
                         ylabel=_label(ds, free[1]) if y is not None else "", masks=masks,
                         points=points, title=title)
