"""``python -m sf_tch.conformance``: the command line (see :mod:`sf_tch.conformance`)."""
import sys

from .cli import main

sys.exit(main())
