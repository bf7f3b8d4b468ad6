"""Review of issue 22's view, drawings and export (no browser here; tests/test_view_browser.py
opens the pages in Chromium).

* the arrows' lengths: one rule (per kind, a 25 % floor), checked on values written here;
* round-off of an exact zero is shown as 0: the Delta's least-norm couples at its symmetric
  pose vanish by symmetry, and its actuator torques equal the virtual-work value computed
  here from the solved crank angles (finite differences of the kinematics, not J);
* the zero rule does not depend on the units;
* the page bundles plotly's own library, unchanged, and loads nothing else;
* the CLI summary counts the states that are not regular; --frame and the export's outputs
  are checked where they enter."""

import base64
import json
import re

import numpy as np
import pytest

import screwkit
from screwkit.cli import main
from screwkit.engine._scene import zero_round_off
from screwkit.scene import FLOOR, arrow_fractions

from delta import DELTA

pytest.importorskip("plotly", reason="the 3D view needs plotly (screwkit[view])")


def page_data(html: str) -> dict:
    m = re.search(r'<script type="application/json" id="screwkit-data">(.*?)</script>', html,
                  re.S)
    return json.loads(m.group(1).replace("<\\/", "</"))


def test_arrow_lengths_by_hand():
    # actuation forces 10, -2 (below a quarter of 10), 0 and n/a; a lone constraint force 5
    frac, floored = arrow_fractions([10.0, -2.0, 0.0, np.nan, 5.0, -4.0],
                                    ["force-a"] * 4 + ["force-c", "torque-c"])
    assert FLOOR == 0.25
    np.testing.assert_array_equal(frac, [1.0, -0.25, 0.25, 0.25, 1.0, -1.0])
    np.testing.assert_array_equal(floored, [False, True, True, True, False, False])
    frac, floored = arrow_fractions([8.0, -3.0], ["force-c", "force-c"])
    np.testing.assert_allclose(frac, [1.0, -0.375])
    assert not floored.any()


@pytest.fixture(scope="module")
def delta(tmp_path_factory):
    path = tmp_path_factory.mktemp("delta") / "delta.yaml"
    path.write_text(DELTA)
    return screwkit.load_pm(str(path))


def test_delta_round_off_is_zero_and_torques_by_virtual_work(delta):
    pose = {"Xo": 0.0, "Yo": 0.0, "Zo": -150.0}
    view = screwkit.analyze(delta, pose, force=[0, 0, -10], torque=[0, 0, 0]).show()
    d = page_data(view.html)
    s = d["states"][0]
    couples = [k for k, r in enumerate(d["rows"]) if r["kind"] == "couple"]
    assert len(couples) == 6
    # by symmetry (a central vertical force on the symmetric Delta) every couple vanishes:
    # the page says 0 (not 1e-13), marked * (statics does not determine it), at the floor
    for k in couples:
        assert s["values"][k] == 0.0
        assert s["text"][k] == f"{d['rows'][k]['label']} = 0 N.mm*"
        assert s["frac"][k] == FLOOR and s["floored"][k]
    # the actuator torques: 3 T dtheta + F_z dz = 0, dtheta/dz from the solved crank angles
    h = 1e-4
    lo = screwkit.solve(delta, {**pose, "Zo": -150.0 - h})
    hi = screwkit.solve(delta, {**pose, "Zo": -150.0 + h})
    dtheta_dz = (hi.joint_values[0][0] - lo.joint_values[0][0]) / (2 * h)
    torque = -(-10.0) / (3 * dtheta_dz)                       # N.mm
    actuated = [k for k, r in enumerate(d["rows"]) if r["actuation"]]
    np.testing.assert_allclose([s["values"][k] for k in actuated], [torque] * 3, rtol=1e-6)
    assert not any(s["floored"][k] for k in actuated)


def test_the_zero_rule_does_not_depend_on_units():
    rng = np.random.default_rng(7)
    values = np.array([3.0, -2.0, 4e-14, 7e-6, 1.0, 2e-15, np.nan])
    torque_rows = np.array([False, False, False, True, True, True, False])
    F, T, L = rng.normal(size=3), rng.normal(size=3) * 50, 40.0
    base = zero_round_off(values, torque_rows, F, T, L)
    for kf, kl in ((1e-3, 1e-2), (1e3, 1e3), (4.44822, 0.0254)):   # kN, m, lbf and in ...
        scaled = values * np.where(torque_rows, kf * kl, kf)
        other = zero_round_off(scaled, torque_rows, F * kf, T * kf * kl, L * kl)
        np.testing.assert_array_equal(other == 0, base == 0)
    np.testing.assert_array_equal(base == 0, [False, False, True, False, False, True, False])
    assert np.isnan(base[-1])


def test_page_bundles_plotly_unchanged_and_loads_nothing_else():
    from plotly.offline import get_plotlyjs
    page = screwkit.analyze("3RRPRR").show().html
    srcs = re.findall(r'<(?:script|link|img|iframe)[^>]*(?:src|href)="([^"]*)"', page)
    assert len(srcs) == 1 and srcs[0].startswith("data:text/javascript;base64,")
    library = base64.b64decode(srcs[0].split(",", 1)[1]).decode("utf-8")
    assert library == get_plotlyjs()          # the well-kept package's code, as it ships
    outside = page.replace(srcs[0], "")       # the page's own text: no address at all
    assert not re.search(r"https?://|ftp://|//cdn\.", outside)


def test_cli_summary_counts_the_flagged_states(tmp_path, capsys):
    out = tmp_path / "v.html"
    rc = main(["view", "3RSR", "--steps", "3", "--html", str(out), "--quiet"])
    assert rc == 0
    line = capsys.readouterr().out.strip()
    levels = [s["level"] for s in page_data(out.read_text())["states"]]
    flagged = {lv: levels.count(lv) for lv in set(levels) if lv != "ok"}
    assert flagged                                        # 3RSR's grid has some
    for lv, n in flagged.items():
        assert f"{n} of 27 {lv}" in line
    rc = main(["view", "3RSR", "--steps", "3", "--html", str(out), "--quiet", "--json"])
    assert json.loads(capsys.readouterr().out)["levels"] == {
        lv: levels.count(lv) for lv in set(levels)}


def test_cli_frame_beyond_the_path(tmp_path, capsys):
    rc = main(["view", "3RRPRR", "--expr", "alpha=t", "--expr", "beta=2", "--expr", "Zo=80",
               "--samples", "5", "--frame", "5", "--html", str(tmp_path / "v.html")])
    err = capsys.readouterr().err
    assert rc == 2 and len(err.strip().splitlines()) == 1
    assert "--frame 5: the path has 5 samples (0 to 4)" in err


@pytest.mark.parametrize("mjcf", ["pm.urdf", "pm.closures.json"])
def test_cli_export_outputs_do_not_overwrite(tmp_path, capsys, mjcf):
    rc = main(["export", "3RRPRR", "--urdf", str(tmp_path / "pm.urdf"), "--mjcf",
               str(tmp_path / mjcf), "--massless"])
    err = capsys.readouterr().err
    assert rc == 2 and len(err.strip().splitlines()) == 1 and "would overwrite" in err
    assert not (tmp_path / "pm.urdf").exists()


def test_a_view_without_workload_says_so():
    """A scene without a workload (force None: a model that declares none, none given) states
    it instead of printing a zero load."""
    import dataclasses
    scene = dataclasses.replace(screwkit.analyze("3RPS").show().scene, force=None,
                                torque=None, workload_source="the model declares none")
    d = scene.to_json()
    assert d["workload"]["force"] is None and d["workload"]["torque"] is None
    assert d["workload"]["text"].startswith("none (the model declares none): no efforts")
    assert "[0, 0, 0]" not in d["workload"]["text"]


def test_a_central_columns_point_is_not_a_corner_of_the_plates():
    """The Tricept's base and platform were drawn through the passive column's attachment
    (A4 at the base centre, a4 at o) as a polygon vertex: a chevron and a boomerang. The
    outline is the hull of the points now: the outer triangle, by hand, in the view's data
    and in the drawing."""
    pytest.importorskip("matplotlib")
    from screwkit.scene import plate_outline
    pm = screwkit.load_pm("3UPS+UP/passive")
    base = np.asarray(pm.world_base_points, float)
    assert np.allclose(plate_outline(base), base[:3])
    from screwkit.viz import draw_pm
    sol = screwkit.analyze(pm, dict(pm.default_pose), force=[0, 0, -100]).solution
    fig = draw_pm(sol.legs, sol.base_points, sol.platform_points, sol.position)
    fig.canvas.draw()
    drawn = {c.get_gid(): [len(p.vertices) for p in c.get_paths()]
             for c in fig.axes[0].collections if c.get_gid() in ("base", "platform")}
    assert drawn == {"base": [4], "platform": [4]}         # a triangle each, closed


def test_view_and_export_errors_name_their_cause(tmp_path, capsys):
    """``view --pose alpha=1e308`` said no pose of the view was reachable (the engine's
    limit was the cause: +-3600 deg, as ``analyze`` says); ``view --grid alpha=1:2:0`` said
    the count goes to 1e7 and ``1:2:100000`` that it goes to 101; an export under a file
    said "File exists"."""
    from screwkit.cli import main
    page = str(tmp_path / "v.html")
    cases = [(["view", "3RRPRR", "--pose", "alpha=1e308", "--html", page],
              "beyond the limit +-3600 deg"),
             (["view", "3RRPRR", "--grid", "alpha=1:2:0", "--html", page], "1 .. 101"),
             (["view", "3RRPRR", "--grid", "alpha=1:2:100000", "--html", page], "1 .. 101")]
    blocker = tmp_path / "afile"
    blocker.write_text("x", encoding="utf-8")
    cases += [(["export", "3RRPRR", "--mjcf", str(blocker / "a.xml"), "--massless"],
               "is a file, not a folder"),
              (["export", "3RRPRR", "--urdf", str(blocker / "b" / "a.urdf")],
               "is a file, not a folder")]
    for argv, said in cases:
        assert main(argv) == 2, argv
        err = capsys.readouterr().err.strip().splitlines()
        assert len(err) == 1 and said in err[0], (argv, err)
