"""``screwkit synthesize MOTION``: PMs synthesized for a motion pattern, verified and ranked."""

from __future__ import annotations

import argparse

from .._progress import add_quiet_argument, progress_bar
from .._types import integer, path, scheduler
from ._common import (catalog_with_model_legs, dask_mapper, default_jobs, dump_json,
                      process_mapper, write_output)

HELP = """Type synthesis of PMs for a motion pattern (3T, 3R, 1T2R = 2R1T, 3T1R, 2T3R, 1T3R,
2T2R, 2T1R). Legs of up to five one-DOF joints (R, P, H and the composites U, S, C, Pa)
are generated under the geometric conditions of type synthesis (axes parallel, through the
centre, normal to the leg ...) and kept when their constraint systems, found by the
reciprocal-screw solver and explained by the observation rules, fit the wrench system
complementary to the motion; with the catalog's leg types (and a model file's, --model)
they are composed into symmetric and asymmetric PMs of N actuated legs (N = the DOF unless
--legs), placed on standard geometries (triangle, rectangle, pentagon; lengths in cm) and
screened at home (the legs' constraint systems must span the complementary system). The
survivors are verified by the engine: the mobility (DOF and instantaneous motion type) at
home and at 6 poses of a finite motion from home, the pattern's finite invariant (no
rotation for 3T, a fixed centre for 3R ...), and J non-singular at home (the actuators
control the motion). They are ranked: actuators nearer the base first, then fewer joints,
the catalog's leg types before generated ones, the condition number of J at home. PMs are
named as the literature names them (3-PRS, 3-RRPaR); VARIANT names the leg types (a
generated leg's name is its letters and, per letter, the direction codes of its axes: n
base normal, t base tangent, r radial, o towards the platform centre, l the leg line, c
through the centre C, x normal to the previous axis and the leg, X/Y the base axes, -
an S; see docs/synthesis.md). Unless --no-passive (or --symmetric), PMs of N
unconstrained actuated legs and one passive central column (the Tricept 3-UPS+UP/passive
for 1T2R), or a catalog leg type made passive at vertex 1 (4-SPS + a passive PRRR for
3T1R), are tried too: J has no actuation row for the passive leg. The engine verifications
run on 2 local processes by default (--jobs), or on a Dask cluster with --workers N /
--scheduler ADDRESS (for wider searches, --wide); the result equals the serial one. --write
DIR writes each listed PM as a model YAML (a passive leg declared {leg: NAME, passive:
true}), with the definitions of the leg types it uses that the packaged catalog lacks,
that 'screwkit analyze DIR/FILE.yaml --force FX,FY,FZ --torque TX,TY,TZ' reads (a written
model declares no workload: give the one to analyse, or add a 'workload:' block)."""

EPILOG = """examples:
  screwkit synthesize 3T --limit 5
  screwkit synthesize 1T2R --json
  screwkit synthesize 3T1R --legs 4 --write models/
  screwkit synthesize 1T2R --workers 2
  screwkit synthesize 1T2R --model my_legs.yaml --no-generate"""


def register(sub):
    p = sub.add_parser("synthesize", help="PMs synthesized for a motion pattern, verified and ranked",
                       description=HELP, epilog=EPILOG,
                       formatter_class=argparse.RawDescriptionHelpFormatter)
    p.add_argument("motion", metavar="MOTION",
                   help="motion pattern: 3T, 3R, 1T2R (2R1T), 3T1R, 2T3R, 1T3R, 2T2R, 2T1R")
    p.add_argument("--legs", type=integer(3, 5), default=None, metavar="N",
                   help="number of actuated legs (default: the DOF; 3, 4 or 5)")
    p.add_argument("--limit", type=integer(1, 10000), default=None, metavar="K",
                   help="list only the K best ranked")
    p.add_argument("--symmetric", action="store_true",
                   help="only symmetric PMs (all legs of one type)")
    both = p.add_mutually_exclusive_group()      # (the one or the other: never both)
    both.add_argument("--passive", action="store_true",
                      help="also PMs with one passive constraining leg (the default)")
    both.add_argument("--no-passive", action="store_true",
                      help="no PMs with a passive leg (a central column or a catalog leg type)")
    p.add_argument("--model", type=path, default=None, metavar="FILE",
                   help="add the leg types of a model file (its 'legs:' list) to the pool")
    p.add_argument("--no-generate", action="store_true",
                   help="the catalog's leg types only (and --model's): no generated legs")
    p.add_argument("--variants", type=integer(1, 20), default=None, metavar="K",
                   help="generated leg types kept per letter word (default 2)")
    p.add_argument("--wide", action="store_true",
                   help="generate legs from every word (H joints, five-joint legs of four or "
                        "five letters): slower, for a Dask cluster")
    p.add_argument("--max-verified", type=integer(1, 10000), default=None, metavar="N",
                   help="at most N engine verifications of the symmetric and mixed PMs "
                        "(default 400); the pair compositions take at most min(N, 40) more and "
                        "the passive-leg ones at most N more (docs/synthesis.md)")
    p.add_argument("--jobs", type=integer(1, 64), default=None, metavar="N",
                   help="local worker processes for the engine verifications (default: 2 on "
                        "Linux with 2 or more cores, else 1)")
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
    """A file name for a PM variant (``2UPU/force+SPR`` -> ``2UPU-force+SPR.yaml``)."""
    return name.replace("/", "-") + ".yaml"


def run(args) -> int:
    from pathlib import Path

    from ...design import VARIANTS, synthesize_motion
    from ...errors import InputError

    if args.symmetric and args.passive:
        raise InputError("--symmetric --passive: a symmetric PM has all its legs of one type, "
                         "a passive leg makes it asymmetric (give one or the other)")
    if args.no_generate and (args.wide or args.variants is not None):
        raise InputError(f"--no-generate with {'--wide' if args.wide else '--variants'}: those "
                         "choose the generated legs, which --no-generate leaves out")
    if args.write is not None and Path(args.write).exists() and not Path(args.write).is_dir():
        raise InputError(f"--write {args.write}: not a directory (give one for the models)")
    if args.write is not None and not Path(args.write).exists():
        try:                        # (made before the search, not found wanting after it)
            Path(args.write).mkdir(parents=True)
        except OSError as exc:
            raise InputError(f"--write {args.write}: cannot make the folder: "
                             f"{exc.strerror or exc}") from None
    mapper = dask_mapper(args)
    if mapper is not None and args.jobs is not None:
        raise InputError("give either --jobs N (local processes) or a Dask cluster")
    if mapper is None:
        mapper = process_mapper(default_jobs(args.jobs))
    catalog = catalog_with_model_legs(args.model) if args.model else None
    with progress_bar(args, "synthesize", "candidate") as progress:
        res = synthesize_motion(args.motion, legs=args.legs, limit=args.limit,
                                asymmetric=not args.symmetric,
                                passive=not args.no_passive and not args.symmetric,
                                progress=progress, mapper=mapper, catalog=catalog,
                                generate=not args.no_generate,
                                variants=args.variants or VARIANTS, wide=args.wide,
                                max_verified=args.max_verified)
    written = []
    if args.write is not None:
        for p in res.listed:
            target = Path(args.write) / file_name(p.variant)
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
          f"screened out at home, {len(res.rejected)} rejected by the engine, {res.pruned} "
          f"mixes not tried); leg pool: {len(res.pool) - res.generated} catalog, "
          f"{res.generated} generated")
    print(f"  complementary wrench system: {m.complement}")
    w = max([12] + [len(p.name) for p in res.listed])
    v = max([8] + [len(p.variant) for p in res.listed])
    print(f"  rank  {'PM':<{w}} {'variant':<{v}} joints  act.pos  cond(J) home  geometry (cm)")
    for p in res.listed:
        print(f"  {p.rank:>4}  {p.name:<{w}} {p.variant:<{v}} {p.joints:>6}"
              f"  {p.actuator_position:>7.2f}  {p.condition_home:>12.4g}  {p.geometry}")
    if any(p.passive for p in res.listed):
        print("  X/passive: a leg of type X with no actuator (a central column, or leg 1); "
              "J has no actuation row for it")
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
