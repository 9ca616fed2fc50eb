"""The code ``dataclasses`` compiles for ncverify's classes, kept between processes.

For every dataclass, Python's ``dataclasses`` writes the source of its ``__init__``,
``__repr__``, ``__eq__`` (and more for a frozen class) and compiles each with ``exec``: for
ncverify's 130 classes that compiling took about a sixth of a small check's CPU time, in
every process. ``dataclasses`` finds ``exec`` as a name of its module, so :func:`install`
gives it one that compiles a source text once: the code object is kept in the user cache
folder under a hash of the text, in a file per Python bytecode version (as ``__pycache__``
keeps modules), and runs exactly as ``exec`` would run the text (same file name, no
inherited ``__future__`` flags). Only the methods of classes in ncverify's own modules are
kept; any other class is compiled as before. A missing, unreadable or broken file, or an
entry of any other type, is compiled anew; after a process compiled anything, the file is
written at exit, through a temporary file renamed into place (unless Python was asked not
to write bytecode, ``-B``).
"""
from __future__ import annotations

import builtins
import hashlib
import marshal
import sys
from pathlib import Path
from types import CodeType

_PACKAGE = __name__.split(".")[0]
_stored: dict[str, dict[str, CodeType]] | None = None  # module -> source hash -> code, as read (on first use)
_used: dict[str, dict[str, CodeType]] = {}  # the same, of the classes made in this process
_missed = False


def install() -> None:
    """Let ``dataclasses`` compile ncverify's methods through the cache."""
    import dataclasses

    dataclasses.exec = _exec


def _exec(source, globals=None, locals=None, /):
    module = globals.get("__name__") if isinstance(globals, dict) else None
    if type(source) is not str or not _is_ours(module):
        return builtins.exec(source, globals, locals)
    return builtins.exec(_code(module, source), globals, locals)


def _is_ours(module) -> bool:
    return isinstance(module, str) and (module == _PACKAGE or module.startswith(_PACKAGE + "."))


def _code(module: str, source: str) -> CodeType:
    global _stored, _missed
    if _stored is None:
        _stored = _read()
    key = hashlib.blake2b(source.encode(), digest_size=20).hexdigest()
    code = _stored.get(module, {}).get(key)
    if code is None:
        code = compile(source, "<string>", "exec", dont_inherit=True)
        if not _missed and not sys.dont_write_bytecode:  # -B / PYTHONDONTWRITEBYTECODE: read, as .pyc files are, never write
            import atexit

            _missed = True
            atexit.register(_write)
    _used.setdefault(module, {})[key] = code
    return code


def _file() -> Path:
    from importlib.util import MAGIC_NUMBER

    from .resources import user_cache_folder

    return user_cache_folder() / "classes" / f"{sys.implementation.cache_tag}-{MAGIC_NUMBER.hex()}.marshal"


def _read() -> dict[str, dict[str, CodeType]]:
    try:
        stored = marshal.loads(_file().read_bytes())
    except (OSError, EOFError, ValueError, TypeError):
        return {}
    if type(stored) is not dict:
        return {}
    return {module: {key: code for key, code in codes.items() if type(key) is str and type(code) is CodeType}
            for module, codes in stored.items() if type(module) is str and type(codes) is dict}


def _write() -> None:
    """The modules whose classes this process made are stored with just those classes'
    code (every class of a module is made when it is imported), so the entries of a
    class since edited do not pile up; other modules' entries are kept as read."""
    from .resources import write_whole

    try:
        data = marshal.dumps((_stored or {}) | _used)
    except ValueError:
        return
    write_whole(_file(), data)
