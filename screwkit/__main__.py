"""``python -m screwkit``: the command-line interface."""

from .cli import run

run()
