"""The kept code of ncverify's dataclass methods (``ncverify.classcode``): every class made
from it has exactly the methods ``dataclasses`` itself makes, a warm cache compiles nothing,
and a broken file or a stale entry costs only compiling. Each run is a fresh interpreter
with its own user cache folder (the test process made its classes long ago)."""
from __future__ import annotations

import json
import marshal
import os
import subprocess
import sys
import textwrap

_RUN = textwrap.dedent("""
    import dataclasses, importlib, json, pkgutil, re, sys
    from types import CodeType, FunctionType
    import ncverify
    if sys.argv[1] == "plain":
        del dataclasses.exec  # dataclasses' own compiling: the reference
    import ncverify.classcode as classcode

    @dataclasses.dataclass
    class Foreign:  # not ncverify's: compiled as before, never kept
        x: int = 0

    for info in pkgutil.walk_packages(ncverify.__path__, "ncverify."):
        try:
            importlib.import_module(info.name)
        except ImportError:  # an optional extra (the language server, plotting)
            pass

    def code_print(code):
        return [code.co_name, code.co_qualname, code.co_filename, code.co_firstlineno, code.co_flags, code.co_argcount,
                code.co_posonlyargcount, code.co_kwonlyargcount, code.co_code.hex(), code.co_names, code.co_varnames,
                code.co_freevars, code.co_cellvars, code.co_linetable.hex(), code.co_exceptiontable.hex(),
                [code_print(c) if isinstance(c, CodeType) else re.sub(" at 0x[0-9a-f]+", "", repr(c)) for c in code.co_consts]]

    def shown(value):
        return re.sub(" at 0x[0-9a-f]+", "", repr(value))

    methods = {}
    for name, module in sorted(sys.modules.items()):
        if not name.startswith("ncverify"):
            continue
        for cls in vars(module).values():
            if isinstance(cls, type) and dataclasses.is_dataclass(cls) and cls.__module__ == name:
                for attribute, value in cls.__dict__.items():
                    if isinstance(value, FunctionType) and value.__code__.co_filename == "<string>":
                        methods[f"{cls.__module__}.{cls.__qualname__}.{attribute}"] = [
                            code_print(value.__code__), shown(value.__annotations__), shown(value.__defaults__), shown(value.__kwdefaults__)]
    compiled = sum(key not in (classcode._stored or {}).get(module, {}) for module, codes in classcode._used.items() for key in codes)
    print(json.dumps({"methods": methods, "compiled": compiled, "foreign": repr(Foreign(3))}))
""")


def _run(tmp_path, mode: str = "cached", **environment: str) -> dict:
    env = {name: value for name, value in os.environ.items() if name != "PYTHONDONTWRITEBYTECODE"}
    env |= {"XDG_CACHE_HOME": str(tmp_path / "cache"), "PYTHONHASHSEED": "0"} | environment  # the same set orders in every run
    done = subprocess.run([sys.executable, "-c", _RUN, mode], capture_output=True, text=True, timeout=300, cwd=tmp_path, env=env)
    assert done.returncode == 0, done.stderr
    return json.loads(done.stdout)


def _cache_file(tmp_path):
    [path] = (tmp_path / "cache" / "ncverify" / "classes").glob("*.marshal")
    return path


def test_classes_made_from_kept_code_have_the_methods_dataclasses_makes(tmp_path):
    plain = _run(tmp_path, "plain")
    cold = _run(tmp_path)
    warm = _run(tmp_path)
    assert len(plain["methods"]) > 300
    assert cold["methods"] == plain["methods"] and warm["methods"] == plain["methods"]
    assert cold["compiled"] > 300 and warm["compiled"] == 0
    assert warm["foreign"] == "Foreign(x=3)"
    assert all(module.startswith("ncverify") for module in marshal.loads(_cache_file(tmp_path).read_bytes()))


def test_a_broken_cache_file_is_compiled_anew_and_rewritten(tmp_path):
    reference = _run(tmp_path)["methods"]
    for damage in (b"\x00garbage", marshal.dumps([1, 2]), marshal.dumps({"ncverify.ir": {"key": "not code"}})):
        _cache_file(tmp_path).write_bytes(damage)
        again = _run(tmp_path)
        assert again["methods"] == reference and again["compiled"] > 300
    assert _run(tmp_path)["compiled"] == 0  # the file was written whole again


def test_entries_of_code_no_class_uses_any_more_are_dropped(tmp_path):
    """A class since edited leaves an entry no source hashes to: the next process that
    compiles anything stores each module it imported with just its classes' code."""
    _run(tmp_path)
    path = _cache_file(tmp_path)
    stored = marshal.loads(path.read_bytes())
    used = dict(stored["ncverify.ir"])
    dropped_key = next(iter(used))
    stored["ncverify.ir"] = {key: code for key, code in used.items() if key != dropped_key} | {"0" * 40: compile("x = 1", "<string>", "exec")}
    path.write_bytes(marshal.dumps(stored))
    assert _run(tmp_path)["compiled"] == 1
    assert set(marshal.loads(path.read_bytes())["ncverify.ir"]) == set(used)


def test_asked_not_to_write_bytecode_it_reads_the_cache_and_never_writes_it(tmp_path):
    cold = _run(tmp_path, PYTHONDONTWRITEBYTECODE="1")
    assert cold["compiled"] > 300 and not (tmp_path / "cache" / "ncverify" / "classes").exists()
    _run(tmp_path)
    assert _run(tmp_path, PYTHONDONTWRITEBYTECODE="1")["compiled"] == 0
