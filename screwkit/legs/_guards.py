"""Limits on everything a user sizes, and strict checks of user-given values (private).

Every value that comes from outside (a leg or PM string, a model file, a command-line
option, a number given to the Python API) is checked here or against these limits, so
that a hostile or mistyped input gives a :class:`~screwkit.errors.ScrewkitError` that
names the field, never a crash, a hang or a silent reinterpretation.  The limits are
listed in ``docs/conventions.md`` ("Input limits").

Numbers
-------
* written as text (command line, CSV cells): ASCII decimal only (``-12.5e3``; no
  ``1_000``, no non-ASCII digits such as ``١٢``, no ``nan``/``inf``), at most
  :data:`MAX_NUMBER_CHARS` characters, finite after conversion (``1e400`` overflows);
* given as values (Python API, YAML): real numbers, never booleans or strings, finite,
  and within the field's magnitude bound.
"""

from __future__ import annotations

import difflib
import math
import numbers
import re

import numpy as np

from ..errors import InputError

__all__ = [
    "MAX_LEG_STRING", "MAX_LEG_LETTERS", "MAX_LEG_JOINTS", "MAX_PM_STRING", "MAX_LEGS",
    "MAX_NAME", "MAX_TEXT", "MAX_NUMBER_CHARS", "MAX_MAGNITUDE", "MAX_ANGLE_DEG",
    "MAX_LENGTH_FACTOR", "MAX_LOAD", "MIN_STIFFNESS", "MAX_STIFFNESS", "MAX_SAMPLES",
    "MAX_BATCH", "MAX_POSES", "MAX_DRAWS", "MAX_SEED",
    "MAX_MODEL_BYTES", "MAX_CSV_BYTES", "MAX_YAML_NODES", "MAX_YAML_DEPTH", "MAX_ENTRIES",
    "MAX_STRUCTURE_CHECKS", "MAX_PATH_CHARS", "MAX_LABEL",
    "did_you_mean", "shorten", "parse_number", "parse_int", "real", "real_vector", "real_array",
    "check_path_text", "read_limited", "decode_utf8", "argtype", "flag", "check_seed",
]

#: Characters of a leg string (``RR_PRR``) and of a PM string (``2SPS+2SPR``).
MAX_LEG_STRING = 64
MAX_PM_STRING = 256
#: Joint letters of one leg, and 1-DOF joints of its equivalent chain (S = 3, U = C = 2).
MAX_LEG_LETTERS = 12
MAX_LEG_JOINTS = 18
#: Legs of one PM.
MAX_LEGS = 6
#: Characters of a name (PM, leg type, dimension, pose parameter) and of a free text
#: (summary, note) in a model.
MAX_NAME = 100
MAX_TEXT = 10_000
#: Characters of a label printed on a figure (--title, --length-unit, --force-unit).
MAX_LABEL = 200
#: Characters of a number written as text, sign and exponent included.
MAX_NUMBER_CHARS = 40
#: Largest magnitude of any number in a model file (dimensions, coordinates, pose values).
MAX_MAGNITUDE = 1e12
#: Largest magnitude of a pose angle, degrees (ten turns).
MAX_ANGLE_DEG = 3600.0
#: Largest pose length (Xo, Yo, Zo) as a multiple of the model's size.
MAX_LENGTH_FACTOR = 1e12
#: Largest magnitude of a workload component (force, torque) in the model's units.
MAX_LOAD = 1e12
#: Range of a stiffness (a row's, a leg's; force/length or torque/rad, model units): a
#: stiffness below it would be a free row (leave the model without it), above it a rigid
#: one (leave the row out); in between every deflection stays finite.
MIN_STIFFNESS = 1e-20
MAX_STIFFNESS = 1e20
#: Samples of a trajectory (--samples, rows of a path file), poses of ``check --poses``,
#: random draws of ``validate --draws``; seeds are 0 .. MAX_SEED.
MAX_SAMPLES = 100_000
MAX_POSES = 1000
MAX_DRAWS = 100
MAX_SEED = 2**32 - 1
#: Poses of one batched call of the Python API (``screwkit.analyze(pm, {"alpha": array})``).
MAX_BATCH = 1_000_000
#: Size of a YAML model file, and of a CSV path file (bytes).
MAX_MODEL_BYTES = 1 << 20
MAX_CSV_BYTES = 16 << 20
#: Nodes of a YAML document once its aliases are expanded, and its nesting depth.
MAX_YAML_NODES = 100_000
MAX_YAML_DEPTH = 64
#: Leg types, PMs or Table I cells of one file; structure checks of one leg type.
MAX_ENTRIES = 1000
MAX_STRUCTURE_CHECKS = 64
#: Characters of a file path given by the user.
MAX_PATH_CHARS = 4096

_NUMBER = re.compile(r"[+-]?(?:[0-9]+(?:\.[0-9]*)?|\.[0-9]+)(?:[eE][+-]?[0-9]+)?")
_INT = re.compile(r"[+-]?[0-9]+")


def did_you_mean(word, choices, n: int = 1) -> str:
    """``" (did you mean 'alpha'?)"`` for the closest of ``choices``, or ``""``."""
    if not isinstance(word, str) or len(word) > MAX_NAME:
        return ""
    pool = [c for c in choices if isinstance(c, str)]
    hit = difflib.get_close_matches(word, pool, n=n, cutoff=0.6)
    if not hit:
        low = {c.lower(): c for c in pool}
        if word.lower() in low:
            hit = [low[word.lower()]]
    return f" (did you mean {hit[0]!r}?)" if hit else ""


def shorten(value, limit: int = 60) -> str:
    """``repr`` of a value, cut to about ``limit`` characters (for messages)."""
    try:
        r = repr(value)
    except Exception:  # pragma: no cover - a repr that fails
        r = f"<{type(value).__name__}>"
    if len(r) <= limit:
        return r
    extra = f"... ({len(value)} characters)" if isinstance(value, str) else "..."
    return r[: limit - 3] + extra


def _non_ascii_hint(text: str) -> str:
    bad = next((c for c in text if ord(c) > 127), None)
    if bad is None:
        return ""
    if bad.isdigit() or bad.isnumeric():
        return f" (the digit {bad!r} is not an ASCII digit 0-9)"
    return f" (non-ASCII character {bad!r})"


def parse_number(text, what: str, *, bound: float | None = None) -> float:
    """A number written as text: ASCII decimal, at most :data:`MAX_NUMBER_CHARS` characters,
    finite (and ``|x| <= bound`` when given).

    Raises
    ------
    InputError
        Naming ``what`` (``"--pose alpha"``, ``"line 3, column 'Zo'"``) and the reason.
    """
    if not isinstance(text, str):
        raise InputError(f"{what}: expected a number written as text, got {type(text).__name__}")
    s = text.strip(" \t")
    if not s:
        raise InputError(f"{what}: empty value (expected a number)")
    if len(s) > MAX_NUMBER_CHARS:
        raise InputError(f"{what}: a number of {len(s)} characters is too long (at most "
                         f"{MAX_NUMBER_CHARS})")
    if not _NUMBER.fullmatch(s):
        low = s.lower().lstrip("+-")
        if low in ("nan", "inf", "infinity"):
            raise InputError(f"{what}: {s!r} is not a finite number")
        if low in ("true", "false", "yes", "no", "on", "off"):
            raise InputError(f"{what}: {s!r} is a boolean, not a number")
        raise InputError(f"{what}: {shorten(s)} is not a number{_non_ascii_hint(s)}")
    x = float(s)
    if not math.isfinite(x):
        raise InputError(f"{what}: {s} overflows (the largest number is about 1.8e308)")
    if bound is not None and abs(x) > bound:
        raise InputError(f"{what}: {s} is beyond the limit +-{bound:g}")
    return x


def parse_int(text, what: str, lo: int | None = None, hi: int | None = None) -> int:
    """An integer written as text (ASCII digits, optional sign), within ``[lo, hi]``."""
    if not isinstance(text, str):
        raise InputError(f"{what}: expected an integer written as text, got {type(text).__name__}")
    s = text.strip(" \t")
    if not s:
        raise InputError(f"{what}: empty value (expected an integer)")
    if len(s) > MAX_NUMBER_CHARS:
        raise InputError(f"{what}: an integer of {len(s)} characters is too long")
    if not _INT.fullmatch(s):
        raise InputError(f"{what}: {shorten(s)} is not an integer{_non_ascii_hint(s)}")
    n = int(s)
    _int_range(n, what, lo, hi)
    return n


def _int_range(n, what, lo, hi):
    if lo is not None and n < lo:
        raise InputError(f"{what}: {n} is below the minimum {lo}"
                         if hi is None else f"{what}: {n} is not in {lo} .. {hi}")
    if hi is not None and n > hi:
        raise InputError(f"{what}: {n} is beyond the limit {hi}"
                         if lo is None else f"{what}: {n} is not in {lo} .. {hi}")


def real(value, what: str, *, bound: float | None = None, error=InputError) -> float:
    """A real number given as a value: not a boolean, not a string, finite, ``|x| <= bound``.

    ``error`` builds the exception from a message (default :class:`InputError`).
    """
    if isinstance(value, (bool, np.bool_)):
        raise error(f"{what} must be a number, not a boolean ({value})")
    if isinstance(value, (str, bytes)):
        raise error(f"{what} must be a number, not a string ({shorten(value)})")
    if not isinstance(value, numbers.Real):
        if isinstance(value, np.ndarray) and value.ndim == 0 and value.dtype.kind in "iuf":
            value = value.item()
        else:
            raise error(f"{what} must be a number, got {type(value).__name__}")
    try:
        x = float(value)
    except (OverflowError, ValueError, TypeError):
        raise error(f"{what} = {shorten(value, 40)} is too large") from None
    if not math.isfinite(x):
        raise error(f"{what} must be finite, got {x}")
    if bound is not None and abs(x) > bound:
        raise error(f"{what} = {x:g} is beyond the limit +-{bound:g}")
    return x


def real_vector(value, what: str, n: int = 3, *, bound: float | None = None,
                error=InputError) -> np.ndarray:
    """``n`` real numbers (a list, tuple or 1-D array), each checked by :func:`real`."""
    if isinstance(value, np.ndarray):
        if value.dtype.kind == "b":
            raise error(f"{what} must be {n} numbers, not booleans")
        items = list(value.reshape(-1)) if value.ndim <= 1 else None
    elif isinstance(value, (list, tuple)):
        items = list(value)
    else:
        items = None
    if items is None or len(items) != n:
        raise error(f"{what} must be {n} numbers, got {shorten(value)}")
    return np.array([real(x, f"{what}[{k}]", bound=bound, error=error)
                     for k, x in enumerate(items)], dtype=float)


def real_array(value, what: str, error=InputError, *, max_size: int | None = None,
               finite: bool = True) -> np.ndarray:
    """A number or a 1-D array of numbers as a float array: no booleans, no strings, no
    objects that are not numbers, finite (NaN, infinity and overflow refused; with
    ``finite=False`` they are kept, for the caller to flag).  With ``max_size``, a longer
    array is refused before anything is converted or copied."""
    n = value.size if isinstance(value, np.ndarray) else (
        len(value) if isinstance(value, (list, tuple)) else 1)
    if max_size is not None and n > max_size:
        raise error(f"{what} has {n} values: at most {max_size} (split the batch)")
    if isinstance(value, (bool, np.bool_)):
        raise error(f"{what} must be a number, not a boolean ({value})")
    if isinstance(value, (str, bytes)):
        raise error(f"{what} must be a number, not a string ({shorten(value)})")
    if isinstance(value, np.ma.MaskedArray) and np.ma.getmaskarray(value).any():
        raise error(f"{what} has masked values (fill them, or leave those poses out)")
    if isinstance(value, (list, tuple)):
        for x in value:
            if isinstance(x, (bool, np.bool_, str, bytes)):
                raise error(f"{what} must be numbers, got {shorten(x)} among them")
    try:
        a = np.asarray(value)
    except (TypeError, ValueError, OverflowError):
        raise error(f"{what} must be a number or a 1-D array of numbers, got "
                    f"{shorten(value)}") from None
    if a.dtype.kind == "b":
        raise error(f"{what} must be numbers, not booleans")
    if a.dtype.kind == "O":
        try:
            a = np.array([real(x, what, error=error) for x in a.reshape(-1)],
                         dtype=float).reshape(a.shape)
        except TypeError:
            raise error(f"{what} must be a number or a 1-D array of numbers") from None
    elif a.dtype.kind not in "iuf":
        raise error(f"{what} must be a number or a 1-D array of numbers, got "
                    f"{shorten(value)}")
    if a.ndim > 1:
        raise error(f"{what} must be a number or a 1-D array, got shape {a.shape}")
    with np.errstate(over="ignore"):
        a = a.astype(float)
    if finite and not np.all(np.isfinite(a)):
        bad = a if a.ndim == 0 else a[~np.isfinite(a)][0]
        raise error(f"{what} is {float(bad)} (must be finite)")
    return a


def check_path_text(path, what: str = "file", error=InputError) -> str:
    """A path given by the user, as text: no NUL byte, not over-long (in total or per part).

    Messages start with ``what`` (e.g. ``"path file 'p.csv'"``)."""
    import os

    try:
        s = os.fspath(path)
    except TypeError:
        raise error(f"{what}: a path must be a string, got {type(path).__name__}") from None
    if isinstance(s, bytes):
        s = os.fsdecode(s)
    if "\x00" in s:
        raise error(f"{what}: the path contains a NUL character")
    if len(s) > MAX_PATH_CHARS:
        raise error(f"{what}: a path of {len(s)} characters is too long (at most "
                    f"{MAX_PATH_CHARS})")
    for part in s.replace("\\", "/").split("/"):
        n = len(part.encode("utf-8", "surrogateescape"))
        if n > 255:
            raise error(f"{what}: a part of the path is {n} bytes long (at most 255)")
    return s


def read_limited(path, max_bytes: int, what: str, error=InputError) -> bytes:
    """The bytes of a file, refusing a file larger than ``max_bytes`` (a device such as
    ``/dev/zero`` is cut there too) and turning every OS error into ``error``; messages
    start with ``what``."""
    s = check_path_text(path, what, error)
    try:
        with open(s, "rb") as fh:
            data = fh.read(max_bytes + 1)
    except OSError as exc:
        raise error(f"cannot read {what}: {exc.strerror or exc}") from None
    if len(data) > max_bytes:
        size = f"{max_bytes >> 20} MiB" if max_bytes >= 1 << 20 else f"{max_bytes >> 10} KiB"
        raise error(f"{what} is larger than {size} (the limit)")
    return data


def decode_utf8(data: bytes, what: str, error=InputError) -> str:
    """Text of ``data`` (UTF-8, a leading BOM dropped); a clear error on other encodings."""
    try:
        return data.decode("utf-8-sig")
    except UnicodeDecodeError as exc:
        line = data.count(b"\n", 0, exc.start) + 1
        raise error(f"{what} is not UTF-8 text: byte 0x{data[exc.start]:02x} at line {line} "
                    f"(offset {exc.start}); save it as UTF-8") from None


def argtype(convert, name: str):
    """An ``argparse`` ``type=`` from a converter that raises :class:`InputError`: the
    error becomes ``argparse.ArgumentTypeError`` (a one-line usage error)."""
    import argparse

    def wrapped(text):
        try:
            return convert(text)
        except InputError as exc:
            raise argparse.ArgumentTypeError(str(exc).removeprefix("value: ")) from None
    wrapped.__name__ = name
    return wrapped


def flag(value, what: str, error=InputError) -> bool:
    """``value`` as a flag: True or False (numpy's too); a string, a number or None is an
    error (``"no"`` is truthy in Python: it read as True)."""
    if isinstance(value, (bool, np.bool_)):
        return bool(value)
    raise error(f"{what} must be True or False, got {value!r:.40}")


def check_seed(seed, what: str = "seed") -> int:
    """A random seed: an integer from 0 to :data:`MAX_SEED` (numpy's generators' range)."""
    if isinstance(seed, (bool, np.bool_)) or not isinstance(seed, numbers.Integral) or \
            not 0 <= seed <= MAX_SEED:
        raise InputError(f"{what} must be an integer from 0 to {MAX_SEED}, got {seed!r:.40}")
    return int(seed)
