"""The first run after an install: ``screwkit analyze 3RRPRR`` with an empty kernel cache.

Prints the wall and CPU time (the command and any child process it starts) of a first run
compiled on two processes (the default where there are two cores) beside one compiled on
one process (``SCREWKIT_COMPILE_PROCESSES=1``), each in a fresh empty cache directory, and
the load average.  ``--repeat`` runs each that many times, alternating.

``--write`` instead compiles the analysis on one process in an empty cache and writes the
kernels it compiled, their argument types and their groups to
``screwkit/engine/_kernels/first_compile.txt`` (see ``_kernels/_warm.py``); run it after a
change of a kernel's arguments (tests/test_first_compile.py says when).

    python benchmarks/first_run.py [--repeat 2] [--command "analyze 3RRPRR"]
    python benchmarks/first_run.py --write
"""

from __future__ import annotations

import argparse
import os
import resource
import shutil
import subprocess
import sys
import tempfile
import time

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
PACKAGE = "screwkit.engine._kernels."
#: The kernels whose compile the child does (and everything compiled under them).
CLOSURE = "solve_pose"
#: The pose kernel's own functions (compiled last, once the closure is in the cache).
POSE = ("run_range",)  # (its loop, `run_poses`, is typed into it)
#: The pose kernel's callees the child compiles after the closure (and everything compiled
#: under them), group ``handed``: this process's share is otherwise the longer (its callees,
#: then the pose kernel itself, some 20 s, while the child's entry points were done some
#: 12 s before: a first run 47-48 s, against 44-45 s so), and these come last in its list
#: (the home predictor, a row template's members, a leg's rows by the general rules), by
#: which time the child has them in the cache.
HANDED = ("template_one", "predict", "leg_rows")


#: This process's kernels that call no kinematics (compiled first, while the child
#: compiles the kinematics under the closure: the rows' calls of them then load from the
#: cache rather than compile them a second time).
FIRST = ("_pack", "_statics", "_small", "_eigen", "_tridiagonal", "_driver")


def ordered(lines):
    """``lines`` with the ``main`` group's kernels of :data:`FIRST` first (the compile
    order otherwise kept)."""
    def key(line):
        group, module = line.split("\t", 2)[:2]
        return 0 if group == "main" and (module in FIRST or "make_" in line) else 1
    mains = [ln for ln in lines if ln.startswith("main\t")]
    it = iter(sorted(mains, key=key))
    return [next(it) if ln.startswith("main\t") else ln for ln in lines]


def _write(command) -> None:
    tmp = tempfile.mkdtemp(prefix="screwkit-first-")
    os.environ["NUMBA_CACHE_DIR"] = tmp
    os.environ["SCREWKIT_COMPILE_PROCESSES"] = "1"
    sys.path.insert(0, ROOT)
    from numba.core import event
    stack, done = [], []

    class Recorder(event.Listener):
        def on_start(self, ev):
            stack.append(ev.data["dispatcher"].py_func.__name__)

        def on_end(self, ev):
            d = ev.data["dispatcher"]
            done.append((d.py_func.__module__, d.py_func.__name__, ev.data["args"],
                         tuple(stack)))
            stack.pop()

    event.register("numba:compile", Recorder())
    from screwkit.cli import main
    try:
        main(command)
    finally:
        shutil.rmtree(tmp, ignore_errors=True)
    rows = []
    for module, name, args, under in done:
        if not module.startswith(PACKAGE):
            continue                      # numba's own (compiled with their callers)
        if CLOSURE in under:
            group = "closure"
        elif under[0] == POSE[0] and any(h in under for h in HANDED):
            group = "handed"
        elif name in POSE:
            group = "pose"
        elif under[0] == POSE[0]:
            group = "main"
        else:
            group = "other"
        rows.append([group, module[len(PACKAGE):], name, args, under[0]])
    # a kernel with other argument types in each process would have two processes add
    # entries to its cache index at once (each naming its entry the same file): the child's
    # entry points that compile it are compiled here
    child = {(r[1], r[2]) for r in rows if r[0] in ("closure", "handed", "other")}
    parent = {(r[1], r[2]) for r in rows if r[0] in ("main", "pose")}
    roots = {r[4] for r in rows if (r[1], r[2]) in child & parent and r[0] == "other"}
    for r in rows:
        if r[0] == "other" and r[4] in roots:
            r[0] = "main"
    lines = [f"{g}\t{m}\t{n}\t{a!r}\n" for g, m, n, a, _ in rows]
    lines = ordered(lines)
    if not lines:           # the analysis failed before compiling: keep the list there is
        sys.exit("first_run.py --write: no kernel was compiled (did the analysis fail?); "
                 "first_compile.txt left as it was")
    path = os.path.join(ROOT, "screwkit", "engine", "_kernels", "first_compile.txt")
    with open(path, "w", encoding="utf-8") as f:
        f.write("# The kernels `screwkit analyze 3RRPRR` compiles, in order: group, module, "
                "function, argument types\n# (written by benchmarks/first_run.py --write; "
                "see _warm.py)\n")
        f.writelines(lines)
    print(f"{len(lines)} kernels written to {path}")


def _run(command, processes: str):
    cache = tempfile.mkdtemp(prefix="screwkit-first-")
    env = dict(os.environ, NUMBA_CACHE_DIR=cache, SCREWKIT_COMPILE_PROCESSES=processes,
               PYTHONPATH=ROOT)
    before = resource.getrusage(resource.RUSAGE_CHILDREN)
    t = time.perf_counter()
    out = subprocess.run([sys.executable, "-m", "screwkit", *command], env=env, cwd=ROOT,
                         capture_output=True, text=True)
    wall = time.perf_counter() - t
    after = resource.getrusage(resource.RUSAGE_CHILDREN)
    shutil.rmtree(cache, ignore_errors=True)
    if out.returncode:
        sys.exit(f"{' '.join(command)} failed: {out.stderr.strip()}")
    cpu = (after.ru_utime - before.ru_utime) + (after.ru_stime - before.ru_stime)
    return wall, cpu, out.stderr.strip()


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--write", action="store_true", help="write first_compile.txt")
    ap.add_argument("--repeat", type=int, default=1)
    ap.add_argument("--command", default="analyze 3RRPRR")
    a = ap.parse_args()
    command = a.command.split()
    if a.write:
        _write(command)
        return
    for k in range(a.repeat):
        for label, processes in (("two processes", "2"), ("one process", "1")):
            wall, cpu, note = _run(command, processes)
            load = os.getloadavg()
            print(f"first run, {label:13s}: wall {wall:6.1f} s  CPU {cpu:6.1f} s  "
                  f"(load {load[0]:.2f} {load[1]:.2f})", flush=True)
            if k == 0 and label == "two processes":
                print(f"  stderr: {note}")


if __name__ == "__main__":
    main()
