"""The model-file JSON Schema, the strict loader's locations, ``screwkit model check`` and
``screwkit catalog PM``.

Independent references: the schema is checked by ``jsonschema`` (a separate
implementation of JSON Schema) against the catalog and every model file under tests/;
the lines an error must name are found by searching the file's text here; the values
``screwkit catalog PM`` must show are read from the catalog YAML with PyYAML.
"""

from __future__ import annotations

import json
import re
from pathlib import Path

import pytest
import yaml

from screwkit.cli import main
from screwkit.errors import CatalogError
from screwkit.pm import catalog_path, check_model_file, model_schema, schema_path, schema_text

ROOT = Path(__file__).resolve().parents[1]
MODELS = [Path(catalog_path()), *sorted((ROOT / "tests").rglob("*.yaml")),
          *sorted((ROOT / "examples").rglob("*.yaml"))]

GOOD = (ROOT / "tests" / "data" / "user_3prs.yaml").read_text(encoding="utf-8")


def _validator():
    jsonschema = pytest.importorskip("jsonschema")
    schema = model_schema()
    jsonschema.Draft202012Validator.check_schema(schema)
    return jsonschema.Draft202012Validator(schema)


def test_packaged_schema_is_current_and_shipped():
    assert Path(schema_path()).read_text(encoding="utf-8") == schema_text(), \
        "screwkit/pm/model.schema.json is stale: screwkit model schema --out screwkit/pm/model.schema.json"
    import importlib.resources
    assert importlib.resources.files("screwkit.pm").joinpath("model.schema.json").is_file()


@pytest.mark.parametrize("path", MODELS, ids=[p.name for p in MODELS])
def test_catalog_and_models_validate(path):
    v = _validator()
    errors = [f"{list(e.absolute_path)}: {e.message}"
              for e in v.iter_errors(yaml.safe_load(path.read_text(encoding="utf-8")))]
    assert not errors, "\n".join(errors)


def test_model_check_passes_the_packaged_catalog(capsys):
    # its file-wide units apply to the PMs that declare none, as the loader applies them
    assert check_model_file(catalog_path()) == []
    assert main(["model", "check", str(catalog_path())]) == 0
    assert "valid" in capsys.readouterr().out


def test_docs_model_blocks_validate():
    """The YAML blocks of the docs that define legs or PMs are valid model files too."""
    v = _validator()
    n = 0
    for page in [ROOT / "README.md", *(ROOT / "docs").glob("*.md")]:
        for m in re.finditer(r"```yaml\n(.*?)```", page.read_text(encoding="utf-8"), re.S):
            if "..." in m.group(1):              # a schematic outline, not a model
                continue
            data = yaml.safe_load(m.group(1))
            if isinstance(data, dict) and ({"pms", "legs"} & set(data)):
                n += 1
                errors = [e.message for e in v.iter_errors(data)]
                assert not errors, f"{page.name}: {errors}"
    assert n >= 1


def test_schema_refuses_what_the_loader_refuses():
    v = _validator()
    data = yaml.safe_load(GOOD)
    assert not list(v.iter_errors(data))
    for path, value in [(("pms", "3PRS", "fraction_x"), 1), (("pms", "3PRS", "dof"), "three"),
                        (("pms", "3PRS", "base", "sidez"), 3), (("legs", 0, "jionts"), [])]:
        bad = yaml.safe_load(GOOD)
        node = bad
        for p in path[:-1]:
            node = node[p]
        node[path[-1]] = value
        assert list(v.iter_errors(bad)), path


def _line_of(text: str, needle: str) -> int:
    return next(i for i, ln in enumerate(text.splitlines(), 1) if needle in ln)


BAD = {   # (edit of the good file, the key, the entry, the field)
    "unknown key": (("    dof: 3\n", "    dof: 3\n    fraction_x: 2\n"), "fraction_x", "3PRS",
                    "fraction_x"),
    "duplicate key": (("    dof: 3\n", "    dof: 3\n    dof: 4\n"), "dof: 4", None, "dof"),
    "wrong type": (("    dof: 3\n", "    dof: three\n"), "dof: three", "3PRS", "dof"),
    "bad rule reference": (("parallel: R2}", "parallel: R7}"), "R7", "PRS/user",
                           "expect.force_lines[0]"),
    "unknown rule key": (("fraction: 0.4", "fractoin: 0.4"), "fractoin", "PRS/user",
                         "joints[1] (R2).at"),
}


@pytest.mark.parametrize("case", BAD, ids=list(BAD))
def test_a_bad_model_names_key_entry_and_line(case, tmp_path):
    (old, new), needle, entry, field = BAD[case]
    text = GOOD.replace(old, new, 1)
    assert text != GOOD
    f = tmp_path / "bad.yaml"
    f.write_text(text, encoding="utf-8")
    line = _line_of(text, needle)
    import screwkit
    with pytest.raises(CatalogError) as ei:
        screwkit.load_pm(str(f))
    msg = str(ei.value)
    assert f"line {line}" in msg, msg
    assert (needle.split(":")[0] if case != "bad rule reference" else "R7") in msg
    if entry:
        assert f"entry {entry!r}" in msg and f"field {field!r}" in msg, msg


def test_model_check_reports_every_problem_at_once(tmp_path, capsys):
    text = GOOD
    for (old, new), *_ in BAD.values():
        if "dof" not in old or "three" in new:
            text = text.replace(old, new, 1)
    text = text.replace("    motion: 1T2R\n", "    motion: 1T2R\n    motion: 2T1R\n")
    text = text.replace("circumradius: r}", "circumradius: r, sidez: 2}")
    f = tmp_path / "bad.yaml"
    f.write_text(text, encoding="utf-8")
    problems = check_model_file(f)
    lines = {p.line for p in problems}
    for needle in ("dof: three", "R7", "fractoin", "motion: 2T1R", "sidez"):
        assert _line_of(text, needle) in lines, (needle, [str(p) for p in problems])
    assert main(["model", "check", str(f)]) == 2
    out = capsys.readouterr().out
    assert out.startswith(f"{f}: {len(problems)} problems")
    assert main(["model", "check", str(f), "--json"]) == 2
    js = json.loads(capsys.readouterr().out)
    assert js["valid"] is False and len(js["problems"]) == len(problems)
    good = tmp_path / "good.yaml"
    good.write_text(GOOD, encoding="utf-8")
    assert check_model_file(good) == []
    assert main(["model", "check", str(good)]) == 0
    assert capsys.readouterr().out.strip() == f"{good}: valid"


def test_model_check_reads_every_part_of_a_dynamics_block(tmp_path, capsys):
    """A ``dynamics:`` block with a bad gravity and a bad platform mass in an otherwise sound
    model: both named, at their lines, and exit 2 (the gravity's check once raised a
    TypeError inside ``model check``: exit 3)."""
    text = "units: {length: m, force: N}\n" + GOOD + (
        "    dynamics:\n      gravity: [0, 0, grav]\n      platform: {mass: -2}\n")
    f = tmp_path / "dyn.yaml"
    f.write_text(text, encoding="utf-8")
    problems = check_model_file(f)
    fields = {p.field for p in problems}
    assert {"dynamics.gravity[2]", "dynamics.platform.mass"} <= fields, [str(p) for p in problems]
    lines = {p.field: p.line for p in problems}
    assert lines["dynamics.gravity[2]"] == _line_of(text, "gravity: [0, 0, grav]")
    assert main(["model", "check", str(f), "--json"]) == 2
    js = json.loads(capsys.readouterr().out)
    assert js["valid"] is False and len(js["problems"]) == len(problems)


def test_model_schema_command(tmp_path, capsys):
    assert main(["model", "schema"]) == 0
    assert json.loads(capsys.readouterr().out) == model_schema()
    out = tmp_path / "sub" / "s.json"
    assert main(["model", "schema", "--out", str(out)]) == 0
    assert out.read_text(encoding="utf-8") == schema_text()


def test_catalog_pm_shows_dimensions_parameters_defaults_units(capsys):
    raw = yaml.safe_load(Path(catalog_path()).read_text(encoding="utf-8"))["pms"]["3RRPRR"]
    assert main(["catalog", "3RRPRR"]) == 0
    out = capsys.readouterr().out
    for k, v in raw["dimensions"].items():
        assert re.search(rf"^  {k} = {v:g} cm$", out, re.M), out
    for p in raw["independent"]:
        default = raw["pose"][p]
        shown = f"{default:g} deg" if p in ("alpha", "beta", "gamma") else f"{80:g} cm"  # 2*L/3
        assert re.search(rf"^  {p}\s+default {shown}", out, re.M), out
    assert "units: lengths cm, forces kN" in out and "limits:" in out
    assert main(["catalog", "3RRPRR", "--json"]) == 0
    card = json.loads(capsys.readouterr().out)
    assert card["dimensions"]["L"]["value"] == raw["dimensions"]["L"]
    assert [p["name"] for p in card["independent"]] == raw["independent"]
    assert main(["catalog", "NOPE"]) == 2


def test_a_circular_rule_reference_is_named():
    from screwkit.errors import GeometryError
    from screwkit.pm import Catalog

    d = {"name": "RR/c", "string": "R_R",
         "joints": [{"axis": {"parallel": "R2"}, "at": "A"}, {"axis": {"parallel": "R1"}, "at": "a"}]}
    cat = Catalog.from_mapping({"legs": [d]}, "t.yaml")
    with pytest.raises(GeometryError, match=r"R1 refers to 'R2'; R2 refers to 'R1'"):
        cat.legs["RR/c"].build()
    # an unknown joint is refused when the file is read, by name, with the field
    d["joints"][1] = {"axis": {"parallel": "R3"}, "at": "a"}
    with pytest.raises(CatalogError, match=r"field 'joints\[1\] \(R2\)\.axis'.*unknown direction "
                                           r"reference 'R3'"):
        Catalog.from_mapping({"legs": [d]}, "t.yaml")
