"""``python -m fretwear``: the command line interface of :mod:`fretwear.cli`."""

import sys

from .cli import main

sys.exit(main())
