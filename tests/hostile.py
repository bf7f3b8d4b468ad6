"""Hostile command lines, family by family, and the one rule they must keep (a helper of
``tests/test_fuzz_hostile.py`` and ``benchmarks/fuzz_hostile.py``, not a test module).

Every family draws command lines of one command with random hostile values of its options
and, through a model file, of the model keys it reads (``workload:``, ``dynamics:``, units).
:func:`run` runs one in-process with a time limit and checks the rule of issue 20:

* exit status 0 with finite output, or non-finite values only where the output flags them
  (a status or a word that says why), warnings one line each (``check``'s exit status 1, a
  check that failed, counts as such an answer); or
* exit status 2 with exactly one line on stderr, ``screwkit CMD: error: ...``;
* never exit status 3 (an internal error), a traceback, another line (a warning) before
  the error, a Python warning (numpy's overflow ...) on stderr, or a run longer than
  :data:`LIMIT` seconds.

:data:`COUNTS` tallies per family the inputs, exits 0, 2 and 3 and hangs.
"""

from __future__ import annotations

import contextlib
import io
import os
import re
import signal
import tempfile
import warnings

from hypothesis import strategies as st

#: Seconds one command may run (a hang otherwise).
LIMIT = 120
#: family -> {"inputs", "exit 0", "exit 2", "exit 3", "hangs"}
COUNTS: dict = {}
DIR = tempfile.mkdtemp(prefix="screwkit-hostile-")

#: Numbers as a user may type them: fine ones, and hostile ones.
NUMS = st.one_of(
    st.sampled_from(["nan", "inf", "-inf", "1e308", "-1e308", "1e-320", "4.9e-324", "1e400",
                     "0", "-0", "-1", "1e12", "1e13", "1e20", "1e21", "1e-21", "", " ", "x",
                     "١٢", "1_0", "0x10", "True", "9" * 50, "2", "5", "-5", "80", "0.5"]),
    st.floats(allow_nan=True, allow_infinity=True, width=64).map(repr),
    st.integers(-10**6, 10**6).map(str),
)
INTS = st.one_of(st.sampled_from(["-1", "0", "1", "2", "3", "1e3", "3.5", "", "nan",
                                  "99999999999", "4294967296", "١", " 2"]),
                 st.integers(-5, 40).map(str))
PATHS = st.sampled_from(["", " ", "\x00", "/", ".", "a/", "x" * 300, "/dev/null",
                         "/nonexistent/dir/f.csv", "ok.out"])
PMS = st.sampled_from(["3RRPRR", "3RPS", "4UPU", "3RSR", "2SPS+2SPR", "3UPU"])
VALUES = st.one_of(st.sampled_from([float("nan"), float("inf"), 1e308, -1e308, 1e-320, 0, -1,
                                    1e13, 1e21, "1e400", "nan", "x", True, None, [], {}, "L*1e300",
                                    2, 5.0, 1e3]),
                   st.floats(allow_nan=True, allow_infinity=True))


def _triple(v):
    return st.sampled_from([f"{v},0,0", f"0,0,{v}", f"{v}", f"{v},{v}", f"1,2,{v},4"])


def _file(name, text) -> str:
    path = os.path.join(DIR, name)
    with open(path, "w", encoding="utf-8") as fh:
        fh.write(text)
    return path


MODEL = """\
units: {{length: {length}, force: {force}}}
pms:
  H3SPR:
    dimensions: {{R: 80, r: 30}}
    base: {{shape: triangle, circumradius: R}}
    platform: {{shape: triangle, circumradius: r}}
    legs: [SPR, SPR, SPR]
    euler: XYZ
    independent: [alpha, beta, Zo]
    pose: {{alpha: 5, beta: -3, Zo: R}}
    dof: 3
{extra}"""


def model_file(draw, tag) -> str:
    """A model file with hostile values of its workload: and dynamics: keys."""
    length = draw(st.sampled_from(["cm", "m", "mm", "furlong"]))
    force = draw(st.sampled_from(["N", "kN", "lbf", "x"]))
    v = draw(VALUES)
    w = draw(VALUES)
    extra = draw(st.sampled_from([
        "",
        f"    workload: {{force: [0, 0, {v!r}], units: {{force: N, length: m}}}}\n",
        f"    workload: {{force: [1, 2, 3], torque: [{v!r}, 0, 0], units: model}}\n",
        f"    workload: {{force: [1, 2, 3]}}\n",
        f"    workload: {{torque: [1, 2], units: {{force: N, length: {w!r}}}}}\n",
        f"    dynamics:\n      platform: {{mass: {v!r}, inertia: [1, 1, {w!r}]}}\n",
        f"    dynamics:\n      gravity: [0, 0, {v!r}]\n      platform: {{mass: 2}}\n",
        f"    dynamics:\n      stiffness: {{actuator: {v!r}, force: {w!r}}}\n",
        f"    dynamics:\n      stiffness: {{beam: {{E: {v!r}, G: 1, area: 1, I: 1, J: 1}}}}\n",
        f"    dynamics:\n      legs: {{friction: {{P: {{viscous: {v!r}}}}}}}\n"
        "      platform: {mass: 1}\n",
    ]))
    return _file(f"{tag}.yaml", MODEL.format(length=length, force=force, extra=extra))


@st.composite
def analyze_argv(draw):
    v, name = draw(NUMS), draw(st.sampled_from(["alpha", "beta", "Zo", "gamma", "x", "F_a1"]))
    pm = draw(PMS)
    return draw(st.sampled_from([
        ["analyze", pm, "--pose", f"{name}={v}"],
        ["analyze", pm, "--force", draw(_triple(v))],
        ["analyze", pm, "--torque", draw(_triple(v)), "--json"],
        ["analyze", pm, "--stiffness", f"{name}={v}", "--force", "0,0,-1"],
        ["analyze", pm, "--set", f"{draw(st.sampled_from(['L', 'R', 'r', 'x']))}={v}"],
        ["analyze", "--model", model_file(draw, "a"), "--units", draw(st.sampled_from(
            ["SI", "model"]))],
        ["analyze", "--model", model_file(draw, "a2"), "--pose", f"{name}={v}", "--json"],
    ]))


@st.composite
def stiffness_argv(draw):
    v = draw(NUMS)
    pm = draw(PMS)
    opt = draw(st.sampled_from(["--k-actuator", "--k-force", "--k-couple"]))
    mass = model_file(draw, "s")
    return draw(st.sampled_from([
        ["stiffness", pm, opt, v],
        ["stiffness", pm, opt, v, "--force", "0,0,-1"],
        ["stiffness", pm, "--row", f"{draw(st.sampled_from(['F_a1', 'T_c1', 'x']))}={v}",
         "--force", "0,0,-1"],
        ["stiffness", "3RPS", "--pose", f"alpha={draw(st.sampled_from(['-43.1288471', v]))}",
         "--pose", "beta=0", "--pose", "Zo=60", "--k-actuator", "2000", "--k-force", "5000",
         "--force", draw(_triple(v))],
        ["stiffness", "--model", mass, "--k-actuator", "100", "--torque", "0,0,1"],
        ["stiffness", "--model", mass, "--mass", mass, "--force", "0,0,-1", "--geometric"],
        ["stiffness", pm, "--mass", draw(PATHS), "--force", "0,0,-1"],
    ]))


@st.composite
def map_argv(draw):
    v, n = draw(NUMS), draw(INTS)
    cmd = draw(st.sampled_from(["map", "size"]))
    base = [cmd, "3RRPRR", "--quiet"]
    grid = draw(st.sampled_from([f"alpha=-5:5:{n}", f"alpha={v}:5:2", f"Zo=70:{v}:2",
                                 f"beta=-1:1:2", f"{v}=0:1:2", "alpha", f"alpha=1:2:3:{n}"]))
    csv = _file("loads.csv", draw(st.sampled_from([
        "Fx,Fy,Fz,Tx,Ty,Tz\n1,2,3,4,5,6\n", f"Fx,Fy,Fz,Tx,Ty,Tz\n{v},0,0,0,0,0\n",
        "Fx,Fx,Fy,Fz,Tx,Ty,Tz\n1,1,2,3,4,5,6\n", "Fx;Fy;Fz;Tx;Ty;Tz\n1;2;3;4;5;6\n", "",
        "Fx,Fy,Fz,Tx,Ty,Tz\n1,2\n"])))
    return draw(st.sampled_from([
        base + ["--grid", grid, "--fix", "beta=0", "--fix", "Zo=80"],
        base + ["--grid", "alpha=-5:5:2", "--fix", f"beta={v}", "--fix", "Zo=80"],
        base + ["--samples", n, "--grid", "alpha=-5:5", "--grid", "beta=-1:1", "--seed",
                draw(INTS)],
        base + ["--grid", "alpha=-5:5:2", "--seed", n],
        base + ["--grid", "alpha=-5:5:2", "--scheduler", draw(st.sampled_from(
            ["tcp://nonsense", "nonsense", "tcp://:1", "tcp://h:0", "tcp://h:99999", ""]))],
        base + ["--grid", "alpha=-5:5:2", "--force", draw(_triple(v))],
        base + ["--grid", "alpha=-5:5:2", "--threads", n],
        [cmd, "3RPS", "--quiet", "--grid", "alpha=-5:5:2"],
        ["map", "3RRPRR", "--quiet", "--grid", "alpha=-5:5:2", "--out", draw(PATHS)],
        ["map", "3RRPRR", "--quiet", "--grid", "alpha=-5:5:2", "--plot", draw(PATHS)],
        ["size", "3RRPRR", "--quiet", "--grid", "alpha=-5:5:2", "--workloads", csv],
        [cmd, "3RRPRR", "--quiet", "--grid", "alpha=-5:5:2", "--units", "SI"],
    ]))


@st.composite
def trajectory_argv(draw):
    v, n = draw(NUMS), draw(INTS)
    pm = draw(st.sampled_from(["3RRPRR", "3RPS"]))
    expr = ["--expr", "alpha=5*t", "--expr", "beta=-3", "--expr", "Zo=80"]
    mass = model_file(draw, "t")
    return draw(st.sampled_from([
        ["trajectory", pm, *expr, "--samples", n],
        ["trajectory", pm, "--expr", f"alpha={v}*t", "--expr", "beta=0", "--expr", "Zo=70",
         "--samples", "3"],
        ["trajectory", pm, "--expr", "alpha=0", "--expr", "beta=0", "--expr", f"Zo=70+{v}*t",
         "--samples", "3"],
        ["trajectory", pm, *expr, "--samples", "3", "--force", draw(_triple(v))],
        ["trajectory", pm, *expr, "--samples", "3", "--out", draw(PATHS)],
        ["trajectory", pm, *expr, "--samples", "3", "--mass", mass],
        ["trajectory", pm, *expr, "--samples", "3", "--gravity", draw(_triple(v))],
        ["trajectory", pm, *expr, "--samples", "3", "--dynamics", "--mass", mass,
         "--force", "0,0,0", "--smoothing", v],
        ["trajectory", pm, *expr, "--samples", "3", "--scheduler", draw(st.sampled_from(
            ["tcp://nonsense", "", "tcp://h:70000"]))],
        ["trajectory", "3RPS", "--expr", "alpha=-43.1288471+1e-6*t", "--expr", "beta=0",
         "--expr", "Zo=60", "--samples", "3", "--force", draw(_triple(v))],
    ]))


@st.composite
def fk_argv(draw):
    v, n = draw(NUMS), draw(INTS)
    return draw(st.sampled_from([
        ["fk", "3RPS", "--actuators", f"r1={v},r2=69.5,r3=64.8"],
        ["fk", "3RPS", "--actuators", f"r1=67.1,r2=69.5,r3={v}", "--all", "--seeds",
         draw(st.sampled_from(["5", "20", n]))],
        ["fk", "3RRPRR", "--actuators", f"q1={v},q2=0,q3=0", "--json"],
        ["fk", "3RPS", "--actuators", "r1=67.1,r2=69.5,r3=64.8", "--seeds", n],
        ["fk", "3RPS", "--actuators", "r1=67.1,r2=69.5,r3=64.8", "--guess", f"alpha={v}"],
    ]))


@st.composite
def export_argv(draw):
    m = model_file(draw, "e")
    return draw(st.sampled_from([
        ["export", "3RRPRR", "--urdf", draw(PATHS)],
        ["export", "--model", m, "--urdf", os.path.join(DIR, "e.urdf")],
        ["export", "3RPS", "--urdf", os.path.join(DIR, "f.urdf"), "--mass", m],
        ["export", "3RPS", "--urdf", os.path.join(DIR, "g.urdf"), "--json"],
    ]))


@st.composite
def model_argv(draw):
    m = model_file(draw, "m")
    return draw(st.sampled_from([["model", "check", m], ["model", "check", m, "--json"],
                                 ["catalog", m], ["analyze", "--model", m, "--force", "1,2,3"]]))


@st.composite
def freedom_argv(draw):
    v = draw(NUMS)
    return draw(st.sampled_from([
        ["freedom", "--leg", draw(st.sampled_from(["", " ", "SPR", "x", "R" * 20]))],
        ["freedom", "--force", f"0,0,0:0,0,{v}"],
        ["freedom", "--couple", f"{v},0,0", "--force", "1,0,0:0,1,0"],
    ]))


@st.composite
def draw_argv(draw):
    v, n = draw(NUMS), draw(INTS)
    out = os.path.join(DIR, "d.png")
    return draw(st.sampled_from([
        ["draw", "3RRPRR", "-o", out, "--view", f"{v},30"],
        ["draw", "3RRPRR", "-o", out, "--dpi", n],
        ["draw", "3RPS", "-o", out],
        ["draw", "3RPS", "-o", draw(PATHS), "--force", draw(_triple(v))],
        ["draw", "3RRPRR", "-o", out, "--pose", f"alpha={v}"],
    ]))


@st.composite
def other_argv(draw):
    """The other commands' counts, seeds, addresses and outputs."""
    v, n = draw(NUMS), draw(INTS)
    return draw(st.sampled_from([
        ["synthesize", "3T", "--legs", n, "--limit", "1", *QUICK_SYNTHESIS],
        ["synthesize", "3T", "--scheduler", draw(st.sampled_from(["tcp://nonsense", "",
                                                                  "tcp://h:0"]))],
        ["synthesize", "3T", "--write", draw(PATHS), "--limit", "1", *QUICK_SYNTHESIS],
        ["synthesize", "3T", "--max-verified", n, "--jobs", n, "--limit", "1",
         "--no-generate", "--no-passive"],
        ["check", "3RPS", "--poses", n, "--seed", draw(INTS)],
        ["check", "3RPS", "--rtol", v],
        ["view", "3RPS", "--html", draw(PATHS), "--steps", n],
        ["view", "3RRPRR", "--html", os.path.join(DIR, "v.html"), "--pose", f"alpha={v}",
         "--steps", "2"],
        ["leg", "RPS", "--seed", n],
    ]))


#: Options that keep a synthesis to a second (the catalog's leg types, a few verifications):
#: the family checks the inputs, not the search.
QUICK_SYNTHESIS = ("--no-generate", "--no-passive", "--jobs", "1", "--max-verified", "3")

#: The families: name -> strategy of command lines.
FAMILIES = {"analyze": analyze_argv(), "stiffness": stiffness_argv(), "map/size": map_argv(),
            "trajectory": trajectory_argv(), "fk": fk_argv(), "export": export_argv(),
            "model keys": model_argv(), "freedom": freedom_argv(), "draw": draw_argv(),
            "other commands": other_argv()}

FLAG_WORDS = ("singular", "unreachable", "invalid", "not computed", "not solved", "flag",
              "null", "rigid", "status")


class _Hang(BaseException):
    """Not an Exception: the CLI's last-resort handler (exit 3) must not swallow it."""


def _alarm(signum, frame):
    raise _Hang()


def run(family: str, argv) -> tuple:
    """Run one command line; ``(status, stdout, stderr)``.  Asserts the rule (module
    docstring) and counts it under ``family``."""
    import screwkit.cli

    c = COUNTS.setdefault(family, {"inputs": 0, "exit 0": 0, "exit 2": 0, "exit 3": 0,
                                   "hangs": 0})
    c["inputs"] += 1
    out, err = io.StringIO(), io.StringIO()
    old = signal.signal(signal.SIGALRM, _alarm)
    signal.alarm(LIMIT)
    cwd = os.getcwd()
    try:
        os.chdir(DIR)
        with contextlib.redirect_stdout(out), contextlib.redirect_stderr(err), \
                warnings.catch_warnings(record=True) as caught:
            warnings.simplefilter("always")        # each would reach the user's stderr
            try:
                code = screwkit.cli.main([str(a) for a in argv])
            except SystemExit as exc:
                code = exc.code
    except _Hang:
        c["hangs"] += 1
        raise AssertionError(f"no answer within {LIMIT} s: {argv}") from None
    finally:
        signal.alarm(0)
        signal.signal(signal.SIGALRM, old)
        os.chdir(cwd)
    o, e = out.getvalue(), err.getvalue()
    if code == 1 and argv[0] == "check" and "FAIL" in o:
        code = 0                  # check's own verdict: a check failed (its documented exit 1)
    c[f"exit {code}"] = c.get(f"exit {code}", 0) + 1
    assert code in (0, 2), (argv, code, e[-600:])
    assert not caught, (argv, [f"{w.category.__name__}: {w.message}" for w in caught][:3])
    assert "Traceback" not in e and "internal error" not in e, (argv, e[-600:])
    lines = [ln for ln in e.splitlines() if ln.strip()]
    if code == 2:
        assert len(lines) == 1 and ": error: " in lines[0] and len(lines[0]) <= 2200, \
            (argv, e[-800:])
    else:
        for ln in lines:          # warnings and notes, one line each, never an error
            assert ": error: " not in ln, (argv, ln)
        low = o.lower()
        if re.search(r"\b(nan|inf)\b", low):
            assert any(w in low for w in FLAG_WORDS), (argv, o[:600])
    return code, o, e
