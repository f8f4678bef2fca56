"""``python -m fretwear.cli``: the command line, as ``fretwear`` and ``python -m fretwear``."""

import sys

from . import main

sys.exit(main())
