"""Rule logic that needs more than a parameter constraint, one module per theme.
Importing this package registers every rule class with :func:`ncverify.check.rule`."""
from . import holder, holes, machine, motion, stock, tooling, tools  # noqa: F401
from . import cycle_hazards  # noqa: F401
from . import modal_hazards  # noqa: F401
from . import fagor  # noqa: F401
from . import heidenhain  # noqa: F401
from . import heidenhain_contour  # noqa: F401
from . import heidenhain_transforms  # noqa: F401
from . import heidenhain_special  # noqa: F401
from . import sinumerik, sinumerik_milling, sinumerik_turning  # noqa: F401
from . import sinumerik_tools  # noqa: F401
