"""The import directions of the interpretation stage: the verdicts and values sit below the
interpreter, the interpreter below the checker, and nothing in ``ncverify/interpret/``
reaches up into the stages after it or back into the ones that make its input."""
from __future__ import annotations

import ast
from pathlib import Path

import pytest

PACKAGE = Path(__file__).resolve().parent.parent / "ncverify"


def imported_modules(path: Path) -> set[str]:
    """Every ``ncverify`` module a file imports, anywhere in it (also inside functions)."""
    module = ".".join(path.relative_to(PACKAGE.parent).with_suffix("").parts)
    package = module if path.name == "__init__.py" else module.rsplit(".", 1)[0]
    found = set()
    for node in ast.walk(ast.parse(path.read_text(encoding="utf-8"))):
        if isinstance(node, ast.Import):
            found.update(alias.name for alias in node.names if alias.name.startswith("ncverify"))
        elif isinstance(node, ast.ImportFrom):
            base = package.split(".")
            if node.level:
                base = base[: len(base) - node.level + 1]
                target = ".".join(base + ([node.module] if node.module else []))
            else:
                target = node.module or ""
            if not target.startswith("ncverify"):
                continue
            found.add(target)
            found.update(f"{target}.{alias.name}" for alias in node.names)
    return found


def _forbidden(path: Path, prefixes: tuple[str, ...]) -> list[str]:
    return sorted(name for name in imported_modules(path) if name.startswith(prefixes))


@pytest.mark.parametrize("path", sorted((PACKAGE / "interpret").rglob("*.py")), ids=lambda p: str(p.relative_to(PACKAGE)))
def test_the_interpreter_imports_no_later_or_earlier_stage(path):
    assert _forbidden(path, ("ncverify.check", "ncverify.checks", "ncverify.report", "ncverify.cli", "ncverify.api",
                             "ncverify.lower", "ncverify.read")) == []


@pytest.mark.parametrize("name", ["verdict.py", "values.py"])
def test_verdicts_and_values_sit_below_the_interpreter(name):
    assert _forbidden(PACKAGE / name, ("ncverify.check", "ncverify.checks", "ncverify.interpret", "ncverify.lower", "ncverify.read")) == []


def test_the_import_resolver_sees_relative_imports():
    """The check above would pass on anything if relative imports were missed."""
    found = imported_modules(PACKAGE / "interpret" / "heidenhain" / "runtime.py")
    assert "ncverify.interpret.cycles" in found and "ncverify.ir" in found
    assert "ncverify.verdict.judge" in imported_modules(PACKAGE / "interpret" / "interpreter.py")
