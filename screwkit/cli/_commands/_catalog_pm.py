"""``screwkit catalog PM``: one PM's dimensions, parameters, defaults, units and limits."""

from __future__ import annotations

import math

from ._common import dump_json, fmt_num

__all__ = ["show_pm", "pm_card"]


def _raw_definition(name_or_path: str, model) -> dict:
    """The PM's entry as written (for its limits and expressions)."""
    from ...pm import default_catalog, load_catalog
    from ...pm._checks import split_path

    path, _ = split_path(name_or_path)
    cat = load_catalog(path) if path is not None else default_catalog()
    d = cat.pms.get(model.name)
    return d if isinstance(d, dict) else {}


def pm_card(name_or_path: str) -> dict:
    """A JSON-ready description of a PM: what a user sets and within which limits."""
    from ... import load_pm
    from ...pm import LENGTH_PARAMS

    pm = load_pm(name_or_path)
    u = pm.units
    raw = _raw_definition(name_or_path, pm)

    def value(k, v):
        return float(v) if k in LENGTH_PARAMS else math.degrees(float(v))

    def unit(k):
        return u.length if k in LENGTH_PARAMS else "deg"

    return {
        "name": pm.name, "string": pm.string, "summary": pm.summary,
        "legs": list(pm.legs), "dof": pm.stated_dof, "motion": pm.motion, "euler": pm.order,
        "units": {"length": u.length, "force": u.force, "torque": u.torque,
                  "declared": bool(u.declared)},
        "dimensions": {k: {"value": float(v), "unit": u.length,
                           "as_written": (raw.get("dimensions") or {}).get(k)}
                       for k, v in pm.dimensions.items()},
        "independent": [{"name": k, "default": value(k, pm.default_pose[k]),
                         "home": value(k, pm.home_pose[k]), "unit": unit(k)}
                        for k in pm.independent],
        "dependent": list(pm.dependent),
        "limits": raw.get("limits") or {},
        "limits_units": "joint values from home: deg for R/H joints, lengths for P joints; "
                        f"extensions and distances in {u.length}",
        "workload": (None if pm.workload is None else
                     {"force": pm.workload.force, "torque": pm.workload.torque,
                      "applied_at": "o", "source": pm.workload.origin,
                      "force_unit": u.force, "torque_unit": u.torque}),
        "source": pm.source, "note": pm.note,
    }


def show_pm(name_or_path: str, as_json: bool = False) -> int:
    card = pm_card(name_or_path)
    if as_json:
        print(dump_json(card))
        return 0
    u = card["units"]
    print(f"PM {card['name']}  ({card['string']}: {'+'.join(card['legs'])})")
    if card["summary"]:
        print(f"  {card['summary']}")
    print(f"  {card['dof']} DOF ({card['motion'] or 'motion not stated'}), Euler order "
          f"{card['euler']} (intrinsic, scipy)")
    units = f"lengths {u['length']}, forces {u['force']}, torques {u['torque']}"
    print(f"units: {units}" + ("" if u["declared"] else " (the model declares no units)"))
    print(f"dimensions ({u['length']}; --set NAME=VALUE):")
    for k, d in card["dimensions"].items():
        written = d["as_written"]
        note = f"   (written {written})" if isinstance(written, str) else ""
        print(f"  {k} = {fmt_num(d['value'])} {d['unit']}{note}")
    print("independent pose parameters (--pose NAME=VALUE; angles in deg):")
    for p in card["independent"]:
        print(f"  {p['name']:<6} default {fmt_num(p['default'])} {p['unit']}   home "
              f"{fmt_num(p['home'])} {p['unit']}")
    print(f"dependent pose parameters (solved): {', '.join(card['dependent']) or 'none'}")
    w = card["workload"]
    if w is None:
        print("workload: none declared (statics need --force FX,FY,FZ and/or --torque "
              "TX,TY,TZ)")
    else:
        from ._common import fmt_vec
        print(f"workload: F = {fmt_vec(w['force'])} {w['force_unit']}, T = "
              f"{fmt_vec(w['torque'])} {w['torque_unit']} at o ({w['source']})")
    lim = card["limits"]
    if lim:
        print(f"limits ({card['limits_units']}):")
        for k, v in lim.items():
            print(f"  {k}: {v}")
    else:
        print("limits: none declared")
    for k in ("source", "note"):
        if card[k]:
            print(f"{k}: {card[k]}")
    return 0
