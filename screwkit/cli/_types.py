"""Strict argument types of the command line (private): numbers in ASCII decimal with a
limit on their size, bounded counts and seeds, labels and paths of bounded length.

Each is an ``argparse`` ``type=``: a bad value gives the one-line error
``screwkit CMD: error: argument --samples: ...`` with exit status 2 (see
:class:`OneLineParser`).
"""

from __future__ import annotations

import argparse
import os

from ..legs._guards import (MAX_LABEL, argtype, check_path_text, parse_int, parse_number,
                            shorten)
from ..errors import InputError

__all__ = ["number", "integer", "label", "path", "output", "scheduler", "OneLineParser",
           "UsageError"]


def number(*, bound: float | None = None, lo: float | None = None, hi: float | None = None):
    """A float option: ASCII decimal, finite, ``|x| <= bound``, ``lo <= x <= hi``."""
    def convert(text):
        x = parse_number(text, "value", bound=bound)
        if lo is not None and x < lo or hi is not None and x > hi:
            rng = f"from {lo:g} to {hi:g}" if lo is not None and hi is not None else \
                (f"at least {lo:g}" if lo is not None else f"at most {hi:g}")
            raise InputError(f"{text.strip()} is not {rng}")
        return x
    return argtype(convert, "number")


def integer(lo: int | None = None, hi: int | None = None):
    """An int option: ASCII digits, ``lo <= n <= hi``."""
    return argtype(lambda text: parse_int(text, "value", lo, hi), "integer")


def label(limit: int = MAX_LABEL):
    """A text printed on a figure: at most ``limit`` characters, no control characters."""
    def convert(text):
        if len(text) > limit:
            raise InputError(f"a text of {len(text)} characters is too long (at most {limit})")
        bad = next((c for c in text if ord(c) < 32 and c not in "\n\t"), None)
        if bad is not None:
            raise InputError(f"control character {bad!r} in {shorten(text)}")
        return text
    return argtype(convert, "label")


def _path(text):
    s = check_path_text(text, "value")
    if not s.strip():
        raise InputError("an empty file name")
    return s


#: A file path: not empty, no NUL character, not over-long.
path = argtype(_path, "path")


def _output(text):
    s = _path(text)
    if os.path.isdir(s) or s.endswith(("/", os.sep)):
        raise InputError(f"{shorten(s)} is a directory, not a file name")
    # (before any work: a part of the path that is a file, a folder not writable)
    parent = os.path.dirname(os.path.abspath(s))
    while not os.path.exists(parent) and os.path.dirname(parent) != parent:
        parent = os.path.dirname(parent)
    if not os.path.isdir(parent):
        raise InputError(f"cannot write {shorten(s)}: {shorten(parent)} is a file, not a folder")
    if not os.access(parent, os.W_OK):
        raise InputError(f"cannot write {shorten(s)}: the folder {shorten(parent)} is not "
                         "writable")
    return s


def _scheduler(text):
    from ..maps._dask import check_address
    return check_address(text, "value")


#: A Dask scheduler address ``tcp://HOST:PORT``.
scheduler = argtype(_scheduler, "address")


#: A file to write: a :data:`path` that is not an existing directory.
output = argtype(_output, "output")

#: The figure formats matplotlib writes (its ``savefig``), by the file's suffix.
FIGURE_FORMATS = ("png", "pdf", "svg", "svgz", "eps", "ps", "jpg", "jpeg", "tif", "tiff",
                  "webp", "gif", "pgf", "raw", "rgba", "avif")


def _figure(text):
    s = _output(text)
    suffix = os.path.splitext(s)[1].lower().lstrip(".")
    if suffix not in FIGURE_FORMATS:
        raise InputError(f"{shorten(s)}: a figure's file name ends in one of "
                         f".{', .'.join(FIGURE_FORMATS[:4])}... (not "
                         f"{'.' + suffix if suffix else 'no suffix'})")
    return s


#: A figure to write: an :data:`output` whose suffix names a format matplotlib writes (checked
#: before any work, not after it).
figure = argtype(_figure, "figure")


def _model_file(text):
    s = _output(text)
    if not s.lower().endswith((".yaml", ".yml")):
        raise InputError(f"{shorten(s)}: a model file's name ends in .yaml or .yml (the "
                         "loaders read it by that suffix)")
    return s


#: A model file to write (YAML; checked before any work).
model_file = argtype(_model_file, "model file")


def _png(text):
    s = _output(text)
    if not s.lower().endswith(".png"):
        raise InputError(f"{shorten(s)}: a screenshot's file name ends in .png")
    return s


#: A PNG screenshot to write (checked before any work).
png = argtype(_png, "png")


class UsageError(Exception):
    """A command-line usage error: ``line`` is its one-line message (exit status 2)."""

    def __init__(self, line: str):
        super().__init__(line)
        self.line = line


class _Once(argparse._StoreAction):
    """An option of one value: given again with another value it is an error (argparse
    would keep the last silently, as a second ``--force`` replaced the first); the same
    value twice is the same request."""

    def __call__(self, parser, namespace, values, option_string=None):
        seen = namespace.__dict__.setdefault("_given_once", set())
        if self.dest in seen and getattr(namespace, self.dest, None) != values:
            parser.error(f"{option_string} given twice with different values: give it once")
        seen.add(self.dest)
        super().__call__(parser, namespace, values, option_string)


class OneLineParser(argparse.ArgumentParser):
    """An ``ArgumentParser`` whose usage errors are one line, ``PROG: error: MESSAGE (see
    PROG --help)``, raised as :class:`UsageError` for :func:`screwkit.cli.main` to print and
    return 2 (the usage itself is in ``--help``).  Its options of one value are given once
    (:class:`_Once`); repeatable ones say so (``action="append"``)."""

    def add_argument(self, *args, **kwargs):
        if args and str(args[0]).startswith("-") and kwargs.get("action") in (None, "store"):
            kwargs["action"] = _Once
        return super().add_argument(*args, **kwargs)

    def error(self, message):
        msg = " ".join(str(message).split())
        if len(msg) > 400:
            msg = msg[:397] + "..."
        raise UsageError(f"{self.prog}: error: {msg} (see '{self.prog} --help')")
