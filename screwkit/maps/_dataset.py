"""A map as an :class:`xarray.Dataset`, and its files (NetCDF, Zarr, CSV).

Dimensions are the grid parameters (``sample`` for random samples); every variable carries
``units`` and ``long_name`` attributes and the Dataset's attributes name the model, its
units, the workload and the thresholds.  Flag variables (``level``, ``singular_kind``) are
small integers with CF ``flag_values`` / ``flag_meanings``.  xarray (``screwkit[maps]``) is
imported on first use.

Files: ``.nc`` NetCDF (the ``scipy`` engine, no extra dependency; NetCDF4 through
``netCDF4`` or ``h5netcdf`` where installed), ``.zarr`` (needs ``zarr``), ``.csv`` long
format (one row per cell, a column per grid parameter and variable, ``NAME [UNIT]``
headers: ``pandas.read_csv`` reads it back).
"""

from __future__ import annotations

from pathlib import Path

import numpy as np

from ..engine import LENGTH_PARAMS
from ..errors import InputError
from ._compute import CONDITIONING_CODES, KIND_CODES, LEVEL_CODES

__all__ = ["xarray", "variable", "build_dataset", "write", "to_csv", "FORMATS"]

FORMATS = (".nc", ".zarr", ".csv")
#: The index variables of a map (``docs/design.md``: definitions and conventions).
INDEX_LONG_NAMES = {
    "iti": "input transmission index (smallest over the active legs)",
    "oti": "output transmission index (smallest over the active legs)",
    "lti": "local transmission index min(ITI, OTI)",
    "cti": "constraint transmission index (smallest over the constraint rows; NaN: none)",
    "sigma_min": "smallest singular value of the normalised J",
}


def xarray():
    """The xarray module, or an :class:`InputError` saying how to install it."""
    try:
        import xarray as xr
    except ImportError:
        raise InputError("maps need xarray (pip install 'screwkit[maps]')") from None
    return xr


def variable(dims, data, attrs):
    """An ``xarray.Variable`` of a numpy array as it is: xarray's probing of other array
    types (its first use imports ``dask.array``, about a second of a map) is skipped, which
    changes nothing for a plain numpy array."""
    return xarray().Variable(dims, np.asarray(data), attrs, fastpath=True)


def index_variable(dim, values, attrs):
    """A dimension coordinate as an ``xarray.IndexVariable`` of a :class:`pandas.Index` (what
    xarray makes of it anyway): built from a numpy array, xarray's index cast probes it for a
    dask array, which imports ``dask.array`` (0.2-0.3 s of a ``map`` command)."""
    import pandas as pd
    return xarray().IndexVariable((dim,), pd.Index(np.asarray(values)), attrs)


def _angle_unit(grid):
    return "deg" if grid.degrees else "rad"


def _param_unit(name, grid, units):
    return units.length if name in LENGTH_PARAMS else _angle_unit(grid)


def build_dataset(model, grid, arrays: dict, meta, force, torque, *, workers=None,
                  cluster=None) -> "xarray.Dataset":
    """The Dataset of a computed map (``arrays`` from :func:`~screwkit.maps._compute.compute`)."""
    xr = xarray()
    u = model.units
    shape = grid.shape
    dims = grid.dims
    to_deg = grid.degrees

    def var(a, unit, long_name, **attrs):
        a = np.asarray(a)
        return variable(dims, a.reshape(shape + a.shape[1:]),
                        dict(units=unit, long_name=long_name, **attrs))

    coords = {}
    if grid.samples:
        coords["sample"] = index_variable("sample", np.arange(grid.size), {"units": "1"})
        for k, v in grid.coords.items():
            coords[k] = variable(("sample",), v, {"units": _param_unit(k, grid, u),
                                                     "long_name": f"pose parameter {k}"})
    else:
        for k in dims:
            coords[k] = index_variable(k, grid.coords[k], {"units": _param_unit(k, grid, u),
                                                          "long_name": f"pose parameter {k}"})
    for k, v in grid.fixed.items():
        coords[k] = variable((), v, {"units": _param_unit(k, grid, u),
                                        "long_name": f"pose parameter {k} (fixed)"})
    a = arrays
    dv = {
        "reachable": var(a["reachable"], "1",
                         "the loop closures are solved from the home assembly"),
        "converged": var(a["converged"], "1", "closure residual <= 1e-10"),
        "ok": var(a["ok"], "1", "reachable, converged, not singular, statics balanced"),
        "residual": var(a["residual"], "1", "length-normalised loop-closure residual"),
        "condition_number": var(a["condition_number"], "1",
                                "normalised condition number of J = [J_a; J_c]"),
        "constraint_condition_number": var(a["constraint_condition_number"], "1",
                                           "normalised condition number of J_c"),
        "det_sign": var(a["det_sign"], "1", "assembly-mode sign of det J (each leg's "
                        "constraint rows oriented by its joints; 0: J not square or "
                        "unreachable)",
                        home_det_sign=int(meta.home_det_sign)),
        "singular": var(a["singular"], "1", "condition number above the threshold"),
        "singular_kind": var(a["singular_kind"], "1", "kind of singularity",
                             flag_values=np.arange(len(KIND_CODES), dtype=np.int8),
                             flag_meanings=" ".join(KIND_CODES)),
        "conditioning": var(a["conditioning"], "1", "conditioning class of the cell",
                            flag_values=np.arange(len(CONDITIONING_CODES), dtype=np.int8),
                            flag_meanings=" ".join(CONDITIONING_CODES)),
        "level": var(a["level"], "1", "trust level of the cell's efforts",
                     flag_values=np.arange(len(LEVEL_CODES), dtype=np.int8),
                     flag_meanings=" ".join(LEVEL_CODES)),
        "amplification": var(a["amplification"], "1",
                             "largest effort over the size of the workload"),
        "equilibrium_residual": var(a["equilibrium_residual"], "1",
                                    "relative platform equilibrium residual"),
    }
    for name, text in INDEX_LONG_NAMES.items():
        if name in a:
            dv[name] = var(a[name], "1", text)
    if any(k.startswith("stiff.") for k in a):
        from ..dynamics import STIFFNESS_FIELDS
        for name, (kind, long_name) in STIFFNESS_FIELDS.items():
            dv[name] = var(a[f"stiff.{name}"], kind if kind in ("1", "rad") else u.of(kind),
                           long_name)
    for p in meta.dependent:
        v = a[f"dep.{p}"]
        unit = u.length if p in LENGTH_PARAMS else _angle_unit(grid)
        if p not in LENGTH_PARAMS and to_deg:
            v = np.degrees(v, out=v)            # (the map's own array: no copy)
        dv[p] = var(v, unit, f"dependent pose parameter {p}")
    rows = zip(meta.labels, meta.quantities, meta.kinds, meta.legs) if "values" in a else ()
    for k, (lab, q, kind, leg) in enumerate(rows):       # (no workload: no force variables)
        what = ("active " + ("torque" if q == "torque" else "force") if kind == "actuation"
                else f"constraint {kind}")
        dv[lab] = var(a["values"][:, k], u.of(q), f"{what} of leg {leg + 1}",
                      row=k, leg=leg + 1, kind=kind)
    n = len(meta.linear)
    for i in range(n):
        if meta.linear[i] and "T_r" in a:
            dv[f"T_r{i + 1}"] = var(a["T_r"][:, i], u.torque,
                                    f"moment of leg {i + 1}'s constraint wrench about its axis",
                                    leg=i + 1)
    for i in range(n):
        dv[f"r{i + 1}"] = var(a["extensions"][:, i], u.length,
                              f"extension |a_{i + 1} - A_{i + 1}| of leg {i + 1}", leg=i + 1)
    for k, i in enumerate(model.active):            # a passive leg has no actuator
        rot = not meta.linear[i]
        v = a["actuators"][:, k]
        if rot and to_deg:
            v = np.degrees(v, out=v)
        dv[f"q_a{i + 1}"] = var(v, _angle_unit(grid) if rot else u.length,
                                f"actuated joint value of leg {i + 1} (from home)", leg=i + 1)
    if "within_limits" in a:
        dv["within_limits"] = var(a["within_limits"], "1",
                                  "every joint, stroke and leg-distance limit holds")
    if "min_leg_distance" in a:
        dv["min_leg_distance"] = var(a["min_leg_distance"], u.length,
                                     "smallest distance between two legs' segments")
    from .. import engine
    attrs = {
        "title": f"screwkit map of {model.name}",
        "pm": model.name, "pm_string": model.string, "order": model.order,
        "independent": ",".join(model.independent), "grid": ",".join(grid.params),
        "defaults": ",".join(grid.defaults),
        "units_length": u.length, "units_force": u.force, "units_torque": u.torque,
        "units_angle": _angle_unit(grid), "units_declared": int(u.declared),
        "normalisation_length": float(model.normalisation.length),
        "force": np.full(3, np.nan) if force is None else np.asarray(force, float),
        "torque": np.full(3, np.nan) if torque is None else np.asarray(torque, float),
        "workload_applied_at": "o",
        "condition_threshold": float(engine.COND_THRESHOLD),
        "home_det_sign": int(meta.home_det_sign),
        "limits_declared": int(model.limits.declared),
        "cells": int(grid.size),
        "computed_on": ("serial" if cluster is None else "dask"),
        "conventions": "wrenches [f; m] about the base origin O; twists [v; w]",
    }
    for k, v in model.home_pose.items():           # radians, model lengths
        attrs[f"home_pose_{k}"] = float(v)
    if grid.samples:
        attrs["seed"] = int(grid.seed)
        for k, (lo, hi) in (grid.box or {}).items():     # the sampling box
            attrs[f"box_{k}"] = np.array([lo, hi], float)
    return xr.Dataset(dv, coords=coords, attrs=attrs)


def write(ds, path) -> str:
    """Write a map to ``.nc``, ``.zarr`` or ``.csv`` (by the suffix); returns the path."""
    p = Path(path)
    suffix = p.suffix.lower()
    if suffix not in FORMATS:
        raise InputError(f"cannot write a map to {str(path)!r}: the file must end in "
                         f"{', '.join(FORMATS)}")
    try:
        p.parent.mkdir(parents=True, exist_ok=True)        # --out dir/map.nc: make dir
        if suffix == ".csv":
            to_csv(ds, p)
        elif suffix == ".nc":
            _to_netcdf(ds, p)
        else:
            try:
                import zarr  # noqa: F401
            except ImportError:
                raise InputError("writing .zarr needs zarr (pip install zarr)") from None
            _plain(ds).to_zarr(str(p), mode="w", consolidated=False)
    except OSError as exc:
        raise InputError(f"cannot write {str(path)!r}: {exc}") from None
    return str(p)


def _plain(ds):
    """Attributes as NetCDF allows them (no bools, no None)."""
    out = ds.copy()
    for v in list(out.variables.values()) + [out]:
        for k, val in list(v.attrs.items()):
            if isinstance(val, (bool, np.bool_)):
                v.attrs[k] = int(val)
            elif val is None:
                v.attrs[k] = ""
    return out


def _to_netcdf(ds, p):
    engine = None
    for mod, name in (("netCDF4", "netcdf4"), ("h5netcdf", "h5netcdf")):
        try:
            __import__(mod)
            engine = name
            break
        except ImportError:
            continue
    _plain(ds).to_netcdf(str(p), engine=engine or "scipy")


#: Rows of the long-format CSV formatted at a time (its memory is that of one chunk).
CSV_ROWS = 32768


def to_csv(ds, out=None):
    """The map in long format: one row per cell (``NAME [UNIT]`` headers; flags by name;
    floats as ``%.15g``, NaN empty, booleans ``True``/``False``: pandas' ``to_csv``
    layout; the workload at ``o`` last, ``workload_F<x|y|z>``, ``workload_T<x|y|z>``, where
    the map has one).  Written to ``out`` (a path) :data:`CSV_ROWS` rows at a time, or returned as
    text without ``out``."""
    heads, columns = _csv_columns(ds)
    n = len(columns[0][1]) if columns else 0
    fmt = ",".join(f for f, _, _ in columns) + "\n"
    parts = [",".join(_csv_field(h) for h in heads) + "\n"]
    f = None if out is None else open(out, "w", encoding="utf-8", newline="")
    try:
        for s in range(0, n, CSV_ROWS):
            rows = min(CSV_ROWS, n - s)
            cells = np.empty((rows, len(columns)), object)
            for j, (_, col, names) in enumerate(columns):
                part = col[s:s + rows]
                cells[:, j] = part if names is None else names[part.astype(int)]
            parts.append(_no_nan(fmt * rows % tuple(cells.ravel().tolist())))
            if f is not None:
                f.write("".join(parts))
                parts = []
        if f is None:
            return "".join(parts)
        f.write("".join(parts))
    finally:
        if f is not None:
            f.close()
    return None


def _csv_columns(ds) -> tuple:
    """``(headers, [(format, values (N,))])`` of the long-format CSV, in column order."""
    dims = _dims(ds)
    grids = np.meshgrid(*[ds[d].values for d in dims], indexing="ij", copy=False) \
        if dims != ("sample",) else [ds["sample"].values]
    shape = tuple(ds.sizes[d] for d in dims)
    cols = {}
    for d, g in zip(dims, grids):
        cols[_head(ds, d)] = np.broadcast_to(g, shape).reshape(-1)
    if dims == ("sample",):
        for k in ds.coords:
            if k != "sample" and ds[k].dims == ("sample",):
                cols[_head(ds, k)] = ds[k].values
    for k in ds.coords:
        if ds[k].ndim == 0:
            cols[_head(ds, k)] = np.full(int(np.prod(shape)), float(ds[k].values))
    for k, v in ds.data_vars.items():
        if v.dims != dims:
            continue                            # the loci (along crossing) are not cells
        names = None
        if "flag_meanings" in v.attrs:                  # flags by name (chunk by chunk)
            names = np.array([_csv_field(x) for x in str(v.attrs["flag_meanings"]).split()])
        cols[_head(ds, k)] = (v.values.reshape(-1), names)
    force, torque = ds.attrs.get("force"), ds.attrs.get("torque")
    if force is not None and np.all(np.isfinite(force)):      # the workload, on every row
        n = int(np.prod(shape))
        for name, v, unit in (("F", force, ds.attrs["units_force"]),
                              ("T", torque, ds.attrs["units_torque"])):
            for j, x in enumerate("xyz"):
                cols[f"workload_{name}{x} [{unit}]"] = np.full(n, float(v[j]))
    return list(cols), [(_csv_format(a) if names is None else "%s", a, names)
                        for a, names in (c if isinstance(c, tuple) else (c, None)
                                         for c in cols.values())]


def _csv_format(a) -> str:
    kind = np.asarray(a).dtype.kind
    return "%.15g" if kind == "f" else "%d" if kind in "iu" else "%s"


def _csv_field(text: str) -> str:
    """A text field as the csv module writes it (quoted only where it must be)."""
    if any(c in text for c in ',"\r\n'):
        return '"' + text.replace('"', '""') + '"'
    return text


def _no_nan(text: str) -> str:
    """NaN fields (``%.15g`` gives ``nan``) left empty, as pandas writes them; only a float
    field can read ``nan`` (the text fields are flag names and headers)."""
    text = text.replace(",nan,", ",,").replace(",nan,", ",,").replace(",nan\n", ",\n")
    text = text.replace("\nnan,", "\n,")
    return text[3:] if text.startswith("nan,") else text


def _dims(ds):
    return tuple(d for d in ds["ok"].dims)


def _head(ds, name):
    unit = ds[name].attrs.get("units", "")
    return f"{name} [{unit}]" if unit and unit != "1" else name
