"""The old name of :mod:`docking.designs.experiment3`: importing it gives that module itself."""

import sys

from docking.designs import experiment3 as _module

sys.modules[__name__] = _module
