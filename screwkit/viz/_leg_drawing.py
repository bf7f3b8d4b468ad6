"""3D drawings of legs (and the conventions of the drawings of legs and PMs), with their wrenches.

:func:`draw_leg` draws one :class:`~screwkit.legs.Leg` (its equivalent chain
and, given an analysis, its constraint and actuation wrenches);
:func:`~screwkit.viz.draw_pm` (:mod:`screwkit.viz._pm_drawing`) draws a PM at one
pose from plain arrays (base and platform polygons, legs, and wrench rows with
values).  Both return a matplotlib ``Figure`` and optionally save it as PNG.

matplotlib is optional (``pip install "screwkit[plot]"``); it is imported
inside the functions, and figures are made on an Agg canvas (no display, no
pyplot global state).

Drawing conventions
-------------------
* equivalent chain: grey polyline ``A -> joint points -> a``;
* R (and H) axis: dark segment of a quarter of the leg length centred at its point;
* P: a grey square sleeve along its sliding direction (the chain runs through it);
* S centre: large purple ball; U centre: small purple dot (its two R axes drawn);
* constraint wrenches have open (white) heads, actuation wrenches filled heads;
* constraint force: arrow at its named point, its line dashed across the drawing;
  where the point is the meeting point of two axes (``R1^R5``) the axes are
  extended to it (dotted);
* constraint couple: arrow with two heads (a free vector: drawn beside the leg where it
  is clear of the joints, the chain and the other arrows, tied to the leg by a dotted
  line);
* actuation wrench: a force is drawn where its line is closest to ``a`` (its line
  dash-dotted); an actuation couple has two filled heads;
* one leg (:func:`draw_leg`): wrenches coloured by kind (blue constraint force, green
  couple, magenta finite-pitch wrench, red actuation); a PM (:func:`draw_pm`): every
  leg, its chain and its wrenches in the leg's colour (:func:`~screwkit.viz.leg_color`,
  the colour of its curves in :func:`~screwkit.viz.plot_fig5`);
* labels are placed by a pass on their screen boxes (:mod:`screwkit.viz._labels`): no
  label covers another label or a marker; a label moved off its anchor gets a leader.

Artists are tagged with matplotlib gids so that callers (and tests) can find
them: arrows ``"force:k"``, ``"couple:k"``, ``"screw:k"`` (k-th constraint
member), ``"actuation:<kind>"``, ``"row:i"`` (the i-th wrench row of :func:`draw_pm`);
polygons ``"base"`` and ``"platform"``; the sleeve of a P joint ``"joint:P2"``; the labels
``"label"``.  Arrows carry their tail and head in data coordinates as ``arrow.xyz``.
"""

from __future__ import annotations

import numpy as np

from ..errors import InputError
from ._artists import _Extent, _arrow, _clip_line, _double_head, _sleeve
from ._axes import _check_3d_axes, _check_view, _finish_axes
from ._figure import COLORS, new_figure, require_matplotlib, save_figure
from ._labels import _Labeller
from ._spots import couple_tail
from ._view import _View, _choose_view

__all__ = ["draw_leg"]

#: The line of a force drawn across the drawing: dash-dot for an actuation force, dashed for
#: a constraint force.
_LINE_STYLE = {True: (0, (6, 2.5, 1.5, 2.5)), False: (0, (5, 4))}

def _leg_direction_groups(leg, extra=()):
    """Directions drawn at each point of a leg (for the choice of view)."""
    L = leg.length
    legdir = (leg.a - leg.A) / L
    groups = {}
    for j in leg.joints:
        if j.spec.origin == "S":
            continue
        key = tuple(np.round(j.point / L, 3))
        groups.setdefault(key, [legdir]).append(j.direction)
    for p, d in extra:
        groups.setdefault(tuple(np.round(np.asarray(p) / L, 3)), []).append(np.asarray(d))
    return list(groups.values()) or [[legdir]]


def _joint_name(name: str, tag) -> str:
    """A joint's label; in a PM drawing it carries the leg number as a subscript (``R1₂``)."""
    return name if tag is None else f"{name}$_{{{tag}}}$"


def _leg_geometry(ax, leg, ext: _Extent, view: _View, joint_labels=True,
                  end_labels=("A", "a"), label_size=7, labeller=None, color=None, leg_tag=None):
    """Draw a leg's chain and joints; returns the set of element kinds drawn.

    ``color``: the chain's colour, also of its joint labels (default grey, labels in the
    colours of the joint kinds; a PM drawing passes the leg's colour);
    ``leg_tag``: the leg number carried by the joint labels.  The joints, end points and
    chain segments are registered with the labeller as obstacles of the labels.
    """
    L = leg.length
    seg = 0.25 * L
    kinds = {"chain", "end"}
    lab = labeller or _Labeller(ax, view, L)
    chain = [leg.A] + [j.point for j in leg.joints] + [leg.a]
    pts = [chain[0]]
    for p in chain[1:]:
        if np.linalg.norm(p - pts[-1]) > 1e-9 * L:
            pts.append(p)
    pts = np.array(pts)
    ax.plot(pts[:, 0], pts[:, 1], pts[:, 2], color=color or COLORS["chain"], lw=3.0,
            alpha=0.9 if color is None else 0.75, solid_capstyle="round", zorder=1)
    ext.add(pts)
    for i in range(len(pts) - 1):
        lab.block(pts[i], pts[i + 1] - pts[i])
        lab.block(pts[i + 1], pts[i] - pts[i + 1])
        lab.segment(pts[i], pts[i + 1])
    centres_done, centre_labels = set(), []
    for j in leg.joints:
        origin = j.spec.origin
        group = f"{origin}{j.spec.position}"
        act = " (actuated)" if j.actuated else ""
        if origin == "S":
            if group not in centres_done:
                centres_done.add(group)
                ax.scatter(*j.point, s=140, color=COLORS["S"], depthshade=False, zorder=4,
                           edgecolors="white", linewidths=0.8)
                lab.marker(j.point, 6.5)
                kinds.add("S")
                if joint_labels:
                    centre_labels.append((j.point, _joint_name(group, leg_tag) + act,
                                          color or COLORS["S"]))
            continue
        if j.spec.parallelogram:
            # the real four-bar, in its plane (normal to the hinges): two bars from the first
            # hinge axis to the second, the two links they join (drawn normal to the bars,
            # along the translation d), and a short stub of each of the four hinges
            h, d, w = j.hinge, j.direction, 0.08 * L
            c = [j.point - w * d, j.point + w * d, j.point + w * d + j.bar, j.point - w * d + j.bar]
            loop = np.array(c + [c[0]])
            ax.plot(*loop.T, color=COLORS["P"], lw=1.8, zorder=3, gid=f"joint:{j.name}")
            for q in c:
                stub = np.array([q - 0.03 * L * h, q + 0.03 * L * h])
                ax.plot(*stub.T, color=COLORS["R"], lw=2.4, zorder=3, solid_capstyle="butt")
            ext.add(np.array(c))
            for k in range(4):
                lab.segment(c[k], c[(k + 1) % 4])
            kinds.add("Pa")
            if joint_labels:
                lab.around(j.point + 0.5 * j.bar + w * d, _joint_name(j.name, leg_tag) + act,
                           color or COLORS["P"], label_size, priority=2)
            continue
        if j.kind == "P":
            d = j.direction
            corners = _sleeve(ax, j.point, d, 0.09 * L, 0.03 * L, COLORS["P"], COLORS["P_fill"],
                              gid=f"joint:{j.name}")
            ext.add(corners)
            lab.segment(j.point - 0.09 * L * d, j.point + 0.09 * L * d)
            lab.marker(j.point, 4.0)
            kinds.add("P")
            if joint_labels:
                lab.block(j.point, d)
                lab.block(j.point, -d)
                lab.around(j.point, _joint_name(j.name, leg_tag) + act, color or COLORS["P"],
                           label_size, priority=2)
            continue
        # R or H axis (also the axes of U and C)
        p0, p1 = j.point - 0.5 * seg * j.direction, j.point + 0.5 * seg * j.direction
        ax.plot(*np.array([p0, p1]).T, color=COLORS["R"], lw=2.4, zorder=3,
                solid_capstyle="butt")
        ext.add(p0, p1)
        lab.segment(p0, p1)
        kinds.add("H" if j.kind == "H" else "R")
        if origin == "U" and group not in centres_done:
            centres_done.add(group)
            ax.scatter(*j.point, s=45, color=COLORS["U"], depthshade=False, zorder=4)
            lab.marker(j.point, 3.5)
            kinds.add("U")
            if joint_labels:
                centre_labels.append((j.point, _joint_name(group, leg_tag), color or COLORS["U"]))
        if joint_labels:
            tag = _joint_name(j.name, leg_tag) + (
                "" if j.kind == "R" else f" ({j.kind}, pitch {j.pitch:.3g})") + act
            sgn = lab.axis_end(j.point, j.direction)
            lab.tip(j.point + sgn * 0.5 * seg * j.direction, sgn * j.direction, tag,
                    color or COLORS["R"], label_size)
        else:
            lab.block(j.point, j.direction)
            lab.block(j.point, -j.direction)
    ax.scatter(*np.array([leg.A, leg.a]).T, s=22, marker="s", color=COLORS["end"],
               depthshade=False, zorder=4)
    lab.marker(leg.A, 2.5)
    lab.marker(leg.a, 2.5)
    if end_labels:
        ends = list(end_labels)
        for k, p in enumerate((leg.A, leg.a)):
            # a U or S centre at an end point: one label for both ("a, U3"), not two
            # labels fighting for the same spot
            same = [t for t in centre_labels if np.linalg.norm(t[0] - p) <= 1e-9 * L] \
                if leg_tag is None else []          # (a PM's joint labels keep leg colours)
            if same:
                ends[k] = ", ".join([ends[k]] + [t[1] for t in same])
                centre_labels = [t for t in centre_labels if not any(t is x for x in same)]
        lab.around(leg.A, ends[0], "k", label_size + 1)
        lab.around(leg.a, ends[1], "k", label_size + 1)
    for q, text, c in centre_labels:
        lab.around(q, text, c, label_size, priority=2)
    return kinds


def draw_leg(leg, analysis=None, ax=None, out=None, *, dpi: int = 150, title: str | None = None,
             length_unit: str = "cm", joint_labels: bool = True, legend: bool = True,
             view=None):
    """Draw one leg with its constraint and actuation wrenches.

    Parameters
    ----------
    leg : Leg
        A placed leg (:func:`screwkit.leg`).
    analysis : LegAnalysis, optional
        ``leg.analyze()``; when given, its constraint wrenches (blue forces,
        green couples) and its actuation wrench (red) are drawn.
    ax : mpl_toolkits.mplot3d.axes3d.Axes3D, optional
        Draw into this axes (default: a new 9 x 6.4 inch figure with the legend
        beside the drawing).
    out : str or Path, optional
        Save the figure there (PNG).
    dpi : int
        Resolution of the saved file.
    title : str, optional
        Default: leg name, marked string and the analysis summary.
    length_unit : str
        Unit of the leg's coordinates, for the axis labels (display only).
    joint_labels, legend : bool
    view : (elev, azim) in degrees, optional
        Default: chosen so that the axes drawn at a common point do not overlap
        on screen (elevation 15-35 deg, azimuth near -60 deg).

    Returns
    -------
    matplotlib.figure.Figure
    """
    require_matplotlib()
    _check_3d_axes(ax)
    L = leg.length
    mid = 0.5 * (leg.A + leg.a)
    legdir = (leg.a - leg.A) / L
    items = []  # (kind, member, colour key, label, gid)
    if analysis is not None:
        nf = nc = ns = 0
        for c in analysis.constraints:
            if c.kind == "force":
                nf += 1
                items.append(("force", c, "force", f"$F_{{c{nf}}}$", f"force:{nf}"))
            elif c.kind == "couple":
                nc += 1
                items.append(("couple", c, "couple", f"$T_{{c{nc}}}$", f"couple:{nc}"))
            else:
                ns += 1
                items.append(("screw", c, "screw", f"$W_{{c{ns}}}$ (pitch {c.pitch:.3g})",
                              f"screw:{ns}"))
        act = analysis.actuation
        if act is not None:
            m = act.member
            sym = {"couple": "T_{a}", "force": "F_{a}"}.get(m.kind, "W_{a}")
            items.append((m.kind, m, "actuation", f"${sym}$ ({act.joint})",
                          f"actuation:{m.kind}"))
    v = _check_view(view)
    if v is None:
        extra = [(c.point, c.direction) for k, c, _, _, _ in items
                 if k != "couple" and c.point is not None]
        v = _choose_view(_leg_direction_groups(leg, extra))
    own = ax is None
    if own:
        fig, ax = new_figure((9.0, 6.4), "3d")
    else:
        fig = ax.figure
    ext = _Extent()
    labeller = _Labeller(ax, v, L)
    kinds = _leg_geometry(ax, leg, ext, v, joint_labels=joint_labels, labeller=labeller)
    arrow_len = 0.4 * L
    lines = []
    for kind, c, ckey, lab, gid in items:
        d = np.asarray(c.direction, float)
        color = COLORS[ckey]
        hollow = ckey != "actuation"          # open heads: constraint wrenches
        if kind == "couple":  # a free vector: drawn beside the leg, away from the joints
            p0, root = couple_tail(v, leg.A, leg.a, arrow_len * d, L,
                                   [m[0] for m in labeller.markers], labeller.segments)
            p1 = p0 + arrow_len * d
            _double_head(ax, p0, p1, color, gid=gid, hollow=hollow)
            ax.plot(*np.array([root, p0]).T, color=color, lw=0.8, ls=":", zorder=2)
            labeller.segment(root, p0)
            ext.add(p0, p1)
            labeller.segment(p0, p1)
            labeller.marker(p1, 5.0)
            labeller.tip(p1, d, lab, color, 8, priority=0)
            kinds.add("actuation-couple" if ckey == "actuation" else "couple")
            continue
        p = np.asarray(c.point if c.point is not None else mid, float)
        if ckey == "actuation":  # drawn where it acts on the platform: nearest to a
            p = p + float(np.dot(leg.a - p, d)) * d
        p1 = p + arrow_len * d
        _arrow(ax, p, p1, color, lw=2.2, gid=gid, hollow=hollow)
        if kind == "screw":  # a second, thinner head marks the finite pitch
            _arrow(ax, p, p + 0.8 * arrow_len * d, color, lw=1.0, scale=10, gid=gid,
                   hollow=hollow)
        ext.add(p, p1)
        labeller.segment(p, p1)
        labeller.marker(p1, 5.0)
        if c.point_name and "^" in c.point_name:  # show where the two axes meet
            for jn in c.point_name.split("^"):
                try:
                    jp = leg.joint(jn).point
                except InputError:
                    continue
                ax.plot(*np.array([jp, c.point]).T, color=COLORS["R"], lw=0.9, ls=":",
                        zorder=2)
            ax.scatter(*c.point, s=14, color=color, depthshade=False, zorder=4)
            labeller.marker(c.point, 2.5)
            kinds.add("meet")
        where = f" through {c.point_name.replace('^', '∩')}" if c.point_name else ""
        labeller.beside(p1 - 0.1 * arrow_len * d, d, lab + where, color, 8)
        lines.append((p, d, color, ckey == "actuation"))
        kinds.add(ckey)
    box = ext.box()
    for p, d, color, act in lines:
        seg = _clip_line(p, d, *box)
        if seg is not None:
            ax.plot(*np.array(seg).T, color=color, lw=1.0, ls=_LINE_STYLE[act], alpha=0.8,
                    zorder=2)
    if title is None:
        title = f"leg {leg.name}  [{leg.string.marked}]"
        if analysis is not None:
            title += f"\nconstraint: {analysis.summary()}; connectivity {analysis.connectivity}"
            if analysis.actuation is not None:
                a = analysis.actuation
                title += f"; actuation: {a.member.kind} ({a.joint})"
    note = f"view: elevation {v.elev:g}°, azimuth {v.azim:g}°"
    _finish_axes(ax, box, v, length_unit, title, kinds, legend, own, note)
    labeller.place()
    save_figure(fig, out, dpi)
    return fig
