"""Actuator and leg sizing: the largest value of every row over a map and a list of workloads.

For every row of ``J`` (each actuator's force or torque, each constraint force or couple)
and every linear leg's ``T_r``, :func:`extremes` finds the largest ``|value|`` over the
usable cells of a map (``ok``, within the model's limits where it declares some, and no
worse than a chosen trust level), with
the signed value, the pose and the cell's trust level; the extensions ``r_i`` and actuated
joint values ``q_ai`` get their range (the strokes).  :func:`size` does it for a list of
workloads and keeps, per row, the worst workload: one map, whose cells are analysed once;
the statics being linear in the workload, every other workload's efforts are formed from
the responses of each cell to six unit workloads (:mod:`screwkit.maps._loads`).

Workloads come from a CSV file (:func:`read_workloads`): a header with ``Fx, Fy, Fz, Tx,
Ty, Tz`` (the model's force and torque units, at ``o``) and optionally ``name``.
"""

from __future__ import annotations

import csv
from dataclasses import dataclass, field

import numpy as np

from ..errors import InputError
from ._compute import CONDITIONING_CODES, LEVEL_CODES
from ._round_off import zero_round_off

__all__ = ["Sizing", "extremes", "mark_determined", "size", "read_workloads", "MAX_WORKLOADS",
           "pose_at"]

#: Largest number of workloads of one sizing.
MAX_WORKLOADS = 1000
_COLS = ("Fx", "Fy", "Fz", "Tx", "Ty", "Tz")


def _cell_dims(ds):
    return ds["ok"].dims


def pose_at(ds, flat: int) -> dict:
    """The independent pose parameters of cell ``flat`` (C order) of a map, in its units."""
    dims = _cell_dims(ds)
    idx = np.unravel_index(int(flat), tuple(ds.sizes[d] for d in dims))
    out = {}
    for p in str(ds.attrs["independent"]).split(","):
        v = ds[p]
        if v.ndim == 0:
            out[p] = float(v.values)
        elif dims == ("sample",):
            out[p] = float(v.values[idx[0]])
        else:
            out[p] = float(v.values[idx[dims.index(p)]])
    return out


def usable(ds, max_level: str = "near-singular") -> np.ndarray:
    """The cells a sizing counts: ``ok``, within the limits, and of a trust level no worse
    than ``max_level`` (flattened)."""
    _level_code(max_level)
    u = ds["ok"].values.reshape(-1).copy()
    u &= ds["level"].values.reshape(-1) <= LEVEL_CODES.index(max_level)
    if "within_limits" in ds:
        u &= ds["within_limits"].values.reshape(-1)
    return u


def _level_code(max_level: str) -> int:
    if max_level not in LEVEL_CODES[:3]:
        raise InputError(f"max_level must be one of {', '.join(LEVEL_CODES[:3])}, got "
                         f"{max_level!r}")
    return LEVEL_CODES.index(max_level)


def extremes(ds, workload_name: str = "", max_level: str = "near-singular", *,
             use=None) -> dict:
    """The largest ``|value|`` of each row and ``T_r`` and the range of each extension and
    actuated joint value over the usable cells of a map (:func:`usable`; JSON-ready).

    ``use`` (flat boolean, optional) replaces :func:`usable` for the ranges and the count of
    usable cells (a sizing over several workloads: the cells counted for any of them); the
    rows' extremes stay those of this map's workload."""
    own = usable(ds, max_level)
    use_rows, use = own, (own if use is None else np.asarray(use, bool))
    lev = ds["level"].values.reshape(-1)
    cls = ds["conditioning"].values.reshape(-1)
    rows = []
    names = [k for k, v in ds.data_vars.items() if "row" in v.attrs]
    names += [k for k in ds.data_vars if k.startswith("T_r")]
    for k in names:
        v = ds[k]
        a = np.where(use_rows, np.abs(v.values.reshape(-1)), -np.inf)
        entry = {"name": k, "kind": v.attrs.get("kind", "T_r"), "leg": int(v.attrs["leg"]),
                 "unit": v.attrs["units"], "long_name": v.attrs["long_name"]}
        if not use_rows.any() or not np.isfinite(a).any():
            entry.update(max_abs=None, value=None, pose=None, level=None, conditioning=None,
                         workload=None)
        else:
            i = int(np.argmax(a))
            entry.update(max_abs=float(a[i]), value=float(v.values.reshape(-1)[i]),
                         pose=pose_at(ds, i), level=LEVEL_CODES[int(lev[i])],
                         conditioning=CONDITIONING_CODES[int(cls[i])], workload=workload_name)
        rows.append(entry)
    ranges = []
    for k in [k for k in ds.data_vars if k[:1] == "r" and k[1:].isdigit()] + \
            [k for k in ds.data_vars if k.startswith("q_a")]:
        v = ds[k].values.reshape(-1)
        e = {"name": k, "unit": ds[k].attrs["units"], "leg": int(ds[k].attrs["leg"]),
             "long_name": ds[k].attrs["long_name"]}
        if use.any():
            lo, hi = int(np.argmin(np.where(use, v, np.inf))), \
                int(np.argmax(np.where(use, v, -np.inf)))
            e.update(min=float(v[lo]), max=float(v[hi]), pose_min=pose_at(ds, lo),
                     pose_max=pose_at(ds, hi))
        else:
            e.update(min=None, max=None, pose_min=None, pose_max=None)
        ranges.append(e)
    zero_round_off(rows, ds)
    return {"rows": rows, "ranges": ranges, "usable_cells": int(use.sum()),
            "cells": int(use.size), "max_level": max_level}



@dataclass(frozen=True, eq=False)
class Sizing:
    """The sizing table of a PM over a map and a list of workloads.

    Attributes
    ----------
    pm : str
    rows : list of dict
        Per row of ``J`` and ``T_r``: ``name``, ``kind``, ``leg``, ``unit``, ``max_abs``,
        ``value`` (signed), ``pose``, ``level``, ``workload``, and ``determined``: False
        where the PM is statically indeterminate and a self-stress changes this value at
        that pose (it is then the least-norm or ``stiffness``-weighted choice, not fixed by
        statics alone; None without a usable cell).
    ranges : list of dict
        Per extension and actuated joint value: ``min``, ``max`` and their poses.
    workloads : list of dict
        ``name``, ``force``, ``torque``.
    usable_cells, cells : int
    max_level : str
    units : dict
    dataset : xarray.Dataset
        The map of the first workload.
    """

    pm: str
    rows: list
    ranges: list
    workloads: list
    usable_cells: int
    cells: int
    max_level: str
    units: dict
    dataset: object = field(repr=False, default=None)

    def to_dict(self) -> dict:
        return {"pm": self.pm, "units": self.units, "workloads": self.workloads,
                "cells": self.cells, "usable_cells": self.usable_cells,
                "max_level": self.max_level,
                "extremes": self.rows, "ranges": self.ranges}


def read_workloads(path) -> list:
    """Workloads from a CSV file (see the module docstring): a list of
    ``(name, force (3,), torque (3,))``.

    A UTF-8 byte-order mark (spreadsheets' "CSV UTF-8") is accepted; a row with more or
    fewer fields than the header, or a value that is not a number of at most
    :data:`~screwkit.legs._guards.MAX_LOAD` in magnitude, is an :class:`InputError` naming
    the file, line and column."""
    import io

    from ..legs._guards import MAX_CSV_BYTES, MAX_LOAD, decode_utf8, parse_number, read_limited
    text = decode_utf8(read_limited(path, MAX_CSV_BYTES, f"workloads {str(path)!r}"),
                       f"workloads {str(path)!r}")
    try:
        reader = csv.DictReader(io.StringIO(text, newline=""))
        rows = []
        for r in reader:
            rows.append((reader.line_num, r))
            if len(rows) > MAX_WORKLOADS:
                raise InputError(f"{path}: more than {MAX_WORKLOADS} workloads")
        head = [str(h).strip() for h in (reader.fieldnames or [])]
    except csv.Error as exc:
        raise InputError(f"{path}: not a readable CSV file ({exc})") from None
    if not rows:
        raise InputError(f"{path}: no workloads (a header Fx,Fy,Fz,Tx,Ty,Tz and one row each)")
    seen = set()
    for h in head:
        if h in seen:
            raise InputError(f"{path}, line 1: column {h!r} is given twice (csv would keep only "
                             "the last one)")
        seen.add(h)
    united = [h for h in head if "[" in h and h.split("[")[0].strip() in (*_COLS, "name")]
    if united:                       # (a trajectory's table carries units; loads are not read so)
        raise InputError(f"{path}, line 1: column {united[0]!r}: a unit in the header is not "
                         "read here: the loads are in the model's force and torque units, in "
                         f"columns named {', '.join(_COLS)} (and optionally name)")
    missing = [c for c in _COLS if c not in head]
    if missing:
        sep = "; the columns must be separated by commas" if any(";" in h for h in head) \
            else ""
        raise InputError(f"{path}: missing column(s) {', '.join(missing)} (need "
                         f"{', '.join(_COLS)}, optionally name{sep})")
    extra = [h for h in head if h not in _COLS and h != "name"]
    if extra:                        # (a misspelt column would be a load silently left out)
        raise InputError(f"{path}, line 1: unknown column(s) {', '.join(map(repr, extra))} "
                         f"(the columns are {', '.join(_COLS)} and optionally name)")
    out, names = [], set()
    for k, (line, r) in enumerate(rows, 1):
        if None in r or any(v is None for v in r.values()):
            n = sum(v is not None for a, v in r.items() if a is not None) + \
                len(r.get(None) or ())
            raise InputError(f"{path}, line {line}: {n} fields, but the header has "
                             f"{len(head)}")
        r = {str(a).strip(): b for a, b in r.items()}
        v = np.array([parse_number(r[c], f"{path}, line {line}, column {c}", bound=MAX_LOAD)
                      for c in _COLS])
        name = str(r.get("name") or f"workload {k}").strip()
        if name in names:
            raise InputError(f"{path}, line {line}: workload name {name!r} is given twice "
                             "(the results are named by it)")
        names.add(name)
        out.append((name, v[:3], v[3:]))
    return out


def size(pm, grid, fix=None, *, workloads=None, samples=None, seed=0, degrees=False,
         stiffness=None, workers=None, cluster=None, scheduler=None, progress=None,
         overrides=None, max_level: str = "near-singular") -> Sizing:
    """Size a PM's actuators and legs over a map (see the module docstring).

    Parameters
    ----------
    pm, grid, fix, samples, seed, degrees, stiffness, workers, cluster, scheduler
        As :func:`screwkit.map`.
    workloads : list of (name, force, torque), optional
        Default: the model's declared workload (an :class:`InputError` when it declares
        none).  At most :data:`MAX_WORKLOADS`.
    progress : callable(done, total), optional
        Over all workloads' cells.
    max_level : str
        The worst trust level of a counted cell: ``near-singular`` (every cell that is not
        singular, near-singular ones included; default), ``ill-conditioned`` or ``ok``.

    Returns
    -------
    Sizing
    """
    from ._map import _cluster, resolve_model, workload

    model = resolve_model(pm, overrides)
    if workloads is None:
        F, T, source = workload(model)
        loads = [(source, F, T)]
    else:
        loads = workload_list(model, workloads)
    cl = _cluster(cluster, scheduler)
    if cl is None:
        return _size(model, grid, fix, loads, samples, seed, degrees, stiffness, workers,
                     None, progress, max_level)
    from ._dask import client_for
    with client_for(cl) as client:              # one cluster for every workload
        return _size(model, grid, fix, loads, samples, seed, degrees, stiffness, workers,
                     client, progress, max_level)


def workload_list(model, workloads) -> list:
    """``[(name, F (3,), T (3,)), ...]`` of the given ``workloads`` (a list of ``(name,
    force, torque)``, 1 to :data:`MAX_WORKLOADS` of them, their names distinct, each force
    and torque three numbers in the model's units), checked."""
    from ._map import workload
    if isinstance(workloads, (str, bytes, dict)):
        loads = [()]
    else:
        try:
            loads = [tuple(x) if not isinstance(x, (str, bytes)) else () for x in workloads]
        except TypeError:
            loads = [()]
    if not 1 <= len(loads) <= MAX_WORKLOADS or any(len(x) != 3 for x in loads):
        raise InputError(f"workloads: 1 to {MAX_WORKLOADS} entries (name, force (3,), torque "
                         f"(3,)), got {str(workloads)[:80]}")
    names = [str(n) for n, _, _ in loads]
    if len(set(names)) != len(names):
        raise InputError(f"workloads: the names must differ, got {str(names)[:80]}")
    if any(F is None or T is None for _, F, T in loads):
        # (a None would take the model's declared load under the given name)
        raise InputError("workloads: give each entry its force and torque (zeros where "
                         "there is none)")
    return [(n,) + tuple(workload(model, F, T)[:2]) for n, (_, F, T) in zip(names, loads)]


def _size(model, grid, fix, loads, samples, seed, degrees, stiffness, workers, client,
          progress, max_level):
    from ._dataset import xarray
    from ._grid import make_grid
    from ._loads import merge_reductions
    from ._map import map_dataset

    xarray()
    g = make_grid(model, grid, fix, samples=samples, seed=seed, degrees=degrees)
    name0, F0, T0 = loads[0]
    # one map: the first workload's, and from the same analyses every other workload's
    # largest efforts (the statics are linear in the workload: _loads)
    first, _, (parts, usable_any) = map_dataset(
        model, g, F0, T0, stiffness=stiffness, workers=workers, cluster=client,
        progress=progress, loads=loads[1:] if len(loads) > 1 else None,
        max_level_code=_level_code(max_level))
    use = None if usable_any is None else usable(first, max_level) | usable_any
    best = extremes(first, name0, max_level, use=use)
    if parts is not None:
        red = merge_reductions(parts)
        for q, row in enumerate(best["rows"]):
            k = int(np.argmax(red["max_abs"][:, q]))           # the first on a tie
            m = red["max_abs"][k, q]
            if np.isfinite(m) and (row["max_abs"] is None or m > row["max_abs"]):
                i = int(red["index"][k, q])
                row.update(max_abs=float(m), value=float(red["value"][k, q]),
                           pose=pose_at(first, i), level=LEVEL_CODES[int(red["level"][k, q])],
                           conditioning=CONDITIONING_CODES[int(
                               first["conditioning"].values.reshape(-1)[i])],
                           workload=loads[1 + k][0])
    zero_round_off(best["rows"], first)
    _mark_determined(model, best["rows"], first, stiffness, F0, T0)
    u = model.units
    return Sizing(model.name, best["rows"], best["ranges"],
                  [{"name": n, "force": F.tolist(), "torque": T.tolist()} for n, F, T in loads],
                  best["usable_cells"], best["cells"], max_level,
                  dict(u.as_dict(), angle=first.attrs["units_angle"]), first)


def mark_determined(model, rows, ds, stiffness=None) -> None:
    """Set ``determined`` on the rows of :func:`extremes` of a map ``ds`` in the model's units
    (not converted by ``map_in_units``), under the map's own workload: True where statics
    alone fixes the value at its extreme's pose, False where it is the least-norm (or
    compliance-weighted) choice of a statically indeterminate ``J``, None without an
    extreme."""
    F = np.nan_to_num(np.asarray(ds.attrs.get("force", [np.nan] * 3), float))
    T = np.nan_to_num(np.asarray(ds.attrs.get("torque", [np.nan] * 3), float))
    _mark_determined(model, rows, ds, stiffness, F, T)


def _mark_determined(model, rows, ds, stiffness, F, T) -> None:
    """Set each row's ``determined``: True where statics alone fixes its value at the pose
    of its extreme, False where a self-stress of a statically indeterminate ``J`` changes
    it (the value is then the least-norm or compliance-weighted choice, as ``*`` marks it
    in ``screwkit analyze``), None without an extreme.  A leg's ``T_r`` is determined when
    no self-stress changes it (checked on the self-stress basis of that pose)."""
    from ..engine import analyze
    from ..engine._pipeline import leg_wrenches_of
    for r in rows:
        r["determined"] = None
    at = [r for r in rows if r.get("pose")]
    if not at:
        return
    keys = list(at[0]["pose"])
    rad = {p: str(ds[p].attrs.get("units", "")) == "deg" for p in keys}
    batch = {p: np.array([np.radians(r["pose"][p]) if rad[p] else r["pose"][p] for r in at])
             for p in keys}
    res = analyze(model, batch, force=F, torque=T, stiffness=stiffness,
                  raise_on_singular=False)                                   # a batch
    labels = list(res.jacobian.labels)
    for k, r in enumerate(at):
        one = res[k]
        if one.statics is None or not one.ok:
            continue
        if one.jacobian.indeterminacy <= 0:
            r["determined"] = True
            continue
        if r["name"] in labels:
            r["determined"] = bool(one.statics.determined[labels.index(r["name"])])
            continue
        jac = one.jacobian
        S = np.asarray(one.statics.self_stress)                     # (k, m), raw rows
        J = np.asarray(jac.J)[None]
        A = np.asarray(one.statics.A)
        a = np.asarray(res.statics._a)[k:k + 1]
        leg = int(r["leg"]) - 1
        t = leg_wrenches_of(J, jac.info, jac.n_actuated, S[None], A, a, total=False)[2][0, :, leg]
        L = float(np.asarray(jac.conditioning.length).reshape(-1)[0])
        size = np.abs(S) @ (np.linalg.norm(J[0, :, :3], axis=1) * L +
                            np.linalg.norm(J[0, :, 3:], axis=1))
        r["determined"] = bool(np.all(np.abs(t) <= 1e-9 * np.maximum(size, 1e-300)))
