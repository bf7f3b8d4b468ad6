"""One machine written in cm and in mm, and with its base frame moved: dynamics and sizing.

Independent reference: the same 3-RPS (with a dynamics block) written by hand in both length
units (every length x10, torques x10, stiffnesses / 10, viscous friction / 10, gravity
x10) and with its base 10 cm higher; a dimensionless output must be the same number in all
three, a length-bearing one must scale by the factor written here.
"""

from __future__ import annotations

import json

import numpy as np
import pytest

from screwkit.cli import main

RPS = """\
units: {{length: {u}, force: kN}}
pms:
  R3:
    string: 3RPS
    dimensions: {{R: {R}, r: {r}}}
    base: {{shape: triangle, circumradius: R{z}}}
    platform: {{shape: triangle, circumradius: r}}{centre}
    legs: [RPS, RPS, RPS]
    euler: XYZ
    independent: [alpha, beta, Zo]
    home: {{alpha: 0, beta: 0, Zo: R{dz}}}
    pose: {{alpha: 5, beta: -3, Zo: R{dz}}}
    dof: 3
    motion: 1T2R
    workload: {{force: [-2, -3, -6], torque: [{t}], units: model}}
    dynamics:
      units: {{mass: kg, length: {u}, force: N}}
      gravity: [0, 0, {g}]
      platform: {{mass: 30, com: [0, 0, {c}], inertia: {{disc: {{radius: {r}, thickness: {c2}}}}}}}
      legs:
        cylinder: {{mass: 3, length: {l}, radius: {c}, inner_radius: {c}}}
        piston: {{mass: 1.5, length: {l}, radius: {c}}}
        friction: {{P: {{viscous: {visc}, coulomb: 2}}}}
"""


def _model(tmp_path, name, k, moved=False):
    text = RPS.format(u="cm" if k == 1 else "mm", R=60 * k, r=30 * k, l=40 * k, c=2 * k,
                      c2=4 * k, g=-981 * k, visc=30 / k,
                      t=", ".join(str(x * k) for x in (-3, -3, 10)),
                      z=", z: 10" if moved else "", dz="+10" if moved else "",
                      centre="\n    centre: [0, 0, 40]" if moved else "")
    p = tmp_path / f"{name}.yaml"
    p.write_text(text)
    return str(p)


def _trajectory(tmp_path, capsys, model, zo):
    out = tmp_path / (model.rsplit("/", 1)[-1] + ".json")
    assert main(["trajectory", "--model", model, "--expr", "alpha=8*sin(2*pi*t)",
                 "--expr", "beta=6*sin(4*pi*t)", "--expr", f"Zo={zo}", "--samples", "21",
                 "--format", "json", "-q", "--dynamics", "--out", str(out)]) == 0
    capsys.readouterr()
    return json.loads(out.read_text())


def _find(d, key):
    if isinstance(d, dict):
        for k, v in d.items():
            if k == key:
                return v
            got = _find(v, key)
            if got is not None:
                return got
    return None


def test_the_kinematic_condition_is_the_same_in_cm_in_mm_and_with_the_base_moved(tmp_path,
                                                                                   capsys):
    """``residuals.kinematic_condition`` (the dependent rates' system, dimensionless) was
    1.00168768 in cm and 1.00169005 in mm: its rows and columns were equilibrated by norms
    that mix forces and torques. It now reads the same in both units and with the base 10 cm
    higher, and the rest of the dynamics scales by the factors written here."""
    cm = _trajectory(tmp_path, capsys, _model(tmp_path, "cm", 1), "55+10*t")
    mm = _trajectory(tmp_path, capsys, _model(tmp_path, "mm", 10), "550+100*t")
    up = _trajectory(tmp_path, capsys, _model(tmp_path, "up", 1, moved=True), "65+10*t")
    kc = [np.asarray(_find(d, "kinematic_condition"), float) for d in (cm, mm, up)]
    assert kc[0].shape == (21,) and np.all(kc[0] >= 1.0) and kc[0].max() > 1.001
    assert np.allclose(kc[1], kc[0], rtol=1e-12) and np.allclose(kc[2], kc[0], rtol=1e-12)


def test_a_structurally_zero_t_r_reads_zero_in_every_unit(tmp_path, capsys):
    """An RPS leg's ``T_r`` (the moment of its constraint wrench about its own axis) is zero
    by its structure: ``size`` printed it as 0 in cm and as 2.8e-12 kN.mm, at some pose, in
    mm. It is now exactly 0 with no pose in both (``round_off``), while the forces, which
    are not round-off, are the same numbers in both units; the 3RRPRR's T_r, which is not
    zero, keeps its value and pose."""
    runs = {}
    for name, k, zo in (("cm", 1, "50:70:3"), ("mm", 10, "500:700:3")):
        model = _model(tmp_path, name, k)
        assert main(["size", "--model", model, "--grid", "alpha=-10:10:5", "--grid",
                     "beta=-10:10:5", "--grid", f"Zo={zo}", "-q", "--json"]) == 0
        runs[name] = {r["name"]: r for r in json.loads(capsys.readouterr().out)["extremes"]}
    for name in ("T_r1", "T_r2", "T_r3"):
        for run in runs.values():
            r = run[name]
            assert r["round_off"] and r["max_abs"] == 0.0 and r["pose"] is None
    for name in ("F_a1", "F_a2", "F_a3", "F_c1"):
        cm, mm = runs["cm"][name], runs["mm"][name]
        assert not cm["round_off"] and cm["max_abs"] > 1.0
        assert mm["max_abs"] == pytest.approx(cm["max_abs"], rel=1e-9)
    assert main(["size", "3RRPRR", "--grid", "alpha=-5:5:3", "--grid", "beta=-5:5:3", "-q",
                 "--json"]) == 0
    rows = {r["name"]: r for r in json.loads(capsys.readouterr().out)["extremes"]}
    assert not rows["T_r1"]["round_off"] and rows["T_r1"]["max_abs"] > 1.0
    assert rows["T_r1"]["pose"] is not None


def test_a_path_file_naming_its_units_drives_the_dynamics_too(tmp_path, capsys):
    """A path CSV whose header names the model's length unit (``Zo [cm]``) was read by
    ``trajectory`` but refused with ``--dynamics`` ("lengths are in undeclared units"): the
    dynamics' reader did not pass the model's unit on. Both headers now give the same
    dynamics."""
    model = _model(tmp_path, "cm", 1)
    outs = []
    for head in ("t,alpha,beta,Zo", "t,alpha [deg],beta [deg],Zo [cm]"):
        p = tmp_path / f"p{len(outs)}.csv"
        p.write_text(head + "\n0,0,0,55\n0.5,2,1,57\n1,4,2,59\n1.5,5,2,60\n2,5,3,61\n")
        out = tmp_path / f"d{len(outs)}.json"
        assert main(["trajectory", "--model", model, "--path", str(p), "--dynamics", "-q",
                     "--format", "json", "--out", str(out)]) == 0, capsys.readouterr().err
        outs.append(json.loads(out.read_text()))
    capsys.readouterr()
    a, b = (_find(d, "kinematic_condition") for d in outs)
    assert a == b and len(a) == 5
    texts = [json.dumps(d, sort_keys=True).replace(f"p{i}.csv", "p.csv")
             for i, d in enumerate(outs)]
    assert texts[0] == texts[1]
