"""Malformed catalogs: every error is a CatalogError naming the entry and the field."""

from __future__ import annotations

import copy

import pytest
import yaml

from screwkit.cli import main
from screwkit.errors import CatalogError
from screwkit.pm import Catalog, load_catalog

GOOD = {
    "name": "MySPR",
    "string": "S_PR",
    "summary": "a test leg",
    "used_by": ["3SPR"],
    "joints": [{"at": "A"}, {"axis": "leg"}, {"axis": "platform.tangent", "at": "a"}],
    "structure": [{"perpendicular": ["R3", "leg"]}],
    "expect": {"forces": 1, "couples": 0, "words": "one force",
               "force_lines": [{"through": "S1", "parallel": "R3"}]},
}


def leg(**changes):
    d = copy.deepcopy(GOOD)
    for k, v in changes.items():
        if v is None:
            d.pop(k)
        else:
            d[k] = v
    return d


def load(*legs):
    return Catalog.from_mapping({"version": 1, "legs": list(legs)}, "test.yaml")


def test_good_entry_loads_and_meets_its_expectation():
    cat = load(leg())
    spec = cat.legs["MySPR"]
    assert spec.check_expectation(spec.build().analyze()) == []


@pytest.mark.parametrize("changes, entry, field", [
    ({"joints": None}, "MySPR", "joints"),                                  # missing field
    ({"string": None}, "MySPR", "string"),
    ({"string": "S_QR"}, "MySPR", "string"),                                # unknown joint letter
    ({"string": 7}, "MySPR", "string"),
    ({"joints": [{"at": "A"}, {"axis": "leg"}]}, "MySPR", "joints"),        # wrong number
    ({"joints": "S at A"}, "MySPR", "joints"),
    ({"joints": [{"at": "A"}, "leg", {"axis": "leg", "at": "a"}]}, "MySPR", "joints[1] (P2)"),
    ({"joints": [{"at": "A"}, {"axis": "leg"}, {"at": "a"}]}, "MySPR", "joints[2] (R3)"),
    ({"joints": [{"at": "A"}, {"axis": "leg", "colour": 1}, {"axis": "leg", "at": "a"}]},
     "MySPR", "joints[1] (P2)"),
    ({"structure": [{"orthogonal": ["R3", "leg"]}]}, "MySPR", "structure[0]"),   # bad checks
    ({"structure": [{"perpendicular": ["R3"]}]}, "MySPR", "structure[0]"),
    ({"structure": [{"parallel": ["R3", "leg"]}, {"meets": ["R3", "R9"]}]}, "MySPR", "structure[1]"),
    ({"structure": "R3 perpendicular to the leg"}, "MySPR", "structure"),
    ({"expect": {"forces": "one"}}, "MySPR", "expect.forces"),
    ({"expect": {"forces": True}}, "MySPR", "expect.forces"),
    ({"expect": {"forces": 1, "force_lines": [{"through": "S1"}]}}, "MySPR",
     "expect.force_lines[0]"),
    ({"expect": {"torques": 1}}, "MySPR", "expect"),
    ({"used_by": "3SPR"}, "MySPR", "used_by"),
    ({"placement": {"A": [1, 0, 0]}}, "MySPR", "placement"),
    ({"placement": {"A": [1, 0], "a": [0, 0, 1]}}, "MySPR", "placement.A"),
    ({"colour": "red"}, "MySPR", "colour"),
])
def test_malformed_entry_names_entry_and_field(changes, entry, field):
    with pytest.raises(CatalogError) as ei:
        load(leg(**changes))
    err = ei.value
    assert (err.entry, err.field) == (entry, field)
    msg = str(err)
    assert f"entry {entry!r}" in msg and f"field {field!r}" in msg and "test.yaml" in msg


def test_missing_name_is_located_by_index():
    with pytest.raises(CatalogError) as ei:
        load(leg(), leg(name=None))
    assert ei.value.entry == "legs[1]" and ei.value.field == "name"
    assert "legs[1]" in str(ei.value) and "'name'" in str(ei.value)


@pytest.mark.parametrize("bad", ["S_PR", ["S", "P", "R"], 3])
def test_non_mapping_entry(bad):
    with pytest.raises(CatalogError) as ei:
        load(leg(), bad)
    assert ei.value.entry == "legs[1]"
    assert "legs[1]" in str(ei.value) and "mapping" in str(ei.value)


@pytest.mark.parametrize("data, field", [(["legs"], None), ({"legs": {"SPR": {}}}, "legs")])
def test_non_mapping_catalog_or_legs(data, field):
    with pytest.raises(CatalogError) as ei:
        Catalog.from_mapping(data, "test.yaml")
    assert ei.value.field == field and "test.yaml" in str(ei.value)


def test_duplicate_name():
    with pytest.raises(CatalogError) as ei:
        load(leg(), leg(string="S_P", joints=[{"at": "A"}, {"axis": "leg"}], structure=[],
                        expect={}))
    assert (ei.value.entry, ei.value.field) == ("MySPR", "name")
    assert "duplicate" in str(ei.value)


def test_bad_yaml_file_names_file_and_line(tmp_path):
    p = tmp_path / "bad.yaml"
    p.write_text("legs:\n  - name: X\n    string: [S_PR\n", encoding="utf-8")
    with pytest.raises(CatalogError) as ei:
        load_catalog(p)
    msg = str(ei.value)
    assert str(p) in msg and "invalid YAML" in msg and "line" in msg


def test_missing_file(tmp_path):
    with pytest.raises(CatalogError) as ei:
        load_catalog(tmp_path / "nowhere.yaml")
    assert "nowhere.yaml" in str(ei.value)


def test_yaml_file_round_trip_names_entry_and_field(tmp_path):
    p = tmp_path / "model.yaml"
    p.write_text(yaml.safe_dump({"legs": [leg(string="S_PX")]}), encoding="utf-8")
    with pytest.raises(CatalogError) as ei:
        load_catalog(p)
    msg = str(ei.value)
    assert str(p) in msg and "'MySPR'" in msg and "'string'" in msg and "'X'" in msg


# ---------------------------------------------------------------- the CLI

@pytest.mark.parametrize("content", [
    "legs:\n  - name: X\n    string: [S_PR\n",                                   # bad YAML
    yaml.safe_dump({"legs": [leg(joints=None)]}),                                # missing field
    yaml.safe_dump({"legs": [leg(string="S_QR")]}),                              # bad letter
    yaml.safe_dump({"legs": [leg(structure=[{"perpendicular": ["R3"]}])]}),      # bad check
    yaml.safe_dump({"legs": [leg(), leg()]}),                                    # duplicate
    yaml.safe_dump(["not", "a", "mapping"]),                                     # non-mapping
])
def test_cli_bad_model_one_line_exit_2(tmp_path, capsys, content):
    p = tmp_path / "bad.yaml"
    p.write_text(content, encoding="utf-8")
    rc = main(["leg", "SPR", "--model", str(p)])
    out, err = capsys.readouterr()
    assert rc == 2
    assert out == ""
    lines = err.strip().splitlines()
    assert len(lines) == 1, err
    assert lines[0].startswith("screwkit leg: error:") and "bad.yaml" in lines[0]
    assert "Traceback" not in err


def test_cli_good_model_adds_a_leg(tmp_path, capsys):
    p = tmp_path / "model.yaml"
    p.write_text(yaml.safe_dump({"legs": [leg()]}), encoding="utf-8")
    rc = main(["leg", "MySPR", "--model", str(p)])
    out, err = capsys.readouterr()
    assert rc == 0 and err == ""
    assert "MySPR" in out and "expectation holds" in out
