"""``python -m sf_tch``: the command line (see :mod:`sf_tch.cli`)."""
import sys

from .cli import main

sys.exit(main())
