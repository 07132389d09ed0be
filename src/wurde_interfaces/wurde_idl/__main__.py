"""``python -m wurde_idl``: see :mod:`wurde_idl.generate`."""

import sys

from .generate import main

sys.exit(main())
