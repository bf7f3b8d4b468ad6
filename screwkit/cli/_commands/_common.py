"""Helpers shared by the CLI sub-commands (JSON output, number formatting)."""

from __future__ import annotations

import json
import math
import sys

import numpy as np

__all__ = ["to_jsonable", "dump_json", "fmt_vec", "fmt_num", "write_output", "emit_table",
           "dask_mapper"]


def to_jsonable(x):
    """Convert numpy values (and inf/nan) into JSON-safe Python objects."""
    if isinstance(x, dict):
        return {str(k): to_jsonable(v) for k, v in x.items()}
    if isinstance(x, (list, tuple)):
        return [to_jsonable(v) for v in x]
    if isinstance(x, np.ndarray):
        return to_jsonable(x.tolist())
    if isinstance(x, (np.floating, float)):
        v = float(x)
        if math.isnan(v):
            return None
        if math.isinf(v):
            return "inf" if v > 0 else "-inf"
        return v
    if isinstance(x, (np.integer,)):
        return int(x)
    if isinstance(x, np.bool_):
        return bool(x)
    return x


def dump_json(obj) -> str:
    return json.dumps(to_jsonable(obj), indent=2)


def fmt_num(x: float, digits: int = 6) -> str:
    if x == 0 or abs(x) < 10.0 ** (-digits - 6):
        return "0"
    return f"{x:.{digits}g}"


def fmt_vec(v, digits: int = 6) -> str:
    c = np.asarray(v, float).ravel()
    # round-off of a component next to large ones prints as 0 whatever the units
    ref = float(np.max(np.abs(c))) if c.size and np.all(np.isfinite(c)) else 0.0
    return "(" + ", ".join("0" if abs(x) <= 1e-12 * ref else fmt_num(float(x), digits)
                           for x in c) + ")"


def write_output(path, text: str) -> None:
    """Write ``text`` to the file ``path``, creating its missing parent folders.

    Raises
    ------
    InputError
        When the folder or the file cannot be written (named in the message).
    """
    from pathlib import Path

    from ...errors import InputError

    try:
        Path(path).parent.mkdir(parents=True, exist_ok=True)
        with open(path, "w", encoding="utf-8", newline="") as fh:
            fh.write(text)
    except OSError as exc:
        raise InputError(f"cannot write {str(path)!r}: {exc.strerror or exc}") from None


def dask_mapper(args):
    """``mapper(fn, items)`` on the Dask cluster that ``--workers N`` / ``--scheduler ADDRESS``
    name (:func:`screwkit.maps.run_tasks`), or None when neither is given."""
    from ...errors import InputError

    if args.workers is not None and args.scheduler:
        raise InputError("give either --workers N or --scheduler ADDRESS")
    if args.workers is None and not args.scheduler:
        return None
    from functools import partial

    from ...maps import run_tasks
    return partial(run_tasks, args.scheduler or args.workers)


def catalog_with_model_legs(path, option: str = "--model"):
    """The packaged catalog extended with the leg types of the model file ``path`` (its
    ``legs:`` list): a file without leg types is an InputError naming ``option``."""
    from ...errors import InputError
    from ...pm import Catalog, default_catalog, load_catalog

    extra = load_catalog(path)
    if not extra.legs:
        raise InputError(f"{option} {path}: the file defines no leg types (a 'legs:' list)")
    cat = default_catalog()
    return Catalog({**cat.legs, **extra.legs}, cat.table1, cat.pms, cat.source)


def default_jobs(jobs):
    """``jobs``, or by default 2 forked processes on Linux with 2 or more cores (elsewhere
    fork is unsafe or unavailable: 1, serial)."""
    import os

    if jobs is not None:
        return jobs
    return min(2, os.cpu_count() or 1) if sys.platform.startswith("linux") else 1


def process_mapper(jobs):
    """``mapper(fn, items, progress)`` on ``jobs`` local worker processes, or None (serial) for
    ``jobs <= 1``, a single item, or where processes cannot be forked (they inherit the
    imported package, so they start in milliseconds; a spawned process would import it
    again).  Results come back in order; ``progress(done, total)`` as they arrive."""
    import multiprocessing as mp

    if jobs is None or jobs <= 1 or "fork" not in mp.get_all_start_methods():
        return None

    def mapper(fn, items, progress=None):
        items = list(items)
        if len(items) < 2:
            return [fn(x) for x in items]
        from concurrent.futures import ProcessPoolExecutor
        out = []
        with ProcessPoolExecutor(min(jobs, len(items)), mp_context=mp.get_context("fork")) as pool:
            # a few items per task: fewer round trips, and the pool stays balanced
            for r in pool.map(fn, items, chunksize=max(1, len(items) // (8 * jobs))):
                out.append(r)
                if progress is not None:
                    progress(len(out), len(items))
        return out
    return mapper


def emit_table(out, text: str) -> None:
    """A command's table: to the file ``out`` (saying so on stderr), else to stdout."""
    if out:
        write_output(out, text)
        print(f"wrote {out}", file=sys.stderr)
    else:
        sys.stdout.write(text)


def add_unit_label_arguments(p, where: str) -> None:
    """``--length-unit`` and ``--force-unit``: the units printed ``where`` (a figure) for a
    model that declares none (:func:`check_unit_labels`)."""
    from .._types import label
    for unit in ("length", "force"):
        p.add_argument(f"--{unit}-unit", type=label(40),
                       help=f"{unit} unit printed {where}, for a model that declares none "
                            "(default: the model's)")


def check_unit_labels(model, length_unit, force_unit) -> None:
    """``--length-unit`` / ``--force-unit`` name the units of a model that declares none (a
    label, not a conversion): one of the known units, and, where the model declares its
    units, the same as those (``--units SI`` converts)."""
    from ...errors import InputError
    from ...pm._units import FORCE_UNITS, LENGTH_UNITS
    u = model.units
    for opt, given, known, declared in (("--length-unit", length_unit, LENGTH_UNITS, u.length),
                                        ("--force-unit", force_unit, FORCE_UNITS, u.force)):
        if given is None:
            continue
        if given not in known:
            raise InputError(f"{opt} {given!r}: not a unit screwkit knows (one of "
                             f"{', '.join(known)})")
        if u.declared and given != declared:
            raise InputError(f"{opt} {given}: {model.name} declares its units ({declared}); "
                             f"{opt} names the units of a model that declares none, it does not "
                             "convert")
