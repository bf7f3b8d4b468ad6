"""Issue 13, figures: what makes them readable without asking (beyond test_figures_quality).

* every label of a drawing sits on a translucent white backing (a line crossing it does not
  hide a minus sign), and no leader line runs through another label;
* joint labels of a PM drawing are in their leg's colour (the colour of its chain);
* the legend of every Fig. 5 panel lies in a band that no curve enters;
* panel (d) names what it shows: the couples T_ci of an indeterminate 4UPU and the torques
  T_ri, or the forces F_ci and the torques T_ri of the 3RRPRR.
"""

from __future__ import annotations

import numpy as np
import pytest

# the paper's workload, stated (only 3RRPRR and 2SPS+2SPR declare it as their default)
PAPER_LOAD = {"force": (-20.0, -30.0, -60.0), "torque": (-30.0, -30.0, 100.0)}
PAPER_ARGS = ["--force=-20,-30,-60", "--torque=-30,-30,100"]

pytest.importorskip("matplotlib")

import screwkit  # noqa: E402
from screwkit.engine import wrench_rows  # noqa: E402
from screwkit.paths import path_from_expressions, run_trajectory  # noqa: E402
from screwkit.viz import draw_pm  # noqa: E402


def to_rgb(c):
    from matplotlib.colors import to_rgb as rgb
    return tuple(round(x, 4) for x in rgb(c))


@pytest.fixture(scope="module")
def drawn():
    out = {}
    for pm, joints in (("4UPU", True), ("3UPU", False)):
        res = screwkit.analyze(pm, **PAPER_LOAD)
        sol = res.solution
        rows, _ = wrench_rows(res)
        fig = draw_pm(sol.legs, sol.base_points, sol.platform_points, sol.position, rows,
                      dpi=70, joint_labels=joints)
        fig.canvas.draw()
        out[pm] = (res, fig)
    return out


def labels(fig):
    return [t for t in fig.axes[0].texts if t.get_gid() == "label"]


@pytest.mark.parametrize("pm", ["4UPU", "3UPU"])
def test_labels_have_a_translucent_white_backing(drawn, pm):
    _, fig = drawn[pm]
    for t in labels(fig):
        patch = t.get_bbox_patch()
        assert patch is not None, t.get_text()
        assert to_rgb(patch.get_facecolor()[:3]) == (1.0, 1.0, 1.0)
        assert 0.3 < patch.get_alpha() < 1.0


@pytest.mark.parametrize("pm", ["4UPU", "3UPU"])
def test_no_leader_runs_through_another_label(drawn, pm):
    from screwkit.viz._label_artist import _anchor_display

    _, fig = drawn[pm]
    ax = fig.axes[0]
    renderer = fig.canvas.get_renderer()
    texts = labels(fig)
    boxes = np.array([[e.x0, e.y0, e.x1, e.y1] for e in
                      (t.get_window_extent(renderer) for t in texts)])
    n_leaders = 0
    for i, t in enumerate(texts):
        if not t.leader:
            continue
        a = _anchor_display(ax, t.anchor)[0]
        end = np.clip(a, boxes[i, :2], boxes[i, 2:])
        if np.linalg.norm(end - a) < 2.0:
            continue
        n_leaders += 1
        pts = a + np.linspace(0.05, 0.95, 40)[:, None] * (end - a)
        for k, b in enumerate(boxes):
            if k == i:
                continue
            inside = (pts[:, 0] > b[0] + 1) & (pts[:, 0] < b[2] - 1) & \
                (pts[:, 1] > b[1] + 1) & (pts[:, 1] < b[3] - 1)
            assert not inside.any(), (t.get_text(), texts[k].get_text())
    assert n_leaders >= 1                       # the check ran on some leader


def test_joint_labels_are_in_the_colour_of_their_leg(drawn):
    res, fig = drawn["4UPU"]
    ax = fig.axes[0]
    for i, leg in enumerate(res.solution.legs):
        chain = [ln for ln in ax.get_lines() if len(ln.get_data_3d()[0]) >= 3
                 and np.allclose(np.array(ln.get_data_3d())[:, 0], leg.A)
                 and np.allclose(np.array(ln.get_data_3d())[:, -1], leg.a)]
        assert len(chain) == 1
        colour = to_rgb(chain[0].get_color())
        mine = [t for t in labels(fig) if f"$_{{{i + 1}}}$" in t.get_text()]
        assert len(mine) >= len(leg.joints)
        assert {to_rgb(t.get_color()) for t in mine} == {colour}


@pytest.fixture(scope="module")
def plotted():
    specs = {"4UPU": ["Xo=5*sin(2*pi*t)", "Yo=-3", "Zo=75+10*t", "gamma=10*cos(2*pi*t)"],
             "3RRPRR": ["alpha=8*sin(2*pi*t)", "beta=6*sin(2*pi*t+1)", "Zo=70+20*t"]}
    out = {}
    for pm, exprs in specs.items():
        model = screwkit.load_pm(pm)
        res = run_trajectory(model, path_from_expressions(exprs, model.independent,
                                                          samples=21), **PAPER_LOAD)
        fig = res.plot(None, dpi=50)
        fig.canvas.draw()
        out[pm] = (res, fig)
    return out


def panel_axes(fig, letter):
    """The axes of panel ``letter`` and its twins (same box)."""
    main = [ax for ax in fig.axes if ax.get_title(loc="left").startswith(f"({letter})")]
    assert len(main) == 1
    return [ax for ax in fig.axes if ax.bbox.bounds == main[0].bbox.bounds]


@pytest.mark.parametrize("pm", ["4UPU", "3RRPRR"])
@pytest.mark.parametrize("letter", "abcd")
def test_every_legend_lies_in_a_band_free_of_curves(plotted, pm, letter):
    _, fig = plotted[pm]
    axes = panel_axes(fig, letter)
    legends = [ax.get_legend() for ax in axes if ax.get_legend() is not None]
    assert len(legends) == 1
    box = legends[0].get_window_extent()
    n = 0
    for ax in axes:
        for ln in ax.get_lines():
            xy = ax.transData.transform(np.column_stack([ln.get_xdata(), ln.get_ydata()]))
            xy = xy[np.all(np.isfinite(xy), axis=1)]
            n += len(xy)
            inside = (xy[:, 0] > box.x0) & (xy[:, 0] < box.x1) & \
                (xy[:, 1] > box.y0) & (xy[:, 1] < box.y1)
            assert not inside.any(), (letter, ln.get_label())
    assert n > 0


def test_panel_d_names_couples_and_torques(plotted):
    res, fig = plotted["4UPU"]
    assert "couple" in res.constraint_kinds
    axes = panel_axes(fig, "d")
    title = axes[0].get_title(loc="left")
    assert "couples $T_{ci}$ and torques $T_{ri}$" in title and "forces" not in title
    assert any(ax.get_ylabel() == "$T_{ci}$, $T_{ri}$ [kN·cm]" for ax in axes)
    res, fig = plotted["3RRPRR"]
    assert "couple" not in res.constraint_kinds
    axes = panel_axes(fig, "d")
    title = axes[0].get_title(loc="left")
    assert "forces $F_{ci}$ and torques $T_{ri}$" in title and "couples" not in title
    assert {ax.get_ylabel() for ax in axes} == {"$F_{ci}$ [kN]", "$T_{ri}$ [kN·cm]"}
