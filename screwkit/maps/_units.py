"""A map or a sizing in SI (``--units SI`` of ``screwkit map`` and ``screwkit size``).

A map is computed in the model's units; its files (NetCDF, Zarr, CSV) and summaries allow
any units, each variable naming its own in ``units``.  :func:`map_in_units` returns the
Dataset with every dimensional variable and coordinate multiplied by its factor to metres,
newtons and newton metres (the engine's :func:`~screwkit.engine._report.output_scales`,
through pint), the ``units`` attributes and the Dataset's unit attributes and workload
renamed; :func:`sizing_in_units` does the same to a :class:`~screwkit.maps.Sizing`.
Dimensionless variables (flags, condition numbers) and angles do not change.

Examples
--------
>>> import screwkit
>>> ds = screwkit.map("3RRPRR", {"Zo": (70, 90, 3)}, fix={"alpha": 5, "beta": -3},
...                   degrees=True)
>>> si = map_in_units(ds, "SI")
>>> si["F_a1"].attrs["units"], si["Zo"].attrs["units"], float(si["Zo"][0])
('N', 'm', 0.7)
"""

from __future__ import annotations

import dataclasses

import numpy as np

__all__ = ["map_in_units", "sizing_in_units"]


def _table(units, which, name):
    """``{model unit: (factor, SI unit)}`` of the dimensional quantities."""
    from ..engine._report import output_scales
    from ..pm import Units
    u = Units(units["length"], units["force"], bool(units.get("declared", True)))
    _, k = output_scales(u, which, name)
    kl, kf, kt = k["length"], k["force"], k["torque"]
    return {u.length: (kl, "m"), u.force: (kf, "N"), u.torque: (kt, "N.m"),
            f"{u.force}/{u.length}": (kf / kl, "N/m"), f"{u.torque}/rad": (kt, "N.m/rad"),
            f"{u.force}/rad": (kf, "N/rad")}, (kl, kf, kt)


def map_in_units(ds, units=None):
    """The map ``ds`` in the model's units (``units=None`` or ``"model"``: ``ds`` itself) or
    in SI (``"SI"``; a model without declared units cannot be converted)."""
    if units is None or units == "model":
        return ds
    a = ds.attrs
    table, (kl, kf, kt) = _table({"length": a["units_length"], "force": a["units_force"],
                                  "declared": a.get("units_declared", 1)}, units, a["pm"])
    out = ds.copy()
    for name in list(out.variables):
        v = out[name]
        unit = v.attrs.get("units")
        if unit not in table:
            continue
        f, new = table[unit]
        conv = v.copy(data=np.asarray(v.values) * f)
        conv.attrs["units"] = new
        if name in out.coords:
            out = out.assign_coords({name: conv})
        else:
            out[name] = conv
    for k in ("Xo", "Yo", "Zo"):               # the recorded home pose and sampling box
        for key in (f"home_pose_{k}", f"box_{k}"):
            if key in a:
                out.attrs[key] = np.asarray(a[key], float) * kl if key.startswith("box") \
                    else float(a[key]) * kl
    out.attrs.update(units_length="m", units_force="N", units_torque="N.m",
                     force=np.asarray(a["force"], float) * kf,
                     torque=np.asarray(a["torque"], float) * kt,
                     units_converted_from=f"{a['units_length']}, {a['units_force']}")
    return out


def sizing_in_units(sizing, units=None):
    """The :class:`~screwkit.maps.Sizing` in the model's units or in SI (its rows' and
    ranges' values, their poses' lengths and the workloads)."""
    if units is None or units == "model":
        return sizing
    u = sizing.units
    table, (kl, kf, kt) = _table(u, units, sizing.pm)

    def pose(p):
        if p is None:
            return None
        return {k: (v * kl if k in ("Xo", "Yo", "Zo") else v) for k, v in p.items()}

    def convert(entry, keys):
        e = dict(entry)
        f, new = table.get(e.get("unit"), (1.0, e.get("unit")))
        for k in keys:
            if e.get(k) is not None:
                e[k] = e[k] * f
        e["unit"] = new
        for k in ("pose", "pose_min", "pose_max"):
            if k in e:
                e[k] = pose(e[k])
        return e

    rows = [convert(r, ("max_abs", "value")) for r in sizing.rows]
    ranges = [convert(r, ("min", "max")) for r in sizing.ranges]
    loads = [dict(w, force=[x * kf for x in w["force"]], torque=[x * kt for x in w["torque"]])
             for w in sizing.workloads]
    ds = None if sizing.dataset is None else map_in_units(sizing.dataset, units)
    return dataclasses.replace(sizing, rows=rows, ranges=ranges, workloads=loads,
                               units=dict(u, length="m", force="N", torque="N.m"), dataset=ds)
