"""``python -m morphogen_stream FILE``."""

import sys

from .cli import main

sys.exit(main())
