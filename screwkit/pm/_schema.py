"""The JSON Schema of catalog and model files, built from the loader's own key sets (private).

:func:`model_schema` assembles one JSON Schema (draft 2020-12) for ``legs_catalog.yaml``
and every user model file: the keys it allows are the very sets the strict loader checks
(``_TOP_KEYS``, ``_LEG_KEYS`` and ``_EXPECT_KEYS`` of :mod:`screwkit.pm._catalog`,
``_PM_KEYS`` and ``_SHAPE_KEYS`` of :mod:`screwkit.pm._loader`, the joint-rule keys of
:mod:`screwkit.legs`, the ``limits:``, ``units:`` and ``dynamics:`` keys), so the schema
cannot drift from the code; this module only adds each field's JSON type and a one-line
description.  The packaged file ``screwkit/pm/model.schema.json`` is this schema
(``screwkit model schema`` prints it; ``tests/test_model_schema.py`` checks the file is
current).  The schema checks structure and types; what it cannot express (a rule's
references, the geometry, the home assembly) is the loader's part
(``screwkit model check FILE`` reports both).
"""

from __future__ import annotations

import json

__all__ = ["model_schema", "schema_text", "schema_path", "SCHEMA_FILE"]

#: File name of the packaged schema (in ``screwkit/pm/``).
SCHEMA_FILE = "model.schema.json"
_ID = "https://screwkit.invalid/schema/model.schema.json"

_NUM = {"type": ["number", "string"],
        "description": "a number or an expression of the dimensions (2*L/3)"}
_TEXT = {"type": "string"}
_VEC3 = {"type": "array", "items": _NUM, "minItems": 3, "maxItems": 3}
_RULE = {"description": "a direction or point rule (see docs/catalog.md)",
         "type": ["string", "number", "array", "object"]}
_BOUNDS = {"type": ["array", "null"], "items": {"type": ["number", "string", "null"]},
           "minItems": 2, "maxItems": 2, "description": "[min, max]; null leaves a bound open"}

#: Type and description of each field, by block; the allowed keys come from the loader.
_PM_TYPES = {
    "string": (_TEXT, "the PM's string, e.g. 3RRPRR or 2SPS+2SPR (default: its name)"),
    "summary": (_TEXT, "one line in words"),
    "note": (_TEXT, "a remark shown with the model"),
    "motion": (_TEXT, "the stated motion type, e.g. 1T2R"),
    "source": (_TEXT, "where the model comes from"),
    "euler": ({"type": "string", "pattern": "^([XYZ]{3}|[xyz]{3})$"},
              "Euler order of scipy's Rotation: intrinsic in upper case (XYX, XYZ, ...), "
              "extrinsic in lower case (xyz, ...)"),
    "dimensions": ({"type": "object", "propertyNames": {"pattern": "^[A-Za-z_][A-Za-z0-9_]*$"},
                    "additionalProperties": _NUM}, "named lengths, in the model's length unit"),
    "base": ({"$ref": "#/$defs/shape"}, "the base vertices A_i"),
    "platform": ({"$ref": "#/$defs/shape"}, "the platform vertices a_i (in {o})"),
    "legs": ({"type": "array", "minItems": 1, "items": {"$ref": "#/$defs/pm_leg"}},
             "one leg type per vertex"),
    "centre": (_VEC3, "the reference point C of the workload"),
    "independent": ({"type": "array", "minItems": 1, "maxItems": 6, "uniqueItems": True,
                     "items": {"$ref": "#/$defs/param"}}, "the independent pose parameters"),
    "pose": ({"$ref": "#/$defs/pose"}, "default values of the independent parameters (deg)"),
    "home": ({"$ref": "#/$defs/pose"}, "home values (deg) where the legs are built"),
    "guess": ({"$ref": "#/$defs/pose"}, "starting values of the dependent parameters (deg)"),
    "dof": ({"type": "integer", "minimum": 1, "maximum": 6}, "the stated degrees of freedom"),
    "units": ({"$ref": "#/$defs/units"}, "the model's units"),
    "limits": ({"$ref": "#/$defs/limits"}, "joint, stroke and leg-distance limits"),
    "dynamics": ({"$ref": "#/$defs/dynamics"}, "masses, inertias, friction, stiffness"),
    "workload": ({"$ref": "#/$defs/workload"},
                 "the default workload at o (with its units); none: statics need one given"),
}
_SHAPE_TYPES = {
    "shape": {"enum": ["triangle", "square", "rectangle", "circle", "points"]},
    "side": _NUM, "circumradius": _NUM, "radius": _NUM, "start": _NUM, "z": _NUM,
    "sides": {"type": "array", "items": _NUM, "minItems": 2, "maxItems": 2},
    "angles": {"type": "array", "items": _NUM},
    "count": {"type": "integer", "minimum": 1},
    "points": {"type": "array", "minItems": 1, "items": _VEC3},
}
_LEG_TYPES = {
    "name": ({"type": "string", "minLength": 1}, "unique; variants as STRING/variant"),
    "string": (_TEXT, "the leg string, '_' before the actuated joint (RR_PRR)"),
    "summary": (_TEXT, "one line in words"),
    "note": (_TEXT, "a remark"),
    "joints": ({"type": "array", "items": {"$ref": "#/$defs/joint"}},
               "one placement rule per letter of the string"),
    "structure": ({"type": "array", "items": {"$ref": "#/$defs/check"}},
                  "checks that hold wherever the leg is assembled"),
    "placement": ({"type": "object", "propertyNames": {"enum": ["A", "a", "o"]},
                   "additionalProperties": _VEC3}, "default end points"),
    "expect": ({"$ref": "#/$defs/expect"}, "the constraint wrenches the leg must exert"),
    "actuation": (_RULE, "the actuation wrench rule"),
    "used_by": ({"type": "array", "items": _TEXT}, "PMs using this leg"),
    "constraint_basis": ({"type": "array", "items": _RULE},
                         "ordered reference directions of the constraint members"),
}
_JOINT_TYPES = {"axis": _RULE, "at": _RULE, "to": _RULE, "note": _TEXT, "pitch": {"type": "number"},
                "axes": {"type": "array", "minItems": 2, "maxItems": 3, "items": _RULE}}
_EXPECT_TYPES = {"forces": {"type": "integer", "minimum": 0},
                 "couples": {"type": "integer", "minimum": 0},
                 "screws": {"type": "integer", "minimum": 0}, "words": _TEXT,
                 "force_lines": {"type": "array", "items": {"type": "object"}},
                 "couples_along": {"type": "array", "items": _RULE}}


def _props(types: dict, keys) -> dict:
    """``properties`` of the loader's ``keys``; every key must have a type here."""
    missing = set(keys) - set(types)
    if missing:          # a key the loader accepts but the schema does not describe: a bug
        raise RuntimeError(f"the schema has no type for {sorted(missing)}")
    out = {}
    for k in sorted(keys):
        t = types[k]
        if isinstance(t, tuple):
            t, desc = t
            t = {**t, "description": desc}
        out[k] = t
    return out


def _obj(types, keys, required=(), **extra) -> dict:
    return {"type": "object", "properties": _props(types, keys), "additionalProperties": False,
            **({"required": list(required)} if required else {}), **extra}


def model_schema() -> dict:
    """The JSON Schema (draft 2020-12) of catalog and model files, as a dict."""
    from ..legs._rules import _JOINT_KEYS
    from ._catalog import _EXPECT_KEYS, _LEG_KEYS, _TOP_KEYS
    from ._limits import _KEYS as _LIMIT_KEYS
    from ._loader import _PM_KEYS, _PM_LEG_KEYS, _SHAPE_KEYS
    from ._model import PARAMS
    from ._bars import BAR_KEYS
    from ._physical import _BEAM_KEYS, _BLOCK_KEYS, _LEG_KEYS as _DYN_LEG_KEYS, _STIFF_KEYS
    from ._units import FORCE_UNITS, LENGTH_UNITS

    param = {"enum": list(PARAMS)}
    lim_types = {
        "joints": {"type": ["object", "array"], "description": "{JOINT: [min, max]} or one per leg"},
        "actuators": {"type": "array", "description": "[min, max] or one per leg"},
        "extensions": {"type": "array", "description": "[min, max] or one per leg"},
        "min_leg_distance": _NUM,
    }
    num_or_obj = {"type": ["number", "string", "array", "object"]}
    bar = _obj({"mass": (_NUM, "each bar's mass"),
                "com": (_NUM, "fraction of the bar from its near hinge (default 0.5)"),
                "inertia": num_or_obj,
                "width": (_NUM, "the bars at -width/2 and +width/2 from the Pa's bar line"),
                "offsets": ({"type": "array", "items": _NUM, "minItems": 2, "maxItems": 2},
                            "each bar's offset along the Pa's translation direction")},
               BAR_KEYS, required=("mass",))
    dyn_leg_types = {k: {"type": "object"} for k in _DYN_LEG_KEYS}
    dyn_leg_types["bars"] = ({"type": "object", "additionalProperties": bar},
                             "{Pa name: its two bars} (a parallelogram's bars)")
    dyn_leg = _obj(dyn_leg_types, _DYN_LEG_KEYS)
    stiff = _obj({"actuator": _NUM, "force": _NUM, "couple": _NUM,
                  "beam": _obj({k: _NUM for k in _BEAM_KEYS}, _BEAM_KEYS)}, _STIFF_KEYS)
    dyn = _obj({
        "units": {"type": ["object", "string"], "description": "{mass: kg, length: cm, force: N}"
                  " or 'model'"},
        "gravity": _VEC3,
        "platform": {"type": "object", "properties": {"mass": _NUM, "com": _VEC3,
                                                      "inertia": num_or_obj}},
        "legs": {"oneOf": [dyn_leg, {"type": "array", "items": dyn_leg}]},
        "stiffness": {"oneOf": [stiff, {"type": "array", "items": stiff}]},
    }, _BLOCK_KEYS)
    pm_types = dict(_PM_TYPES)
    pm_leg_types = {
        "leg": ({"oneOf": [{"type": "string"}, {"$ref": "#/$defs/leg"}]},
                "a leg type's name, or a leg type written inline (as an entry of legs:)"),
        "axes": ({"type": "object", "propertyNames": {"pattern": "^[RPHUSC][0-9]+[abc]?$"},
                  "additionalProperties": _RULE}, "{JOINT: direction rule} replaced"),
        "passive": ({"type": "boolean"}, "a leg without an actuator (true): it adds its "
                    "constraint wrenches and no actuation row"),
    }
    top_types = {
        "version": ({"type": "integer", "const": 1}, "the file format version"),
        "units": ({"$ref": "#/$defs/units"}, "units of every PM of the file that declares none"),
        "legs": ({"type": "array", "items": {"$ref": "#/$defs/leg"}}, "leg types"),
        "table1": ({"type": "array", "items": {"type": ["string", "array"]}},
                   "the paper's Table I, cell by cell"),
        "pms": ({"type": "object", "additionalProperties": {"$ref": "#/$defs/pm"}},
                "parallel manipulators by name"),
    }
    return {
        "$schema": "https://json-schema.org/draft/2020-12/schema",
        "$id": _ID,
        "title": "screwkit catalog or model file",
        "description": "Leg types (legs:), Table I (table1:) and parallel manipulators (pms:) "
                       "of screwkit (docs/pm_models.md, docs/catalog.md). Generated by "
                       "screwkit.pm.model_schema(); keys starting with 'x-' are free.",
        "type": "object",
        **_obj(top_types, _TOP_KEYS),
        "patternProperties": {"^x-": {}},
        "$defs": {
            "param": param,
            "pose": {"type": "object", "propertyNames": param, "additionalProperties": _NUM},
            "units": {"type": "object", "minProperties": 1, "additionalProperties": False,
                      "properties": {"length": {"enum": list(LENGTH_UNITS)},
                                     "force": {"enum": list(FORCE_UNITS)}}},
            "shape": _obj(_SHAPE_TYPES, _SHAPE_KEYS),
            "pm_leg": {"oneOf": [
                {"type": "string", "description": "a leg type's name"},
                {"type": "object", "required": ["leg"], "additionalProperties": False,
                 "properties": _props(pm_leg_types, _PM_LEG_KEYS)}]},
            "pm": _obj(pm_types, _PM_KEYS,
                       required=("base", "platform", "legs", "independent", "dof")),
            "joint": {"oneOf": [{"type": "null"}, _obj(_JOINT_TYPES, _JOINT_KEYS)]},
            "check": {"type": "object", "minProperties": 1, "maxProperties": 1,
                      "additionalProperties": False,
                      "properties": {k: {"type": "array", "minItems": 2, "maxItems": 2}
                                     for k in ("perpendicular", "parallel", "meets", "through")}},
            "expect": _obj(_EXPECT_TYPES, _EXPECT_KEYS),
            "leg": _obj(_LEG_TYPES, _LEG_KEYS, required=("name", "string", "joints")),
            "limits": _obj(lim_types, _LIMIT_KEYS),
            "dynamics": dyn,
            "workload": {"type": "object", "additionalProperties": False,
                         "anyOf": [{"required": ["force"]}, {"required": ["torque"]}],
                         "required": ["units"],
                         "properties": {
                             "force": {**_VEC3, "description": "at o, base axes"},
                             "torque": {**_VEC3, "description": "at o, base axes"},
                             "units": {"oneOf": [
                                 {"const": "model"},
                                 {"type": "object", "additionalProperties": False,
                                  "required": ["force", "length"],
                                  "properties": {"force": {"type": "string"},
                                                 "length": {"type": "string"}}}],
                                 "description": "{force: kN, length: cm} (torque in "
                                                "force.length) or 'model'"},
                             "source": {"type": "string", "maxLength": 500,
                                        "description": "where the workload comes from"}}},
        },
    }


def schema_text() -> str:
    """The schema as the packaged file holds it (sorted keys, 2-space indent, final newline)."""
    return json.dumps(model_schema(), indent=2, sort_keys=True) + "\n"


def schema_path() -> str:
    """Path of the packaged schema file ``screwkit/pm/model.schema.json``."""
    from pathlib import Path
    return str(Path(__file__).with_name(SCHEMA_FILE))
