"""Issue 13, figures: what can be checked on the drawings and plots an engineer reads.

The figures are opened (PNG size, not blank) and their artists inspected:
* one colour per leg: every arrow of a leg, its chain and its curves in every panel share one
  colour, different legs differ, and the drawing and the plot agree;
* labels: no two label boxes overlap and no label covers a marker, checked on boxes measured
  with plain matplotlib texts rebuilt from matplotlib's own projection after a draw, and on
  pixels (each label rendered alone);
* P joints are sleeves along the joint axis; couples are drawn away from the joints;
* undetermined values (4UPU) are marked, checked against a self-stress basis computed here
  (the null space of J^T by SVD);
* the singularity plot has a condition-number panel and a symmetric log force axis; curves
  that coincide stay visible (thinner, on top, labelled);
* the T_ri note comes from the data: through a_i for the 3RPS and through A_i for the
  2SPS+2SPR, checked on the Jacobian rows (a point q is on the line [f; m] iff q x f = m);
  no note and plotted T_ri for the 3RRPRR.
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

SINGULAR = "8.617907119683968"         # 2SPS+2SPR: alpha = gamma = this at t = 0.5, beta = 0


def read_png(path):
    import matplotlib.image as mpimg
    return mpimg.imread(path)[..., :3].astype(float)


def not_blank(img) -> float:
    return float(np.mean(np.any(img < 0.9, axis=2)))


def to_rgb(c):
    from matplotlib.colors import to_rgb as rgb
    return tuple(round(x, 4) for x in rgb(c))


def labels_of(ax):
    return [t for t in ax.texts if t.get_gid() == "label"]


def rebuilt_boxes(fig, ax, texts):
    """Window boxes of plain 2D texts placed where matplotlib's own projection (``ax.M``,
    set by the draw) puts each label's anchor, shifted by its offset in points."""
    from matplotlib.text import Text
    from matplotlib.transforms import IdentityTransform
    from mpl_toolkits.mplot3d import proj3d

    renderer = fig.canvas.get_renderer()
    out = []
    for t in texts:
        x, y, _ = proj3d.proj_transform(*([c] for c in t.anchor), ax.M)
        d = ax.transData.transform((x[0], y[0])) + np.array(t.offset) * fig.dpi / 72.0
        clone = Text(d[0], d[1], t.get_text(), fontsize=t.get_fontsize(),
                     ha=t.get_ha(), va=t.get_va(), transform=IdentityTransform())
        clone.set_figure(fig)
        bb = clone.get_window_extent(renderer)
        out.append((bb.x0, bb.y0, bb.x1, bb.y1))
    return np.array(out)


def overlap(a, b) -> float:
    dx = min(a[2], b[2]) - max(a[0], b[0])
    dy = min(a[3], b[3]) - max(a[1], b[1])
    return max(dx, 0.0) * max(dy, 0.0)


def marker_boxes(fig, ax):
    """Screen boxes of the scatter markers (points A_i, a_i, o, joint centres)."""
    from mpl_toolkits.mplot3d import proj3d

    out = []
    for c in ax.collections:
        if not hasattr(c, "_offsets3d"):
            continue
        xs, ys, zs = (np.atleast_1d(np.asarray(v, float)) for v in c._offsets3d)
        x, y, _ = proj3d.proj_transform(xs, ys, zs, ax.M)
        d = ax.transData.transform(np.column_stack([x, y]))
        r = np.sqrt(np.atleast_1d(c.get_sizes()))[0] / 2.0 * fig.dpi / 72.0
        out += [(p[0] - r, p[1] - r, p[0] + r, p[1] + r) for p in d]
    return np.array(out)


def chain_colour(ax, leg):
    """Colour of the 3D line drawn through A, the joints and a of ``leg``."""
    for line in ax.get_lines():
        x, y, z = (np.asarray(v, float) for v in line.get_data_3d())
        if len(x) >= 3 and np.allclose([x[0], y[0], z[0]], leg.A) and \
                np.allclose([x[-1], y[-1], z[-1]], leg.a):
            return to_rgb(line.get_color())
    raise AssertionError(f"no chain line for the leg at {leg.A}")


# ----------------------------------------------------------------------------- drawings

@pytest.fixture(scope="module")
def drawings(tmp_path_factory):
    d = tmp_path_factory.mktemp("draw")
    out = {}
    for pm, joints in (("4UPU", False), ("3RPS", False), ("3UPU", False), ("4UPU", True)):
        res = screwkit.analyze(pm, **PAPER_LOAD)
        sol = res.solution
        rows, _ = wrench_rows(res)
        path = d / f"{pm}.png" if pm in ("4UPU", "3UPU") and not joints else None
        fig = draw_pm(sol.legs, sol.base_points, sol.platform_points, sol.position, rows,
                      out=path, dpi=70, joint_labels=joints)     # its label pass sets ax.M
        out[(pm, joints)] = (res, rows, fig, path)
    return out


@pytest.mark.parametrize("key", [("4UPU", False), ("3UPU", False)])
def test_drawing_png_size_and_not_blank(drawings, key):
    _, _, fig, path = drawings[key]
    img = read_png(path)
    w, h = fig.get_size_inches() * 70
    assert img.shape[:2] == (round(h), round(w))
    assert not_blank(img) > 0.05 and img.std() > 0.05


@pytest.mark.parametrize("key", [("4UPU", False), ("3RPS", False), ("3UPU", False)])
def test_one_colour_per_leg_in_the_drawing(drawings, key):
    res, rows, fig, _ = drawings[key]
    ax = fig.axes[0]
    by_leg = {}
    for a in ax.patches:
        gid = a.get_gid() or ""
        if gid.startswith("row:"):
            leg = rows[int(gid[4:])]["leg"]
            by_leg.setdefault(leg, set()).add(to_rgb(a.get_edgecolor()))
    n = res.model.n_legs
    assert sorted(by_leg) == list(range(n))
    assert all(len(c) == 1 for c in by_leg.values()), by_leg       # one colour per leg
    colours = [next(iter(by_leg[i])) for i in range(n)]
    assert len(set(colours)) == n                                   # legs differ
    for i, leg in enumerate(res.solution.legs):
        assert chain_colour(ax, leg) == colours[i]
        for t in labels_of(ax):                                     # its value labels too
            if t.get_text().startswith(("$F_{a%d}" % (i + 1), "$T_{c%d}" % (i + 1))):
                assert to_rgb(t.get_color()) == colours[i]


@pytest.mark.parametrize("key", [("4UPU", False), ("3RPS", False), ("3UPU", False),
                                 ("4UPU", True)])
def test_no_label_over_another_label_or_a_marker(drawings, key):
    _, _, fig, _ = drawings[key]
    ax = fig.axes[0]
    texts = labels_of(ax)
    assert len(texts) >= 10
    boxes = rebuilt_boxes(fig, ax, texts)
    renderer = fig.canvas.get_renderer()
    for t, b in zip(texts, boxes):                     # the artist reports the same box
        e = t.get_window_extent(renderer)
        np.testing.assert_allclose([e.x0, e.y0, e.x1, e.y1], b, atol=0.6)
    for i in range(len(texts)):
        for k in range(i + 1, len(texts)):
            assert overlap(boxes[i], boxes[k]) == 0.0, (texts[i].get_text(), texts[k].get_text())
    for i, b in enumerate(boxes):
        for m in marker_boxes(fig, ax):
            assert overlap(b, m) <= 1.0, texts[i].get_text()      # at most a pixel's corner
    fb = fig.bbox
    assert np.all(boxes[:, 0] >= fb.x0) and np.all(boxes[:, 2] <= fb.x1)
    assert np.all(boxes[:, 1] >= fb.y0) and np.all(boxes[:, 3] <= fb.y1)


def test_labels_do_not_overlap_on_pixels(drawings):
    """Each label rendered alone (everything else hidden): no pixel is inked by two."""
    _, _, fig, _ = drawings[("4UPU", False)]
    ax = fig.axes[0]
    texts = labels_of(ax)
    hidden = [a for a in ax.get_children() + fig.legends + fig.texts
              if a.get_visible() and a not in texts]
    if fig._suptitle is not None:
        hidden.append(fig._suptitle)
    for a in hidden:
        a.set_visible(False)
    ax.set_axis_off()
    masks = []
    try:
        for t in texts:
            for u in texts:
                u.set_visible(u is t)
            fig.canvas.draw()
            img = np.asarray(fig.canvas.buffer_rgba())[..., :3]
            masks.append(np.any(img < 200, axis=-1))
    finally:
        for a in hidden + texts:
            a.set_visible(True)
        ax.set_axis_on()
    total = np.sum(masks, axis=0)
    assert all(m.any() for m in masks)
    assert total.max() == 1, "two labels ink the same pixel"


def test_joint_labels_carry_the_leg_number(drawings):
    res, _, fig, _ = drawings[("4UPU", True)]
    texts = {t.get_text() for t in labels_of(fig.axes[0])}
    for i, leg in enumerate(res.solution.legs):
        for j in leg.joints:
            assert any(t.startswith(f"{j.name}$_{{{i + 1}}}$") for t in texts), (i, j.name)


def test_p_joints_are_sleeves_along_their_axis(drawings):
    res, _, fig, _ = drawings[("3UPU", False)]
    ax = fig.axes[0]
    sleeves = [c for c in ax.collections if (c.get_gid() or "").startswith("joint:P")]
    joints = [j for leg in res.solution.legs for j in leg.joints if j.kind == "P"]
    assert len(sleeves) == len(joints) == 3
    assert not [a for a in ax.patches if (a.get_gid() or "").startswith("joint:")]  # no arrows
    L = res.model.normalisation.length
    for j in joints:
        (s,) = [s for s in sleeves if np.allclose(s.xyz.mean(axis=0), j.point, atol=1e-9 * L)]
        # the faces drawn are the box of these corners
        verts = np.asarray(s._faces, float).reshape(-1, 3)        # matplotlib's own copy
        assert {tuple(np.round(v, 9)) for v in verts} == {tuple(np.round(v, 9)) for v in s.xyz}
        c = s.xyz - s.xyz.mean(axis=0)
        axis = np.linalg.svd(c, full_matrices=False)[2][0]          # longest extent
        assert abs(abs(axis @ j.direction) - 1.0) < 1e-9
        extent = c @ axis
        assert 0.1 * leg_length(res, j) < np.ptp(extent) < 0.3 * leg_length(res, j)


def leg_length(res, joint):
    for leg in res.solution.legs:
        if any(j is joint for j in leg.joints):
            return leg.length
    raise AssertionError


def test_couples_are_drawn_away_from_the_joints(drawings):
    """3UPU: each couple arrow keeps >= 12 pixels on screen from every joint and from the
    P sleeves (it used to lie on the P arrows)."""
    from mpl_toolkits.mplot3d import proj3d

    res, rows, fig, _ = drawings[("3UPU", False)]
    ax = fig.axes[0]
    pts = np.array([j.point for leg in res.solution.legs for j in leg.joints])
    x, y, _ = proj3d.proj_transform(*pts.T, ax.M)
    joints = ax.transData.transform(np.column_stack([x, y]))
    n_couples = 0
    for a in ax.patches:
        gid = a.get_gid() or ""
        if gid.startswith("row:") and rows[int(gid[4:])]["kind"] == "couple":
            n_couples += 1
            p0, p1 = a.xyz
            s = p0 + np.linspace(0, 1, 25)[:, None] * (p1 - p0)
            x, y, _ = proj3d.proj_transform(*s.T, ax.M)
            arrow = ax.transData.transform(np.column_stack([x, y]))
            d = np.linalg.norm(arrow[:, None] - joints[None], axis=-1)
            assert d.min() >= 12.0 * fig.dpi / 100.0, d.min()
    assert n_couples >= 3


def _self_stress_rows(res):
    """Rows of J that a self-stress (x with J^T x = 0) moves: computed here by SVD."""
    J = res.jacobian.J
    L = res.model.normalisation.length
    Jn = J / np.linalg.norm(np.hstack([J[:, :3] * L, J[:, 3:]]), axis=1)[:, None]
    Jn = np.hstack([Jn[:, :3] * L, Jn[:, 3:]])
    u, s, vt = np.linalg.svd(Jn.T)
    rank = int(np.sum(s > 1e-9 * s[0]))
    null = vt[rank:]
    return np.flatnonzero(np.abs(null).max(axis=0) > 1e-9) if len(null) else np.array([], int)


def test_undetermined_values_are_marked_in_the_drawing(drawings):
    res, rows, fig, _ = drawings[("4UPU", False)]
    moved = set(_self_stress_rows(res).tolist())
    assert moved == {4, 5, 6, 7}                      # the four couples, not the actuators
    texts = [t.get_text() for t in labels_of(fig.axes[0])]
    for k, r in enumerate(rows):
        (t,) = [x for x in texts if x.startswith(r["label"] + " =")]
        assert t.endswith("*") == (k in moved), t
    notes = " ".join(t.get_text() for t in fig.texts)
    assert "* not determined by statics" in notes
    _, rows3, fig3, _ = drawings[("3RPS", False)]
    assert not any(t.get_text().endswith("*") for t in labels_of(fig3.axes[0]))


# ----------------------------------------------------------------------------- Fig. 5 plots

@pytest.fixture(scope="module")
def plots(tmp_path_factory):
    d = tmp_path_factory.mktemp("fig5")
    specs = {
        "3RPS": ["alpha=5*sin(2*pi*t)", "beta=3*sin(2*pi*t+1)", "Zo=70+20*t"],
        "3RRPRR": ["alpha=8*sin(2*pi*t)", "beta=6*sin(2*pi*t+1)", "Zo=70+20*t"],
        "4UPU": ["Xo=5*sin(2*pi*t)", "Yo=-3", "Zo=75+10*t", "gamma=10*cos(2*pi*t)"],
        "2SPS+2SPR": [f"alpha=2*{SINGULAR}*t", "beta=0", f"gamma=2*{SINGULAR}*t", "Zo=80"],
    }
    out = {}
    for pm, exprs in specs.items():
        model = screwkit.load_pm(pm)
        res = run_trajectory(model, path_from_expressions(exprs, model.independent,
                                                          samples=21), **PAPER_LOAD)
        path = d / f"{pm.replace('+', '_')}.png" if pm == "2SPS+2SPR" else None
        fig = res.plot(path, dpi=50)
        if pm == "4UPU":
            fig.canvas.draw()            # at the figure's dpi, for the legend's window box
        out[pm] = (res, fig, path)
    return out


def panel(fig, letter):
    for ax in fig.axes:
        if ax.get_title(loc="left").startswith(f"({letter})"):
            return ax
    raise AssertionError(f"no panel ({letter})")


def curves(fig):
    return {ln.get_label(): ln for ax in fig.axes for ln in ax.get_lines()
            if not ln.get_label().startswith("_")}


def curve(fig, name):
    """The curve whose label starts with mathtext ``name`` (e.g. ``$r_{1}$``)."""
    got = [ln for lab, ln in curves(fig).items() if lab.split(" ")[0].rstrip("*") == name]
    assert len(got) == 1, (name, list(curves(fig)))
    return got[0]


@pytest.mark.parametrize("pm", ["2SPS+2SPR"])
def test_plot_png_size_and_not_blank(plots, pm):
    _, fig, path = plots[pm]
    img = read_png(path)
    w, h = fig.get_size_inches() * 50
    assert img.shape[:2] == (round(h), round(w))
    assert not_blank(img) > 0.05


@pytest.mark.parametrize("pm", ["3RRPRR", "2SPS+2SPR", "4UPU"])
def test_one_colour_per_leg_in_every_panel(plots, pm):
    res, fig, _ = plots[pm]
    n = res.n_legs
    colour = {i: to_rgb(curve(fig, f"$r_{{{i + 1}}}$").get_color()) for i in range(n)}
    assert len(set(colour.values())) == n
    for i in range(n):
        assert to_rgb(curve(fig, f"$F_{{a{i + 1}}}$").get_color()) == colour[i]
    for lab, leg in zip(res.constraint_labels, res.constraint_legs):
        name = f"${lab.split('_')[0]}_{{{lab.split('_')[1]}}}$"
        assert to_rgb(curve(fig, name).get_color()) == colour[leg], lab
    for lab, ln in curves(fig).items():
        if lab.startswith("$T_{r"):
            i = int(lab[5]) - 1
            assert to_rgb(ln.get_color()) == colour[i]                   # T_ri as F_ci
            assert ln.get_linestyle() in ("--", ":")                    # torques dashed
            assert ln.get_markerfacecolor() == "white"                  # open markers


def test_drawing_and_plot_share_the_leg_colours(plots, drawings):
    res, fig, _ = plots["4UPU"]
    dres, _, dfig, _ = drawings[("4UPU", False)]
    for i, leg in enumerate(dres.solution.legs):
        assert chain_colour(dfig.axes[0], leg) == to_rgb(curve(fig, f"$r_{{{i + 1}}}$")
                                                         .get_color())


def test_notes_come_from_the_data(plots):
    """3RPS: the constraint forces pass through a_i (not A_i); 2SPS+2SPR: through A_i;
    3RRPRR: T_ri does not vanish, so it is plotted and no note is printed."""
    for pm, end in (("3RPS", "a"), ("2SPS+2SPR", "A")):
        res, fig, _ = plots[pm]
        a = screwkit.analyze(pm, **PAPER_LOAD)
        J, sol = a.jacobian.J, a.solution
        for k, r in enumerate(a.jacobian.rows):
            if r.kind != "force":
                continue
            f, m = J[k, :3], J[k, 3:]
            q = (sol.platform_points if end == "a" else sol.base_points)[r.leg]
            other = (sol.base_points if end == "a" else sol.platform_points)[r.leg]
            assert np.linalg.norm(np.cross(q, f) - m) < 1e-9 * np.linalg.norm(m) + 1e-9
            assert np.linalg.norm(np.cross(other, f) - m) > 1e-3 * np.linalg.norm(other)
        assert np.abs(res.T_r[res.ok]).max() < 1e-9 * np.nanmax(np.abs(res.leg_wrenches))
        sup = fig._suptitle.get_text()
        assert "all $T_{ri}$ = 0" in sup and f"through ${end}_i$" in sup, sup
        other_end = "A" if end == "a" else "a"
        assert f"${other_end}_i$" not in sup
        assert not [lab for lab in curves(fig) if lab.startswith("$T_{r")]
    res, fig, _ = plots["3RRPRR"]
    assert np.abs(res.T_r).max() > 1.0
    assert "T_{ri}$ = 0" not in fig._suptitle.get_text()
    assert {f"$T_{{r{i}}}$ (right axis)" for i in (1, 2, 3)} <= set(curves(fig))
    res, fig, _ = plots["2SPS+2SPR"]
    assert "legs 1, 4: no constraint" in fig._suptitle.get_text()   # SPS legs carry none


def test_undetermined_values_are_marked_in_the_plot(plots):
    res, fig, _ = plots["4UPU"]
    a = screwkit.analyze(res.pm, **PAPER_LOAD)
    moved = _self_stress_rows(a)
    labels = set(curves(fig))
    for k, lab in enumerate(a.jacobian.labels):
        name = f"${lab.split('_')[0]}_{{{lab.split('_')[1]}}}$"
        assert (name + "*" in labels) == (k in moved), (lab, sorted(labels))
    d = panel(fig, "d")
    legends = [ax.get_legend() for ax in fig.axes if ax.get_legend() is not None]
    assert any("not determined by statics" in lg.get_title().get_text() for lg in legends)
    assert not [lab for lab in curves(plots["3RRPRR"][1]) if lab.endswith("*")]
    # the legend of (d) (eight curves) lies in a band that no curve enters
    twin = [ax for ax in fig.axes if ax is not d and ax.bbox.bounds == d.bbox.bounds]
    box = (twin[0] if twin else d).get_legend().get_window_extent()
    for ax in [d] + twin:
        for ln in ax.get_lines():
            xy = ax.transData.transform(np.column_stack([ln.get_xdata(), ln.get_ydata()]))
            xy = xy[np.all(np.isfinite(xy), axis=1)]
            inside = (xy[:, 0] > box.x0) & (xy[:, 0] < box.x1) & (xy[:, 1] > box.y0) & \
                (xy[:, 1] < box.y1)
            assert not inside.any(), ln.get_label()


def test_singularity_plot(plots):
    res, fig, _ = plots["2SPS+2SPR"]
    assert res.counts()["singular"] == 1
    e = panel(fig, "e")                                   # the condition number
    assert e.get_yscale() == "log"
    (line,) = [ln for ln in e.get_lines() if ln.get_label() == "condition number"]
    c = np.asarray(line.get_ydata(), float)
    ok = np.isfinite(res.condition_number)
    np.testing.assert_allclose(c[ok], res.condition_number[ok])
    c_ax = panel(fig, "c")                                # forces: symmetric log
    assert c_ax.get_yscale() == "symlog"
    lt = c_ax.yaxis.get_transform().linthresh
    fa = np.abs(res.active[res.ok])
    assert lt <= np.median(fa) < 10 * lt and np.log10(lt) == round(np.log10(lt))
    assert fa.max() > 5 * lt                              # the spike is on the log part
    for pm in ("3RRPRR", "4UPU"):                         # regular paths stay linear
        assert panel(plots[pm][1], "c").get_yscale() == "linear"
    # coinciding curves: r4 = r1 and r3 = r2 are labelled and drawn thinner on top
    b = panel(fig, "b")
    lines = [ln for ln in b.get_lines() if ln.get_label().startswith("$r")]
    labels = [ln.get_label() for ln in lines]
    assert "$r_{4}$ (= $r_{1}$)" in labels and "$r_{3}$ (= $r_{2}$)" in labels
    for i in range(len(lines) - 1):
        assert lines[i + 1].get_zorder() > lines[i].get_zorder()
        assert lines[i + 1].get_linewidth() < lines[i].get_linewidth()
    np.testing.assert_allclose(res.extensions[res.ok, 3], res.extensions[res.ok, 0], rtol=1e-9)


@pytest.mark.parametrize("key", [("4UPU", False), ("3RPS", False), ("3UPU", False)])
def test_drawing_note_names_the_arrows_drawn_at_the_floor(drawings, key):
    """The note lists exactly the arrows shorter than 25 % of the largest of their kind."""
    from screwkit.viz._pm_drawing import scale_key
    _, rows, fig, _ = drawings[key]
    top = {}
    for r in rows:
        top[scale_key(r)] = max(top.get(scale_key(r), 0.0), abs(r["value"]))
    small = [r["label"] for r in rows if abs(r["value"]) < 0.25 * top[scale_key(r)]]
    note = " ".join(t.get_text() for t in fig.texts)
    if small:
        assert "drawn at 25% of the largest of its kind" in note
        assert note.split("n/a): ")[1].split("\n")[0].split(", ") == small
    else:
        assert "drawn at 25%" not in note
