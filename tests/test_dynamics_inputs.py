"""Inputs of the dynamics: exact derivatives of path expressions (automatic differentiation),
the mass model of the ``dynamics:`` block (units, cylinder and piston, errors), the CLI."""

from __future__ import annotations

import json
import os

import numpy as np
import pytest

import screwkit
from screwkit.dynamics import derivatives, motion_from_expressions
from screwkit.pm import Units, cylinder_body, dynamics_for, parse_expression

T = np.array([0.1, 0.3, 0.7, 1.3])

# expression, f', f'' written by hand
CASES = [
    ("3*t**2 + 2*t - 1", lambda t: 6 * t + 2, lambda t: 6 + 0 * t),
    ("sin(2*t)", lambda t: 2 * np.cos(2 * t), lambda t: -4 * np.sin(2 * t)),
    ("cos(t)**3", lambda t: -3 * np.cos(t) ** 2 * np.sin(t),
     lambda t: 6 * np.cos(t) * np.sin(t) ** 2 - 3 * np.cos(t) ** 3),
    ("tan(t/2)", lambda t: 0.5 / np.cos(t / 2) ** 2,
     lambda t: 0.5 * np.tan(t / 2) / np.cos(t / 2) ** 2),
    ("asin(t/2)", lambda t: 1 / np.sqrt(4 - t ** 2), lambda t: t / (4 - t ** 2) ** 1.5),
    ("acos(t/2)", lambda t: -1 / np.sqrt(4 - t ** 2), lambda t: -t / (4 - t ** 2) ** 1.5),
    ("atan(t)", lambda t: 1 / (1 + t ** 2), lambda t: -2 * t / (1 + t ** 2) ** 2),
    ("sqrt(t)", lambda t: 0.5 / np.sqrt(t), lambda t: -0.25 * t ** -1.5),
    ("exp(-t)*t", lambda t: np.exp(-t) * (1 - t), lambda t: np.exp(-t) * (t - 2)),
    ("log(1+t)", lambda t: 1 / (1 + t), lambda t: -1 / (1 + t) ** 2),
    ("t/(1+t)", lambda t: 1 / (1 + t) ** 2, lambda t: -2 / (1 + t) ** 3),
    ("t**t", lambda t: t ** t * (np.log(t) + 1),
     lambda t: t ** t * ((np.log(t) + 1) ** 2 + 1 / t)),
    ("atan2(t, 2)", lambda t: 2 / (4 + t ** 2), lambda t: -4 * t / (4 + t ** 2) ** 2),
    ("abs(t-0.5)", lambda t: np.sign(t - 0.5), lambda t: 0 * t),
    ("max(t, 0.5, t**2)", lambda t: np.where(t > 1, 2 * t, np.where(t > 0.5, 1, 0)),
     lambda t: np.where(t > 1, 2.0, 0.0)),
    ("-min(t, 2*pi*e)", lambda t: -1 + 0 * t, lambda t: 0 * t),
]


@pytest.mark.parametrize("text, d1, d2", CASES, ids=[c[0] for c in CASES])
def test_jets_against_hand_derivatives(text, d1, d2):
    f, g1, g2 = derivatives(parse_expression(text), T)
    assert np.allclose(f, parse_expression(text)(T), rtol=1e-14, atol=0)
    assert np.allclose(g1, d1(T), rtol=1e-13, atol=1e-14)
    assert np.allclose(g2, d2(T), rtol=1e-12, atol=1e-13)


def test_jets_against_the_complex_step():
    """A second method for the first derivative: the complex step (exact to rounding)."""
    text = "10*sin(2*pi*t+1)*exp(-t/3) + sqrt(4+t**2)/(2+cos(t))"
    h = 1e-30
    z = np.sin(2 * np.pi * (T + 1j * h) + 1) * 10 * np.exp(-(T + 1j * h) / 3) + \
        np.sqrt(4 + (T + 1j * h) ** 2) / (2 + np.cos(T + 1j * h))
    _, g1, g2 = derivatives(parse_expression(text), T)
    assert np.allclose(g1, z.imag / h, rtol=1e-13)
    e = 1e-4
    _, a, _ = derivatives(parse_expression(text), T + e)
    _, b, _ = derivatives(parse_expression(text), T - e)
    assert np.allclose(g2, (a - b) / (2 * e), rtol=1e-6)


def test_jet_errors():
    with pytest.raises(screwkit.InputError, match="derivative is not finite"):
        derivatives(parse_expression("sqrt(t)"), np.array([0.0, 1.0]))
    # the power rule at 0 with integer exponents is finite
    f, g1, g2 = derivatives(parse_expression("t**1 + t**2 + t**0"), np.array([0.0]))
    assert (f[0], g1[0], g2[0]) == (1.0, 1.0, 2.0)


def test_motion_in_degrees_is_converted_to_radians():
    m = motion_from_expressions(["alpha=10*t**2", "beta=0", "Zo=80+3*t"],
                                ("alpha", "beta", "Zo"), samples=3, t_range=(0, 2))
    assert np.allclose(m.accelerations["alpha"], np.radians(20))
    assert np.allclose(m.rates["Zo"], 3) and np.allclose(m.rates["beta"], 0)
    assert "automatic differentiation" in m.method


def test_units_factors():
    u = Units("cm", "kN")
    assert u.factor("kg", "mass") == pytest.approx(1e-5)          # 1 kN.s^2/cm = 1e5 kg
    assert u.factor("m", "length") == pytest.approx(100)
    assert u.factor("N", "force") == pytest.approx(1e-3)
    assert u.of("mass") == "kN.s^2/cm"
    assert Units("mm", "N").factor("kg", "mass") == pytest.approx(1e-3)
    with pytest.raises(screwkit.InputError, match="cannot convert"):
        u.factor("kg", "length")


def test_mass_block_conversion_and_defaults():
    pm = screwkit.load_pm("3RPS")
    p = dynamics_for(pm, {"units": {"mass": "kg", "length": "m", "force": "N"},
                          "gravity": [0, 0, -9.81],
                          "platform": {"mass": 10, "com": [0.01, 0, 0.02], "inertia": [1, 2, 2.5]},
                          "legs": {"cylinder": {"mass": 3, "length": 0.4, "radius": 0.03},
                                   "piston": {"mass": 2, "length": 0.4}}})
    assert p.gravity == pytest.approx([0, 0, -981.0])
    assert p.platform.mass == pytest.approx(1e-4)
    assert p.platform.com == pytest.approx([1.0, 0, 2.0])
    assert np.diag(p.platform.inertia) == pytest.approx([0.1, 0.2, 0.25])   # kg.m^2 -> 0.1
    leg = pm.home_legs[0]
    d = (leg.a - leg.A) / np.linalg.norm(leg.a - leg.A)
    (s_c, cyl), (s_p, pis) = p.legs[0].links
    assert (s_c, s_p) == (0, 1)                # after R1 (the cylinder), after P2 (the piston)
    assert cyl.com == pytest.approx(leg.A + 20 * d) and pis.com == pytest.approx(leg.a - 20 * d)
    m, r, ln = 3e-5, 3.0, 40.0
    assert d @ cyl.inertia @ d == pytest.approx(m * r ** 2 / 2)
    e = np.cross(d, [0, 0, 1.0])
    e /= np.linalg.norm(e)
    assert e @ cyl.inertia @ e == pytest.approx(m * (3 * r ** 2 + ln ** 2) / 12)
    q = dynamics_for(pm, {"platform": {"mass": 10}})
    assert q.gravity == pytest.approx([0, 0, -980.665]) and "standard gravity" in q.notes[1]
    assert q.massless_legs and q.total_mass() == pytest.approx(1e-4)


def test_cylinder_body_formula():
    b = cylinder_body(2.0, [0, 0, 0], [0, 0, 1], length=0.5, radius=0.1, inner_radius=0.05)
    assert np.diag(b.inertia) == pytest.approx([2 * (3 * 0.0125 + 0.25) / 12] * 2
                                               + [2 * 0.0125 / 2])


@pytest.mark.parametrize("block, field", [
    ({"platform": {"mass": -1}}, "dynamics.platform.mass"),
    ({"platform": {"mass": 1, "inertia": [1, 1, 3]}}, "dynamics.platform.inertia"),
    ({"platform": {"mass": 1, "inertai": [1, 1, 1]}}, "dynamics.platform"),
    ({"legs": {"links": {"R9": {"mass": 1}}}}, "dynamics.legs.links"),
    ({"legs": {"links": {"S3": {"mass": 1}}}}, "dynamics.legs.links.S3"),
    ({"legs": [{}, {}]}, "dynamics.legs"),
    ({"units": {"mass": "kilo"}}, "dynamics.units"),
    ({"stiffness": {"actuator": 0}}, "dynamics.stiffness.actuator"),
    ({"stiffness": {"beam": {"E": 1}}}, "dynamics.stiffness.beam"),
    ({"gravity": [0, 0]}, "dynamics.gravity"),
    ({"legs": {"friction": {"Q1": {"viscous": 1}}}}, "dynamics.legs.friction"),
])
def test_mass_block_errors_name_the_field(block, field):
    pm = screwkit.load_pm("3RPS")
    with pytest.raises(screwkit.CatalogError) as exc:
        dynamics_for(pm, block)
    assert exc.value.field == field


def test_cylinder_needs_a_linear_actuator_along_the_leg():
    pm = screwkit.load_pm("3RSR")
    with pytest.raises(screwkit.CatalogError, match="actuated P joint along the leg line"):
        dynamics_for(pm, {"legs": {"cylinder": {"mass": 1, "length": 10}}})


def test_the_loader_reads_the_dynamics_block(tmp_path):
    from pathlib import Path
    pm = screwkit.load_pm(str(Path(__file__).parent / "data" / "stewart_6sps.yaml"))
    assert pm.dynamics is not None and len(pm.dynamics.legs) == 6
    assert pm.dynamics.legs[0].stiffness.actuator == pytest.approx(2e3)
    assert screwkit.load_pm("3RRPRR").dynamics is None


def test_trajectory_dynamics_cli(tmp_path, capsys):
    from screwkit.cli import main
    mass = tmp_path / "mass.yaml"
    mass.write_text("dynamics:\n  platform: {mass: 40}\n  legs:\n"
                    "    cylinder: {mass: 4, length: 50, radius: 4}\n"
                    "    piston: {mass: 2, length: 50, radius: 2}\n")
    png = tmp_path / "dyn.png"
    args = ["trajectory", "3RRPRR", "--expr", "alpha=8*sin(2*pi*t)", "--expr", "beta=5",
            "--expr", "Zo=80+10*t", "--samples", "21", "--dynamics", "--mass", str(mass)]
    assert main(args + ["--plot", str(png)]) == 0
    cap = capsys.readouterr()
    out = cap.out.splitlines()
    # the block declares no units: the ones taken are said (kg, the model's cm, N)
    assert "converted from kg, cm, N, s to kN.s^2/cm, cm, kN, s" in cap.err
    assert "standard gravity" in cap.err
    assert len(out) == 22 and "F_a1_dyn [kN]" in out[0] and "F_a1 [kN]" in out[0]
    assert png.stat().st_size > 10000
    assert main(args + ["--format", "json"]) == 0
    d = json.loads(capsys.readouterr().out)
    assert d["columns"]["F_a1_dyn"]["unit"] == "kN" and d["units"]["time"] == "s"
    assert main(args[:-2]) == 2                       # no masses: one line, exit 2
    assert "declares no masses" in capsys.readouterr().err


def test_the_dynamics_table_says_which_workload_it_carries(tmp_path, capsys):
    """The --dynamics CSV ends with the workload at o (as the static table does), in the
    model's units: the paper's declared load here, the given one with --force."""
    import csv
    import io

    from screwkit.cli import main
    mass = tmp_path / "mass.yaml"
    mass.write_text("dynamics:\n  platform: {mass: 40}\n")
    base = ["trajectory", "3RRPRR", "--expr", "alpha=8*sin(2*pi*t)", "--expr", "beta=8",
            "--expr", "Zo=80", "--samples", "3", "--t-range", "0", "0.5", "--dynamics",
            "--mass", str(mass)]
    for extra, load in (([], [-20, -30, -60, -30, -30, 100]),
                        (["--force", "0,0,-1"], [0, 0, -1, 0, 0, 0])):
        assert main(base + extra) == 0
        rows = list(csv.reader(io.StringIO(capsys.readouterr().out)))
        names = [h.split(" [")[0] for h in rows[0]]
        cols = [names.index(f"workload_{c}") for c in ("Fx", "Fy", "Fz", "Tx", "Ty", "Tz")]
        assert rows[0][cols[0]] == "workload_Fx [kN]" and rows[0][cols[3]] == "workload_Tx [kN.cm]"
        for r in rows[1:]:
            assert [float(r[c]) for c in cols] == load


def test_a_power_with_a_variable_exponent_has_its_value_where_only_a_rate_fails():
    """``0**t`` at t = 0 is 1 (its rate is what is not finite there: the message says the
    derivative, not the value); ``2**t`` has the rates ln 2 2^t and ln^2 2 2^t."""
    from screwkit.errors import InputError
    with pytest.raises(InputError, match="its first derivative is not finite at t = 0"):
        derivatives(parse_expression("0**t"), np.array([0.0]))
    t = np.array([0.0, 0.5, 1.0])
    f, d1, d2 = derivatives(parse_expression("2**t"), t)
    np.testing.assert_allclose(f, 2.0 ** t, rtol=1e-15)
    np.testing.assert_allclose(d1, np.log(2.0) * 2.0 ** t, rtol=1e-14)
    np.testing.assert_allclose(d2, np.log(2.0) ** 2 * 2.0 ** t, rtol=1e-14)


def test_zero_to_a_positive_variable_power_is_zero_with_zero_rates():
    """``0**t`` is identically 0 for t > 0 (so are its rates); ``0.5**(2*t)`` = 4^-t has the
    rates -2 ln 2 4^-t and 4 ln^2 2 4^-t (by hand)."""
    t = np.array([0.25, 1.0, 3.0])
    for x in derivatives(parse_expression("0**t"), t):
        assert np.array_equal(x, np.zeros(3))
    f, d1, d2 = derivatives(parse_expression("0.5**(2*t)"), t)
    np.testing.assert_allclose(f, 4.0 ** -t, rtol=1e-15)
    np.testing.assert_allclose(d1, -2.0 * np.log(2.0) * 4.0 ** -t, rtol=1e-14)
    np.testing.assert_allclose(d2, 4.0 * np.log(2.0) ** 2 * 4.0 ** -t, rtol=1e-14)


@pytest.mark.skipif(not os.path.exists("/dev/zero"), reason="no /dev/zero")
def test_a_mass_file_is_read_bounded(tmp_path, capsys):
    """``--mass /dev/zero`` read without limit (out of memory, or exit 3): a mass file is
    read as a model file is, at most 1 MiB, one line and exit 2 beyond."""
    from screwkit.cli import main
    for cmd in (["export", "3RRPRR", "--mjcf", str(tmp_path / "a.xml")],
                ["trajectory", "3RPS", "--dynamics", "--force", "0,0,0", "--expr", "alpha=t",
                 "--expr", "beta=0", "--expr", "Zo=60", "--samples", "3"]):
        assert main(cmd + ["--mass", "/dev/zero"]) == 2
        err = capsys.readouterr().err.strip().splitlines()
        assert len(err) == 1 and "larger than 1 MiB" in err[0]


def test_near_singular_samples_are_not_said_to_be_nan(tmp_path, capsys):
    """A near-singular sample's dynamic efforts are computed (large): the note said their
    values were NaN, as for singular or unreachable ones."""
    import csv
    import io

    from screwkit.cli import main
    mass = tmp_path / "m.yaml"
    mass.write_text("dynamics:\n  platform: {mass: 2}\n", encoding="utf-8")
    assert main(["trajectory", "3RPS", "--dynamics", "--force", "0,0,0", "--expr", "alpha=0",
                 "--expr", "beta=0", "--expr", "Zo=60+1e6*t", "--samples", "5", "--mass",
                 str(mass)]) == 0
    out, err = capsys.readouterr()
    rows = list(csv.reader(io.StringIO(out)))
    status = [h.split(" [")[0] for h in rows[0]].index("status")
    col = [h.split(" [")[0] for h in rows[0]].index("F_a1_dyn")
    near = [r for r in rows[1:] if r[status] == "near-singular"]
    assert near and all(np.isfinite(float(r[col])) for r in near)
    line = [x for x in err.splitlines() if "near-singular" in x]
    assert line and "NaN" not in line[0] and "large and sensitive" in line[0]


def test_dynamics_table_in_si_by_hand_factors(tmp_path, capsys):
    """``trajectory --dynamics --units SI`` was refused. The catalog's 3-RPS is in cm and kN:
    by hand 1 cm = 0.01 m, 1 kN = 1000 N, 1 kN.cm = 10 N.m (an energy: J), 1 kN.s^2/cm =
    1e5 kg; every column of the SI JSON is the model-unit one times its factor."""
    from screwkit.cli import main
    mass = tmp_path / "m.yaml"
    mass.write_text("dynamics:\n  units: {mass: kg, length: cm, force: N}\n"
                    "  platform: {mass: 3}\n", encoding="utf-8")
    base = ["trajectory", "3RPS", "--dynamics", "--force", "0,0,-1", "--torque", "2,0,0",
            "--expr", "alpha=5*t", "--expr", "beta=-3*t", "--expr", "Zo=60+10*t",
            "--samples", "6", "--mass", str(mass), "--format", "json"]
    out = []
    for extra in ([], ["--units", "SI"]):
        assert main(base + extra) == 0
        out.append(json.loads(capsys.readouterr().out))
    m, si = out
    k = {"kN": (1000.0, "N"), "cm": (0.01, "m"), "kN.cm": (10.0, "N.m"),
         "cm/s": (0.01, "m/s"), "cm/s^2": (0.01, "m/s^2"), "kN.cm/s": (10.0, "N.m/s"),
         "s": (1.0, "s"), "deg": (1.0, "deg"), "rad/s": (1.0, "rad/s"),
         "rad/s^2": (1.0, "rad/s^2")}
    assert set(si["columns"]) == set(m["columns"])
    for name, col in m["columns"].items():
        f, unit = k[col["unit"]]
        assert si["columns"][name]["unit"] == unit, name
        a = np.array(col["values"], float)
        b = np.array(si["columns"][name]["values"], float)
        np.testing.assert_allclose(b, f * a, rtol=1e-12, atol=1e-300, err_msg=name)
    assert m["units"]["mass"] == "kN.s^2/cm" and si["units"]["mass"] == "N.s^2/m"
    assert si["workload"]["force"] == [0, 0, -1000.0] and si["workload"]["torque_unit"] == "N.m"
