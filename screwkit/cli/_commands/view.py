"""``screwkit view PM --html OUT.html``: the interactive 3D view of a PM over a grid of poses or
along a path."""

from __future__ import annotations

import argparse
import sys

from ...errors import InputError
from .._progress import add_quiet_argument, progress_bar
from .._types import integer, label, output, png
from ._common import dump_json
from .analyze import add_load_arguments, add_pm_arguments, parse_assignments, parse_load, \
    resolve_model

HELP = """Write the interactive 3D view of a PM as one self-contained HTML page (plotly.js
bundled: it opens with no network): the base, the platform and the legs with every joint
drawn by kind (R axis, P sleeve, S ball, U cross, H axis with its helix, Pa parallelogram),
the actuation and constraint forces as arrows on their lines and the couples as
double-headed arrows, each sized by its value and labelled with it in the model's units
(F_a1 = 19.36 kN), one colour per leg (the colours of every figure), a legend, the
singularity level and the workload used. Without a path the page has one slider per
independent pose parameter, over a grid of poses around --pose that the engine solves
(--steps values each, or --grid NAME=START:STOP:COUNT); with --expr or --path (as
'trajectory' takes them) it has a time slider with play/pause. Angles in degrees."""

EPILOG = """examples:
  screwkit view 3RRPRR --pose alpha=5 --pose beta=-3 --pose Zo=80 --html view.html
  screwkit view 2SPS+2SPR --grid alpha=-10:10:9 --steps 3 --html view.html
  screwkit view 3RRPRR --expr "alpha=8*sin(2*pi*t)" --expr "beta=6*sin(2*pi*t+1)" \\
      --expr "Zo=70+20*t" --samples 101 --html path.html --png path.png"""


def register(sub):
    from ...paths import add_path_arguments

    p = sub.add_parser("view", help="interactive 3D view of a PM (HTML page with sliders)",
                       description=HELP, epilog=EPILOG,
                       formatter_class=argparse.RawDescriptionHelpFormatter)
    add_pm_arguments(p)
    g = p.add_argument_group("grid of poses (without a path)")
    g.add_argument("--grid", metavar="NAME=START:STOP:COUNT", action="append", default=[],
                   help="the slider of one independent parameter (degrees for angles; "
                        "repeatable); the others span +-10 deg or +-10 %% of the "
                        "characteristic length around --pose")
    g.add_argument("--steps", type=integer(1, 101), metavar="N",
                   help="values per slider (default: 21, 21, 9, 5, 3, 3 for 1 to 6 "
                        "parameters; at most 4096 poses in all)")
    add_path_arguments(p)
    add_load_arguments(p)
    p.add_argument("--html", type=output, required=True, metavar="OUT.html",
                   help="the page to write")
    p.add_argument("--png", type=png, metavar="OUT.png",
                   help="also a screenshot of the page in headless Chromium (needs playwright "
                        "and a Chromium on the PATH)")
    p.add_argument("--frame", type=integer(0, 1 << 20), metavar="K",
                   help="the sample shown first along a path (0-based; default 0)")
    p.add_argument("--title", type=label(), help="title of the page (default: the PM)")
    p.add_argument("--json", action="store_true", help="print a JSON summary")
    add_quiet_argument(p)
    p.set_defaults(func=run)


def _grid(items, independent):
    from ...maps import parse_range
    from ...paths._view import MAX_VIEW_STEPS

    out = {}
    for text in items:
        name, rng = parse_range(text, "--grid", max_count=MAX_VIEW_STEPS)
        if len(rng) != 3:
            raise InputError(f"--grid {name}: give START:STOP:COUNT")
        if name in out:
            raise InputError(f"--grid {name} is given twice")
        out[name] = rng
    return out or None


def run(args) -> int:
    from ...paths import path_from_args, view
    from ...scene import require_plotly

    require_plotly()                           # fail at once, naming the extra
    has_path = bool(args.expr or args.path)
    if has_path and (args.pose or args.grid or args.steps):
        raise InputError("give either a path (--expr/--path) or --pose/--grid/--steps, not both")
    if args.frame is not None and not has_path:
        raise InputError("--frame picks a sample of a path: give --expr or --path")
    if args.png:
        from ...scene._browser import _require
        _require()                             # playwright and Chromium, before the work
    pose = parse_assignments(args.pose, "--pose")
    model = resolve_model(args)
    force, torque = parse_load(args)            # none given, none declared: no efforts shown
    with progress_bar(args, "view", "pose") as progress:
        if has_path:
            path = path_from_args(args, model.independent,
                                  model.units.length if model.units.declared else None)
            if args.frame is not None and args.frame >= len(path):
                raise InputError(f"--frame {args.frame}: the path has {len(path)} samples "
                                 f"(0 to {len(path) - 1})")
            v = view(model, path=path, force=force, torque=torque, title=args.title,
                     start=args.frame, progress=progress)
        else:
            v = view(model, pose or None, grid=_grid(args.grid, model.independent),
                     steps=args.steps, force=force, torque=torque, degrees=True,
                     title=args.title, progress=progress)
    sc = v.scene
    if all(s.level == "unreachable" for s in sc.states):     # (a page with nothing drawn)
        raise InputError(f"none of the {len(sc.states)} poses of the view is reachable: centre "
                         "it on a reachable pose (--pose, or a path that passes through "
                         "reachable poses)")
    written = v.write_html(args.html)
    shot = None
    if args.png:
        from ...scene import screenshot
        shot = screenshot(written, args.png)
        if shot["errors"]:
            raise InputError(f"the page reported errors in Chromium: {shot['errors'][0]}")
    state = sc.states[sc.start]
    levels = _level_counts(sc.states)
    if args.json:
        print(dump_json({"html": written, "png": shot["png"] if shot else None, "pm": sc.pm,
                         "states": len(sc.states), "start": sc.start,
                         "controls": "grid" if hasattr(sc.controls, "params") else "time",
                         "workload": {"force": sc.force, "torque": sc.torque,
                                      "applied_at": "o", "source": sc.workload_source,
                                      "force_unit": sc.units.get("force"),
                                      "torque_unit": sc.units.get("torque"),
                                      "text": sc.workload_text},
                         "level": state.level,
                         "levels": levels}))
        return 0
    n = len(sc.states)
    kind = (f"{' x '.join(str(len(v)) for v in sc.controls.values)} poses on sliders "
            f"({', '.join(sc.controls.params)})" if hasattr(sc.controls, "params")
            else f"{n} sample{'s' if n != 1 else ''} on a time slider")
    # a state that is not regular is flagged on the page; the summary counts them
    flagged = "; ".join(f"{c} of {n} {lv}" for lv, c in levels.items() if lv != "ok")
    print(f"wrote {written} ({sc.pm}: {kind}; workload {sc.workload_text}; shown first: "
          f"level {state.level}" + (f"; {flagged}" if flagged else "") + ")")
    if shot:
        print(f"wrote {shot['png']}", file=sys.stderr)
    return 0


def _level_counts(states) -> dict:
    """How many states are at each singularity level, from the best to the worst."""
    order = ("ok", "ill-conditioned", "near-singular", "singular", "unreachable")
    seen = [s.level for s in states]
    return {lv: seen.count(lv) for lv in order + tuple(sorted(set(seen) - set(order)))
            if seen.count(lv)}
