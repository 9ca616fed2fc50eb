"""Rule logic that needs more than a parameter constraint, one module per theme.
Importing this package registers every rule class with :func:`ncverify.check.rule`."""
from . import holes, machine, motion, stock, tools  # noqa: F401
