"""Command-line interface (``screwkit``, ``python -m screwkit``): the top layer.

:func:`main` runs a command line and returns its exit status; :func:`run` is the console
entry point (main, then the process ends); :func:`build_parser` the argparse
parser (``docs/gen_cli_md.py`` renders it); :data:`COMMANDS` the sub-commands,
one module each in ``screwkit.cli._commands``.
"""

from ._main import COMMANDS, build_parser, main, run

__all__ = ["main", "run", "build_parser", "COMMANDS"]
