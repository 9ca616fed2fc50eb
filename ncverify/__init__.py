"""ncverify: a verifier and static analyser for CNC part programs.

The pipeline is one module per stage: :mod:`ncverify.read` (text to blocks, per dialect),
:mod:`ncverify.lower` (blocks to the dialect-neutral :mod:`ncverify.ir`),
:mod:`ncverify.interpret` (the abstract machine), :mod:`ncverify.check` (rules) and
:mod:`ncverify.report` (text, JSON, SARIF).

    >>> from ncverify import check_text
    >>> result = check_text("G21 G90\\nG01 X10. Y5.\\nM30\\n")
    >>> [d.rule for d in result.diagnostics]
    ['core.feed-missing', ...]
"""
__version__ = "0.1.0"

from .api import FileResult, InputError, check_file, check_text  # noqa: E402
from .settings import Settings  # noqa: E402

__all__ = ["FileResult", "InputError", "Settings", "check_file", "check_text", "__version__"]
