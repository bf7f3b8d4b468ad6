"""Progress bars of the long commands (``trajectory``, ``validate``, ``check --all``; tqdm).

The bar is drawn by :mod:`tqdm.auto` (a widget in a Jupyter kernel, text on a terminal) on
standard error, only when standard error is a terminal or the command runs inside a
notebook, and never with ``--quiet``; it appears once the work has lasted half a second,
and shows the rate and the time left. tqdm is imported only when a bar is shown.
"""

from __future__ import annotations

import contextlib
import sys
from collections.abc import Callable, Iterator

__all__ = ["add_quiet_argument", "progress_bar", "bar_wanted"]

#: A progress callback: ``(done, total)``.
Progress = Callable[[int, int], None]
#: Seconds of work before a bar appears (a short run prints nothing).
DELAY = 0.5


def add_quiet_argument(p) -> None:
    """``--quiet``/``-q`` on a sub-command's parser."""
    p.add_argument("-q", "--quiet", action="store_true",
                   help="no progress bar (one is shown on a terminal for long runs)")


def _in_notebook() -> bool:
    shell = getattr(sys.modules.get("IPython"), "get_ipython", lambda: None)()
    return shell is not None and "IPKernelApp" in getattr(shell, "config", {})


def bar_wanted(args, stream=None) -> bool:
    """Whether to draw a bar: not ``--quiet``, and a terminal or a notebook."""
    if getattr(args, "quiet", False) or getattr(args, "no_progress", False):
        return False
    stream = sys.stderr if stream is None else stream
    try:
        tty = bool(stream.isatty())
    except (AttributeError, ValueError):
        tty = False
    return tty or _in_notebook()


@contextlib.contextmanager
def progress_bar(args, desc: str, unit: str, total: int | None = None) -> Iterator[Progress | None]:
    """A ``(done, total)`` callback that moves a tqdm bar, or None when no bar is wanted.

    The bar is closed when the block ends (also on an error).
    """
    if not bar_wanted(args):
        yield None
        return
    from tqdm.auto import tqdm

    bar = tqdm(total=total, desc=desc, unit=unit, delay=DELAY, file=sys.stderr, leave=False,
               dynamic_ncols=True)

    def update(done: int, total_: int) -> None:
        if bar.total != total_:
            bar.total = total_
        bar.update(max(0, int(done) - bar.n))
        if bar.n >= total_ and bar._time() - bar.start_t >= bar.delay:
            bar.refresh()      # tqdm redraws at most every 0.1 s: show the finished count

    try:
        yield update
    finally:
        bar.close()
