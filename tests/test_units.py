"""Units on every printed number: JSON, text, plot labels; conversions to SI through pint.

Independent references: 1 kN = 1000 N and 1 kN.cm = 10 N.m (by hand), the model's declared
units, and what a rotary actuator's effort is (a torque: force x length).
"""

import json

import numpy as np
import pytest

import screwkit
from screwkit.cli import main
from screwkit.errors import CatalogError, InputError

# the paper's workload, stated (only 3RRPRR and 2SPS+2SPR declare it as their default)
PAPER_LOAD = {"force": (-20.0, -30.0, -60.0), "torque": (-30.0, -30.0, 100.0)}
PAPER_ARGS = ["--force=-20,-30,-60", "--torque=-30,-30,100"]


def _json(capsys, *argv):
    assert main(list(argv) + ["--json"]) == 0
    return json.loads(capsys.readouterr().out)


def test_linear_actuators_in_kn(capsys):
    d = _json(capsys, "analyze", "3RRPRR")
    assert d["units"]["length"] == "cm" and d["units"]["force"] == "kN"
    assert d["units"]["torque"] == "kN.cm" and d["units"]["declared"]
    for leg in d["legs"]:
        assert leg["active_unit"] == "kN" and leg["actuation"]["effort"] == "force"
        assert all(c["unit"] == "kN" for c in leg["constraints"])
        assert leg["torque_unit"] == "kN.cm" and "about its axis" in leg["torque_name"]
    assert d["workload"]["force_unit"] == "kN" and d["workload"]["torque_unit"] == "kN.cm"
    assert d["statics"]["units"] == ["kN"] * 6


def test_rotary_actuators_are_torques(capsys):
    d = _json(capsys, "analyze", "3RSR", *PAPER_ARGS)
    for leg in d["legs"]:
        assert leg["active_unit"] == "kN.cm" and leg["actuation"]["effort"] == "torque"
        assert "torque" not in leg                 # T_r is defined for linear legs only
    assert d["statics"]["units"][:3] == ["kN.cm"] * 3
    assert d["statics"]["T_r"] == [None, None, None]
    assert main(["analyze", "3RSR", *PAPER_ARGS]) == 0
    text = capsys.readouterr().out
    active = [ln for ln in text.splitlines() if " active " in ln]
    assert len(active) == 3 and all(" kN.cm " in ln for ln in active)


def test_constraint_couples_are_torques(capsys):
    d = _json(capsys, "analyze", "3UPU", *PAPER_ARGS)
    units = [c["unit"] for leg in d["legs"] for c in leg["constraints"]]
    kinds = [c["kind"] for leg in d["legs"] for c in leg["constraints"]]
    assert kinds == ["couple"] * 3 and units == ["kN.cm"] * 3


def test_si_conversion(capsys):
    model = _json(capsys, "analyze", "3RSR", *PAPER_ARGS)
    assert main(["analyze", "3RSR", "--json", "--units", "SI", *PAPER_ARGS]) == 0
    si = json.loads(capsys.readouterr().out)
    assert si["units"]["length"] == "m" and si["units"]["torque"] == "N.m"
    np.testing.assert_allclose(si["statics"]["active"], np.array(model["statics"]["active"]) * 10,
                               rtol=1e-12)               # kN.cm -> N.m
    np.testing.assert_allclose(si["statics"]["constraint"],
                               np.array(model["statics"]["constraint"]) * 1000, rtol=1e-12)
    np.testing.assert_allclose(si["extensions"], np.array(model["extensions"]) / 100, rtol=1e-12)
    assert si["pose"]["alpha"] == pytest.approx(model["pose"]["alpha"])      # degrees stay
    # the text report converts too (its values: tests/test_units_si_text.py)
    assert main(["analyze", "3RSR", "--units", "SI", *PAPER_ARGS]) == 0
    assert "units: lengths m, forces N, torques N.m" in capsys.readouterr().out


def test_text_carries_units(capsys):
    assert main(["analyze", "3RRPRR"]) == 0
    text = capsys.readouterr().out
    assert "units: lengths cm, forces kN, torques kN.cm" in text
    assert "extensions r_i (cm)" in text and "T_ri" in text and "(kN.cm)" in text


def test_plot_labels_carry_units(tmp_path):
    pytest.importorskip("matplotlib")
    from screwkit.paths import path_from_expressions, run_trajectory
    pm = screwkit.load_pm("3RSR")
    path = path_from_expressions(["alpha=2*sin(2*pi*t)", "beta=-1", "Zo=40"], pm.independent,
                                 samples=9)
    fig = run_trajectory(pm, path, **PAPER_LOAD).plot(tmp_path / "rsr.png")
    labels = [ax.get_ylabel() for ax in fig.axes]
    assert any("F_{ai}" in lab and "kN·cm" in lab for lab in labels), labels
    assert any("cm" in lab and "length" in lab for lab in labels)


def test_drawing_labels_rotary_torques(tmp_path):
    pytest.importorskip("matplotlib")
    from screwkit.engine import wrench_rows
    from screwkit.viz import draw_pm
    res = screwkit.analyze("3RSR", **PAPER_LOAD)
    sol = res.solution
    rows, _ = wrench_rows(res)
    u = res.model.units
    fig = draw_pm(sol.legs, sol.base_points, sol.platform_points, sol.position, rows,
                  out=tmp_path / "d.png", force_unit=u.force, torque_unit="kN·cm",
                  length_unit=u.length)
    texts = [t.get_text() for ax in fig.axes for t in ax.texts]
    act = [t for t in texts if t.startswith("$T_{a")]
    assert len(act) == 3 and all(t.endswith("kN·cm") for t in act), texts


def test_undeclared_and_bad_units(tmp_path, capsys):
    pm = screwkit.load_pm(str(__import__("pathlib").Path(__file__).parent / "data" /
                              "user_pm.yaml"))
    assert not pm.units.declared and pm.units.length == "[L]"   # a dimension, not a placeholder
    res = screwkit.analyze(pm, **PAPER_LOAD)
    with pytest.raises(InputError, match="declares no units"):
        res.to_dict("SI")
    text = (__import__("pathlib").Path(__file__).parent / "data" / "user_pm.yaml").read_text()
    bad = tmp_path / "bad.yaml"
    bad.write_text("units: {length: furlong, force: kN}\n" + text)
    with pytest.raises(CatalogError, match="units.length"):
        screwkit.load_pm(str(bad))


def test_trajectory_in_si_by_hand_factors_and_on_its_plot(tmp_path):
    """``in_units("SI")``: cm -> m is 0.01, kN -> N is 1000, kN.cm -> N.m is 10 (by hand);
    the SI CSV (its own conversion) and the plot's labels agree."""
    pytest.importorskip("matplotlib")
    pytest.importorskip("pint")
    from screwkit.paths import path_from_expressions, run_trajectory
    pm = screwkit.load_pm("3RRPRR")
    path = path_from_expressions(["alpha=4*sin(2*pi*t)", "beta=2", "Zo=70+20*t"],
                                 pm.independent, samples=11)
    res = run_trajectory(pm, path, **PAPER_LOAD)
    si = res.in_units("SI")
    assert res.in_units() is res
    np.testing.assert_allclose(si.extensions, 0.01 * res.extensions, rtol=1e-12)
    np.testing.assert_allclose(si.params["Zo"], 0.01 * res.params["Zo"], rtol=1e-12)
    np.testing.assert_allclose(si.params["alpha"], res.params["alpha"], rtol=0)
    np.testing.assert_allclose(si.active, 1000.0 * res.active, rtol=1e-12)
    np.testing.assert_allclose(si.constraint, 1000.0 * res.constraint, rtol=1e-12)
    np.testing.assert_allclose(si.T_r, 10.0 * res.T_r, rtol=1e-12)
    np.testing.assert_allclose(si.leg_wrenches[..., :3], 1000.0 * res.leg_wrenches[..., :3])
    np.testing.assert_allclose(si.leg_wrenches[..., 3:], 10.0 * res.leg_wrenches[..., 3:])
    np.testing.assert_allclose(si.force, 1000.0 * res.force)
    csv_si = {c: v for c, v, _ in res.columns_with_units("SI")}
    for c, v, _ in si.columns_with_units():
        np.testing.assert_allclose(v, csv_si[c], rtol=1e-12, err_msg=c)
    fig = si.plot(tmp_path / "si.png")
    labels = [ax.get_ylabel() for ax in fig.axes]
    assert any("F_{ai}" in lab and "[N]" in lab for lab in labels), labels
    assert any("[m]" in lab for lab in labels) and not any("cm" in lab for lab in labels)


def test_cli_trajectory_plot_in_si(tmp_path, capsys):
    pytest.importorskip("matplotlib")
    pytest.importorskip("pint")
    from screwkit.cli import main
    argv = ["trajectory", "3RRPRR", "--expr", "alpha=3*t", "--expr", "beta=1",
            "--expr", "Zo=80", "--samples", "5", "--units", "SI", "-q",
            "--out", str(tmp_path / "t.csv"), "--plot", str(tmp_path / "t.png")]
    assert main(argv) == 0 and (tmp_path / "t.png").stat().st_size > 0
    assert main(argv + ["--length-unit", "mm"]) == 2
    assert "not with --units SI" in capsys.readouterr().err


def test_cli_unit_labels_name_units_they_do_not_convert(tmp_path, capsys):
    # --length-unit / --force-unit label the plot of a model that declares no units: a unit
    # screwkit knows, and never another than a declared one (the values are not converted)
    pytest.importorskip("matplotlib")
    from screwkit.cli import main
    draw = ["draw", "3RRPRR", "-o", str(tmp_path / "d.png")]
    assert main(draw + ["--length-unit", "furlong"]) == 2
    assert "not a unit screwkit knows" in capsys.readouterr().err
    assert main(draw + ["--force-unit", "lbf"]) == 2          # 3RRPRR declares kN
    assert "declares its units (kN)" in capsys.readouterr().err
    assert main(draw + ["--length-unit", "cm", "--force-unit", "kN"]) == 0
    traj = ["trajectory", "3RRPRR", "--expr", "alpha=3*t", "--expr", "beta=1", "--expr",
            "Zo=80", "--samples", "3", "-q", "--out", str(tmp_path / "t.csv")]
    assert main(traj + ["--length-unit", "mm"]) == 2
    assert "declares its units (cm)" in capsys.readouterr().err
