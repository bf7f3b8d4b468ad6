"""Where the time of one warm pose goes: ``screwkit.analyze`` at one pose, warm-started
from a neighbour, beside the parts of it, in the same run.

* ``analyze``: ``screwkit.analyze(pm, near, guess=previous.solution)`` under the model's
  declared workload (the paper's for its two PMs), else a stated one, all of it;
* ``kernel, one pose``: the analysis kernel's call that ``analyze`` makes (captured from a
  call of it, then called again with the same arguments: the same warm start, the same
  work), numba's dispatch included;
* ``kernel, no pose``: the same call on no pose (numba's dispatch of its arrays and the
  kernel's workspaces, allocated each call);
* ``dispatch alone``: an empty compiled function called with the same arrays;
* ``outputs as arrays``: the 25 outputs of the launch as arrays by name, as one pose makes
  them (``_outputs.OnePose``) and as a batch does (``_outputs.views_of``).

``analyze`` less ``kernel, one pose`` is the Python around the kernel.  Each figure is the
best of ``--repeat`` rounds of ``--calls`` calls, the variants alternated round by round
(the machines are noisy); microseconds a call.  ``--json`` for a record.

Run: ``python benchmarks/one_pose_breakdown.py [--pm 3RRPRR] [--repeat 7] [--calls 500]
[--json]``.
"""

from __future__ import annotations

import argparse
import json
import sys
import time

import numpy as np


def _capture(pm, near, prev, load):
    """The analysis kernel's arguments and the one-pose outputs' record of one ``analyze``
    call of ``near``."""
    import screwkit
    from screwkit.engine import _launch, _outputs
    got = {}
    launch, views = _launch._launch, _outputs.OnePose.views

    def spy_launch(serial, par, args, N, *a, **kw):
        got["call"] = (serial, args, kw.get("path") or (_launch._NO_PATH_F, _launch._NO_PATH_I))
        return launch(serial, par, args, N, *a, **kw)

    def spy_views(self, f, i, frozen=False):
        got["one"] = (self, f, i, frozen)
        return views(self, f, i, frozen)
    _launch._launch, _outputs.OnePose.views = spy_launch, spy_views
    try:
        screwkit.analyze(pm, near, guess=prev.solution, **load)
    finally:
        _launch._launch, _outputs.OnePose.views = launch, views
    return got


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--pm", default="3RRPRR")
    ap.add_argument("--repeat", type=int, default=7)
    ap.add_argument("--calls", type=int, default=500)
    ap.add_argument("--json", action="store_true")
    args = ap.parse_args(argv)
    if not 1 <= args.repeat <= 100 or not 1 <= args.calls <= 100_000:
        ap.error("--repeat must be 1 to 100 and --calls 1 to 100000")
    import numba
    import screwkit
    from screwkit.engine import _outputs
    from screwkit.engine._chains import chains_of
    pm = screwkit.load_pm(args.pm)
    # the model's declared workload (the paper's for its two PMs), else this one, said below
    load = {} if pm.workload is not None else dict(force=np.array([0.0, 0.0, -100.0]),
                                                   torque=np.zeros(3))
    source = ("the model's declared workload" if not load else
              "F = (0, 0, -100), T = (0, 0, 0) at o, model units (the model declares none)")
    one = dict(pm.default_pose)
    near = {p: v + (0.002 if p in ("alpha", "beta", "gamma") else 0.001 * pm.normalisation.length)
            for p, v in one.items()}
    prev = screwkit.analyze(pm, one, **load)
    got = _capture(pm, near, prev, load)
    serial, kargs, path = got["call"]
    plan, f, i, frozen = got["one"]
    # (the launch plan whose one-pose records these are: its layout, for the batch's views)
    layout = next(p.out for k, p in chains_of(pm).flat.packed.items()
                  if k[0] == "plan" and p.one is plan)

    @numba.njit
    def empty(*a):
        return 0

    variants = {
        "analyze": lambda: screwkit.analyze(pm, near, guess=prev.solution, **load),
        "kernel, one pose": lambda: serial(*kargs, 0, 1, *path),
        "kernel, no pose": lambda: serial(*kargs, 0, 0, *path),
        "dispatch alone": lambda: empty(*kargs, 0, 1, *path),
        "outputs as arrays, one pose's records": lambda: plan.views(f, i, frozen),
        "outputs as arrays, a batch's views": lambda: _outputs.views_of(f, i, layout, True),
    }
    for fn in variants.values():          # (compiled, loaded and warm before timing)
        for _ in range(20):
            fn()
    best = dict.fromkeys(variants, float("inf"))
    for _ in range(args.repeat):
        for name, fn in variants.items():
            t = time.perf_counter()
            for _ in range(args.calls):
                fn()
            best[name] = min(best[name], (time.perf_counter() - t) / args.calls * 1e6)
    if args.json:
        json.dump({"pm": args.pm, "workload": source, "us": best}, sys.stdout, indent=1)
        print()
        return 0
    print(f"one warm pose of the {args.pm} (best of {args.repeat} rounds of {args.calls} "
          f"calls, microseconds a call; workload: {source})")
    for name, us in best.items():
        print(f"  {name:40s} {us:9.2f}")
    print(f"  {'Python around the kernel':40s} {best['analyze'] - best['kernel, one pose']:9.2f}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
