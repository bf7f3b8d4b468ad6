"""3D drawings of legs and PMs (screwkit.viz) and ``screwkit leg --draw``.

Geometry checks compare the drawn arrows with lines built here from the leg's
joints (rule 2: a constraint force meets every R axis; rule 3: a couple is
perpendicular to every R axis), not with the analysis that the drawing used.
"""

from __future__ import annotations

import sys

import numpy as np
import pytest

pytest.importorskip("matplotlib")

import screwkit  # noqa: E402
from screwkit.cli import main  # noqa: E402
from screwkit.errors import InputError  # noqa: E402
from screwkit.legs import Placement  # noqa: E402
from screwkit.pm import default_catalog  # noqa: E402
from screwkit.viz import draw_leg, draw_pm, require_matplotlib  # noqa: E402
from screwkit.viz._artists import _clip_line  # noqa: E402


def read_png(path):
    """RGB array in [0, 1] of a PNG file."""
    try:
        from PIL import Image
        return np.asarray(Image.open(path).convert("RGB"), dtype=float) / 255.0
    except ImportError:  # pragma: no cover
        import matplotlib.image as mpimg
        return mpimg.imread(path)[..., :3].astype(float)


def assert_not_blank(img, min_fraction=0.03):
    """Not a blank page: enough pixels differ from the (white) background."""
    background = np.median(img.reshape(-1, 3), axis=0)
    differs = np.abs(img - background).max(axis=-1) > 0.1
    assert differs.mean() > min_fraction, differs.mean()
    assert img.std() > 0.05


def colour_fraction(img, hex_colour, tol=0.12):
    rgb = np.array([int(hex_colour[i:i + 2], 16) for i in (1, 3, 5)]) / 255.0
    return float((np.abs(img - rgb).max(axis=-1) < tol).mean())


def arrows(fig, prefix):
    ax = fig.axes[0]
    return [p for p in ax.patches if (p.get_gid() or "").startswith(prefix)]


def unit(v):
    v = np.asarray(v, float)
    return v / np.linalg.norm(v)


def parallel(u, v, tol=1e-9):
    return np.linalg.norm(np.cross(unit(u), unit(v))) < tol


def meet_point(p1, d1, p2, d2):
    """Intersection of two (intersecting) lines, by least squares p1 + s d1 = p2 + u d2."""
    A = np.column_stack([d1, -np.asarray(d2)])
    s, u = np.linalg.lstsq(A, np.asarray(p2) - p1, rcond=None)[0]
    x1, x2 = p1 + s * np.asarray(d1), p2 + u * np.asarray(d2)
    assert np.linalg.norm(x1 - x2) < 1e-9
    return x1


# ----------------------------------------------------------------------------- legs

@pytest.fixture(scope="module")
def drawn(tmp_path_factory):
    out = {}
    d = tmp_path_factory.mktemp("legs")
    for name in ("SPR", "RRPRR", "UPU/couple"):
        leg = screwkit.leg(name)
        path = d / (name.replace("/", "_") + ".png")
        fig = draw_leg(leg, leg.analyze(), out=path, dpi=80)
        out[name] = (leg, fig, path)
    return out


@pytest.mark.parametrize("name", ["SPR", "RRPRR", "UPU/couple"])
def test_leg_png_has_the_right_size_and_is_not_blank(drawn, name):
    leg, fig, path = drawn[name]
    img = read_png(path)
    w, h = fig.get_size_inches() * 80
    assert img.shape[:2] == (round(h), round(w))
    assert_not_blank(img)
    # the P joint is drawn as a sleeve; the actuation wrench in red
    sleeves = [c for c in fig.axes[0].collections if (c.get_gid() or "").startswith("joint:P")]
    assert len(sleeves) == sum(j.kind == "P" for j in leg.joints) == 1
    assert colour_fraction(img, "#d6261e") > 1e-4


def test_wrench_colours_follow_the_constraint_kinds(drawn):
    spr = read_png(drawn["SPR"][2])
    upu = read_png(drawn["UPU/couple"][2])
    assert colour_fraction(spr, "#2166ac") > 1e-4      # a constraint force
    assert colour_fraction(spr, "#1b7837") < 1e-5      # no couple
    assert colour_fraction(upu, "#1b7837") > 1e-4      # a constraint couple
    assert colour_fraction(upu, "#2166ac") < 1e-5      # no force


def test_spr_force_arrow_lies_on_the_line_through_S_parallel_to_R(drawn):
    leg, fig, _ = drawn["SPR"]
    (arrow,) = arrows(fig, "force:")
    tail, head = arrow.xyz
    np.testing.assert_allclose(tail, leg.A, atol=1e-9)   # S centre
    assert parallel(head - tail, leg.joint("R3").direction)


def test_rrprr_force_arrow_starts_where_R1_meets_R5(drawn):
    leg, fig, _ = drawn["RRPRR"]
    r1, r5 = leg.joint("R1"), leg.joint("R5")
    q = meet_point(r1.point, r1.direction, r5.point, r5.direction)
    (arrow,) = arrows(fig, "force:")
    tail, head = arrow.xyz
    np.testing.assert_allclose(tail, q, atol=1e-9)
    assert parallel(head - tail, leg.joint("R2").direction)
    labels = " ".join(t.get_text() for t in fig.axes[0].texts)
    assert "R1∩R5" in labels


def test_upu_couple_arrows_are_perpendicular_to_every_U_axis(drawn):
    leg, fig, _ = drawn["UPU/couple"]
    heads = arrows(fig, "couple:")
    assert len(heads) == 2          # two arrowheads
    for a in heads:
        d = a.xyz[1] - a.xyz[0]
        for j in leg.joints:
            if j.kind == "R":
                assert abs(np.dot(unit(d), j.direction)) < 1e-9
    lengths = sorted(np.linalg.norm(a.xyz[1] - a.xyz[0]) for a in heads)
    assert lengths[0] == pytest.approx(0.8 * lengths[1])


def test_actuation_force_is_drawn_along_the_leg_at_a(drawn):
    leg, fig, _ = drawn["SPR"]
    (arrow,) = arrows(fig, "actuation:")
    tail, head = arrow.xyz
    np.testing.assert_allclose(tail, leg.a, atol=1e-9)
    assert parallel(head - tail, leg.a - leg.A)


def test_equal_aspect(drawn):
    for leg, fig, _ in drawn.values():
        ax = fig.axes[0]
        ranges = np.array([np.ptp(ax.get_xlim()), np.ptp(ax.get_ylim()), np.ptp(ax.get_zlim())])
        aspect = np.asarray(ax.get_box_aspect(), float)
        np.testing.assert_allclose(aspect / aspect.max(), ranges / ranges.max(), rtol=1e-6)
        # the whole leg is inside the limits
        for p in leg.points:
            assert ax.get_xlim()[0] <= p[0] <= ax.get_xlim()[1]
            assert ax.get_zlim()[0] <= p[2] <= ax.get_zlim()[1]


def test_labels_and_axis_units(drawn):
    leg, fig, _ = drawn["RRPRR"]
    ax = fig.axes[0]
    texts = {t.get_text().strip() for t in ax.texts}
    for j in leg.joints:
        assert any(j.name in t for t in texts), j.name
    assert {"A", "a"} <= texts
    assert ax.get_xlabel() == "x [cm]" and ax.get_zlabel() == "z [cm]"
    assert "RRPRR" in fig._suptitle.get_text()
    legend_texts = [t.get_text() for t in fig.legends[0].get_texts()]
    assert "R axis" in legend_texts and any("constraint force" in t for t in legend_texts)


def test_draw_into_given_axes_and_explicit_view(tmp_path):
    from screwkit.viz import new_figure

    fig, ax = new_figure((5, 5), "3d")
    leg = screwkit.leg("SPR")
    got = draw_leg(leg, None, ax=ax, view=(30, -45), out=tmp_path / "x.png", dpi=50)
    assert got is fig
    assert (ax.elev, ax.azim) == (30, -45)
    assert not arrows(got, "force:")          # no analysis: no wrenches
    assert_not_blank(read_png(tmp_path / "x.png"))
    fig2, ax2 = new_figure((4, 4))
    ax2 = fig2.add_subplot(1, 1, 1)
    with pytest.raises(InputError, match="3D axes"):
        draw_leg(leg, ax=ax2)
    with pytest.raises(InputError, match="view"):
        draw_leg(leg, view="top")


def test_drawing_is_invariant_under_translation_of_the_leg():
    leg = screwkit.leg("SPR")
    shift = np.array([1000.0, -500.0, 20.0])
    moved = leg.moved(np.eye(3), shift)
    a1 = arrows(draw_leg(leg, leg.analyze()), "force:")[0].xyz
    a2 = arrows(draw_leg(moved, moved.analyze()), "force:")[0].xyz
    np.testing.assert_allclose(a2[0] - a1[0], shift, atol=1e-9)
    np.testing.assert_allclose(a2[1] - a2[0], a1[1] - a1[0], atol=1e-9)


def test_unwritable_output_is_an_input_error(tmp_path):
    leg = screwkit.leg("SPR")
    blocker = tmp_path / "a-file"          # a file as the parent: unwritable even for root
    blocker.write_text("not a directory")
    with pytest.raises(InputError, match="cannot write figure"):
        draw_leg(leg, out=blocker / "x.png")
    draw_leg(leg, out=tmp_path / "new-dir" / "x.png")   # missing folders are created
    assert (tmp_path / "new-dir" / "x.png").stat().st_size > 0


def test_missing_matplotlib_says_how_to_install(monkeypatch):
    monkeypatch.setitem(sys.modules, "matplotlib", None)
    with pytest.raises(InputError, match=r'pip install "screwkit\[plot\]"'):
        require_matplotlib()
    with pytest.raises(InputError, match="screwkit\\[plot\\]"):
        draw_leg(screwkit.leg("SPR"))


def test_clip_line_ends_on_the_box():
    lo, hi = np.zeros(3), np.array([10.0, 20.0, 30.0])
    p, d = np.array([5.0, 5.0, 5.0]), unit([1.0, 1.0, 0.0])
    a, b = _clip_line(p, d, lo, hi)
    for q in (a, b):
        assert np.all(q >= lo - 1e-12) and np.all(q <= hi + 1e-12)
        assert np.min(np.minimum(np.abs(q - lo), np.abs(q - hi))) < 1e-9  # on a face
        assert parallel(q - p, d) or np.allclose(q, p)
    assert _clip_line(np.array([50.0, 0, 0]), np.array([0, 1.0, 0]), lo, hi) is None


# ----------------------------------------------------------------------------- CLI

def test_cli_leg_draw(tmp_path, capsys):
    out = tmp_path / "spr.png"
    assert main(["leg", "SPR", "--draw", str(out)]) == 0
    assert f"drawing saved to {out}" in capsys.readouterr().out
    assert_not_blank(read_png(out))
    out2 = tmp_path / "upu.png"
    assert main(["leg", "UPU/couple", "--json", "--draw", str(out2)]) == 0
    import json
    assert json.loads(capsys.readouterr().out)["figure"] == str(out2)
    assert out2.exists()
    (tmp_path / "no").write_text("a file, not a folder")
    assert main(["leg", "SPR", "--draw", str(tmp_path / "no" / "x.png")]) == 2
    err = capsys.readouterr().err             # (said before any work: session 70)
    assert "cannot write" in err and "is a file, not a folder" in err


# ----------------------------------------------------------------------------- PM

def three_spr():
    spec = default_catalog().find_leg("SPR")
    o = np.array([0.0, 0.0, 80.0])
    legs, B, P = [], [], []
    for k in range(3):
        th = np.radians(120.0 * k)
        A = np.array([100 * np.cos(th), 100 * np.sin(th), 0.0])
        a = np.array([50 * np.cos(th), 50 * np.sin(th), 80.0])
        legs.append(spec.build(Placement(A, a, O=np.zeros(3), o=o)))
        B.append(A)
        P.append(a)
    return legs, np.array(B), np.array(P), o


VALUES = {"actuation": [32.0, -12.5, 21.0], "force": [-8.0, 14.0, 5.5]}


def pm_rows(legs):
    """Rows built from the geometry: actuation along A_i a_i, constraint force through
    A_i along the platform tangent (the SPR's R axis)."""
    rows = []
    for i, leg in enumerate(legs):
        rows.append({"kind": "actuation", "leg": i, "direction": leg.a - leg.A,
                     "point": leg.A, "value": VALUES["actuation"][i]})
        rows.append({"kind": "force", "leg": i, "direction": leg.joint("R3").direction,
                     "point": leg.A, "value": VALUES["force"][i]})
    return rows


@pytest.fixture(scope="module")
def pm_figure(tmp_path_factory):
    legs, B, P, o = three_spr()
    path = tmp_path_factory.mktemp("pm") / "pm.png"
    fig = draw_pm(legs, B, P, o, pm_rows(legs), out=path, dpi=70, title="3-SPR")
    return legs, fig, path


def test_pm_png_not_blank_and_polygons(pm_figure):
    legs, fig, path = pm_figure
    img = read_png(path)
    assert img.shape[:2] == tuple(round(x) for x in fig.get_size_inches()[::-1] * 70)
    assert_not_blank(img)
    gids = [c.get_gid() for c in fig.axes[0].collections]
    assert "base" in gids and "platform" in gids


def test_pm_arrows_scale_with_value_and_carry_its_sign(pm_figure):
    legs, fig, _ = pm_figure
    rows = pm_rows(legs)
    from screwkit.viz._pm_drawing import FLOOR, scale_key
    assert FLOOR == 0.25
    vmax = {}                      # each kind on its own: actuation forces, constraint forces
    for r in rows:
        vmax[scale_key(r)] = max(vmax.get(scale_key(r), 0.0), abs(r["value"]))
    lengths = {}
    for i, r in enumerate(rows):
        (a,) = arrows(fig, f"row:{i}")
        tail, head = a.xyz
        vec = head - tail
        # on the row's line, pointing along value * direction
        line_d = unit(r["direction"])
        assert parallel(vec, line_d)
        assert np.linalg.norm(np.cross(tail - r["point"], line_d)) < 1e-9
        assert np.sign(np.dot(vec, line_d)) == np.sign(r["value"])
        lengths[i] = np.linalg.norm(vec)
    longest = {}
    for i, r in enumerate(rows):
        longest[scale_key(r)] = max(longest.get(scale_key(r), 0.0), lengths[i])
    for i, r in enumerate(rows):
        want = max(abs(r["value"]) / vmax[scale_key(r)], 0.25)
        assert lengths[i] / longest[scale_key(r)] == pytest.approx(want, rel=1e-9)


def test_pm_actuation_arrows_start_at_the_platform_points(pm_figure):
    legs, fig, _ = pm_figure
    for i, leg in enumerate(legs):
        (a,) = arrows(fig, f"row:{2 * i}")
        np.testing.assert_allclose(a.xyz[0], leg.a, atol=1e-9)


def test_pm_value_labels_with_units(pm_figure):
    legs, fig, _ = pm_figure
    texts = [t.get_text() for t in fig.axes[0].texts]
    assert "$F_{a2}$ = -12.5 kN" in texts
    assert "$F_{c1}$ = -8 kN" in texts
    assert "$A_{1}$" in texts and "$a_{3}$" in texts


def test_pm_couples_values_override_and_custom_units():
    legs, B, P, o = three_spr()
    rows = [{"kind": "couple", "leg": 0, "direction": [0, 0, 1], "point": None, "value": 1.0},
            {"kind": "couple", "leg": 1, "direction": [0, 0, 1], "point": None, "value": 1.0,
             "label": "$M$"}]
    fig = draw_pm(legs, B, P, o, rows, values=[-50.0, 100.0], torque_unit="N.m")
    heads = arrows(fig, "row:0")
    assert len(heads) == 2              # double head
    tail, head = heads[0].xyz
    # beside its leg (a free vector), clear of the joints: off the leg's line by 12-35 %
    # of the base radius (100), between 25 % and 75 % of the leg's length
    A, a = legs[0].A, legs[0].a
    s = float(np.dot(tail - A, unit(a - A))) / np.linalg.norm(a - A)
    off = np.linalg.norm(np.cross(tail - A, unit(a - A)))
    assert 0.25 - 1e-9 <= s <= 0.75 + 1e-9 and 12.0 - 1e-9 <= off <= 35.0 + 1e-9
    assert min(np.linalg.norm(tail - j.point) for j in legs[0].joints) > 10.0
    assert head[2] < tail[2]            # negative value: points down
    np.testing.assert_allclose(unit(head - tail), [0, 0, -1], atol=1e-12)
    (l0, l1) = (np.linalg.norm(np.subtract(*arrows(fig, f"row:{i}")[0].xyz)) for i in (0, 1))
    assert l0 / l1 == pytest.approx(0.5)
    texts = [t.get_text() for t in fig.axes[0].texts]
    assert "$T_{r1}$ = -50 N.m" in texts and "$M$ = 100 N.m" in texts


@pytest.mark.parametrize("row, piece", [
    ({"kind": "torque", "leg": 0, "direction": [1, 0, 0], "point": [0, 0, 0]}, "kind 'torque'"),
    ({"kind": "force", "leg": 3, "direction": [1, 0, 0], "point": [0, 0, 0]}, "leg 3"),
    ({"kind": "force", "leg": 0, "direction": [0, 0, 0], "point": [0, 0, 0]}, "direction"),
    ({"kind": "force", "leg": 0, "direction": [1, 0, 0], "point": None}, "needs a point"),
    ({"kind": "force", "leg": 0, "direction": [1, 0], "point": [0, 0, 0]}, "direction"),
])
def test_pm_bad_rows(row, piece):
    legs, B, P, o = three_spr()
    with pytest.raises(InputError) as info:
        draw_pm(legs, B, P, o, [dict(row, value=1.0)])
    assert piece in str(info.value) and "wrench row 0" in str(info.value)


def test_pm_bad_inputs():
    legs, B, P, o = three_spr()
    with pytest.raises(InputError, match="base_points"):
        draw_pm(legs, B[:, :2], P, o)
    with pytest.raises(InputError, match="o must be"):
        draw_pm(legs, B, P, [0, 0])
    with pytest.raises(InputError, match="2 values given for 1 wrench rows"):
        draw_pm(legs, B, P, o, pm_rows(legs)[:1], values=[1.0, 2.0])
