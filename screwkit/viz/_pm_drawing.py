"""The drawing of a PM at one pose, from plain arrays (base and platform polygons, legs,
wrench rows with values).

See :mod:`screwkit.viz._leg_drawing` for the drawing conventions and the gids of the
artists; polygons are tagged ``"base"`` and ``"platform"``, the i-th wrench row ``"row:i"``.
"""

from __future__ import annotations

import numpy as np

from ..errors import InputError
from ..scene import FLOOR, arrow_fractions, plate_outline
from ..scene import scale_key as _kind_key
from ._artists import _Extent, _arrow, _clip_line, _double_head
from ._axes import _check_3d_axes, _check_view, _finish_axes
from ._figure import COLORS, leg_color, new_figure, require_matplotlib, save_figure
from ._labels import _Labeller
from ._leg_drawing import _LINE_STYLE, _leg_geometry
from ._spots import couple_tail
from ._view import _choose_pm_view

__all__ = ["draw_pm"]

_ROW_KINDS = ("actuation", "force", "couple")


def scale_key(row) -> str:
    """The arrows one row (a dict) is scaled with: :func:`screwkit.scene.scale_key` of its
    quantity (force or torque) and whether it is an actuation wrench."""
    q = row.get("quantity") or ("torque" if row["kind"] == "couple" else "force")
    return _kind_key(q, bool(row.get("actuation", row["kind"] == "actuation")))


#: How far (times the drawing's size) a constraint force starting on a joint centre or an end
#: point is moved along its line, out of the marker drawn there.
_CLEAR = 0.08


def _on_a_marker(p, legs, size) -> bool:
    """True where ``p`` is an S or U centre or an end point A, a of a leg (a marker)."""
    for leg in legs:
        pts = [leg.A, leg.a] + [j.point for j in leg.joints if j.spec.origin in "SU"]
        if np.min(np.linalg.norm(np.asarray(pts, float) - p, axis=1)) <= 1e-6 * size:
            return True
    return False


def _check_rows(rows, values, n_legs):
    rows = list(rows or [])
    if values is not None:
        values = np.asarray(values, float).reshape(-1)
        if values.size != len(rows):
            raise InputError(f"{values.size} values given for {len(rows)} wrench rows")
    out = []
    for i, r in enumerate(rows):
        if not isinstance(r, dict):
            raise InputError(f"wrench row {i}: expected a dict, got {type(r).__name__}")
        kind = r.get("kind")
        if kind not in _ROW_KINDS:
            raise InputError(f"wrench row {i}: kind {kind!r} is not one of "
                             f"{', '.join(_ROW_KINDS)}")
        leg = r.get("leg")
        if isinstance(leg, bool) or not isinstance(leg, (int, np.integer)) \
                or not 0 <= leg < n_legs:
            raise InputError(f"wrench row {i}: leg {leg!r} is not an index 0..{n_legs - 1}")
        try:
            d = np.asarray(r.get("direction"), float).reshape(-1)
        except (TypeError, ValueError):
            d = np.zeros(0)
        if d.shape != (3,) or not np.all(np.isfinite(d)) or np.linalg.norm(d) == 0:
            raise InputError(f"wrench row {i}: direction must be a non-zero finite 3-vector")
        d = d / np.linalg.norm(d)
        p = r.get("point")
        if p is not None:
            p = np.asarray(p, float).reshape(-1)
            if p.shape != (3,) or not np.all(np.isfinite(p)):
                raise InputError(f"wrench row {i}: point must be a finite 3-vector")
        elif kind != "couple":
            raise InputError(f"wrench row {i}: a {kind} needs a point on its line")
        v = float(values[i]) if values is not None else float(r.get("value", np.nan))
        q = r.get("quantity")
        if q not in (None, "force", "torque"):
            raise InputError(f"wrench row {i}: quantity must be 'force' or 'torque', got {q!r}")
        det = r.get("determined", True)
        act = r.get("actuation", kind == "actuation")
        if not isinstance(det, (bool, np.bool_)) or not isinstance(act, (bool, np.bool_)):
            raise InputError(f"wrench row {i}: 'determined' and 'actuation' must be True or "
                             "False")
        out.append(dict(kind=kind, leg=int(leg), direction=d, point=p, value=v,
                        label=r.get("label"), quantity=q, determined=bool(det),
                        actuation=bool(act)))
    return out


def _default_labels(rows):
    sym = {"actuation": "F_{{a{}}}", "force": "F_{{c{}}}", "couple": "T_{{r{}}}"}
    bases = [sym[r["kind"]].format(r["leg"] + 1) for r in rows]
    seen = {}
    for r, b in zip(rows, bases):
        if r["label"]:
            continue
        if bases.count(b) > 1:
            seen[b] = seen.get(b, 0) + 1
            b = b[:-1] + f",{seen[b]}}}"
        r["label"] = f"${b}$"


def _three_digits(v: float) -> str:
    """3 significant digits like ``{:.3g}`` (trailing zeros dropped), without an exponent
    for 0.001 <= |v| < 1e5."""
    a = abs(v)
    if a == 0.0 or not 1e-3 <= a < 1e5:
        return f"{v:.3g}"
    r = float(f"{v:.3g}")
    digits = 2 - int(np.floor(np.log10(abs(r))))
    text = f"{r:.{max(digits, 0)}f}"
    return text.rstrip("0").rstrip(".") if "." in text else text


def _polygon(ax, pts, face, edge, alpha, ext, gid=None):
    from mpl_toolkits.mplot3d.art3d import Poly3DCollection

    P = plate_outline(pts)         # (a central column's point is not a corner)
    if len(P) >= 3:
        poly = Poly3DCollection([P], facecolors=face, edgecolors="none", alpha=alpha, zorder=0)
        poly.set_gid(gid)
        ax.add_collection3d(poly)
    loop = np.vstack([P, P[:1]])
    ax.plot(*loop.T, color=edge, lw=1.2, zorder=1)
    ext.add(P)


def _as_points(x, name):
    try:
        P = np.asarray(x, float)
    except (TypeError, ValueError):
        raise InputError(f"{name} must be an (n, 3) array of numbers") from None
    if P.ndim != 2 or P.shape[1] != 3 or P.shape[0] < 1 or not np.all(np.isfinite(P)):
        raise InputError(f"{name} must be a finite (n, 3) array of points, got shape "
                         f"{P.shape}")
    return P


def draw_pm(legs, base_points, platform_points_world, o, rows=None, values=None, ax=None,
            out=None, title=None, *, force_unit: str = "kN", torque_unit: str = "kN.cm",
            length_unit: str = "cm", dpi: int = 150, joint_labels: bool = False,
            value_format: str | None = None, view=None, indeterminate_note: str | None = None):
    """Draw a PM at one pose with its wrench rows.

    Every leg, its chain, its wrench arrows and their labels are drawn in the leg's colour
    (:func:`~screwkit.viz.leg_color`, the colour of its curves in
    :func:`~screwkit.viz.plot_fig5`); actuation wrenches have filled heads, constraint
    wrenches open heads.

    Parameters
    ----------
    legs : sequence of Leg
        The placed legs at this pose.
    base_points : array_like (n, 3)
        Base polygon vertices ``A_i`` (in order around the polygon).
    platform_points_world : array_like (n, 3)
        Platform polygon vertices ``a_i`` in world coordinates.
    o : array_like (3,)
        Platform centre.
    rows : sequence of dict, optional
        Wrenches to draw, each ``{"kind": "actuation"|"force"|"couple", "leg": i,
        "direction": (3,), "point": (3,) or None, "value": float}`` and
        optionally ``"label"`` (mathtext allowed; default ``F_a{i+1}``,
        ``F_c{i+1}``, ``T_r{i+1}``), ``"quantity"`` (``"force"`` or ``"torque"``: the
        unit of the value), ``"actuation"`` (a couple that is an actuation torque;
        default: kind is ``"actuation"``) and ``"determined"`` (False: statics does not
        fix the value, e.g. the least-norm couples of an indeterminate PM; its label gets
        a ``*`` and the note explains it).  The drawn vector is ``value * direction``
        (direction normalised); arrow lengths are proportional to ``|value|``
        relative to the largest of the same kind (:func:`screwkit.scene.arrow_fractions`:
        actuation forces, constraint forces and torques scaled each on their own), with a
        floor of 25 % (:data:`screwkit.scene.FLOOR`) so that small values stay visible.
        A force is drawn on its line at the point nearest to its leg's
        platform point ``a`` (a constraint force that would start on a joint centre or an
        end point is moved along its line, clear of the marker there), its line dashed
        (dash-dotted for an actuation force);
        a couple as a double-headed arrow beside its leg, where it is clear of the
        joints, chains and other arrows, tied to the leg by a dotted line.  A NaN value
        is drawn at the floor length and labelled ``n/a``.
    values : array_like (len(rows),), optional
        Values overriding the rows' ``"value"`` (e.g. a statics solution).
    ax : Axes3D, optional
    out : str or Path, optional
        Save as PNG.
    title : str, optional
    force_unit, torque_unit, length_unit : str
        Units printed in the labels.
    dpi : int
    joint_labels : bool
        Label every joint, with its leg number as a subscript (``R1`` of leg 2 is
        ``R1₂``; cluttered for a whole PM; default off).
    value_format : str, optional
        Format of the values in the labels (default: 3 significant digits, written
        without an exponent between 0.001 and 100000: ``1420``, ``2.37``).
    view : (elev, azim) in degrees, optional
        Default: the view nearest (20, -60) in which no point ``A_i``, ``a_i``,
        ``o`` hides behind another or behind a leg.
    indeterminate_note : str, optional
        The note explaining the ``*`` of undetermined values (default: "not determined
        by statics (least-norm value)").

    Returns
    -------
    matplotlib.figure.Figure
    """
    require_matplotlib()
    _check_3d_axes(ax)
    legs = list(legs)
    if not legs:
        raise InputError("draw_pm needs at least one leg")
    B = _as_points(base_points, "base_points")
    Pw = _as_points(platform_points_world, "platform_points_world")
    o = np.asarray(o, float).reshape(-1)
    if o.shape != (3,) or not np.all(np.isfinite(o)):
        raise InputError("o must be a finite 3-vector")
    rows = _check_rows(rows, values, len(legs))
    _default_labels(rows)
    size = float(np.max(np.linalg.norm(B - B.mean(axis=0), axis=1))) if len(B) > 1 else 0.0
    if size == 0.0:
        size = max(leg.length for leg in legs)
    v = _check_view(view)
    if v is None:
        v = _choose_pm_view(legs, B, Pw, o, size)
    own = ax is None
    if own:
        fig, ax = new_figure((10.0, 7.2), "3d")
    else:
        fig = ax.figure
    ext = _Extent()
    _polygon(ax, B, COLORS["base"], "#636363", 0.35, ext, gid="base")
    _polygon(ax, Pw, COLORS["platform"], "#525252", 0.45, ext, gid="platform")
    kinds = {"base", "platform"}
    labeller = _Labeller(ax, v, size)
    for P in (B, Pw):                     # the polygons' edges: labels keep off them too
        for k in range(len(P)):
            labeller.segment(P[k], P[(k + 1) % len(P)])
    for i, leg in enumerate(legs):
        kinds |= _leg_geometry(ax, leg, ext, v, joint_labels=joint_labels,
                               end_labels=(f"$A_{{{i + 1}}}$", f"$a_{{{i + 1}}}$"), label_size=7,
                               labeller=labeller, color=leg_color(i), leg_tag=i + 1)
    ax.scatter(*o, s=25, color="#252525", depthshade=False, zorder=4)
    labeller.marker(o, 3.0)
    labeller.around(o, "o", "#252525", 8)
    drawn, floored = _draw_rows(ax, legs, rows, labeller, ext, v, size, force_unit,
                                torque_unit, value_format)
    kinds |= drawn
    box = ext.box(pad=0.05)
    for r in rows:
        if r["kind"] != "couple":
            seg = _clip_line(r["_p0"], r["direction"], *box)
            if seg is not None:
                ax.plot(*np.array(seg).T, color=leg_color(r["leg"]), lw=0.8,
                        ls=_LINE_STYLE[r["actuation"]], alpha=0.6, zorder=2)
                labeller.segment(*seg)
    note = []
    if rows:
        note.append("arrow lengths proportional to |value|\n(actuation forces, constraint "
                    "forces\nand torques each scaled on their own)")
        if floored:
            # four labels a line: the note keeps inside the figure however many there are
            lines = [", ".join(floored[k:k + 4]) for k in range(0, len(floored), 4)]
            note.append(f"drawn at {FLOOR:.0%} of the largest of its kind\n(value below "
                        f"{FLOOR:.0%} or n/a): " + ",\n".join(lines))
    if any(not r["determined"] for r in rows):
        note.append("* " + (indeterminate_note or
                            "not determined by statics\n  (least-norm value)"))
    leg_entries = [(leg_color(i), f"leg {i + 1} ({leg.name})") for i, leg in enumerate(legs)]
    _finish_axes(ax, box, v, length_unit, title, kinds, True, own, "\n".join(note) or None,
                 legs=leg_entries)
    labeller.place()
    save_figure(fig, out, dpi)
    return fig


def _draw_rows(ax, legs, rows, labeller, ext, v, size, force_unit, torque_unit, value_format):
    """The wrench arrows of ``rows`` and their value labels; returns the kinds drawn and the
    labels of the arrows drawn at the floor length."""
    max_len = 0.6 * size
    kinds, floored = set(), []
    fracs, low = arrow_fractions([r["value"] for r in rows], [scale_key(r) for r in rows])
    for irow, r in enumerate(rows):
        leg = legs[r["leg"]]
        is_couple = r["kind"] == "couple"
        key = r.get("quantity") or ("torque" if is_couple else "force")
        val = r["value"]
        color = leg_color(r["leg"])
        hollow = not r["actuation"]
        kinds.add(("actuation-couple" if r["actuation"] else "couple") if is_couple
                  else "actuation" if r["actuation"] else "force")
        unit = torque_unit if key == "torque" else force_unit
        star = "" if r["determined"] else "*"
        shown = value_format.format(val) if value_format else _three_digits(val)
        text = f"{r['label']} = {shown} {unit}{star}" if np.isfinite(val) \
            else f"{r['label']} = n/a"
        if low[irow]:
            floored.append(r["label"])
        vec = fracs[irow] * max_len * r["direction"]
        if is_couple:
            p0, root = couple_tail(v, leg.A, leg.a, vec, size,
                                   [m[0] for m in labeller.markers], labeller.segments)
            _double_head(ax, p0, p0 + vec, color, lw=2.0, scale=13, gid=f"row:{irow}",
                         hollow=hollow)
            ax.plot(*np.array([root, p0]).T, color=color, lw=0.8, ls=":", zorder=2)
            labeller.segment(root, p0)
        else:
            d, q = r["direction"], r["point"]
            p0 = q + float(np.dot(leg.a - q, d)) * d  # the line's point nearest to a
            if not r["actuation"] and _on_a_marker(p0, legs, size):
                # a force slides on its line: start it clear of the ball or dot it would
                # hide under (the 2SPS+2SPR's F_c2 at the S centre A2)
                p0 = p0 + _CLEAR * size * vec / np.linalg.norm(vec)
            _arrow(ax, p0, p0 + vec, color, lw=2.2, scale=13, gid=f"row:{irow}", hollow=hollow)
        r["_p0"] = p0
        ext.add(p0, p0 + vec)
        labeller.segment(p0, p0 + vec)
        labeller.marker(p0 + vec, 5.0)
        owner = labeller.arrow(p0, p0 + vec)
        u = vec / np.linalg.norm(vec)
        if is_couple:
            labeller.tip(p0 + vec, u, text, color, 7.5, priority=0)
        else:
            labeller.beside(p0 + 0.75 * vec, u, text, color, 7.5, owner=owner)
    return kinds, floored
