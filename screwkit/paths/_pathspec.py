"""Path input: pose parameters as functions of a time-like parameter ``t``.

A path gives the *independent* pose parameters of a PM (e.g. ``alpha, beta,
Zo`` for the 3RRPRR) at N samples.  It is read either from

* a CSV file with a header row: a column ``t`` and one column per independent
  parameter (``Xo, Yo, Zo`` in length units, ``alpha, beta, gamma`` in
  **degrees**); blank lines and lines starting with ``#`` are skipped; or
* expressions ``name=EXPR`` in ``t`` (see :mod:`screwkit.pm._expressions`; angles
  in degrees) sampled at ``samples`` equally spaced values of ``t`` over
  ``t_range`` (default ``[0, 1]``).

The resulting :class:`PathSpec` holds angles in **radians** (the Python API's
unit); :meth:`PathSpec.display` gives them back in degrees.

Examples
--------
>>> from screwkit.paths import path_from_expressions
>>> p = path_from_expressions(["alpha=10*t", "beta=0", "Zo=70+30*t"],
...                           independent=("alpha", "beta", "Zo"), samples=3)
>>> p.t
array([0. , 0.5, 1. ])
>>> p.display()["alpha"], p.values["Zo"]
(array([ 0.,  5., 10.]), array([ 70.,  85., 100.]))
"""

from __future__ import annotations

import csv
import difflib
from dataclasses import dataclass, field

import numpy as np

from ..legs._guards import (MAX_ANGLE_DEG, MAX_CSV_BYTES, MAX_MAGNITUDE, MAX_NAME, MAX_SAMPLES,
                       check_path_text, decode_utf8, parse_number, read_limited, real, shorten)
from ..errors import InputError
from ..pm import parse_expression

__all__ = ["PathSpec", "POSE_PARAMETERS", "ANGLE_PARAMETERS", "path_from_csv",
           "path_from_expressions", "parse_assignment", "add_path_arguments", "expr_sampling",
           "path_from_args"]

#: All pose parameters a path may name, in display order.
POSE_PARAMETERS = ("Xo", "Yo", "Zo", "alpha", "beta", "gamma")
#: The angles (degrees in files and at the CLI, radians in the API).
ANGLE_PARAMETERS = frozenset({"alpha", "beta", "gamma"})


@dataclass(frozen=True)
class PathSpec:
    """Samples of the independent pose parameters along a path.

    Attributes
    ----------
    t : ndarray (N,)
        Strictly increasing sample parameter.
    values : dict str -> ndarray (N,)
        One array per independent parameter; angles in radians.
    source : str
        Where the path came from (file name or the expressions), for messages.
    """

    t: np.ndarray
    values: dict
    source: str = ""
    independent: tuple = field(default=())

    def __post_init__(self):
        t = np.array(self.t, dtype=float).reshape(-1)
        t.setflags(write=False)
        object.__setattr__(self, "t", t)
        vals = {}
        for k, v in self.values.items():
            a = np.array(v, dtype=float).reshape(-1)
            if a.shape != t.shape:
                raise InputError(f"path parameter {k!r} has {a.size} samples, t has {t.size}")
            a.setflags(write=False)
            vals[k] = a
        object.__setattr__(self, "values", vals)
        if not self.independent:
            object.__setattr__(self, "independent", tuple(vals))

    @property
    def n_samples(self) -> int:
        return int(self.t.size)

    @property
    def names(self) -> tuple:
        """Parameter names in :data:`POSE_PARAMETERS` order."""
        return tuple(sorted(self.values, key=_order))

    def display(self) -> dict:
        """The values with angles in degrees (for plots and tables)."""
        return {k: (np.degrees(v) if k in ANGLE_PARAMETERS else v.copy())
                for k, v in self.values.items()}

    def sample(self, i: int) -> dict:
        """Parameter values (floats, angles in radians) at sample ``i``."""
        return {k: float(v[i]) for k, v in self.values.items()}

    def __len__(self) -> int:
        return self.n_samples


def _order(name):
    return POSE_PARAMETERS.index(name) if name in POSE_PARAMETERS else len(POSE_PARAMETERS)


def _check_names(given, independent, where: str):
    """Raise on unknown or missing parameter names."""
    independent = tuple(independent)
    if not independent:
        raise InputError("no independent pose parameters given")
    for n in independent:
        if n not in POSE_PARAMETERS:
            raise InputError(f"{n!r} is not a pose parameter ({', '.join(POSE_PARAMETERS)})")
    indep = set(independent)
    unknown = [n for n in given if n not in indep]
    if unknown:
        parts = []
        for n in unknown:
            if n in POSE_PARAMETERS:
                parts.append(f"{n!r} is not independent here (it follows from the others)")
            else:
                hint = difflib.get_close_matches(n, list(POSE_PARAMETERS) + ["t"], n=1)
                parts.append(f"{n!r} is unknown"
                             + (f" (did you mean {hint[0]!r}?)" if hint else ""))
        raise InputError(f"{where}: {'; '.join(parts)}; the independent parameters are "
                         f"{', '.join(independent)}")
    missing = [n for n in independent if n not in given]
    if missing:
        raise InputError(f"{where}: missing {', '.join(missing)} (the independent parameters "
                         f"are {', '.join(independent)})")


def _check_t(t, where: str, line_of=None):
    if t.size == 0:
        raise InputError(f"{where}: no samples")
    d = np.diff(t)
    bad = np.flatnonzero(~(d > 0))
    if bad.size:
        i = int(bad[0]) + 1
        loc = f"line {line_of[i]}" if line_of else f"sample {i}"
        raise InputError(f"{where}: t must increase strictly; {loc} has t = {t[i]:g} after "
                         f"{t[i - 1]:g}")


def path_from_csv(path, independent, *, angle_unit: str = "deg",
                  length_unit: str | None = None) -> PathSpec:
    """Read a path from a CSV file.

    Parameters
    ----------
    path : str or Path
        CSV with a header row: ``t`` and one column per independent parameter.
    independent : sequence of str
        The PM's independent pose parameters, e.g. ``("alpha", "beta", "Zo")``.
    angle_unit : {"deg", "rad"}
        Unit of the angle columns in the file (default degrees), unless a column's header
        names its own: ``alpha [rad]``.
    length_unit : str, optional
        The model's length unit: a length column may then name it (``Zo [cm]``, as
        ``screwkit trajectory`` writes its CSV header); a header naming another unit is
        refused, never converted silently.

    Returns
    -------
    PathSpec

    Raises
    ------
    InputError
        Unreadable file, missing/unknown/duplicate column, a cell that is empty,
        not a number, NaN or infinite (with its line and column), t not strictly
        increasing.
    """
    if angle_unit not in ("deg", "rad"):
        raise InputError(f"angle_unit must be 'deg' or 'rad', not {angle_unit!r}")
    where = check_path_text(path, "path file")
    label = f"path file {shorten(where)}"
    text = decode_utf8(read_limited(where, MAX_CSV_BYTES, label), label)
    rows = []  # (line number, cells)
    header, header_line = None, None
    for lineno, cells in _csv_lines(text):
        if header is None:
            header, header_line = [c.strip() for c in cells], lineno
            header, col_units = _header_units(header, angle_unit, length_unit,
                                              f"{where}: line {lineno}")
            continue
        rows.append((lineno, cells))
    if header is None:
        raise InputError(f"{where}: empty file (expected a header row: t, "
                         f"{', '.join(independent)})")
    seen = set()
    for j, name in enumerate(header):
        if len(name) > MAX_NAME:
            raise InputError(f"{where}: line {header_line}: column {j + 1} has a name of "
                             f"{len(name)} characters")
        if not name:
            raise InputError(f"{where}: line {header_line}: column {j + 1} has no name")
        if name in seen:
            raise InputError(f"{where}: line {header_line}: column {name!r} appears twice")
        seen.add(name)
    if "t" not in seen:
        raise InputError(f"{where}: line {header_line}: no column 't' (columns: "
                         f"{', '.join(header)})")
    _check_names([n for n in header if n != "t"], independent, f"{where}: line {header_line}")
    if not rows:
        raise InputError(f"{where}: no data rows after the header")
    if len(rows) > MAX_SAMPLES:
        raise InputError(f"{where}: {len(rows)} data rows: a path has at most {MAX_SAMPLES} "
                         "samples")
    if len(header) > len(POSE_PARAMETERS) + 1:
        raise InputError(f"{where}: line {header_line}: {len(header)} columns (t and at most "
                         f"{len(POSE_PARAMETERS)} pose parameters)")
    data = np.empty((len(rows), len(header)))
    for i, (lineno, cells) in enumerate(rows):
        if len(cells) != len(header):
            raise InputError(f"{where}: line {lineno}: {len(cells)} cells, the header has "
                             f"{len(header)}")
        for j, cell in enumerate(cells):
            s = cell.strip()
            col = header[j]
            if not s:
                raise InputError(f"{where}: line {lineno}, column {col!r}: empty cell")
            bound = MAX_ANGLE_DEG if (col in ANGLE_PARAMETERS and col_units[col] == "deg") else \
                (np.radians(MAX_ANGLE_DEG) if col in ANGLE_PARAMETERS else None)
            data[i, j] = parse_number(s, f"{where}: line {lineno}, column {col!r}", bound=bound)
    lines = [ln for ln, _ in rows]
    t = data[:, header.index("t")]
    _check_t(t, where, line_of=lines)
    values = {}
    for j, name in enumerate(header):
        if name == "t":
            continue
        col = data[:, j]
        values[name] = np.radians(col) if (name in ANGLE_PARAMETERS and col_units[name] == "deg") \
            else col
    return PathSpec(t, values, where, tuple(independent))


def _header_units(header, angle_unit, length_unit, where):
    """Split ``name [unit]`` headers: ``(names, {name: unit})``, the angle columns' unit
    (``deg`` or ``rad``, default ``angle_unit``) and a length column's (the model's only)."""
    names, units = [], {}
    for cell in header:
        name, sep, rest = cell.partition("[")
        name, unit = (name.strip(), rest.rstrip().rstrip("]").strip()) if sep else (cell, None)
        names.append(name)
        if name in ANGLE_PARAMETERS:
            if unit not in (None, "deg", "rad"):
                raise InputError(f"{where}: column {shorten(cell)}: an angle is in deg or rad")
            units[name] = unit or angle_unit
        elif unit is not None and name in POSE_PARAMETERS:
            if length_unit is None or unit != length_unit:
                raise InputError(f"{where}: column {shorten(cell)}: the model's lengths are "
                                 f"in {length_unit or 'undeclared units'}; write the column "
                                 "in them (no conversion is made)")
        elif unit is not None and name == "t":
            raise InputError(f"{where}: column {shorten(cell)}: t is a path parameter "
                             "without a unit")
    return names, units


def _csv_lines(text):
    """Yield (1-based line number, cells) of the non-blank, non-comment CSV lines."""
    for lineno, line in enumerate(text.splitlines(), 1):
        if not line.strip() or line.lstrip().startswith("#"):
            continue
        yield lineno, next(csv.reader([line]))


def parse_assignment(text: str) -> tuple:
    """Split ``"name=EXPR"`` into ``(name, expr)``."""
    if not isinstance(text, str) or "=" not in text:
        raise InputError(f"expected NAME=EXPRESSION (e.g. alpha=10*sin(2*pi*t)), got {text!r}")
    name, expr = text.split("=", 1)
    name = name.strip()
    if not name.isidentifier():
        raise InputError(f"{text!r}: {name!r} is not a parameter name")
    if not expr.strip():
        raise InputError(f"{text!r}: empty expression for {name}")
    return name, expr


def path_from_expressions(exprs, independent, *, samples: int = 51, t_range=(0.0, 1.0),
                          angle_unit: str = "deg") -> PathSpec:
    """Sample a path given by expressions in ``t``.

    Parameters
    ----------
    exprs : sequence of str ``"name=EXPR"``, or mapping name -> EXPR
    independent : sequence of str
        The PM's independent pose parameters; each must get exactly one expression.
    samples : int
        Number of samples N (>= 1); ``t`` runs over ``t_range`` inclusive.
    t_range : (float, float)
        ``(t0, t1)`` with ``t1 > t0`` (or equal when ``samples == 1``).
    angle_unit : {"deg", "rad"}
        Unit in which the angle expressions are written (default degrees).

    Returns
    -------
    PathSpec
    """
    if angle_unit not in ("deg", "rad"):
        raise InputError(f"angle_unit must be 'deg' or 'rad', not {angle_unit!r}")
    if isinstance(exprs, dict):
        pairs = list(exprs.items())
    else:
        if isinstance(exprs, str):
            exprs = [exprs]
        pairs = [parse_assignment(e) for e in exprs]
    names = [n for n, _ in pairs]
    dup = sorted({n for n in names if names.count(n) > 1})
    if dup:
        raise InputError(f"expression given twice for {', '.join(dup)}")
    _check_names(names, independent, "path expressions")
    if isinstance(samples, (bool, np.bool_)) or not isinstance(samples, (int, np.integer)):
        raise InputError(f"samples must be an integer, not {shorten(samples)}")
    n = int(samples)
    if not 1 <= n <= MAX_SAMPLES:
        raise InputError(f"samples must be from 1 to {MAX_SAMPLES}, not {n}")
    if not (isinstance(t_range, (list, tuple)) and len(t_range) == 2):
        raise InputError(f"t range must be two numbers, not {shorten(t_range)}")
    t0, t1 = (real(x, "t range", bound=MAX_MAGNITUDE) for x in t_range)
    if t1 < t0 or (t1 == t0 and n > 1):
        raise InputError(f"t range [{t0:g}, {t1:g}] must have t1 > t0")
    t = np.linspace(t0, t1, n)
    values = {}
    for name, text in pairs:
        try:
            v = parse_expression(text)(t)
        except InputError as exc:
            raise InputError(f"{name}: {exc}") from None
        if name in ANGLE_PARAMETERS:
            lim = MAX_ANGLE_DEG if angle_unit == "deg" else np.radians(MAX_ANGLE_DEG)
            k = int(np.argmax(np.abs(v)))
            if abs(v[k]) > lim:
                raise InputError(f"{name}: the expression reaches {v[k]:g} {angle_unit} at t = "
                                 f"{t[k]:g}, beyond the limit +-{lim:g} {angle_unit} (ten turns)")
        values[name] = np.radians(v) if (name in ANGLE_PARAMETERS and angle_unit == "deg") else v
    src = "; ".join(f"{k}={e.strip()}" for k, e in pairs)
    return PathSpec(t, values, src, tuple(independent))


def add_path_arguments(parser) -> None:
    """Add ``--path FILE``, ``--expr NAME=EXPR`` (repeatable), ``--samples N`` and
    ``--t-range T0 T1`` to an argparse parser (for a CLI sub-command)."""
    g = parser.add_argument_group("path (angles in degrees)")
    from ..legs._guards import argtype, parse_int

    def integer(lo, hi):
        return argtype(lambda text: parse_int(text, "value", lo, hi), "integer")

    number = argtype(lambda text: parse_number(text, "value", bound=MAX_MAGNITUDE), "number")
    path = argtype(lambda text: check_path_text(text, "value"), "path")
    g.add_argument("--path", metavar="FILE", type=path,
                   help="CSV with a header row: t and the independent pose parameters "
                        "(angles in degrees; a header may name its unit: alpha [rad], Zo [cm] "
                        "in the model's length unit)")
    g.add_argument("--expr", action="append", metavar="NAME=EXPR", default=[],
                   help="a pose parameter as an expression in t, e.g. "
                        "'alpha=10*sin(2*pi*t)' (repeat for each parameter)")
    g.add_argument("--samples", type=integer(1, MAX_SAMPLES), default=None,
                   help=f"samples of t for --expr (default 51, at most {MAX_SAMPLES}; a --path "
                        "file's rows are its samples)")
    g.add_argument("--t-range", type=number, nargs=2, default=None,
                   metavar=("T0", "T1"), help="range of t for --expr (default 0 1)")


def expr_sampling(args) -> tuple:
    """``(samples, t_range)`` of ``--expr`` (defaults 51, (0, 1)); with ``--path`` they are
    an error: the file's rows are its samples, and silently ignored they would not be."""
    samples, t_range = getattr(args, "samples", None), getattr(args, "t_range", None)
    if getattr(args, "path", None) and (samples is not None or t_range is not None):
        raise InputError("--samples and --t-range sample the --expr expressions; a --path "
                         "file's rows are its samples: drop them")
    return (51 if samples is None else samples,
            (0.0, 1.0) if t_range is None else tuple(t_range))


def path_from_args(args, independent, length_unit: str | None = None) -> PathSpec:
    """The :class:`PathSpec` described by parsed :func:`add_path_arguments` options
    (``length_unit``: the model's, which a ``--path`` file's header may name)."""
    if getattr(args, "path", None) and getattr(args, "expr", None):
        raise InputError("give either --path FILE or --expr NAME=EXPR, not both")
    samples, t_range = expr_sampling(args)
    if getattr(args, "path", None):
        return path_from_csv(args.path, independent, length_unit=length_unit)
    if getattr(args, "expr", None):
        return path_from_expressions(args.expr, independent, samples=samples, t_range=t_range)
    raise InputError(f"no path given: use --path FILE or --expr NAME=EXPR for each of "
                     f"{', '.join(independent)}")
