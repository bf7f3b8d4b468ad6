"""``python -m screwkit.cli``: the command-line interface."""

import sys

from ._main import main

sys.exit(main())
