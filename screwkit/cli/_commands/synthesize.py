"""``screwkit synthesize MOTION``: PMs synthesized for a motion pattern, verified and ranked."""

from __future__ import annotations

import argparse
import sys

from .._progress import add_quiet_argument, progress_bar
from .._types import integer, path, scheduler
from ._common import dask_mapper, dump_json, write_output

HELP = """Type synthesis of PMs for a motion pattern (3T, 3R, 1T2R = 2R1T, 3T1R, 2T3R, 1T3R,
2T2R, 2T1R). The leg types of the catalog (and a few extra arrangements) whose constraint
systems fit the wrench system complementary to the motion are composed into symmetric and
asymmetric PMs of N actuated legs (N = the DOF unless --legs), placed on standard geometries
(triangle, rectangle, pentagon; lengths in cm) and screened at home (the legs' constraint
systems must span the complementary system). The survivors are verified by the engine:
the mobility (DOF and instantaneous motion type) at home and at 6 poses of a finite motion
from home, the pattern's finite invariant (no rotation for 3T, a fixed centre for 3R ...),
and J non-singular at home (the actuators control the motion). They are ranked by joint
count, actuators nearer the base, and the condition number of J at home. With --passive
(not with --symmetric), PMs of N actuated legs and one passive constraining leg (no
actuator, e.g. 4SPS + a passive PRRR for 3T1R) are tried too: their J leaves out the
passive leg's actuation row. --workers N / --scheduler ADDRESS run the engine
verifications on a Dask cluster (the result equals the serial one). --write DIR
writes each listed PM as a model YAML that 'screwkit analyze DIR/FILE.yaml' reads, except
the PMs with a passive leg (screwkit models cannot declare a passive leg yet: they are named
on stderr and not written)."""

EPILOG = """examples:
  screwkit synthesize 3T --limit 5
  screwkit synthesize 1T2R --json
  screwkit synthesize 3T1R --legs 4 --write models/
  screwkit synthesize 1T2R --workers 2"""


def register(sub):
    p = sub.add_parser("synthesize", help="PMs synthesized for a motion pattern, verified and ranked",
                       description=HELP, epilog=EPILOG,
                       formatter_class=argparse.RawDescriptionHelpFormatter)
    p.add_argument("motion", metavar="MOTION",
                   help="motion pattern: 3T, 3R, 1T2R (2R1T), 3T1R, 2T3R, 1T3R, 2T2R, 2T1R")
    p.add_argument("--legs", type=integer(1, 6), default=None, metavar="N",
                   help="number of actuated legs (default: the DOF; 3, 4 or 5)")
    p.add_argument("--limit", type=integer(1, 10000), default=None, metavar="K",
                   help="list only the K best ranked")
    p.add_argument("--symmetric", action="store_true",
                   help="only symmetric PMs (all legs of one type)")
    p.add_argument("--passive", action="store_true",
                   help="also PMs with one passive constraining leg (models cannot declare a "
                        "passive leg yet: these are listed, not written)")
    p.add_argument("--workers", type=integer(1, 64), default=None, metavar="N",
                   help="verify the candidates on a local Dask cluster of N worker processes")
    p.add_argument("--scheduler", default=None, metavar="tcp://HOST:PORT", type=scheduler,
                   help="verify the candidates on a running Dask scheduler")
    p.add_argument("--write", type=path, default=None, metavar="DIR",
                   help="write each listed PM as DIR/<name>.yaml")
    p.add_argument("--json", action="store_true", help="print JSON instead of text")
    add_quiet_argument(p)
    p.set_defaults(func=run)


def file_name(name: str) -> str:
    """A file name for a PM name (``2UPU/force+SPR`` -> ``2UPU-force+SPR.yaml``)."""
    return name.replace("/", "-") + ".yaml"


def run(args) -> int:
    from pathlib import Path

    from ...design import synthesize_motion

    mapper = dask_mapper(args)
    with progress_bar(args, "synthesize", "candidate") as progress:
        res = synthesize_motion(args.motion, legs=args.legs, limit=args.limit,
                                asymmetric=not args.symmetric,
                                passive=args.passive and not args.symmetric,
                                progress=progress, mapper=mapper)
    written = []
    if args.write is not None:
        for p in res.listed:
            if p.passive:
                print(f"screwkit synthesize: {p.name} not written: a model cannot declare a "
                      "passive leg yet", file=sys.stderr)
                continue
            target = Path(args.write) / file_name(p.name)
            write_output(target, p.model_yaml())
            written.append(str(target))
    if args.json:
        out = res.to_dict()
        if written:
            out["written"] = written
        print(dump_json(out))
        return 0 if res.listed else 1
    m = res.motion
    print(f"{m.name} ({m.dof} DOF, independent {' '.join(m.independent)}): {res.verified} PMs "
          f"verified of {res.tried} candidates with {res.n_legs} legs ({res.screened_out} "
          f"screened out at home, {len(res.rejected)} rejected by the engine)")
    print(f"  complementary wrench system: {m.complement}")
    w = max([32] + [len(p.name) for p in res.listed])
    print(f"  rank  {'PM':<{w}} joints  actuators           act.pos  cond(J) home  geometry (cm)")
    for p in res.listed:
        print(f"  {p.rank:>4}  {p.name:<{w}} {p.joints:>6}  {' '.join(dict.fromkeys(p.actuators)):<19}"
              f" {p.actuator_position:>7.2f}  {p.condition_home:>12.4g}  {p.geometry}")
    if any(p.passive for p in res.listed):
        print("  passive-X: leg 1 of type X has no actuator (actuators lists the actuated "
              "legs; cond(J) without its actuation row)")
    if res.listed:
        v = res.listed[0].verdict
        print(f"  each verified at {len(v.checks)} poses (home and {len(v.checks) - 1} along a "
              f"finite motion from home: DOF {m.dof}, type {m.name}); act.pos: mean position "
              "of the actuated joint in its leg (1 = on the base); cond(J): length-normalised, "
              "dimensionless")
    if len(res.listed) < res.verified:
        print(f"  ({res.verified - len(res.listed)} more verified PMs not listed: --limit)")
    for f in written:
        print(f"  wrote {f}")
    return 0 if res.listed else 1
