"""Command-line interface (``screwkit``, ``python -m screwkit``): the top layer.

:func:`main` is the console entry point; :func:`build_parser` the argparse
parser (``docs/gen_cli_md.py`` renders it); :data:`COMMANDS` the sub-commands,
one module each in ``screwkit.cli._commands``.
"""

from ._main import COMMANDS, build_parser, main

__all__ = ["main", "build_parser", "COMMANDS"]
