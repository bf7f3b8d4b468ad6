"""Fig. 5 panels (screwkit.viz.plot_fig5) on synthetic data."""

from __future__ import annotations

import numpy as np
import pytest

pytest.importorskip("matplotlib")

from screwkit.errors import InputError  # noqa: E402
from screwkit.viz import plot_fig5  # noqa: E402

N = 41
T = np.linspace(0.0, 2.0, N)
POSE = {"alpha": 10 * np.sin(np.pi * T), "beta": 5 * np.cos(np.pi * T), "Zo": 80 + 10 * T}
EXT = np.column_stack([90 + k + 3 * np.sin(np.pi * T + k) for k in range(3)])
FA = np.column_stack([-30 + 20 * np.sin(np.pi * T + k) for k in range(3)])
FC = np.column_stack([5 * np.cos(np.pi * T + k) for k in range(3)])
TR = np.column_stack([50 * np.sin(0.5 * np.pi * T + k) for k in range(3)])


def read_png(path):
    try:
        from PIL import Image
        return np.asarray(Image.open(path).convert("RGB"), dtype=float) / 255.0
    except ImportError:  # pragma: no cover
        import matplotlib.image as mpimg
        return mpimg.imread(path)[..., :3].astype(float)


def panel(fig, letter):
    """The main axes of a panel, found by its title."""
    for ax in fig.axes:
        if ax.get_title(loc="left").startswith(f"({letter})"):
            return ax
    raise AssertionError(f"no panel ({letter})")


def curves(fig):
    """label -> Line2D over all axes (twins included)."""
    out = {}
    for ax in fig.axes:
        for line in ax.get_lines():
            lab = line.get_label()
            if not lab.startswith("_"):
                out[lab] = line
    return out


@pytest.fixture(scope="module")
def full(tmp_path_factory):
    path = tmp_path_factory.mktemp("fig5") / "fig5.png"
    flags = (T > 0.9) & (T < 1.2)
    fig = plot_fig5(T, POSE, EXT, FA, FC, TR, flags=flags, out=path, dpi=60,
                    title="3RRPRR")
    return fig, path, flags


def test_png_size_and_not_blank(full):
    fig, path, _ = full
    img = read_png(path)
    w, h = fig.get_size_inches() * 60
    assert img.shape[:2] == (round(h), round(w))
    non_white = (img.min(axis=-1) < 0.9).mean()
    assert non_white > 0.03 and img.std() > 0.05


def test_four_panels_with_quantities_and_units(full):
    fig, _, _ = full
    a, b, c, d = (panel(fig, x) for x in "abcd")
    assert a.get_ylabel() == "angle [deg]"
    twin_labels = {ax.get_ylabel() for ax in fig.axes}
    assert "length [cm]" in twin_labels
    assert b.get_ylabel() == "$r_i$ [cm]"
    assert c.get_ylabel() == "$F_{ai}$ [kN]"
    assert d.get_ylabel() == "$F_{ci}$ [kN]" and "$T_{ri}$ [kN·cm]" in twin_labels
    assert "forces" in d.get_title(loc="left") and "torques" in d.get_title(loc="left")
    for ax in (c, d):
        assert ax.get_xlabel() == "t"


def test_curves_are_the_input_outside_flagged_samples(full):
    fig, _, flags = full
    lines = curves(fig)
    for i in range(3):
        for lab, data in ((f"$r_{{{i + 1}}}$", EXT[:, i]), (f"$F_{{a{i + 1}}}$", FA[:, i]),
                          (f"$F_{{c{i + 1}}}$", FC[:, i])):
            y = np.asarray(lines[lab].get_ydata(), float)
            np.testing.assert_array_equal(y[~flags], data[~flags])
            assert np.isnan(y[flags]).all()
        y = np.asarray(lines[f"$T_{{r{i + 1}}}$ (right axis)"].get_ydata(), float)
        np.testing.assert_array_equal(y[~flags], TR[~flags, i])
    np.testing.assert_array_equal(np.asarray(lines[r"$\alpha$"].get_ydata())[~flags],
                                  POSE["alpha"][~flags])


def test_flagged_samples_are_shaded_on_every_panel(full):
    fig, _, flags = full
    lo, hi = T[flags][0], T[flags][-1]
    for x in "abcd":
        ax = panel(fig, x)
        spans = [p for p in ax.patches if p.get_width() > 0]
        assert spans, x
        x0 = min(p.get_x() for p in spans)
        x1 = max(p.get_x() + p.get_width() for p in spans)
        assert x0 < lo and x1 > hi            # covers the flagged samples ...
        assert x0 > T[~flags & (T < lo)][-1] - 1e-12   # ... and not the regular ones
    assert f"{int(flags.sum())} of {N} samples" in fig._suptitle.get_text()


def test_three_panels_without_constraint_data_and_radian_pose():
    pose_rad = {"alpha": np.radians(POSE["alpha"]), "Zo": POSE["Zo"]}
    fig = plot_fig5(T, pose_rad, EXT, FA, pose_angles_in="rad")
    titles = [ax.get_title(loc="left")[:3] for ax in fig.axes if ax.get_title(loc="left")]
    assert titles == ["(a)", "(b)", "(c)"]
    np.testing.assert_allclose(curves(fig)[r"$\alpha$"].get_ydata(), POSE["alpha"])


def test_only_forces_in_panel_d_custom_labels_and_units():
    fig = plot_fig5(T, POSE, EXT[:, :2], FA[:, :2], constraint_forces=FC[:, :2],
                    labels={"constraint_forces": ["$F_{c2}$", "$F_{c3}$"]},
                    units={"force": "N", "length": "mm"})
    d = panel(fig, "d")
    assert "torques" not in d.get_title(loc="left")
    assert d.get_ylabel() == "$F_{ci}$ [N]" and panel(fig, "b").get_ylabel() == "$r_i$ [mm]"
    assert {"$F_{c2}$", "$F_{c3}$"} <= set(curves(fig))


def test_non_finite_values_break_the_curve():
    fa = FA.copy()
    fa[5, 0] = np.inf
    fig = plot_fig5(T, POSE, EXT, fa)
    assert np.isnan(curves(fig)["$F_{a1}$"].get_ydata()[5])


@pytest.mark.parametrize("kwargs, piece", [
    ({"extensions": EXT[:-1]}, "extensions must have shape (N, k) with N = 41"),
    ({"active": "abc"}, "active must be an array of numbers"),
    ({"constraint_torques": TR[:3]}, "constraint_torques"),
    ({"pose": {"alpha": T[:3]}}, "pose['alpha']"),
    ({"pose": [1, 2]}, "pose must be a dict"),
    ({"flags": np.zeros(3, bool)}, "flags must have shape (41,)"),
    ({"units": {"speed": "m/s"}}, "unknown unit keys"),
    ({"labels": {"active": ["x"]}}, "labels['active'] has 1 names for 3 columns"),
    ({"t": T[::-1]}, "t must increase strictly"),
    ({"t": np.full(N, np.nan)}, "NaN"),
    ({"pose_angles_in": "grad"}, "pose_angles_in"),
    ({"legs": {"active": [0, 1]}}, "legs['active'] has 2 leg indices for 3 columns"),
    ({"legs": {"active": ["x", 1, 2]}}, "legs['active'] must be leg indices"),
    ({"determined": {"active": np.ones(2, bool)}}, "determined['active'] must have shape"),
    ({"condition_number": T[:3]}, "condition_number must have shape (N, k) with N = 41"),
    ({"force_scale": "log"}, "force_scale must be 'auto', 'linear' or 'symlog'"),
])
def test_bad_inputs_raise_input_errors(kwargs, piece):
    args = dict(t=T, pose=POSE, extensions=EXT, active=FA)
    args.update(kwargs)
    with pytest.raises(InputError) as info:
        plot_fig5(**args)
    assert piece in str(info.value), str(info.value)


def test_leg_colours_markers_and_the_columns_legs():
    """Column j of the constraint forces is drawn in the colour of the leg given for it,
    the colour of that leg's r_i and F_ai; its torques dashed with open markers."""
    fig = plot_fig5(T, POSE, EXT, FA, FC[:, :2], TR[:, :2],
                    legs={"constraint_forces": [2, 1], "constraint_torques": [2, 0]})
    c = curves(fig)
    col = {i: c[f"$r_{{{i + 1}}}$"].get_color() for i in range(3)}
    assert len(set(col.values())) == 3
    for i in range(3):
        assert c[f"$F_{{a{i + 1}}}$"].get_color() == col[i]
        assert c[f"$F_{{a{i + 1}}}$"].get_marker() == c[f"$r_{{{i + 1}}}$"].get_marker()
    assert c["$F_{c1}$"].get_color() == col[2] and c["$F_{c2}$"].get_color() == col[1]
    t1, t2 = c["$T_{r1}$ (right axis)"], c["$T_{r2}$ (right axis)"]
    assert t1.get_color() == col[2] and t2.get_color() == col[0]
    assert t1.get_linestyle() == "--" and t1.get_markerfacecolor() == "white"


def test_determined_flags_mark_the_names():
    det = np.ones((N, 3), bool)
    det[5, 1] = False
    fig = plot_fig5(T, POSE, EXT, FA, FC, determined={"constraint_forces": det})
    names = set(curves(fig))
    assert "$F_{c2}$*" in names and "$F_{c1}$" in names and "$F_{c3}$" in names
    titles = [ax.get_legend().get_title().get_text() for ax in fig.axes if ax.get_legend()]
    assert any("not determined by statics" in t for t in titles)


def test_symlog_near_a_singularity_and_the_condition_panel():
    """A 1/distance spike with a spiking condition number: symmetric log axes whose linear
    part ends at the power of ten below the median magnitude; a smooth path stays linear."""
    d = np.abs(T - 1.0) + 0.02
    spike = np.column_stack([30.0 / d, -25.0 / d, 20.0 + 0 * d])
    cond = 3.0 / d
    fig = plot_fig5(T, POSE, EXT, spike, condition_number=cond,
                    condition_levels={"ill-conditioned": 1e2})
    c = panel(fig, "c")
    assert c.get_yscale() == "symlog"
    lt = c.yaxis.get_transform().linthresh
    med = np.median(np.abs(spike))
    assert lt <= med < 10 * lt and float(np.log10(lt)).is_integer()
    e = panel(fig, "d")                           # no constraint panel: (d) is the condition
    assert e.get_yscale() == "log"
    np.testing.assert_allclose(e.get_lines()[0].get_ydata(), cond)
    assert "ill-conditioned" in " ".join(t.get_text() for t in e.texts)
    smooth = plot_fig5(T, POSE, EXT, spike, condition_number=np.full(N, 3.0))
    assert panel(smooth, "c").get_yscale() == "linear"   # no singularity: linear


def test_equal_curves_stay_visible():
    ext = EXT.copy()
    ext[:, 2] = ext[:, 0]
    fig = plot_fig5(T, POSE, ext, FA)
    lines = [ln for ln in panel(fig, "b").get_lines() if ln.get_label().startswith("$r")]
    assert lines[2].get_label() == "$r_{3}$ (= $r_{1}$)"
    assert lines[2].get_zorder() > lines[0].get_zorder()
    assert lines[2].get_linewidth() < lines[0].get_linewidth()
