"""Issue 22: the 3D view's page in a real headless browser (Debian's Chromium, driven by
Playwright): no console error and no request to the network, the WebGL canvas drawn with
every leg's colour (pixels of a screenshot), a slider (moved with the keyboard, as a user
would) changes the drawing and the numbers shown, which are the page data's; play/pause
moves a trajectory along.

Skipped, with the reason, only where Playwright or a Chromium cannot be had (``.ci/run``
installs Debian's chromium when it is missing)."""

import io
import json
import re

import numpy as np
import pytest

import screwkit

pytest.importorskip("plotly", reason="the 3D view needs plotly (screwkit[view])")
pytest.importorskip("playwright.sync_api", reason="the browser tests need playwright "
                    "(screwkit[test])")

from screwkit.scene import browser, find_chromium  # noqa: E402
from screwkit.viz import LEG_COLORS  # noqa: E402

if find_chromium() is None:
    pytest.skip("no Chromium on this machine (apt-get install chromium, or set "
                "SCREWKIT_CHROMIUM)", allow_module_level=True)


def pixels(png_bytes):
    import matplotlib.image as mpimg
    return (mpimg.imread(io.BytesIO(png_bytes), format="png")[..., :3] * 255).astype(int)


def colour_count(img, hex_colour, tol=24):
    rgb = np.array([int(hex_colour[k:k + 2], 16) for k in (1, 3, 5)])
    return int(np.sum(np.all(np.abs(img - rgb) <= tol, axis=-1)))


def plot_shot(s):
    return pixels(s.page.locator("#sk-plot").screenshot())


def test_cli_png(tmp_path, capsys):
    # (first: Playwright runs one browser at a time in a thread, and the others share one)
    from screwkit.cli import main
    html, png = tmp_path / "v.html", tmp_path / "v.png"
    rc = main(["view", "3UPU", "--steps", "1", "--html", str(html), "--png", str(png),
               "--json"])
    assert rc == 0
    info = json.loads(capsys.readouterr().out)
    assert info["png"] == str(png)
    import matplotlib.image as mpimg
    img = (mpimg.imread(png)[..., :3] * 255).astype(int)
    for i in range(3):
        assert colour_count(img, LEG_COLORS[i]) > 100


@pytest.fixture(scope="module")
def chromium():
    with browser() as b:
        yield b


@pytest.fixture(scope="module")
def grid_file(tmp_path_factory):
    out = tmp_path_factory.mktemp("view") / "grid.html"
    screwkit.view("2SPS+2SPR", {"alpha": 4, "beta": 3, "gamma": 2, "Zo": 80}, steps=3,
                  degrees=True).write_html(out)
    return out


def test_grid_page_in_chromium(chromium, grid_file):
    s = chromium.open(grid_file)
    if True:
        s.wait_drawn()
        page = s.page
        assert page.locator("#sk-plot canvas").count() >= 1
        before = plot_shot(s)
        # every leg's colour is on the canvas (its chain and arrows)
        for i in range(4):
            assert colour_count(before, LEG_COLORS[i]) > 150, f"leg {i + 1} not drawn"
        data = page.evaluate("window.screwkitView.data")
        k0 = page.evaluate("window.screwkitView.state()")
        assert k0 == data["start"]
        shown = page.locator("#sk-values td.sk-num").all_inner_texts()
        assert shown == [t.split(" = ")[1] for t in data["states"][k0]["text"]]
        status = page.locator("#sk-status").inner_text()
        assert "singularity level: regular" in status and "condition number" in status
        assert "workload: F = [-20, -30, -60] kN" in page.locator("#sk-workload").inner_text()
        # a user moves the alpha slider to its first value with the keyboard
        page.focus("#sk-slider-alpha")
        page.keyboard.press("Home")
        page.wait_for_timeout(800)
        k1 = page.evaluate("window.screwkitView.state()")
        assert k1 != k0
        assert data["states"][k1]["pose"]["alpha"] == pytest.approx(
            data["controls"]["params"][0]["values"][0])
        after = plot_shot(s)
        changed = np.mean(np.any(np.abs(after - before) > 30, axis=-1))
        assert changed > 0.002, "moving the slider did not change the drawing"
        shown = page.locator("#sk-values td.sk-num").all_inner_texts()
        assert shown == [t.split(" = ")[1] for t in data["states"][k1]["text"]]
        assert s.errors == [], s.errors
        assert s.requests == [], s.requests


def test_trajectory_plays(chromium, tmp_path):
    from screwkit.paths import path_from_expressions, run_trajectory
    path = path_from_expressions(["alpha=8*sin(2*pi*t)", "beta=6*sin(2*pi*t+1)", "Zo=70+20*t"],
                                 ("alpha", "beta", "Zo"), samples=21)
    out = tmp_path / "path.html"
    run_trajectory("3RRPRR", path).show().write_html(out)
    s = chromium.open(out)
    if True:
        s.wait_drawn()
        page = s.page
        assert page.evaluate("window.screwkitView.state()") == 0
        img = plot_shot(s)
        for i in range(3):
            assert colour_count(img, LEG_COLORS[i]) > 150, f"leg {i + 1} not drawn"
        page.click("#sk-play")
        page.wait_for_timeout(1500)
        page.click("#sk-play")                    # pause
        k = page.evaluate("window.screwkitView.state()")
        assert k > 0
        page.wait_for_timeout(600)
        assert page.evaluate("window.screwkitView.state()") == k      # paused
        assert re.search(rf"sample {k + 1} of 21", page.locator("#sk-controls").inner_text())
        assert s.errors == [] and s.requests == []
