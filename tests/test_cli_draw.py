"""Issue 6: `screwkit draw PM` (a 3D drawing of a PM at a pose with its wrenches).

The rows handed to draw_pm are checked against the statics (values, lines); the arrows drawn
are checked against value x direction (their length ratios are the value ratios); the PNG is
opened and checked."""

import numpy as np
import pytest

import screwkit
from screwkit.cli import main
from screwkit.engine import wrench_rows
from screwkit.viz import draw_pm

# the paper's workload, stated (only 3RRPRR and 2SPS+2SPR declare it as their default)
PAPER_LOAD = {"force": (-20.0, -30.0, -60.0), "torque": (-30.0, -30.0, 100.0)}
PAPER_ARGS = ["--force=-20,-30,-60", "--torque=-30,-30,100"]


def _png(path):
    import matplotlib.image as mpimg
    return mpimg.imread(path)[..., :3]


def _not_blank(img):
    return float(np.mean(np.any(img < 0.9, axis=2)))


@pytest.fixture(scope="module")
def rrprr():
    return screwkit.analyze("3RRPRR", {"alpha": 5, "beta": -3, "Zo": 80}, degrees=True)


def test_draw_3rrprr_png(tmp_path, capsys):
    out = tmp_path / "d.png"
    rc = main(["draw", "3RRPRR", "--pose", "alpha=5", "--pose", "beta=-3", "--pose", "Zo=80",
               "-o", str(out)])
    err = capsys.readouterr().err
    assert rc == 0 and f"wrote {out}" in err
    img = _png(out)
    assert img.shape[0] >= 800 and img.shape[1] >= 1000
    assert _not_blank(img) > 0.05


def test_rows_are_the_statics_on_their_lines(rrprr):
    rows, skipped = wrench_rows(rrprr)
    st, jac = rrprr.statics, rrprr.jacobian
    assert skipped == []
    assert [r["kind"] for r in rows] == ["actuation"] * 3 + ["force"] * 3
    assert [r["label"] for r in rows] == ["$F_{a1}$", "$F_{a2}$", "$F_{a3}$",
                                          "$F_{c1}$", "$F_{c2}$", "$F_{c3}$"]
    for r, v, vec, row in zip(rows, st.values, st.vectors, jac.J):
        assert r["value"] == v
        np.testing.assert_allclose(r["value"] * r["direction"], vec, atol=1e-12 * abs(v) + 1e-12)
        # the drawn line (point, direction) is the line of the Jacobian row [f; m]: m = p x f
        f = row[:3]
        np.testing.assert_allclose(np.cross(f, r["direction"]), 0.0, atol=1e-12)
        np.testing.assert_allclose(np.cross(r["point"], f), row[3:], atol=1e-9)


def test_arrows_drawn_are_value_times_direction(rrprr):
    rows, _ = wrench_rows(rrprr)
    sol = rrprr.solution
    fig = draw_pm(sol.legs, sol.base_points, sol.platform_points, sol.position, rows)
    arrows = {}
    for a in fig.axes[0].patches + fig.axes[0].artists:
        gid = a.get_gid() or ""
        if gid.startswith("row:"):
            arrows.setdefault(int(gid[4:]), a.xyz)
    assert sorted(arrows) == list(range(6))
    vals = np.array([r["value"] for r in rows])
    lengths = []
    for k, (p0, p1) in arrows.items():
        v = p1 - p0
        d = rows[k]["direction"] * np.sign(vals[k])
        assert v @ d > 0 and np.linalg.norm(np.cross(v, d)) < 1e-9 * np.linalg.norm(v)
        lengths.append(np.linalg.norm(v))
    from screwkit.viz._pm_drawing import scale_key
    keys = [scale_key(r) for r in rows]
    for key in set(keys):          # each kind scaled on its own (actuation, constraint forces)
        same = np.array([k == key for k in keys])
        big = same & (np.abs(vals) >= 0.25 * np.abs(vals[same]).max())   # above the floor
        ratio = np.array(lengths)[big] / np.abs(vals)[big]
        np.testing.assert_allclose(ratio, ratio[0], rtol=1e-9)


def test_draw_2sps2spr_and_couples(tmp_path, capsys):
    out = tmp_path / "s.png"
    assert main(["draw", "2SPS+2SPR", "-o", str(out), "--view", "25,-70"]) == 0
    assert _not_blank(_png(out)) > 0.05
    res = screwkit.analyze("3UPU", **PAPER_LOAD)
    rows, _ = wrench_rows(res)
    assert [r["kind"] for r in rows][3:] == ["couple"] * 3
    assert [r["label"] for r in rows][3:] == ["$T_{c1}$", "$T_{c2}$", "$T_{c3}$"]
    out2 = tmp_path / "u.png"
    assert main(["draw", "3UPU", "-o", str(out2), *PAPER_ARGS]) == 0
    assert _not_blank(_png(out2)) > 0.05


def test_singular_pose_is_drawn_without_values(tmp_path, capsys):
    out = tmp_path / "sing.png"
    s = "8.617907119683968"          # alpha = gamma at the actuation singularity (beta = 0, Zo = 80)
    rc = main(["draw", "2SPS+2SPR", "--pose", f"alpha={s}", "--pose", "beta=0",
               "--pose", f"gamma={s}", "--pose", "Zo=80", "-o", str(out)])
    err = capsys.readouterr().err
    assert rc == 0 and "actuation singularity" in err and out.exists()
    res = screwkit.analyze("2SPS+2SPR", {"alpha": float(s), "beta": 0, "gamma": float(s),
                                         "Zo": 80}, degrees=True, raise_on_singular=False)
    rows, _ = wrench_rows(res)
    assert all(np.isnan(r["value"]) for r in rows)


@pytest.mark.parametrize("argv, piece", [
    (["3RRPRR", "-o", "x.png", "--view", "20"], "--view"),
    (["3RRPRR", "-o", "x.png", "--pose", "alpha=70"], "unreachable"),
    (["3RRPRR", "-o", "x.png", "--dpi", "5"], "--dpi"),
    # a regular file as the parent directory fails even for root (CI runs as root,
    # where a missing directory would simply be created)
    (["3RRPRR", "-o", "{blocker}/x.png"], "cannot write"),
])
def test_errors_exit_2(capsys, tmp_path, argv, piece):
    blocker = tmp_path / "a-file"
    blocker.write_text("not a directory")
    argv = [a.format(blocker=blocker) for a in argv]
    rc = main(["draw", *argv, *PAPER_ARGS])
    err = capsys.readouterr().err
    assert rc == 2 and piece in err and err.count("\n") == 1
