"""The old name of :mod:`docking.designs.study`: importing it gives that module itself."""

import sys

from docking.designs import study as _module

sys.modules[__name__] = _module
