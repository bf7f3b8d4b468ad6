"""``--units SI`` in the text report and the trajectory table, and units in the CSV header.

The conversion factors are written here by hand (1 cm = 0.01 m, 1 kN = 1000 N,
1 kN.cm = 10 N.m), not taken from the code (which goes through pint): each SI value
printed must be the model-unit value printed times its factor, line by line.
"""

from __future__ import annotations

import io
import json
import re
from pathlib import Path

import numpy as np
import pytest

from screwkit.cli import main

# the paper's workload, stated (only 3RRPRR and 2SPS+2SPR declare it as their default)
PAPER_LOAD = {"force": (-20.0, -30.0, -60.0), "torque": (-30.0, -30.0, 100.0)}
PAPER_ARGS = ["--force=-20,-30,-60", "--torque=-30,-30,100"]

pytest.importorskip("pint")

L, F, T = 0.01, 1000.0, 10.0            # cm -> m, kN -> N, kN.cm -> N.m (by hand)
NUM = r"[-+]?(?:\d+\.?\d*|\.\d+)(?:e[-+]?\d+)?"
PMS = {"3RRPRR": ["--pose", "alpha=5", "--pose", "beta=-3", "--pose", "Zo=80"],   # linear
       "3RSR": PAPER_ARGS,                                                         # rotary
       "3SPU+PRRR": PAPER_ARGS}                                                    # couples


def _run(capsys, *argv):
    rc = main(list(argv))
    out, err = capsys.readouterr()
    assert rc == 0, err
    return out


def _nums(text):
    return [float(x) for x in re.findall(NUM, text)]


def _close(si, model, factor, rtol=2e-5):
    """Printed to 6 (J: 5) significant digits; fmt_num prints |x| < 1e-12 as 0."""
    si, model = np.asarray(si, float), np.asarray(model, float) * factor
    assert si.shape == model.shape, (si, model)
    scale = max(np.abs(model).max(initial=0.0), 1e-300)
    np.testing.assert_allclose(si, model, rtol=rtol, atol=1e-9 * scale)


def _group(pattern, line):
    m = re.search(pattern, line)
    assert m, (pattern, line)
    return m


@pytest.mark.parametrize("pm", PMS)
def test_text_si_values_are_the_model_values_times_the_factors(capsys, pm):
    model = _run(capsys, "analyze", pm, *PMS[pm]).splitlines()
    si = _run(capsys, "analyze", pm, *PMS[pm], "--units", "SI").splitlines()
    assert len(model) == len(si)
    seen = set()
    vec = r"\(([^)]*)\)"
    for a, b in zip(model, si):
        if not b.startswith("units:"):               # (which names the model's)
            assert not re.search(r"\bkN|\bcm\b", b), b
        # every line that names a model unit, or whose numbers change, names an SI unit
        if re.search(r"\bkN|\bcm\b", a) or _nums(a) != _nums(b):
            assert re.search(r"(\bm\b|\bN\b|N\.m|/m\b)", b), b
        if _nums(a) == _nums(b) and not re.match(r"\s+leg \d+ force \(kN\)", a):
            continue                                 # no dimensional number on the line
        if re.match(r"\s+\d+\. ", a):                                     # A_i, a_i
            ma, mb = (_group(r"A\d+ = " + vec + r"\s+a\d+ = " + vec, x) for x in (a, b))
            _close(_nums(mb[1]) + _nums(mb[2]), _nums(ma[1]) + _nums(ma[2]), L)
            assert b.endswith(" m")
            seen.add("legs")
        elif a.startswith("pose ("):
            pa, pb = (dict(re.findall(r"(\w+)=(" + NUM + ")", x)) for x in (a, b))
            for k in pa:
                _close([float(pb[k])], [float(pa[k])], L if k in ("Xo", "Yo", "Zo") else 1.0)
            assert b.startswith("pose (deg, m)")
            seen.add("pose")
        elif a.startswith("extensions"):
            ra, rb = (re.findall(r"r\d+=(" + NUM + ")", x) for x in (a, b))
            _close([float(x) for x in rb], [float(x) for x in ra], L)
            assert b.startswith("extensions r_i (m)")
            seen.add("extensions")
        elif a.rstrip().endswith(("; cm]", "[1/cm; 1]")):                 # rows of J
            xa, xb = np.array(_nums(a)[:6]), np.array(_nums(b)[:6])
            if a.rstrip().endswith("[1; cm]"):       # force effort: [1; length]
                assert b.rstrip().endswith("[1; m]")
                _close(xb, xa * np.r_[1, 1, 1, L, L, L], 1.0, rtol=2e-4)
            else:                                    # torque effort: [1/length; 1]
                assert b.rstrip().endswith("[1/m; 1]")
                _close(xb, xa * np.r_[1 / L, 1 / L, 1 / L, 1, 1, 1], 1.0, rtol=2e-4)
            seen.add("J")
        elif a.startswith("statics for F"):
            ma, mb = (_group(r"F = " + vec + r" \S+ and T = " + vec, x) for x in (a, b))
            _close(_nums(mb[1]), _nums(ma[1]), F)
            _close(_nums(mb[2]), _nums(ma[2]), T)
            seen.add("workload")
        elif re.match(r"\s+leg \d+ (active|constraint)", a):
            pat = r"\s(" + NUM + r")\*?\s+(\S+)\s+vector " + vec + r" (\S+)"
            ma, mb = _group(pat, a), _group(pat, b)
            unit = {"kN": ("N", F), "kN.cm": ("N.m", T)}
            assert mb[2] == unit[ma[2]][0] and mb[4] == unit[ma[4]][0], b
            _close([float(mb[1])], [float(ma[1])], unit[ma[2]][1])
            _close(_nums(mb[3]), _nums(ma[3]), unit[ma[4]][1])
            if "line through (" in a:
                pa, pb = (_group(r"line through " + vec + r" (\S+)", x) for x in (a, b))
                assert pb[2] == "m"
                _close(_nums(pb[1]), _nums(pa[1]), L)
            seen.add("torque rows" if ma[2] == "kN.cm" else "force rows")
        elif "T_ri" in a:
            ta, tb = (re.findall(r"T_r\d+=(" + NUM + ")", x) for x in (a, b))
            _close([float(x) for x in tb], [float(x) for x in ta], T)
            assert "(N.m)" in b
            seen.add("T_r")
        elif re.match(r"\s+leg \d+ force \(kN\)", a):
            assert re.match(r"\s+leg \d+ force \(N\) ", b) and "(N.m)" in b, b
            ma, mb = (_group(r"force \(\S+\) " + vec + r".*\(\S+\) " + vec, x) for x in (a, b))
            _close(_nums(mb[1]), _nums(ma[1]), F)
            _close(_nums(mb[2]), _nums(ma[2]), T)
            seen.add("resultants")
        elif "twist space here" in a:
            pa, pb = (re.findall(r"pitch (" + NUM + ")", x) for x in (a, b))
            _close([float(x) for x in pb], [float(x) for x in pa], L)
            ha, hb = (_group(r"H\(p=([^)]*)\)", x) for x in (a, b))
            _close(_nums(hb[1]), _nums(ha[1]), L)
            la, lb = (re.findall(r"through " + vec, x) for x in (a, b))
            _close(_nums(" ".join(lb)), _nums(" ".join(la)), L)
            assert "(m/rad)" in b
            seen.add("twists")
        elif re.match(r"\s+leg \d+: ITI", a) or a.lstrip().startswith("constraint rows:"):
            # transmission indices (unit-free: unchanged) and their arms (lengths)
            ia, ib = (re.findall(r"(?:ITI|OTI|CTI) (" + NUM + "|n/a)", x) for x in (a, b))
            assert ia == ib, (a, b)
            aa = re.findall(r"arm (" + NUM + r") cm\)", a)
            ab = re.findall(r"arm (" + NUM + r") m\)", b)
            _close([float(x) for x in ab], [float(x) for x in aa], L)
            seen.add("transmission arms")
        elif a.startswith("units:"):
            assert b.startswith("units: lengths m, forces N, torques N.m, angles deg")
        else:
            pytest.fail(f"a line whose numbers change and that this test does not check: {b}")
    want = {"legs", "pose", "extensions", "J", "workload", "resultants", "transmission arms"}
    want |= {"3RRPRR": {"force rows", "T_r", "twists"}, "3RSR": {"torque rows", "twists"},
             "3SPU+PRRR": {"force rows", "torque rows", "T_r"}}[pm]
    assert want <= seen, want - seen


@pytest.mark.parametrize("pm", ["3RSR", "3SPU+PRRR"])
def test_si_json_rows_balance_the_load_in_si(capsys, pm):
    """The SI report's rows of J (rotary rows: force per torque; couple rows) times the SI
    values balance the SI workload ``[F; T + o x F]`` about O, and sum to each leg's wrench."""
    d = json.loads(_run(capsys, "analyze", pm, *PMS[pm], "--json", "--units", "SI"))
    J, x = np.array(d["jacobian"]), np.array(d["statics"]["values"])
    o = np.array([d["pose"][k] for k in ("Xo", "Yo", "Zo")])
    Fw, Tw = np.array(d["workload"]["force"]), np.array(d["workload"]["torque"])
    W = np.r_[Fw, Tw + np.cross(o, Fw)]
    np.testing.assert_allclose(J.T @ x + W, 0, atol=1e-9 * np.abs(J.T @ x).max())
    for leg in d["legs"]:
        w = sum(c["value"] * np.array(c["unit_wrench"]) for c in leg["constraints"])
        if "actuation" in leg:
            w = w + leg["active"] * np.array(leg["actuation"]["unit_wrench"])
        np.testing.assert_allclose(w, leg["wrench"], atol=1e-9 * np.abs(W).max())


EXPR = ["--expr", "alpha=2*sin(2*pi*t)", "--expr", "beta=-1", "--expr", "Zo=40+5*t",
        "--samples", "5"]
SI_UNIT = {"cm": ("m", L), "kN": ("N", F), "kN.cm": ("N.m", T), "deg": ("deg", 1.0)}


@pytest.mark.parametrize("pm", ["3RSR", "3SPU+PRRR"])
def test_trajectory_csv_header_units_and_si_table(capsys, pm):
    pd = pytest.importorskip("pandas")
    expr = EXPR if pm == "3RSR" else ["--expr", "Xo=5+2*t", "--expr", "Yo=-3", "--expr",
                                      "Zo=80", "--expr", "gamma=10+10*t", "--samples", "5"]
    model = pd.read_csv(io.StringIO(_run(capsys, "trajectory", pm, *expr, *PAPER_ARGS)))
    si = pd.read_csv(io.StringIO(_run(capsys, "trajectory", pm, *expr, "--units", "SI", *PAPER_ARGS)))
    assert len(model) == len(si) == 5 and (model["status"] == "ok").all()
    assert model.columns[0] == "t" and model.columns[-1] == "message"
    for ca, cb in zip(model.columns, si.columns):
        name, _, unit = ca.partition(" [")
        if not unit:                                 # t, status, condition number, ...
            assert cb == ca
            if ca not in ("status", "message"):
                np.testing.assert_array_equal(si[cb], model[ca])
            continue
        unit = unit.rstrip("]")
        assert cb == f"{name} [{SI_UNIT[unit][0]}]"
        _close(si[cb].to_numpy(), model[ca].to_numpy(), SI_UNIT[unit][1], rtol=1e-10)
    heads = list(model.columns)
    if pm == "3RSR":                      # rotary actuators: torques; no T_r columns
        assert "T_a1 [kN.cm]" in heads and not any(h.startswith("T_r") for h in heads)
    else:                                 # the PRRR leg's couples are torques
        assert "F_a1 [kN]" in heads and {"T_c4.1 [kN.cm]", "T_c4.2 [kN.cm]"} <= set(heads)


def test_trajectory_resultants_equal_analyze(capsys):
    """The trajectory's per-leg constraint resultants (CSV and JSON) are analyze's at the
    same pose, and in SI the JSON's are the model's times the factors."""
    pd = pytest.importorskip("pandas")
    expr = ["--expr", "Xo=5+2*t", "--expr", "Yo=-3", "--expr", "Zo=80", "--expr", "gamma=10+10*t",
            "--samples", "3"]
    df = pd.read_csv(io.StringIO(_run(capsys, "trajectory", "3SPU+PRRR", *expr, *PAPER_ARGS)))
    js = json.loads(_run(capsys, "trajectory", "3SPU+PRRR", *expr, "--format", "json", *PAPER_ARGS, *PAPER_ARGS))
    js_si = json.loads(_run(capsys, "trajectory", "3SPU+PRRR", *expr, "--format", "json", *PAPER_ARGS,
                            "--units", "SI"))
    res, res_si = js["constraint_resultant"], js_si["constraint_resultant"]
    assert res["force_unit"] == "kN" and res_si["moment_unit"] == "N.m"
    _close(np.array(res_si["force"]), np.array(res["force"]), F, rtol=1e-12)
    _close(np.array(res_si["moment"]), np.array(res["moment"]), T, rtol=1e-12)
    k = 2
    pose = [f"--pose={p}={float(df[f'{p} [cm]' if p != 'gamma' else 'gamma [deg]'][k])!r}"
            for p in ("Xo", "Yo", "Zo", "gamma")]
    a = json.loads(_run(capsys, "analyze", "3SPU+PRRR", *pose, "--json", *PAPER_ARGS))
    for i, leg in enumerate(a["legs"]):
        r = leg["constraint_resultant"]
        scale = max(np.abs(r["moment"]).max(), 1.0)
        csv_f = [df[f"res{i + 1}_f{x} [kN]"][k] for x in "xyz"]
        csv_m = [df[f"res{i + 1}_m{x} [kN.cm]"][k] for x in "xyz"]
        np.testing.assert_allclose(csv_f, r["force"], atol=1e-8 * scale)
        np.testing.assert_allclose(csv_m, r["moment"], atol=1e-8 * scale)
        np.testing.assert_allclose(res["moment"][k][i], r["moment"], atol=1e-8 * scale)
        assert res["determined"][k][i] == (r["force_determined"] and r["moment_determined"])


def test_trajectory_si_refusals(capsys):
    data = Path(__file__).with_name("data") / "user_3prs.yaml"        # declares no units
    rc = main(["trajectory", "3PRS", "--model", str(data), *EXPR, "--units", "SI", *PAPER_ARGS])
    err = capsys.readouterr().err
    assert rc == 2 and "declares no units" in err and err.count("\n") == 1
    rc = main(["analyze", "3PRS", "--model", str(data), "--units", "SI", *PAPER_ARGS])
    err = capsys.readouterr().err
    assert rc == 2 and "declares no units" in err


def test_a_path_file_may_name_its_units(tmp_path, capsys):
    """The pose columns of a trajectory CSV (``alpha [deg]``, ``Zo [cm]``) read back as a
    path; a column in radians is read as such; a length in another unit is refused."""
    pd = pytest.importorskip("pandas")
    expr = ["--expr", "alpha=5*t", "--expr", "beta=-3*t", "--expr", "Zo=70+10*t",
            "--samples", "4"]
    out = pd.read_csv(io.StringIO(_run(capsys, "trajectory", "3RRPRR", *expr)))
    cols = ["t", "alpha [deg]", "beta [deg]", "Zo [cm]"]
    f = tmp_path / "p.csv"
    out[cols].to_csv(f, index=False)
    back = pd.read_csv(io.StringIO(_run(capsys, "trajectory", "3RRPRR", "--path", str(f))))
    np.testing.assert_allclose(back["F_a1 [kN]"], out["F_a1 [kN]"], rtol=1e-9)
    rad = out[cols].rename(columns={"beta [deg]": "beta [rad]"})
    rad["beta [rad]"] = np.radians(rad["beta [rad]"])
    rad.to_csv(f, index=False)
    back = pd.read_csv(io.StringIO(_run(capsys, "trajectory", "3RRPRR", "--path", str(f))))
    np.testing.assert_allclose(back["beta [deg]"], out["beta [deg]"], rtol=1e-9, atol=1e-12)
    f.write_text("t,alpha [deg],beta,Zo [m]\n0,0,0,0.7\n1,5,-3,0.8\n")
    assert main(["trajectory", "3RRPRR", "--path", str(f)]) == 2
    err = capsys.readouterr().err
    assert "Zo [m]" in err and "in cm" in err and err.count("\n") == 1


def test_a_rotary_actuator_in_a_u_joint_is_a_torque(tmp_path):
    """UP+2UPS/rotational (what `synthesize --write` gives): legs 2 and 3 are actuated at the
    first R of their U (a revolute of the leg's R/P chain, though the joint is named U1a):
    their efforts are torques, labelled T_a, in kN.cm, scaled by 10 into N.m (a force by
    1000 into N); by virtual work against a finite difference of the actuated joints,
    sum tau_i dq_i equals the workload's work on the platform's motion."""
    text = """pms:
  UP+2UPS/rotational:
    string: UP+2UPS
    dimensions: {R: 60, r: 30}
    base: {shape: triangle, circumradius: R}
    platform: {shape: triangle, circumradius: r}
    euler: XYZ
    legs: [UP, UPS/rotational, UPS/rotational]
    independent: [alpha, beta, Zo]
    home: {alpha: 0, beta: 0, Zo: R}
    pose: {alpha: 0, beta: 0, Zo: R}
    dof: 3
    motion: 1T2R
    units: {length: cm, force: kN}
"""
    import screwkit
    path = tmp_path / "rot.yaml"
    path.write_text(text, encoding="utf-8")
    pm = screwkit.load_pm(str(path))
    assert pm.home_legs[1].actuated_joint.kind == "R" and pm.home_legs[0].actuated_joint.kind == "P"
    F, T = np.array([0.0, 0.0, -1.0]), np.array([0.5, 0.0, 0.0])
    pose = {"alpha": 0.05, "beta": -0.03, "Zo": 62.0}
    an = screwkit.analyze(pm, pose, force=F, torque=T)
    assert [r.label for r in an.jacobian.info[:3]] == ["F_a1", "T_a2", "T_a3"]
    d, s = an.to_dict(), an.to_dict(units="SI")
    act, act_si = np.array(d["statics"]["active"]), np.array(s["statics"]["active"])
    np.testing.assert_allclose(act_si, act * np.array([1000.0, 10.0, 10.0]), rtol=1e-12)
    # virtual work: the actuated joints' efforts against the workload, by finite differences
    h = 1e-6
    for k in ("alpha", "beta", "Zo"):
        sols = [screwkit.analyze(pm, dict(pose, **{k: pose[k] + e}), force=F, torque=T)
                for e in (-h, h)]
        dq = (np.asarray(sols[1].solution.actuator_values)
              - np.asarray(sols[0].solution.actuator_values))
        dp = np.asarray(sols[1].solution.position) - np.asarray(sols[0].solution.position)
        R0, R1 = (np.asarray(x.solution.rotation) for x in sols)
        S = R1 @ R0.T                  # a small rotation [dtheta]x + I (world axes)
        w = np.array([S[2, 1] - S[1, 2], S[0, 2] - S[2, 0], S[1, 0] - S[0, 1]]) / 2
        work = act @ dq + F @ dp + T @ w
        assert abs(work) <= 1e-6 * (np.abs(act) @ np.abs(dq) + 1e-30), (k, work)


def test_the_mobility_strings_of_the_json_are_in_its_units(capsys):
    """analyze --units SI --json: the twist space's points and pitches in m (they were left
    in cm while units.length said m); the directions unchanged."""
    d = json.loads(_run(capsys, "analyze", "3RRPRR", "--json"))
    s = json.loads(_run(capsys, "analyze", "3RRPRR", "--json", "--units", "SI"))
    a, b = d["mobility"]["instantaneous"], s["mobility"]["instantaneous"]
    assert "(cm/rad)" in a and "(m/rad)" in b
    pa = [float(x) for x in re.findall(NUM, a.split("through", 1)[1].split("along")[0])]
    pb = [float(x) for x in re.findall(NUM, b.split("through", 1)[1].split("along")[0])]
    np.testing.assert_allclose(pb, np.array(pa) * L, rtol=1e-3)   # (4 digits printed)


def test_the_joint_values_of_the_json_are_in_its_units(capsys):
    """analyze --units SI --json: each P joint's value in m (it was left in cm while
    units.length said m), each R joint's in rad as it is; the leg's P joint and its
    actuator value one number."""
    d = json.loads(_run(capsys, "analyze", "3RRPRR", "--json"))
    s = json.loads(_run(capsys, "analyze", "3RRPRR", "--json", "--units", "SI"))
    for a, b in zip(d["legs"], s["legs"]):
        assert a["joint_value_units"] == ["rad", "rad", "cm", "rad", "rad"]    # R R P R R
        assert b["joint_value_units"] == ["rad", "rad", "m", "rad", "rad"]
        factor = np.array([1.0, 1.0, L, 1.0, 1.0])
        np.testing.assert_allclose(b["joint_values"], np.array(a["joint_values"]) * factor,
                                   rtol=1e-12, atol=1e-15)
        assert b["joint_values"][2] == pytest.approx(b["actuator_value"], rel=1e-12)


_TRICEPT = """\
units: {{length: {unit}, force: N}}
legs:
  - name: UP/column
    string: U_P
    summary: the Tricept's passive column
    joints:
      - {{at: A, axes: [base.X, {{perpendicular: [U1a, leg]}}]}}
      - {{axis: leg}}
    structure:
      - {{perpendicular: [U1b, leg]}}
pms:
  tricept:
    string: 3UPS+UP/passive
    dimensions: {{R: {R}, r: {r}, H: {H}}}
    base: {{points: [[R, 0, 0], [-R/2, R*sqrt(3)/2, 0], [-R/2, -R*sqrt(3)/2, 0], [0, 0, 0]]}}
    platform: {{points: [[r, 0, 0], [-r/2, r*sqrt(3)/2, 0], [-r/2, -r*sqrt(3)/2, 0], [0, 0, 0]]}}
    legs: [UPS, UPS, UPS, {{leg: UP/column, passive: true}}]
    euler: XYZ
    independent: [alpha, beta, Zo]
    home: {{alpha: 0, beta: 0, Zo: H}}
    pose: {{alpha: 5, beta: -3, Zo: H}}
    dof: 3
    motion: 1T2R
"""


def test_stiffness_in_si_is_the_same_pm_written_in_metres(tmp_path, capsys):
    """``stiffness --units SI`` of a Tricept written in mm equals the report of the same
    Tricept written in m (every dimension / 1000, the stiffnesses and the load converted by
    hand: N/mm -> N/m x 1000, N.mm/rad -> N.m/rad / 1000, N.mm -> N.m / 1000), which the
    engine computes in metres from the start: stiffness, compliance, deflection, principal
    stiffnesses, row stiffnesses, o."""
    files = {}
    for unit, k in (("mm", 1.0), ("m", 1e-3)):
        files[unit] = tmp_path / f"tricept_{unit}.yaml"
        files[unit].write_text(_TRICEPT.format(unit=unit, R=300 * k, r=110 * k, H=650 * k))
    pose = ["--pose", "alpha=4", "--pose", "beta=-6"]
    ka, kf, kc, torque = 2e4, 5e4, 3e9, (100.0, -200.0, 50.0)       # N/mm, N/mm, N.mm/rad
    mm = json.loads(_run(capsys, "stiffness", "--model", str(files["mm"]), *pose,
                         "--pose", "Zo=620", "--k-actuator", f"{ka}", "--k-force", f"{kf}",
                         "--k-couple", f"{kc}", "--force=10,-20,-300",
                         "--torque=" + ",".join(map(str, torque)), "--units", "SI", "--json"))
    m = json.loads(_run(capsys, "stiffness", "--model", str(files["m"]), *pose,
                        "--pose", "Zo=0.62", "--k-actuator", f"{ka * 1e3}", "--k-force",
                        f"{kf * 1e3}", "--k-couple", f"{kc * 1e-3}", "--force=10,-20,-300",
                        "--torque=" + ",".join(str(t * 1e-3) for t in torque), "--json"))
    assert mm["units"]["length"] == "m" and mm["units"]["converted_from"]["length"] == "mm"
    assert mm["units"]["stiffness"] == m["units"]["stiffness"]
    K_si, K_m = np.array(mm["stiffness"]), np.array(m["stiffness"])
    assert np.allclose(K_si, K_m, rtol=1e-8, atol=1e-10 * np.abs(K_m).max())
    C_si, C_m = np.array(mm["compliance"]), np.array(m["compliance"])
    assert np.allclose(C_si, C_m, rtol=1e-8, atol=1e-10 * np.abs(C_m).max())
    for part in ("translation", "rotation"):
        assert np.allclose(mm["deflection"][part], m["deflection"][part], rtol=1e-8,
                           atol=1e-12 * np.abs(m["deflection"][part]).max())
    for which in ("translational", "rotational"):
        assert np.allclose(mm["principal"][which]["stiffness"],
                           m["principal"][which]["stiffness"], rtol=1e-8)
    assert [r["unit"] for r in mm["rows"]] == [r["unit"] for r in m["rows"]]
    assert np.allclose([r["stiffness"] for r in mm["rows"]], [r["stiffness"] for r in m["rows"]],
                       rtol=1e-12)
    assert np.allclose(mm["o"], m["o"], rtol=1e-10, atol=1e-12)
    assert mm["pose"]["Zo"] == pytest.approx(0.62, rel=1e-12)
    assert np.allclose(mm["workload"]["torque"], np.array(torque) * 1e-3, rtol=1e-12)
    text = _run(capsys, "stiffness", "--model", str(files["mm"]), *pose, "--pose", "Zo=620",
                "--k-actuator", f"{ka}", "--k-force", f"{kf}", "--k-couple", f"{kc}",
                "--force=10,-20,-300", "--units", "SI")
    assert "(converted from the model's mm, N)" in text and "[N/m]" in text
    assert "N.mm" not in text and "N/mm" not in text
