"""Command-line interface: a thin shell over the Python API.

Each sub-command lives in its own module ``screwkit.cli._commands.<name>`` exposing
``register(subparsers)``; errors derived from :class:`ScrewkitError` are printed
on one line and give exit status 2, never a traceback.
"""

from __future__ import annotations

import argparse
import importlib
import os
import re
import sys

from ..errors import ScrewkitError

__all__ = ["main", "run", "build_parser", "COMMANDS"]

#: Sub-command modules, in the order of ``screwkit --help``.
COMMANDS = ["leg", "catalog", "analyze", "check", "model", "trajectory", "draw", "validate", "map", "size",
            "optimize", "fk", "stiffness", "freedom", "export", "view", "synthesize"]


def build_parser(command: str | None = None) -> argparse.ArgumentParser:
    """The parser of every sub-command, or of ``command`` alone (what ``main`` parses when
    the command line starts with that command's name: the other commands' modules, and what
    they import to describe their arguments, are then not imported)."""
    from .. import __version__

    from ._types import OneLineParser

    p = OneLineParser(
        prog="screwkit",
        description="Screw-theory statics of limited-DOF parallel manipulators. "
                    "Twists [v; w] and wrenches [f; m] about the base origin; angles in "
                    "degrees at the command line.")
    p.add_argument("--version", action="version", version=f"screwkit {__version__}")
    sub = p.add_subparsers(dest="command", metavar="COMMAND")
    for name in (COMMANDS if command is None else [command]):
        importlib.import_module(f"._commands.{name}", __package__).register(sub)
    return p


def _one_line(exc, limit: int = 2000) -> str:
    """The message of an error on one line, at most ``limit`` characters."""
    msg = " ".join(str(exc).split())
    return msg if len(msg) <= limit else msg[: limit - 3] + "..."


def _unrecognized(parser, command, extra, args=None) -> str:
    """One line for arguments no option takes, with the closest option of ``command``."""
    import difflib
    what = f"screwkit {command}" if command else "screwkit"
    options: list[str] = []

    def child(p, name):
        sub = next((a for a in p._actions if isinstance(a, argparse._SubParsersAction)), None)
        return sub.choices.get(name) if sub is not None and name else None

    sp = child(parser, command) or parser
    action_name = getattr(args, "model_command", None)      # (screwkit model ACTION ...)
    if action_name and child(sp, action_name) is not None:
        sp, what = child(sp, action_name), f"{what} {action_name}"
    for action in sp._actions:
        options += [o for o in action.option_strings if o.startswith("--")]
    hint = ""
    first = next((w for w in extra if w.startswith("-")), None)
    if first:
        close = difflib.get_close_matches(first.split("=")[0], options, n=1, cutoff=0.75)
        hint = f"; did you mean {close[0]}?" if close else ""
    return (f"{what}: error: unrecognized arguments: {' '.join(extra)}{hint} "
            f"(see '{what} --help')")


def _json_usage_error(words, line: str) -> None:
    """With ``--json`` asked, a usage error is a JSON object on stdout too (as every other
    error of a command that prints JSON), so that a script reads one."""
    if "--json" in words:
        _print_json({"error": {"type": "UsageError", "message": line.split("error: ", 1)[-1]}})


def _print_json(obj) -> None:
    """An error's JSON object on stdout; where its reader has gone (a closed pipe) the line
    on stderr has said it: nothing more, the exit status stays the error's."""
    import json
    try:
        print(json.dumps(obj, indent=2))
        sys.stdout.flush()
    except OSError:
        try:                                 # (the buffered rest would fail again at exit)
            import os
            os.dup2(os.open(os.devnull, os.O_WRONLY), sys.stdout.fileno())
        except (OSError, ValueError):
            pass


#: A value that starts with a minus sign: a negative number or a list of numbers.
_NEGATIVE = re.compile(r"^-(\d|\.\d)[\d.,eE+:-]*$")


def _negative_values(parser, words: list) -> list:
    """``--force -20,-30,-60`` as ``--force=-20,-30,-60``: argparse takes a word that starts
    with ``-`` and is not a plain negative number for an option, and the paper's own
    workload is all negative.  Only for the options that take one value."""
    import argparse
    one = set()
    todo = [parser]
    while todo:
        p = todo.pop()
        for a in p._actions:
            if isinstance(a, argparse._SubParsersAction):
                todo.extend(a.choices.values())
            elif a.option_strings and a.nargs is None and not isinstance(
                    a, (argparse._StoreConstAction, argparse._CountAction,
                        argparse._HelpAction, argparse._VersionAction)):
                one.update(a.option_strings)
    out: list = []
    for w in words:
        if out and out[-1] in one and isinstance(w, str) and _NEGATIVE.match(w):
            out[-1] = f"{out[-1]}={w}"
        else:
            out.append(w)
    return out


def main(argv=None) -> int:
    from ._types import UsageError

    if sys.stdout is None:                  # (started with its output closed: ``>&-``)
        if sys.stderr is not None:
            print("screwkit: error: the standard output is closed", file=sys.stderr)
        return 2
    words = sys.argv[1:] if argv is None else list(argv)
    parser = build_parser(words[0] if words and words[0] in COMMANDS else None)
    words = _negative_values(parser, words)
    try:
        args, extra = parser.parse_known_args(words)
    except UsageError as exc:                  # one line, exit status 2
        print(exc.line, file=sys.stderr)
        _json_usage_error(words, exc.line)
        return 2
    if extra:                                  # said by the command whose help lists its own
        line = _unrecognized(parser, getattr(args, "command", None), extra, args)
        print(line, file=sys.stderr)
        _json_usage_error(words, line)
        return 2
    if not getattr(args, "func", None):       # no command (or action): what there is, exit 2
        parser.print_help()
        what = f"screwkit {args.command}" if getattr(args, "command", None) else "screwkit"
        print(f"{what}: error: a command is needed (listed above)", file=sys.stderr)
        return 2
    try:
        return int(args.func(args) or 0)
    except ScrewkitError as exc:
        what = " ".join(x for x in (args.command, getattr(args, "model_command", None)) if x)
        print(f"screwkit {what}: error: {_one_line(exc)}", file=sys.stderr)
        if getattr(args, "json", False):       # --json always prints a JSON object
            err: dict[str, str | int | float] = {"type": type(exc).__name__, "message": str(exc)}
            for k in ("kind", "condition_number", "residual"):
                v = getattr(exc, k, None)
                if isinstance(v, (int, float, str)) and v == v and v not in (float("inf"),):
                    err[k] = v
            _print_json({"error": err})
        return 2
    except BrokenPipeError:  # e.g. piped into head
        return 0
    except OSError as exc:    # the system's, not a bug: a full disk, a closed output...
        print(f"screwkit {args.command}: error: {exc.strerror or type(exc).__name__}"
              + (f": {exc.filename}" if exc.filename else "")
              + " (writing or reading a file or the output)", file=sys.stderr)
        return 2
    except Exception as exc:  # a bug: still one line, but say so (SCREWKIT_DEBUG=1 re-raises)
        import os
        if os.environ.get("SCREWKIT_DEBUG"):
            raise
        print(f"screwkit {args.command}: internal error ({type(exc).__name__}: "
              f"{_one_line(exc, 300)}); "
              "please report it (SCREWKIT_DEBUG=1 shows the traceback)", file=sys.stderr)
        return 3
    except KeyboardInterrupt:
        print("screwkit: interrupted", file=sys.stderr)
        return 130


def run(argv=None):
    """The console command (``screwkit``, ``python -m screwkit``): :func:`main`, then the
    process ends with its exit status.

    A command that computed leaves numba's loaded kernels, LLVM and many Python objects
    behind, whose orderly teardown takes longer than a one-pose analysis (0.1 to 0.2 s).
    With the output flushed and nothing left that an orderly exit would finish (no other
    live non-daemon thread, no child process, no coverage measurement, no Dask
    distributed client), the process ends at once."""
    code = main(argv)
    try:
        for stream in (sys.stdout, sys.stderr):
            if stream is not None:
                stream.flush()
    except OSError as exc:                   # (the output's last bytes could not be written)
        if code == 0 and sys.stderr is not None:
            try:
                print(f"screwkit: error: {exc.strerror or exc} (writing the output)",
                      file=sys.stderr)
            except (OSError, ValueError):
                pass
        sys.exit(code or 2)
    except ValueError:
        sys.exit(code)
    if _nothing_pending():
        os._exit(code)
    sys.exit(code)


def _nothing_pending() -> bool:
    """Whether an orderly exit has nothing to finish (see :func:`run`)."""
    import threading
    if any(m in sys.modules for m in ("coverage", "distributed")):
        return False
    main_thread = threading.main_thread()
    if any(t is not main_thread and t.is_alive() and not t.daemon
           for t in threading.enumerate()):
        return False
    mp = sys.modules.get("multiprocessing")
    return not (mp is not None and mp.active_children())
