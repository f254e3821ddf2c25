"""The old name of :mod:`docking.designs.calibration`: importing it gives that module itself."""

import sys

from docking.designs import calibration as _module

sys.modules[__name__] = _module
