"""Run the code blocks of a Markdown page and compare the outputs they show.

Used by ``tests/test_docs_run.py`` on README.md and every ``docs/*.md``. The conventions
(also described in docs/architecture.md, "Documentation, packaging and progress"):

* **```python blocks** of a page run in order in one namespace (one per page), in the
  test's temporary working directory. A statement may show what it prints in a trailing
  comment that starts with ``# ->``; the comment lines right below it, with their ``#`` in
  the same column, continue the output::

      print(res.summary())            # -> 1 force
      print(a.round(3))               # -> [[ 20.12   -6.894  49.489]
                                      #     [ 23.366 -16.754  52.089]]

  A bare expression with a ``# ->`` comment shows its ``repr`` (as in the REPL). The
  comparison is doctest's (``ELLIPSIS``: ``...`` matches anything; ``NORMALIZE_WHITESPACE``).
  A ``print(`` line with any other trailing comment is refused, so a shown output cannot
  silently go unchecked. A block written as a doctest (``>>>`` prompts) is run by doctest
  with the same options, in the page's namespace.
* **```console / ```bash / ```sh blocks**: each line that starts with ``$ `` is a command
  (a trailing ``\\`` continues it); the lines after it, up to the next ``$``, are its shown
  output (stdout and stderr), compared the same way. A last shown line ``[exit N]`` states
  the exit status; otherwise it must be 0. ``screwkit ...`` runs in-process through
  ``screwkit.cli.main``; any other command (or one with shell operators) runs in ``bash``
  with the venv's ``bin`` first on ``PATH``. Blocks without a ``$`` line (set-up
  instructions) are not run.
* An HTML comment ``<!-- docs-run: skip -->`` on the line before a fence leaves that block
  out (say why in the text); ``<!-- docs-run: slow -->`` runs it only when
  ``SCREWKIT_DOCS_SLOW=1``.
"""

from __future__ import annotations

import ast
import contextlib
import doctest
import io
import os
import re
import shlex
import subprocess
import sys
import tokenize
from dataclasses import dataclass
from pathlib import Path

FLAGS = doctest.ELLIPSIS | doctest.NORMALIZE_WHITESPACE
SHELL_LANGS = {"console", "bash", "sh", "shell", "shell-session"}
_FENCE = re.compile(r"^(?P<indent>[ ]*)```(?P<lang>[\w+-]*)[^\n]*\n(?P<body>.*?)^(?P=indent)```[ \t]*$",
                    re.M | re.S)
_MARK = re.compile(r"<!--\s*docs-run:\s*(\w+)\s*-->\s*$")
_SHELL_OPS = re.compile(r"[|<>;&`]|\$\(")
_EXIT = re.compile(r"^\[exit (\d+)\]$")


@dataclass(frozen=True)
class Block:
    """One fenced code block: its language, text (dedented), first line in the page, mark."""

    lang: str
    text: str
    line: int
    mark: str | None


class DocsRunError(AssertionError):
    """A block failed: the page, line and what differed."""


def blocks(text: str) -> list[Block]:
    """The fenced code blocks of a Markdown text, in order."""
    out = []
    for m in _FENCE.finditer(text):
        indent = len(m.group("indent"))
        body = "\n".join(ln[indent:] for ln in m.group("body").splitlines()) + "\n"
        line = text.count("\n", 0, m.start()) + 2          # 1-based line of the block's first line
        before = text[:m.start()].rstrip("\n").rsplit("\n", 1)[-1]
        mark = _MARK.search(before)
        out.append(Block(m.group("lang").lower(), body, line, mark.group(1) if mark else None))
    return out


# --------------------------------------------------------------------------- comparison

def _check(want: str, got: str, where: str) -> None:
    if not doctest.OutputChecker().check_output(want.rstrip() + "\n", got.rstrip() + "\n", FLAGS):
        raise DocsRunError(f"{where}: shown output differs from what it prints\n"
                           f"--- shown:\n{want.rstrip()}\n--- printed:\n{got.rstrip()}")


# --------------------------------------------------------------------------- python blocks

def _markers(code: str, where: str) -> dict[int, str]:
    """``{line: shown output}`` of the ``# ->`` comments of a block (1-based block lines)."""
    lines = code.splitlines()
    comments = {}                                   # line -> (col, text, code before it?)
    for tok in tokenize.generate_tokens(io.StringIO(code).readline):
        if tok.type == tokenize.COMMENT:
            row, col = tok.start
            comments[row] = (col, tok.string, bool(lines[row - 1][:col].strip()))
    out, row = {}, 1
    while row <= len(lines):
        c = comments.get(row)
        if c is None:
            row += 1
            continue
        col, text, has_code = c
        if not re.match(r"#\s*->", text):
            if has_code and "print(" in lines[row - 1][:col]:
                raise DocsRunError(f"{where}, line {row}: a print(...) with a trailing comment "
                                   f"that is not a '# ->' output: {text!r}")
            row += 1
            continue
        shown = [re.sub(r"^#\s*->\s?", "", text)]
        nxt = row + 1
        while nxt in comments and not comments[nxt][2] and comments[nxt][0] == col \
                and not re.match(r"#\s*->", comments[nxt][1]):
            shown.append(comments[nxt][1][1:])
            nxt += 1
        out[row] = "\n".join(shown)
        row = nxt
    return out


def run_python(code: str, ns: dict, filename: str, first_line: int) -> None:
    """Run one script block statement by statement, checking the ``# ->`` outputs."""
    where = f"{filename}:{first_line}"
    tree = ast.parse(code, filename)
    shown = _markers(code, where)
    for stmt in tree.body:
        rows = [r for r in shown if stmt.lineno <= r <= stmt.end_lineno]
        at = f"{filename}:{first_line + stmt.lineno - 1}"
        single = isinstance(stmt, ast.Expr) and bool(rows)
        mod = ast.Interactive([stmt]) if single else ast.Module([stmt], type_ignores=[])
        ast.increment_lineno(mod, first_line - 1)
        buf = io.StringIO()
        with contextlib.redirect_stdout(buf):
            saved_hook = sys.displayhook
            sys.displayhook = lambda v: None if v is None else print(repr(v))
            try:
                exec(compile(mod, filename, "single" if single else "exec"), ns)
            finally:
                sys.displayhook = saved_hook
        if rows:
            _check("\n".join(shown[r] for r in sorted(rows)), buf.getvalue(), at)


def run_doctest(code: str, ns: dict, filename: str, first_line: int) -> None:
    test = doctest.DocTestParser().get_doctest(code, ns, filename, filename, first_line - 1)
    out = io.StringIO()
    runner = doctest.DocTestRunner(optionflags=FLAGS)
    runner.run(test, out=out.write, clear_globs=False)
    if runner.failures:
        raise DocsRunError(f"{filename}:{first_line}: doctest failed\n{out.getvalue()}")


# --------------------------------------------------------------------------- shell blocks

def commands(text: str) -> list[tuple[str, list[str], int]]:
    """``(command, shown output lines, block line)`` of every ``$`` line of a shell block."""
    out, lines, i = [], text.splitlines(), 0
    while i < len(lines):
        if not lines[i].startswith("$ "):
            i += 1
            continue
        start, cmd = i, lines[i][2:]
        while cmd.rstrip().endswith("\\") and i + 1 < len(lines):
            i += 1
            cmd = cmd.rstrip()[:-1] + " " + lines[i].strip()
        i += 1
        shown = []
        while i < len(lines) and not lines[i].startswith("$ "):
            shown.append(lines[i])
            i += 1
        while shown and not shown[-1].strip():
            shown.pop()
        out.append((cmd, shown, start + 1))
    return out


def run_command(cmd: str, cwd: Path) -> tuple[int, str]:
    """Run one shown command in ``cwd``: ``(exit status, stdout + stderr)``."""
    argv = shlex.split(cmd, comments=True)
    if argv and argv[0] == "screwkit" and not _SHELL_OPS.search(cmd.split("#")[0]):
        from screwkit.cli import main

        buf = io.StringIO()
        with contextlib.redirect_stdout(buf), contextlib.redirect_stderr(buf):
            try:
                status = main(argv[1:])
            except SystemExit as exc:                   # argparse errors and --help
                status = exc.code if isinstance(exc.code, int) else 1
        return int(status or 0), buf.getvalue()
    env = dict(os.environ)
    env["PATH"] = str(Path(sys.executable).parent) + os.pathsep + env.get("PATH", "")
    proc = subprocess.run(["bash", "-c", cmd], cwd=cwd, env=env, capture_output=True, text=True,
                          timeout=300)
    return proc.returncode, proc.stdout + proc.stderr


#: The one-line note of a first compile depends on the kernel cache, not on the page: left
#: out of a command's output before the comparison.
_COMPILE_NOTE = re.compile(r"^screwkit: compiling .*\n?", re.M)


def run_shell(text: str, filename: str, first_line: int, cwd: Path) -> None:
    for cmd, shown, row in commands(text):
        where = f"{filename}:{first_line + row - 1}"
        expect = 0
        if shown and _EXIT.match(shown[-1].strip()):
            expect = int(_EXIT.match(shown[-1].strip()).group(1))
            shown = shown[:-1]
        status, got = run_command(cmd, cwd)
        got = _COMPILE_NOTE.sub("", got)
        if status != expect:
            raise DocsRunError(f"{where}: `{cmd}` exited with {status} (expected {expect})\n{got}")
        if shown:
            _check("\n".join(shown), got, f"{where} (`{cmd}`)")


# --------------------------------------------------------------------------- a page

def run_page(path: Path, cwd: Path, *, slow: bool = False) -> dict:
    """Run every block of one page in order; returns counts of what ran."""
    text = path.read_text(encoding="utf-8")
    name = path.name if path.parent.name != "docs" else f"docs/{path.name}"
    ns: dict = {"__name__": "__main__"}
    counts = {"python": 0, "doctest": 0, "commands": 0, "skipped": 0}
    for b in blocks(text):
        if b.lang not in SHELL_LANGS | {"python", "py", "pycon"}:
            continue
        if b.mark == "skip" or (b.mark == "slow" and not slow):
            counts["skipped"] += 1
            continue
        if b.lang in SHELL_LANGS:
            n = len(commands(b.text))
            if n:
                run_shell(b.text, name, b.line, cwd)
                counts["commands"] += n
        elif re.search(r"^>>> ", b.text, re.M):
            run_doctest(b.text, ns, name, b.line)
            counts["doctest"] += 1
        else:
            run_python(b.text, ns, name, b.line)
            counts["python"] += 1
    return counts
