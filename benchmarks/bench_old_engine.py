"""The compiled core against the numpy engine it replaced, on this machine, in the same run.

The issue "The compiled core" set its targets from figures of the numpy engine taken on
another machine (random 3RRPRR poses 63k-109k/s, a path 89k-129k samples/s, one warm pose
3.96-4.42 ms) and names them "10x faster in batches and 40x for one pose".  This script
measures that engine here: the last commit before the compiled core (``OLD_ENGINE``,
extracted from this checkout's history with ``git archive`` into a temporary directory)
and this checkout's screwkit run as two processes on the same workloads, alternated round by
round (the machines are noisy: read the ratios), and prints each speed-up beside the one
the issue's target makes over its figures:

* ``random``: 100,000 random poses of the 3RRPRR (``bench_engine.py``'s: alpha, beta in
  +-10 deg, Zo in 60-100 cm), of 2SPS+2SPR, 3RPS, 4SPS+SPR and the 6-SPS (around their
  default poses), each from home; target 1,000,000 poses/s for the 3RRPRR (9.2-15.9x the
  issue's figures), 500,000 for the others (the issue gave no figures of theirs);
* ``path``: the 100,000-sample 3RRPRR path of ``bench_engine.py`` (``path=True``); target
  2,000,000 samples/s (15.5-22.5x);
* ``one warm pose``: ``screwkit.analyze`` at one pose with the previous pose as guess, the
  3RRPRR (``bench_engine.py``'s poses) and the 6-SPS; target 100 us (39.6-44.2x).

Every case runs under the paper's workload, given.  The 6-SPS came with the compiled core:
the numpy engine reads it from a copy of its catalog with the current catalog's 6SPS
entry added (the same model: the two engines' actuator forces at its default pose are
compared before timing, as are the 3RRPRR's).  Each figure is the best of ``--repeat``
rounds (each time in a round the best of two calls; a warm pose: per call of 500); each
speed-up the median over the rounds of the old engine's time over the new one's in the
same round.  Needs git and this repository's history; ``--json`` for a record.

Run: ``python benchmarks/bench_old_engine.py [--n 100000] [--repeat 3] [--json]``.
"""

from __future__ import annotations

import argparse
import json
import os
import re
import subprocess
import sys
import tempfile
import time

import numpy as np

#: The last commit of the numpy engine (the parent of the compiled core's first commit).
OLD_ENGINE = "34824d6"
ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
F_LOAD = [-20.0, -30.0, -60.0]
T_LOAD = [-30.0, -30.0, 100.0]
WARM_CALLS = 500
#: The issue's targets over its numpy engine's figures (low, high speed-ups; it gave none of
#: the other PMs).
ISSUE_RATIOS = {"random 3RRPRR": (1e6 / 109e3, 1e6 / 63e3),
                "path 3RRPRR": (2e6 / 129e3, 2e6 / 89e3),
                "one warm pose": (3.96e-3 / 100e-6, 4.42e-3 / 100e-6)}

# The server each engine runs: it builds the cases from the poses given, then times the
# case named on each line of its input and prints the best time of two calls (seconds).
SERVER = r"""
import json, sys, time
import numpy as np
import screwkit
spec = json.load(open(sys.argv[1]))
data = np.load(spec["poses"])
load = dict(force=spec["force"], torque=spec["torque"])

def model(name):
    return screwkit.load_pm(spec["catalog"] + "#" + name if spec["catalog"] else name)

cases, check = {}, {}
for case in spec["cases"]:
    kind, name = case.split(" ", 1) if not case.startswith("one") else ("one", case[14:])
    m = model(name)
    check[name] = screwkit.analyze(m, **load).statics.active.tolist()
    if kind in ("random", "path"):
        pose = {k[len(case) + 1:]: data[k] for k in data.files if k.startswith(case + ":")}
        path = kind == "path"
        cases[case] = (lambda m=m, pose=pose, path=path:
                       screwkit.analyze(m, pose, path=path, **load))
    else:
        one = {k[len(case) + 1:]: float(data[k]) for k in data.files
               if k.startswith(case + ":") and not k.endswith("~")}
        near = {k[len(case) + 1:-1]: float(data[k]) for k in data.files
                if k.startswith(case + ":") and k.endswith("~")}
        prev = screwkit.analyze(m, one, **load)
        calls = spec["warm_calls"]
        cases[case] = (lambda m=m, near=near, prev=prev, calls=calls:
                       [screwkit.analyze(m, near, guess=prev.solution, **load)
                        for _ in range(calls)])
    cases[case]()                        # (loaded, compiled and warm before timing)
print(json.dumps({"file": screwkit.__file__, "forces": check}), flush=True)
for line in sys.stdin:
    fn = cases[line.strip()]
    best = float("inf")
    for _ in range(2):
        t = time.perf_counter()
        fn()
        best = min(best, time.perf_counter() - t)
    print(best, flush=True)
"""


def _poses(n):
    """The cases' poses by ``"case:param"`` (a warm pose's neighbour ``"case:param~"``), the
    same random streams as ``bench_engine.py``."""
    import screwkit
    from bench_engine import _random_pose        # (this script's folder is on the path)
    rng = np.random.default_rng(0)
    out = {}
    alpha, beta = np.radians(rng.uniform(-10, 10, n)), np.radians(rng.uniform(-10, 10, n))
    Zo = rng.uniform(60, 100, n)
    out.update({"random 3RRPRR:alpha": alpha, "random 3RRPRR:beta": beta,
                "random 3RRPRR:Zo": Zo})
    for name in ("2SPS+2SPR", "3RPS", "4SPS+SPR", "6SPS"):
        m = screwkit.load_pm(name)
        for p, v in _random_pose(m, n, rng).items():
            out[f"random {name}:{p}"] = v
    s = np.linspace(0, 1, n)
    out.update({"path 3RRPRR:alpha": np.radians(10 * np.sin(2 * np.pi * s)),
                "path 3RRPRR:beta": np.radians(8 * np.cos(2 * np.pi * s)),
                "path 3RRPRR:Zo": 70 + 20 * s})
    out.update({"one warm pose 3RRPRR:alpha": np.radians(5.0),
                "one warm pose 3RRPRR:beta": np.radians(-3.0), "one warm pose 3RRPRR:Zo": 80.0,
                "one warm pose 3RRPRR:alpha~": np.radians(5.1),
                "one warm pose 3RRPRR:beta~": np.radians(-3.0),
                "one warm pose 3RRPRR:Zo~": 80.2})
    m = screwkit.load_pm("6SPS")
    for p, v in m.default_pose.items():
        out[f"one warm pose 6SPS:{p}"] = v
        out[f"one warm pose 6SPS:{p}~"] = v + (0.002 if p in ("alpha", "beta", "gamma") else 0.1)
    return out


def _old_tree(tmp):
    """The numpy engine's package in ``tmp/old``, and its catalog with the 6SPS added."""
    old = os.path.join(tmp, "old")
    os.makedirs(old)
    try:
        archive = subprocess.run(["git", "-C", ROOT, "archive", OLD_ENGINE, "screwkit",
                                  "legs_catalog.yaml"],
                                 capture_output=True, check=True).stdout
    except (OSError, subprocess.CalledProcessError) as exc:
        sys.exit(f"bench_old_engine: cannot extract commit {OLD_ENGINE} with git from {ROOT} "
                 f"(a checkout with its history is needed): {exc}")
    subprocess.run(["tar", "-x", "-C", old], input=archive, check=True)
    with open(os.path.join(ROOT, "legs_catalog.yaml")) as f:
        new = f.read()
    start = new.index("\n  6SPS:")
    end = re.search(r"\n  \S[^\n]*:\n|\n\S", new[start + 3:])
    entry = new[start:start + 3 + end.start()] if end else new[start:]
    with open(os.path.join(old, "legs_catalog.yaml")) as f:     # (the package's: a link)
        text = f.read()
    if not re.search(r"\npms:", text) or text.rstrip().rfind("\npms:") < text.rfind("\ntable1:"):
        sys.exit("bench_old_engine: the old catalog does not end with its PMs")
    catalog = os.path.join(tmp, "old_catalog.yaml")
    with open(catalog, "w") as f:
        f.write(text.rstrip("\n") + entry + "\n")
    return old, catalog


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--n", type=int, default=100_000)
    ap.add_argument("--repeat", type=int, default=3)
    ap.add_argument("--json", action="store_true")
    args = ap.parse_args(argv)
    if not 1 <= args.repeat <= 50 or not 100 <= args.n <= 1_000_000:
        ap.error("--repeat must be 1 to 50 and --n 100 to 1000000")
    cases = ["random 3RRPRR", "random 2SPS+2SPR", "random 3RPS", "random 4SPS+SPR",
             "random 6SPS", "path 3RRPRR", "one warm pose 3RRPRR", "one warm pose 6SPS"]
    with tempfile.TemporaryDirectory() as tmp:
        old, catalog = _old_tree(tmp)
        poses = os.path.join(tmp, "poses.npz")
        np.savez(poses, **_poses(args.n))
        procs = {}
        for name, path, cat in (("old", old, catalog), ("new", None, "")):
            spec = os.path.join(tmp, f"{name}.json")
            with open(spec, "w") as f:
                json.dump({"poses": poses, "catalog": cat, "cases": cases, "force": F_LOAD,
                           "torque": T_LOAD, "warm_calls": WARM_CALLS}, f)
            # (the old engine's extracted package; the new: this checkout's)
            env = dict(os.environ, PYTHONPATH=path or ROOT)
            # (in the temporary directory: "-c" puts the working directory first on the
            # path, where a checkout's own screwkit would come before the old one)
            procs[name] = subprocess.Popen([sys.executable, "-c", SERVER, spec], env=env,
                                           cwd=tmp, stdin=subprocess.PIPE,
                                           stdout=subprocess.PIPE, text=True)
        said = {name: json.loads(p.stdout.readline()) for name, p in procs.items()}
        for name, where in (("old", old), ("new", ROOT)):
            if os.path.dirname(said[name]["file"]) != os.path.join(where, "screwkit"):
                sys.exit(f"bench_old_engine: the {name} engine's process imported "
                         f"{said[name]['file']}, not {os.path.join(where, 'screwkit')}")
        checks = {name: s["forces"] for name, s in said.items()}
        for pm, forces in checks["old"].items():
            dev = np.max(np.abs(np.subtract(forces, checks["new"][pm])))
            if not dev <= 1e-9 * np.max(np.abs(forces)):
                sys.exit(f"bench_old_engine: the engines' actuator forces of the {pm} at its "
                         f"default pose differ by {dev:.3g}: not the same model")
        best = {c: {"old": float("inf"), "new": float("inf")} for c in cases}
        ratios = {c: [] for c in cases}
        for r in range(args.repeat):
            for case in cases:
                got = {}
                for name in (("old", "new") if r % 2 == 0 else ("new", "old")):
                    procs[name].stdin.write(case + "\n")
                    procs[name].stdin.flush()
                    got[name] = float(procs[name].stdout.readline())
                    best[case][name] = min(best[case][name], got[name])
                ratios[case].append(got["old"] / got["new"])
        for p in procs.values():
            p.stdin.close()
            p.wait()
    record = []
    for case in cases:
        one = case.startswith("one")
        per = WARM_CALLS if one else args.n
        issue = ISSUE_RATIOS.get("one warm pose" if one else case)
        record.append({"case": case, "old_s": best[case]["old"] / per,
                       "new_s": best[case]["new"] / per,
                       "speedup": float(np.median(ratios[case])),
                       "issue": list(issue) if issue else None})
    if args.json:
        json.dump({"old_engine": OLD_ENGINE, "n": args.n, "repeat": args.repeat,
                   "cases": record}, sys.stdout, indent=1)
        print()
        return 0
    print(f"the numpy engine ({OLD_ENGINE}) and this screwkit on this machine, paper workload; "
          f"best of {args.repeat} alternated rounds, speed-ups the medians over the rounds")
    for rec in record:
        if rec["case"].startswith("one"):
            figs = f"{rec['old_s'] * 1e3:9.3f} ms -> {rec['new_s'] * 1e6:8.1f} us"
        else:
            figs = f"{1 / rec['old_s']:9,.0f}/s -> {1 / rec['new_s']:10,.0f}/s"
        said = (f"  (the issue's target: {rec['issue'][0]:.1f}-{rec['issue'][1]:.1f}x its "
                "figures)" if rec["issue"] else "")
        print(f"  {rec['case']:22s} {figs}  {rec['speedup']:5.1f}x faster{said}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
