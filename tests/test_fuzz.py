"""Hostile input: only ScrewkitError escapes the API, the CLI exits 0 or 2 with one-line errors.

Property tests (hypothesis, derandomised so that CI sees the same examples every run):

* >= 10 000 generated leg and PM strings through ``parse_leg``, ``parse_pm``, ``screwkit.leg``
  and ``screwkit.load_pm`` (as names);
* >= 500 mutated YAML models (structured mutations of ``tests/data/user_3prs.yaml`` and
  ``user_pm.yaml``: deleted, renamed and retyped keys, hostile values; byte-level mutations;
  alias bombs, deep nesting, non-UTF-8 and oversized files) through ``screwkit.load_pm``;
* CLI runs in-process (``screwkit.cli.main``) with hostile option values: exit status 0 or 2,
  an error is one line on stderr.

Each example runs within a time bound (``deadline``) and a memory bound (``RLIMIT_AS``: at
most 1 GiB more address space).  Then one regression test per class of problem found by fuzzing (each
with its error class and a word of its message).
"""

from __future__ import annotations

import contextlib
import copy
import io
import os
import string
import tempfile
from pathlib import Path

import numpy as np
import pytest
import yaml
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st

import screwkit
import screwkit.cli
import screwkit.pm
from screwkit.errors import CatalogError, InputError, ParseError, ScrewkitError
from screwkit.legs import parse_leg, parse_pm

DATA = Path(__file__).parent / "data"
TEXTS = {k: (DATA / f).read_text(encoding="utf-8")
         for k, f in (("3prs", "user_3prs.yaml"), ("rhs", "user_pm.yaml"))}
BASES = {k: yaml.safe_load(v) for k, v in TEXTS.items()}
MEMORY = 1 << 30              # address space one example may add (bytes)
OUT = tempfile.mkdtemp(prefix="screwkit-fuzz-out-")      # where a drawing that succeeds goes
PNG = os.path.join(OUT, "x.png")


def fuzz_settings(n, deadline_ms):
    return settings(max_examples=n, deadline=deadline_ms, derandomize=True, database=None,
                    suppress_health_check=[HealthCheck.too_slow, HealthCheck.data_too_large,
                                           HealthCheck.filter_too_much])


def _address_space() -> int:
    with open("/proc/self/statm") as fh:
        return int(fh.read().split()[0]) * os.sysconf("SC_PAGE_SIZE")


@contextlib.contextmanager
def memory_bound(limit=MEMORY):
    """Run with at most ``limit`` bytes of address space more than now (``RLIMIT_AS``): an
    input that blows the memory up raises MemoryError, which fails the test, instead of
    swapping the machine to death.  (No bound where ``/proc`` or ``resource`` is missing.)"""
    try:
        import resource
        soft, hard = resource.getrlimit(resource.RLIMIT_AS)
        cap = _address_space() + limit
        if hard != resource.RLIM_INFINITY:
            cap = min(cap, hard)
        resource.setrlimit(resource.RLIMIT_AS, (cap, hard))
    except (ImportError, OSError, ValueError):
        yield
        return
    try:
        yield
    finally:
        resource.setrlimit(resource.RLIMIT_AS, (soft, hard))


#: How many strings and models the property tests generated (the docstring's counts).
COUNTS = {"strings": 0, "models": 0}


def only_screwkit_errors(fn, *args, **kwargs):
    """Call; a ScrewkitError is a fine answer, any other exception fails the test."""
    try:
        return fn(*args, **kwargs)
    except ScrewkitError as exc:
        msg = str(exc)
        assert msg and len(msg) < 5000, msg[:200]
        return exc


# --------------------------------------------------------------------------- strings

_LEG_ALPHABET = list("RPHUSC") * 8 + list("_+- 0123456789") + list("rphusc") + \
    ["\u0332", "١", "３", "Ｒ", "ſ", "é", "\x00", "\t", "\n", "/", "#", "K", "x"]

leg_text = st.one_of(
    st.lists(st.sampled_from(_LEG_ALPHABET), max_size=16).map("".join),
    st.text(max_size=12),
    st.builds(lambda c, s, n: c + s * n, st.sampled_from(["", "3", "6", "7", "99", "١"]),
              st.sampled_from(["R", "RPS", "S", "_R", "RPS+", "U"]), st.integers(0, 120)),
)


@fuzz_settings(600, 2000)
@given(st.lists(leg_text, min_size=8, max_size=14))
def test_leg_strings_raise_only_parse_errors(texts):
    with memory_bound():
        for text in texts:
            COUNTS["strings"] += 1
            for fn in (parse_leg, parse_pm):
                r = only_screwkit_errors(fn, text)
                if isinstance(r, ScrewkitError):
                    assert isinstance(r, ParseError)
                else:   # accepted: upper-case ASCII letters only, within the limits
                    letters = r.text if fn is parse_leg else "".join(lg.text for lg in r.legs)
                    assert set(letters) <= set("RPHUSC") and len(text) <= 256


_PM_PIECES = ["R", "P", "H", "U", "S", "C", "_", "2", "3", "-", "+", " ", "r", "s", "١", "0"]


@fuzz_settings(500, 2000)
@given(st.lists(st.lists(st.sampled_from(_PM_PIECES), max_size=40).map("".join),
                min_size=8, max_size=14))
def test_pm_strings_raise_only_parse_errors(texts):
    with memory_bound():
        for text in texts:
            COUNTS["strings"] += 1
            r = only_screwkit_errors(parse_pm, text)
            if not isinstance(r, ScrewkitError):
                assert 1 <= len(r.legs) <= 6
                assert all(1 <= lg.dof <= 18 for lg in r.legs)


@fuzz_settings(300, 3000)
@given(leg_text)
def test_leg_api_and_pm_names(text):
    COUNTS["strings"] += 1
    with memory_bound():
        r = only_screwkit_errors(screwkit.leg, text)
        if not isinstance(r, ScrewkitError):
            only_screwkit_errors(r.analyze)
        only_screwkit_errors(screwkit.load_pm, text)


# --------------------------------------------------------------------------- YAML models

_HOSTILE = st.one_of(
    st.booleans(), st.none(),
    st.integers(min_value=-10**30, max_value=10**30),
    st.floats(allow_nan=True, allow_infinity=True),
    st.sampled_from(["nan", ".inf", "1e400", "١٢", "R**R**R", "9" * 60, "x" * 300, "yes",
                     "-R", "R*1e300", "", "3rps", "XYZ", "alpha", "triangle", 1e12, 1e13,
                     -1e-300, 2**70, 7, 1000, "leg", "PRS/user"]),
    st.text(max_size=8),
    st.lists(st.integers(-5, 5), max_size=7),
    st.dictionaries(st.sampled_from(["a", "shape", "leg", "axis", "at"]), st.integers(0, 3),
                    max_size=2),
)


def _paths(d, prefix=()):
    yield prefix
    if isinstance(d, dict):
        for k, v in d.items():
            yield from _paths(v, prefix + (k,))
    elif isinstance(d, list):
        for i, v in enumerate(d):
            yield from _paths(v, prefix + (i,))


def _typo(key, i, c):
    k = str(key)
    i %= len(k) + 1
    return k[:i] + c + k[i + 1:] if i < len(k) else k + c


@st.composite
def mutated_models(draw):
    which = draw(st.sampled_from(sorted(BASES)))
    d = copy.deepcopy(BASES[which])
    for _ in range(draw(st.integers(1, 3))):
        paths = [p for p in _paths(d) if p]
        if not paths:
            break
        p = paths[draw(st.integers(0, len(paths) - 1))]
        parent = d
        for k in p[:-1]:
            parent = parent[k]
        key = p[-1]
        op = draw(st.sampled_from(["delete", "rename", "set", "set", "append"]))
        if op == "delete":
            del parent[key]
        elif op == "rename" and isinstance(parent, dict):
            parent[_typo(key, draw(st.integers(0, 20)), draw(st.sampled_from(string.ascii_letters)))] \
                = parent.pop(key)
        elif op == "append" and isinstance(parent, list):
            parent.append(copy.deepcopy(parent[key]))
        else:
            parent[key] = draw(_HOSTILE)
    return yaml.safe_dump(d, allow_unicode=True).encode("utf-8")


@st.composite
def byte_mutated_models(draw):
    text = TEXTS[draw(st.sampled_from(sorted(TEXTS)))].encode("utf-8")
    lines = text.splitlines(True)
    op = draw(st.sampled_from(["dup_line", "del_line", "insert", "truncate", "swap"]))
    if op == "dup_line":          # a duplicated key, mostly
        i = draw(st.integers(0, len(lines) - 1))
        lines.insert(i, lines[i])
        return b"".join(lines)
    if op == "del_line":
        del lines[draw(st.integers(0, len(lines) - 1))]
        return b"".join(lines)
    if op == "insert":
        i = draw(st.integers(0, len(text)))
        junk = draw(st.one_of(st.binary(min_size=1, max_size=6),
                              st.sampled_from([b"&a ", b"*a", b": ", b"- ", b"{", b"]", b"\xff",
                                               b"\xc3", b"!!python/name:os.system ", b"<<: ",
                                               b"? ", b"\t", b" yes", b".nan"])))
        return text[:i] + junk + text[i:]
    if op == "truncate":
        return text[: draw(st.integers(0, len(text)))]
    i, j = sorted(draw(st.tuples(st.integers(0, len(lines) - 1), st.integers(0, len(lines) - 1))))
    lines[i], lines[j] = lines[j], lines[i]
    return b"".join(lines)


def bomb(fan, depth, where):
    lines = ["x0: &x0 [" + ", ".join(["1"] * fan) + "]"]
    lines += [f"x{k}: &x{k} [" + ", ".join([f"*x{k - 1}"] * fan) + "]" for k in range(1, depth)]
    doc = TEXTS["3prs"]
    if where == "note":
        doc = doc.replace("    euler: XYZ", f"    note: *x{depth - 1}\n    euler: XYZ")
        lines = [f"x-{ln}" for ln in lines]
        lines = [ln.replace("*x", "*x-").replace("&x", "&x-") for ln in lines]
    return ("\n".join(lines) + "\n" + doc).encode()


special_models = st.one_of(
    st.builds(bomb, st.integers(2, 12), st.integers(2, 9), st.sampled_from(["top", "note"])),
    st.builds(lambda n, c: ("pms: " + c[0] * n + "1" + c[1] * n).encode(), st.integers(1, 3000),
              st.sampled_from([("[", "]"), ("{a: ", "}")])),
    st.builds(lambda b: b, st.binary(max_size=300)),
    st.builds(lambda enc: TEXTS["3prs"].replace("user model", "usér modèl").encode(enc),
              st.sampled_from(["latin-1", "utf-16", "cp1252", "utf-8-sig"])),
    st.builds(lambda n: (TEXTS["3prs"] + "# " + "x" * n + "\n").encode(),
              st.sampled_from([10, 1 << 20])),
    st.builds(lambda a: f"a: &a [1, *a]\n{TEXTS['3prs']}".encode() if a else
              b"pms:\n  X: &x\n    base: *x\n", st.booleans()),
)


@pytest.fixture(scope="module")
def model_file():
    d = tempfile.mkdtemp(prefix="screwkit-fuzz-")
    return os.path.join(d, "model.yaml")


def load_model(path, data, load=screwkit.load_pm):
    COUNTS["models"] += 1
    with open(path, "wb") as fh:
        fh.write(data)
    with memory_bound():
        m = only_screwkit_errors(load, path)
    if not isinstance(m, ScrewkitError):
        assert m.stated_dof in (1, 2, 3, 4, 5, 6)
    return m


@fuzz_settings(300, 5000)
@given(mutated_models())
def test_mutated_models(model_file, data):
    load_model(model_file, data)


@fuzz_settings(160, 5000)
@given(byte_mutated_models())
def test_byte_mutated_models(model_file, data):
    # text-level damage: the model layer (screwkit.pm.load_pm) reads and validates the file;
    # assembling the default pose (screwkit.load_pm) is covered by the structured mutations
    load_model(model_file, data, screwkit.pm.load_pm)


@fuzz_settings(60, 5000)
@given(special_models)
def test_hostile_model_files(model_file, data):
    load_model(model_file, data)


def test_the_counts_of_generated_inputs():
    """>= 10 000 strings and >= 500 models, when the property tests above ran (in order)."""
    if COUNTS["strings"] == 0 or COUNTS["models"] == 0:
        pytest.skip("run with the property tests above")
    assert COUNTS["strings"] >= 10_000 and COUNTS["models"] >= 500, COUNTS


# --------------------------------------------------------------------------- CLI

def run_cli(argv):
    out, err = io.StringIO(), io.StringIO()
    with contextlib.redirect_stdout(out), contextlib.redirect_stderr(err):
        try:
            code = screwkit.cli.main(argv)
        except SystemExit as exc:            # argparse
            code = exc.code
    return code, out.getvalue(), err.getvalue()


def assert_clean_exit(argv):
    with memory_bound():
        code, out, err = run_cli(argv)
    assert code in (0, 2), (argv, code, err[-500:])
    assert "Traceback" not in err and "internal error" not in err, err[-500:]
    if code == 2:
        errors = [ln for ln in err.splitlines() if ": error: " in ln]
        assert len(errors) == 1 and len(errors[0]) <= 2200, err[-500:]
    return code, out, err


_NUMS = st.one_of(
    st.sampled_from(["1e400", "-1e400", "1e308", "1e13", "nan", "inf", "-inf", "١٢", "１２", "1_000",
                     "0x10", "", " ", "9" * 60, "9" * 5000, "True", "yes", "5", "-0", ".5", "5.",
                     "1e-400", "4.9e-324", "²", "\x00", "x" * 3000, "+5", "−5", "1,2"]),
    st.floats(allow_nan=True, allow_infinity=True).map(repr),
    st.integers(-10**20, 10**20).map(str),
    st.text(max_size=6),
)
_INTS = st.one_of(st.sampled_from(["10**12", "1000000000000", "9" * 5000, "-1", "0", "١٢", "２",
                                   "1_0", "1e3", "3.5", "", " 7", "True", "100000", "100001"]),
                  st.integers(-10**15, 10**15).map(str))


@st.composite
def argv_lists(draw):
    """A command line with one hostile value; the rest is valid.  The values are checked
    before any model is loaded, so most runs end quickly (exit 2); some succeed."""
    v, n = draw(_NUMS), draw(_INTS)
    name = draw(st.one_of(st.sampled_from(["alpha", "beta", "Zo", "alfa", "L", "F_a1"]),
                          st.text(max_size=5)))
    return draw(st.sampled_from([
        ["analyze", "3RRPRR", "--pose", f"{name}={v}"],
        ["analyze", "3RRPRR", "--force", f"{v},0,0"],
        ["analyze", "3RRPRR", "--torque", f"0,0,{v}", "--json"],
        ["analyze", "3RRPRR", "--set", f"{name}={v}"],
        ["analyze", "3RRPRR", "--stiffness", f"F_a1={v}"],
        ["analyze", draw(leg_text)],
        ["analyze", "--model", draw(st.sampled_from(["/dev/null", "/", "x" * 300, "\x00",
                                                     "a" * 256 + ".yaml", "/nonexistent.yaml"]))],
        ["leg", draw(leg_text)],
        ["leg", "RPS", "--seed", n],
        ["check", "3RRPRR", "--poses", n],
        ["check", "3RRPRR", "--rtol", v],
        ["trajectory", "3RRPRR", "--expr", "alpha=0", "--expr", "beta=0", "--expr", "Zo=80",
         "--samples", n],
        ["trajectory", "3RRPRR", "--expr", f"alpha={v}", "--expr", "beta=0", "--expr", "Zo=80",
         "--samples", "2"],
        ["trajectory", "3RRPRR", "--t-range", "0", v, "--expr", "alpha=t"],
        ["draw", "3RRPRR", "-o", PNG, "--view", f"{v},30"],
        ["draw", "3RRPRR", "-o", PNG, "--dpi", n],
        ["draw", "3RRPRR", "-o", PNG, "--title", "t" * draw(st.integers(150, 5000))],
        ["validate", "RPS", "--no-catalog", "--draws", n],
        ["validate", "RPS", "--no-catalog", "--draws", "1", "--seed", n],
        ["validate", draw(leg_text), "--no-catalog", "--draws", "1"],
    ]))


@fuzz_settings(120, 15000)
@given(argv_lists())
def test_cli_exits_0_or_2_with_one_line_errors(argv):
    assert_clean_exit(argv)


# --------------------------------------------------------------------------- regressions

def expect(cls, word, fn, *args, **kwargs):
    with pytest.raises(cls) as ei:
        fn(*args, **kwargs)
    assert word.lower() in str(ei.value).lower(), str(ei.value)
    assert len(str(ei.value)) < 2000
    return ei.value


@pytest.mark.parametrize("text, word", [
    ("rps", "did you mean 'RPS'"),                 # lower case: a hint, not a generic geometry
    ("3rrprr", "did you mean '3RRPRR'"),
    ("ſPS", "not an ASCII letter"),               # 'ſ'.upper() == 'S'
    ("ＲPS", "not an ASCII letter"),
    ("١RPS", "not an ASCII digit"),               # int('١') == 1
    ("R" * 100, "too long"),                       # 10**7 letters used to hang
    ("R" * 13, "at most 12"),
    ("SSSSSSS", "at most 18"),
    ("9" * 5000 + "RPS", "too long"),             # int() of 5000 digits: ValueError
    ("99RPS", "1 to 6"),
    ("0003RPS", "1 to 6"),
    ("6S\n", "unknown joint letter"),
])
def test_parser_regressions(text, word):
    expect(ParseError, word, parse_pm, text)


def test_leg_lowercase_is_not_a_generic_leg():
    expect(ParseError, "upper case", screwkit.leg, "upu")


@pytest.mark.parametrize("name, cls, word", [
    ("3RRPRR" + "x" * 300, CatalogError, "too long"),        # OSError: file name too long
    ("a" * 256, CatalogError, "too long"),
    ("é" * 200, CatalogError, "too long"),
    ("3rrprr", CatalogError, "upper case"),
    ("3RRPRX", CatalogError, "did you mean '3RRPRR'"),
    ("a\x00.yaml", CatalogError, "NUL"),                     # ValueError: embedded null byte
    ("a" * 300 + ".yaml", CatalogError, "at most 255"),
])
def test_pm_name_regressions(name, cls, word):
    expect(cls, word, screwkit.load_pm, name)


def _write(tmp_path, data, name="m.yaml"):
    p = tmp_path / name
    p.write_bytes(data if isinstance(data, bytes) else data.encode("utf-8"))
    return str(p)


T = TEXTS["3prs"]
DIMS = "dimensions: {R: 60, r: 30}"


@pytest.mark.parametrize("data, word", [
    (T.encode("latin-1").replace(b"user", b"us\xe9r"), "not UTF-8"),  # UnicodeDecodeError
    (T.encode("utf-16"), "not UTF-8"),
    (bytes(range(256)) * 4, "not UTF-8"),
    (T + "#" + "x" * (1 << 20), "larger than 1 MiB"),              # 10 MB files were read whole
    ("x0: &x0 [1,1,1,1,1,1,1,1,1,1]\n" + "".join(
        f"x{k}: &x{k} [" + ",".join([f"*x{k - 1}"] * 10) + "]\n" for k in range(1, 9)) + T,
     "expands to more than"),                                       # alias bomb: a hang
    ("a: &a [1, *a]\n" + T, "recursive alias"),
    ("pms: " + "[" * 200 + "]" * 200, "nested"),
    (T.replace("    dof: 3\n", "    dof: 3\n    dof: 2\n"), "duplicate key 'dof'"),
    (T.replace(DIMS, "dimensions: {R: 60, r: 30, R: 70}"), "duplicate key 'R'"),
    (T.replace(DIMS, "dimensions: {R: true, r: 30}"), "boolean"),   # float(True) == 1
    (T.replace("dof: 3", "dof: yes"), "boolean"),
    (T.replace(DIMS, "dimensions: {R: .nan, r: 30}"), "not a finite number"),
    (T.replace(DIMS, "dimensions: {R: " + "9" * 5000 + ", r: 30}"), "too long"),  # ValueError
    (T.replace(DIMS, "dimensions: {R: 1.0e+300, r: 30}"), "beyond the limit"),
    (T.replace(DIMS, "dimensions: {R: 1e300, r: 30}"), "beyond the limit"),  # 1e300: YAML 1.2 float
    (T.replace(DIMS, "dimensions: {R: '١٢', r: 30}"), "not an ASCII digit"),
    (T.replace("    dof: 3\n", "    dof: 3\n    dofs: 3\n"), "did you mean 'dof'"),
    (T.replace("    summary: vertical", "    sumary: vertical"), "did you mean 'summary'"),
    (T.replace("pms:", "pm:"), "did you mean 'pms'"),
    (T.replace("{shape: triangle, circumradius: r}", "{shape: triangel, circumradius: r}"),
     "did you mean 'triangle'"),
    (T.replace("{shape: triangle, circumradius: r}", "{shape: circle, radius: r, count: 100000000}"),
     "1 to 6"),                                                     # 1e8 vertices: a hang
    (T.replace("home: {alpha: 0,", "home: {alfa: 0,"), "did you mean 'alpha'"),
    (T.replace("pose: {alpha: 4,", "pose: {alpha: 1.0e+20,"), "beyond the limit"),
    (T.replace("pose: {alpha: 4,", "pose: {alpha: 5000,"), "3600"),
    (T.replace("fraction: 0.4", "fraction: R**R**R"), "not a string"),  # ValueError in float()
    (T.replace("string: _PRS", "string: _prs"), "did you mean '_PRS'"),
    (T.replace("string: _PRS", "string: " + "R" * 100), "too long"),
    (T.replace("legs: [PRS/user, PRS/user, PRS/user]", "legs: [PRS/usr, PRS/user, PRS/user]"),
     "did you mean 'PRS/user'"),
    (T + "\nunits: {length: furlong}\n", "unknown length unit"),
    ("!!python/object/apply:os.system ['echo hi']\n", "constructor"),
])
def test_model_file_regressions(tmp_path, data, word):
    expect(CatalogError, word, screwkit.load_pm, _write(tmp_path, data))


def test_yaml_1e3_is_a_number_and_x_keys_are_free(tmp_path):
    text = "x-shapes: &tri {shape: triangle, circumradius: R}\n" + \
        T.replace("base: {shape: triangle, circumradius: R}", "base: *tri") \
         .replace(DIMS, "dimensions: {R: 6e1, r: 30}")
    m = screwkit.load_pm(_write(tmp_path, text))
    assert m.dimensions["R"] == 60.0


def test_device_and_directory_are_refused(tmp_path):
    os.symlink("/dev/zero", tmp_path / "zero.yaml")
    expect(CatalogError, "larger than", screwkit.load_pm, str(tmp_path / "zero.yaml"))
    (tmp_path / "dir.yaml").mkdir()
    expect(CatalogError, "cannot read", screwkit.load_pm, str(tmp_path / "dir.yaml"))


@pytest.mark.parametrize("kwargs, word", [
    ({"force": [1e308, 0, 0]}, "beyond the limit"),          # all-NaN statics with exit 0
    ({"torque": [0, 0, -1e308]}, "beyond the limit"),
    ({"force": [10**400, 0, 0]}, "too large"),               # OverflowError
    ({"force": [True, 0, 0]}, "boolean"),
    ({"force": ["5", 0, 0]}, "string"),
    ({"force": [[1, 2], 0, 0]}, "number"),                   # ValueError (inhomogeneous)
    ({"force": [np.nan, 0, 0]}, "finite"),
    ({"pose": {"Zo": 1e200}}, "beyond the limit"),            # LinAlgError in the solver
    ({"pose": {"alpha": 10**400}}, "too large"),              # OverflowError
    ({"pose": {"alpha": 1e4}, "degrees": True}, "3600"),      # continuation hang at 1e15 deg
    ({"pose": {"alpha": "١٢"}}, "string"),
    ({"pose": {"alpha": [True, False]}}, "among them"),
    ({"pose": {"alfa": 1.0}}, "did you mean 'alpha'"),
    ({"overrides": {"L": True}}, "boolean"),
    ({"overrides": {"L": 10**400}}, "too large"),
    ({"overrides": {"L": 1e300}}, "beyond the limit"),
    ({"overrides": {"Lx": 1.0}}, "did you mean 'L'"),
])
def test_api_value_regressions(kwargs, word):
    expect(InputError, word, screwkit.analyze, "3RRPRR", **kwargs)


@pytest.mark.parametrize("argv, word", [
    (["analyze", "3RRPRR", "--pose", "alpha=1e400"], "overflows"),
    (["analyze", "3RRPRR", "--pose", "Zo=1e308"], "beyond the limit"),     # LinAlgError: exit 3
    (["analyze", "3RRPRR", "--force", "1e308,0,0"], "beyond the limit"),   # NaN output, exit 0
    (["analyze", "3RRPRR", "--pose", "alpha=١٢"], "not an ASCII digit"),
    (["analyze", "3RRPRR", "--pose", "alpha=1_000"], "not a number"),
    (["analyze", "3RRPRR", "--pose", "alpha=nan"], "not a finite number"),
    (["analyze", "3RRPRR", "--pose", "alpha=" + "9" * 400], "too long"),
    (["analyze", "3RRPRR", "--pose", "alpha=1", "--pose", "alpha=2"], "twice"),
    (["analyze", "3RRPRR", "--set", "L=True"], "boolean"),
    (["analyze", "3rrprr"], "did you mean '3RRPRR'"),
    (["analyze", "x" * 300], "too long"),                                   # OSError: exit 3
    (["analyze", "--model", "/dev/zero"], "not a regular file"),            # MemoryError: exit 3
    (["analyze", "--model", "a\x00.yaml"], "NUL"),                          # ValueError: exit 3
    (["leg", "rps"], "did you mean 'RPS'"),
    (["leg", "RPS", "--seed", "-1"], "0 .. 4294967295"),
    (["leg", "RPS", "--seed", "١٢"], "not an ASCII digit"),
    (["trajectory", "3RRPRR", "--samples", "1000000000000", "--expr", "alpha=0"], "1 .. 100000"),
    (["trajectory", "3RRPRR", "--expr", "alpha=" + "9" * 400, "--expr", "beta=0",
      "--expr", "Zo=80"], "too long"),                                      # OverflowError
    (["trajectory", "3RRPRR", "--expr", "alpha=1e15", "--expr", "beta=0", "--expr", "Zo=80",
      "--samples", "3"], "3600"),                                           # a hang
    (["trajectory", "3RRPRR", "--expr", "alpha=0x10*t", "--expr", "beta=0", "--expr", "Zo=80"],
     "decimal"),
    (["trajectory", "3RRPRR", "--path", "/dev/zero"], "larger than"),       # MemoryError
    (["check", "3RRPRR", "--poses", "1000000000000"], "1 .. 1000"),         # a hang
    (["check", "3RRPRR", "--seed", "-1"], "0 .. 4294967295"),               # ValueError: exit 3
    (["check", "3RRPRR", "--rtol", "1e308"], "from 0 to 1"),
    (["validate", "RPS", "--draws", "1000000000000"], "1 .. 100"),          # a hang
    (["draw", "3RRPRR", "-o", PNG, "--title", "x" * 100000], "too long"),  # a hang
    (["draw", "3RRPRR", "-o", PNG, "--view", "1e400,30"], "overflows"),
    (["draw", "3RRPRR", "-o", "/"], "is a directory"),                      # wrote /.png
])
def test_cli_regressions(argv, word):
    code, out, err = assert_clean_exit(argv)
    assert code == 2 and word.lower() in err.lower(), err


def test_csv_path_regressions(tmp_path):
    for body, word in [("t,alpha,beta,Zo\n0,١,0,80\n", "not an ASCII digit"),
                       ("t,alpha,beta,Zo\n0,1_0,0,80\n", "not a number"),
                       ("t,alpha,beta,Zo\n0,True,0,80\n", "boolean"),
                       ("t,alpha,beta,Zo\n0,1e308,0,80\n", "beyond the limit"),
                       ("t,alpha,beta,Zo\n0," + "9" * 5000 + ",0,80\n", "too long")]:
        p = tmp_path / "p.csv"
        p.write_text(body, encoding="utf-8")
        code, _, err = assert_clean_exit(["trajectory", "3RRPRR", "--path", str(p)])
        assert code == 2 and word.lower() in err.lower(), err
    (tmp_path / "b.csv").write_bytes(b"t,alpha,beta,Zo\n0,\xe9,0,80\n")
    code, _, err = assert_clean_exit(["trajectory", "3RRPRR", "--path", str(tmp_path / "b.csv")])
    assert code == 2 and "not utf-8" in err.lower()


def test_expression_literals():
    from screwkit.pm import parse_expression
    expect(InputError, "too long", parse_expression, "9" * 400)
    expect(InputError, "overflows", parse_expression, "1e400*t")
    expect(InputError, "decimal", parse_expression, "1_000*t")
