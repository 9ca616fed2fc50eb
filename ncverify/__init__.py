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

from . import classcode as _classcode  # noqa: E402

_classcode.install()  # before any module of the package defines its dataclasses

__all__ = ["FileResult", "InputError", "Settings", "check_file", "check_text", "__version__"]

_API = {"FileResult": "api", "InputError": "api", "check_file": "api", "check_text": "api", "Settings": "settings"}


def __getattr__(name: str):
    """The API names are loaded on first use, so that importing the package (as the command
    line does before anything else) loads no numerical library: the command line settles
    their thread pools first (:mod:`ncverify.cli`)."""
    if name not in _API:
        raise AttributeError(f"module 'ncverify' has no attribute {name!r}")
    from importlib import import_module

    value = getattr(import_module(f".{_API[name]}", __name__), name)
    globals()[name] = value
    return value
