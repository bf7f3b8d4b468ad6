"""Issue 22: the interactive 3D view's page (no browser here: tests/test_view_browser.py
opens it in Chromium).

The page's numbers are read back from the HTML (the JSON of #screwkit-data) and compared
with ``screwkit.analyze`` run on its own at the same poses, and with a trajectory's table;
the labels with a formatting written here; the page is checked to be self-contained."""

import json
import math
import re

import numpy as np
import pytest

import screwkit
from screwkit.cli import main
from screwkit.errors import InputError

pytest.importorskip("plotly", reason="the 3D view needs plotly (screwkit[view])")

POSE = {"alpha": 5.0, "beta": -3.0, "Zo": 80.0}


def page_data(html: str) -> dict:
    m = re.search(r'<script type="application/json" id="screwkit-data">(.*?)</script>', html,
                  re.S)
    assert m, "no data element in the page"
    return json.loads(m.group(1).replace("<\\/", "</"))


def four_digits(v: float) -> str:
    """4 significant digits, no exponent, trailing zeros dropped (written independently of
    screwkit.scene.format_value)."""
    r = float(f"{v:.4g}")
    places = max(3 - int(math.floor(math.log10(abs(r)))), 0)
    return f"{r:.{places}f}".rstrip("0").rstrip(".")


@pytest.fixture(scope="module")
def grid_view():
    return screwkit.view("3RRPRR", POSE, steps=3, degrees=True)


@pytest.fixture(scope="module")
def grid_page(grid_view):
    return grid_view.html


def test_page_is_self_contained(grid_page):
    assert not re.search(r"https?://|ftp://|//cdn\.", grid_page), "an external URL in the page"
    srcs = re.findall(r'<(?:script|link|img|iframe)[^>]*(?:src|href)="([^"]*)"', grid_page)
    assert srcs and all(s.startswith("data:") for s in srcs)
    assert len(grid_page) < 20e6


def test_numbers_equal_analyze_at_the_pose(grid_page):
    d = page_data(grid_page)
    s = d["states"][d["start"]]
    ref = screwkit.analyze("3RRPRR", POSE, degrees=True)
    assert s["pose"]["alpha"] == pytest.approx(5.0, abs=1e-12)
    assert s["pose"]["beta"] == pytest.approx(-3.0, abs=1e-12)
    labels = [r["label"] for r in d["rows"]]
    assert labels == [r.label for r in ref.jacobian.rows]
    np.testing.assert_allclose(s["values"], ref.statics.values, rtol=1e-9, atol=1e-9)
    assert s["level"] == ref.level and s["status"] == "ok"
    assert s["condition_number"] == pytest.approx(ref.jacobian.condition_number, rel=1e-9)
    # the labels as the issue writes them: F_a1 = 19.36 kN
    assert s["text"][0] == "F_a1 = 19.36 kN"
    for text, r, v in zip(s["text"], d["rows"], ref.statics.values):
        unit = d["units"][r["quantity"]]
        assert text == f"{r['label']} = {four_digits(v)} {unit}"
    # the workload is stated
    assert d["workload"]["force"] == [-20.0, -30.0, -60.0]
    assert "the paper's workload" in d["workload"]["text"] and "kN" in d["workload"]["text"]


def test_every_grid_cell_is_the_engine_at_that_pose(grid_page):
    d = page_data(grid_page)
    ps = d["controls"]["params"]
    assert [p["name"] for p in ps] == ["alpha", "beta", "Zo"]
    assert [len(p["values"]) for p in ps] == [3, 3, 3]
    assert len(d["states"]) == 27
    # C order: the last parameter varies fastest
    cell = (0, 2, 1)
    k = (cell[0] * 3 + cell[1]) * 3 + cell[2]
    pose = {p["name"]: p["values"][c] for p, c in zip(ps, cell)}
    assert pose["alpha"] == pytest.approx(-5.0) and pose["beta"] == pytest.approx(7.0)
    s = d["states"][k]
    for name, v in pose.items():
        assert s["pose"][name] == pytest.approx(v, abs=1e-9)
    ref = screwkit.analyze("3RRPRR", pose, degrees=True)
    np.testing.assert_allclose(s["values"], ref.statics.values, rtol=1e-9, atol=1e-9)
    # the drawn platform is the solved one
    np.testing.assert_allclose(s["platform"], ref.solution.platform_points, atol=1e-9)


def test_legs_and_joints_by_kind(grid_page):
    d = page_data(grid_page)
    from screwkit.viz import LEG_COLORS
    assert [lg["color"] for lg in d["legs"]] == list(LEG_COLORS[:3])
    assert [lg["label"] for lg in d["legs"]] == [f"leg {i} (RRPRR)" for i in (1, 2, 3)]
    s = d["states"][d["start"]]
    kinds = [[j["k"] for j in leg["joints"]] for leg in s["legs"]]
    assert kinds == [["R", "R", "P", "R", "R"]] * 3
    act = [[j["name"] for j in leg["joints"] if j["act"]] for leg in s["legs"]]
    assert act == [["P3"]] * 3


def test_joint_kinds_of_compound_letters():
    v = screwkit.analyze("3SPU+PRRR").show()
    d = page_data(v.html)
    kinds = [[j["k"] for j in leg["joints"]] for leg in d["states"][0]["legs"]]
    assert kinds == [["S", "P", "U"]] * 3 + [["P", "R", "R", "R"]]
    u = d["states"][0]["legs"][0]["joints"][2]
    assert abs(np.dot(u["d"], u["d2"])) < 1e-9          # the U cross: two crossed axes
    labels = [r["label"] for r in d["rows"]]
    assert labels[-2:] == ["T_c4.1", "T_c4.2"] and d["rows"][-1]["kind"] == "couple"


def test_rotary_actuator_is_a_torque():
    d = page_data(screwkit.analyze("3RSR", raise_on_singular=False, force=(-20.0, -30.0, -60.0),
                                   torque=(-30.0, -30.0, 100.0)).show().html)   # stated
    assert [r["label"] for r in d["rows"][:3]] == ["T_a1", "T_a2", "T_a3"]
    assert d["rows"][0]["quantity"] == "torque"
    assert d["states"][0]["text"][0].endswith("kN.cm")


def test_trajectory_show_is_the_trajectory():
    from screwkit.paths import path_from_expressions, run_trajectory
    path = path_from_expressions(["alpha=8*sin(2*pi*t)", "beta=6*sin(2*pi*t+1)", "Zo=70+20*t"],
                                 ("alpha", "beta", "Zo"), samples=9)
    res = run_trajectory("3RRPRR", path)
    d = page_data(res.show().html)
    assert d["controls"]["type"] == "time" and d["controls"]["t"] == pytest.approx(res.t)
    got = np.array([s["values"][:3] for s in d["states"]])
    np.testing.assert_allclose(got, res.active, rtol=1e-12)
    got_c = np.array([s["values"][3:] for s in d["states"]])
    np.testing.assert_allclose(got_c, res.constraint, rtol=1e-12)


def test_singular_pose_is_shown_as_such():
    res = screwkit.analyze("2SPS+2SPR", {"alpha": 8.617907119683968, "beta": 0,
                                         "gamma": 8.617907119683968, "Zo": 80},
                           degrees=True, raise_on_singular=False)
    assert res.statics is None
    d = page_data(res.show().html)
    s = d["states"][0]
    assert s["level"] == "singular" and s["status"] == "singular"
    assert all(t.endswith("= n/a") for t in s["text"])
    assert all(v is None for v in s["values"])


def test_grid_size_is_bounded():
    with pytest.raises(InputError, match="at most 4096"):
        screwkit.view("2SPS+2SPR", steps=9)          # 9^4 = 6561 poses
    with pytest.raises(InputError, match="not an independent pose parameter"):
        screwkit.view("3RRPRR", {"gamma": 3}, degrees=True)


def test_cli_view_writes_the_page(tmp_path, capsys):
    out = tmp_path / "v.html"
    rc = main(["view", "3RRPRR", "--grid", "alpha=-5:5:3", "--steps", "1", "--html", str(out),
               "--force", "0,0,-10", "--json"])
    assert rc == 0
    info = json.loads(capsys.readouterr().out)
    assert info["states"] == 3 and info["controls"] == "grid"
    w = info["workload"]             # (structured, as the other commands' JSON; text beside)
    assert "F = [0, 0, -10] kN" in w["text"] and w["source"] == "given"
    assert w["force"] == [0.0, 0.0, -10.0] and w["force_unit"] == "kN"
    d = page_data(out.read_text())
    # the model's default pose (alpha = 5 deg) is the grid cell nearest it
    assert d["states"][d["start"]]["pose"]["alpha"] == pytest.approx(5.0, abs=1e-12)


def test_cli_view_refuses_a_path_with_a_pose(tmp_path, capsys):
    rc = main(["view", "3RRPRR", "--pose", "alpha=3", "--expr", "alpha=t", "--html",
               str(tmp_path / "v.html")])
    err = capsys.readouterr().err
    assert rc == 2 and len(err.strip().splitlines()) == 1 and "not both" in err


def test_cli_names_the_extra_when_plotly_is_missing(tmp_path, capsys, monkeypatch):
    import builtins
    real = builtins.__import__

    def no_plotly(name, *a, **k):
        if name.split(".")[0] == "plotly":
            raise ImportError("no plotly")
        return real(name, *a, **k)

    monkeypatch.setattr(builtins, "__import__", no_plotly)
    from screwkit.scene import _page
    _page._library.cache_clear()
    rc = main(["view", "3RRPRR", "--html", str(tmp_path / "v.html")])
    err = capsys.readouterr().err
    assert rc == 2 and len(err.strip().splitlines()) == 1
    assert 'pip install "screwkit[view]"' in err


def test_passive_leg_is_marked_and_has_no_actuation_arrow(tmp_path):
    from tricept import TRICEPT
    (tmp_path / "tricept.yaml").write_text(TRICEPT)
    tri = screwkit.load_pm(str(tmp_path / "tricept.yaml"))
    res = screwkit.analyze(tri, force=[0, 0, -500], torque=[0, 0, 0])
    d = page_data(res.show().html)
    assert [lg["passive"] for lg in d["legs"]] == [False, False, False, True]
    assert d["legs"][3]["label"] == "leg 4 (UP/column) · passive"
    rows = [(r["leg"], r["kind"]) for r in d["rows"]]
    assert (3, "actuation") not in rows and (3, "couple") in rows
    assert "F = [0, 0, -500] N, T = [0, 0, 0] N.mm at o (given)" == d["workload"]["text"]
    np.testing.assert_allclose(d["states"][0]["values"], res.statics.values, rtol=1e-12)


def test_jupyter_shows_the_same_page_inline(grid_view, grid_page):
    import html as html_lib
    frame = grid_view._repr_html_()
    assert frame.startswith("<iframe srcdoc=\"") and "height: 820px" in frame
    inner = html_lib.unescape(frame[len("<iframe srcdoc=\""):frame.index("\" style=")])
    assert page_data(inner)["states"] == page_data(grid_page)["states"]
    assert repr(grid_view) == ("View(3RRPRR: 27 poses on sliders (alpha, beta, Zo); "
                               "write_html(path), or display it in Jupyter)")
