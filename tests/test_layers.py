"""The import directions between the stages: read -> lower -> interpret -> check -> report,
with the shared vocabulary (values, verdicts, IR, source, context, tables ...) below them all.

A module may import its own stage, the stages before it and the base; the rules (check)
read the trace, never the text or its lowering, so they import neither ``read`` nor
``lower``. Imports inside functions count: they are dependencies too. No module imports
itself through others (no import cycle), and the checker imports no rule module: the rule
modules build on it, and the registry above both joins them.
"""
from __future__ import annotations

import ast
from pathlib import Path

import ncverify

PACKAGE = Path(ncverify.__file__).parent
STAGES = ("base", "read", "lower", "interpret", "check", "report")
_CHECK = {"ncverify.check", "ncverify.rule_registry", "ncverify.material", "ncverify.turning_stock", "ncverify.modelled"}
_REPORT = {"ncverify", "ncverify.api", "ncverify.watchdog", "ncverify.cli", "ncverify.report", "ncverify.lsp",  # watchdog: api under a budget
           # batches over libraries and what they write: the API's callers
           "ncverify.batch", "ncverify.cache", "ncverify.cluster", "ncverify.plot", "ncverify.pool", "ncverify.progress", "ncverify.sarif"}

def stage(module: str) -> str:
    if module.startswith("ncverify.read."):
        return "read"
    if module.startswith("ncverify.lower."):
        return "lower"
    if module == "ncverify.interpret" or module.startswith("ncverify.interpret."):
        return "interpret"
    if module in _CHECK or module.startswith("ncverify.checks"):
        return "check"
    if module in _REPORT or module.startswith("ncverify.lsp."):
        return "report"
    return "base"


def _module_name(path: Path) -> str:
    parts = ("ncverify",) + path.relative_to(PACKAGE).with_suffix("").parts
    return ".".join(parts[:-1] if parts[-1] == "__init__" else parts)


def _resolve(name: str) -> str:
    """The module an imported name lives in: ``ncverify.lower.modal_call`` for ``from
    ..lower import modal_call``, ``ncverify.check`` for ``from ..check import show``."""
    relative = PACKAGE.parent / name.replace(".", "/")
    while not (relative.with_suffix(".py").exists() or (relative / "__init__.py").exists()):
        name, relative = name.rsplit(".", 1)[0], relative.parent
    return name


def imports(path: Path, on_load_only: bool = False) -> set[str]:
    return imports_in(path.read_text(encoding="utf-8"), _module_name(path), path.name == "__init__.py", on_load_only)


def imports_in(source: str, module: str, is_package: bool = False, on_load_only: bool = False) -> set[str]:
    """The ncverify modules ``source`` (the text of ``module``) imports, anywhere in it, or
    only where it runs when the module is loaded (outside functions)."""
    package = module if is_package else module.rsplit(".", 1)[0]
    found = set()
    for node in _loaded_nodes(ast.parse(source)) if on_load_only else ast.walk(ast.parse(source)):
        if isinstance(node, ast.ImportFrom):
            base = package.split(".")[: len(package.split(".")) - node.level + 1] if node.level else []
            target = ".".join(base + ([node.module] if node.module else []))
            found |= {_resolve(f"{target}.{alias.name}") for alias in node.names if target.startswith("ncverify")}
        elif isinstance(node, ast.Import):
            found |= {_resolve(alias.name) for alias in node.names if alias.name.startswith("ncverify")}
    return found - {module}


def _loaded_nodes(tree):
    """The nodes that run when the module is loaded: everything but function bodies."""
    pending = [tree]
    while pending:
        node = pending.pop()
        yield node
        pending.extend(child for child in ast.iter_child_nodes(node) if not isinstance(child, (ast.FunctionDef, ast.AsyncFunctionDef)))


def wrong_arrows() -> set[tuple[str, str]]:
    wrong = set()
    for path in PACKAGE.rglob("*.py"):
        importer = _module_name(path)
        for imported in imports(path):
            if _allowed(stage(importer), stage(imported)):
                continue
            wrong.add((importer, imported))
    return wrong


def _allowed(importer: str, imported: str) -> bool:
    if importer == "check" and imported in ("read", "lower"):
        return False
    return STAGES.index(imported) <= STAGES.index(importer)


def import_graph() -> dict[str, set[str]]:
    """Which module imports which, when it is loaded or inside a function."""
    return {_module_name(path): imports(path) for path in PACKAGE.rglob("*.py")}


def import_cycles(graph: dict[str, set[str]]) -> list[list[str]]:
    """The strongly connected groups of more than one module (Tarjan's algorithm)."""
    index, low, stack, on_stack, groups = {}, {}, [], set(), []

    def visit(module):
        index[module] = low[module] = len(index)
        stack.append(module)
        on_stack.add(module)
        for imported in graph.get(module, ()):
            if imported not in index:
                visit(imported)
                low[module] = min(low[module], low[imported])
            elif imported in on_stack:
                low[module] = min(low[module], index[imported])
        if low[module] == index[module]:
            group = []
            while True:
                member = stack.pop()
                on_stack.discard(member)
                group.append(member)
                if member == module:
                    break
            if len(group) > 1:
                groups.append(sorted(group))

    for module in sorted(graph):
        if module not in index:
            visit(module)
    return groups


def test_no_import_points_against_the_pipeline():
    assert wrong_arrows() == set()


def test_no_import_cycle():
    assert import_cycles(import_graph()) == []


def test_the_checker_imports_no_rule_module():
    """The checker and what it owns (the cut stock, the declared state) sit below the rules."""
    below_the_rules = ("ncverify.check", "ncverify.material", "ncverify.turning_stock", "ncverify.modelled")
    assert {(module, imported) for module in below_the_rules for imported in import_graph()[module] if imported.startswith("ncverify.checks")} == set()


def test_a_cycle_is_found():
    """The check above would pass on anything if the search missed cycles."""
    graph = {"a": {"b"}, "b": {"c"}, "c": {"a"}, "d": {"a"}}
    assert import_cycles(graph) == [["a", "b", "c"]]


def test_no_rule_module_imports_private_names():
    """Helpers rule modules share are public (checks/common.py, or the dialect's module)."""
    private = []
    for path in (PACKAGE / "checks").glob("*.py"):
        for node in ast.walk(ast.parse(path.read_text(encoding="utf-8"))):
            if isinstance(node, ast.ImportFrom):
                private += [f"{path.name}: {alias.name}" for alias in node.names if alias.name.startswith("_")]
    assert private == []


def test_the_stages_are_told_apart():
    assert stage("ncverify.read.iso") == "read" and stage("ncverify.lower.iso") == "lower"
    assert stage("ncverify.interpret") == stage("ncverify.interpret.runtime") == stage("ncverify.interpret.control_flow") == "interpret"
    assert stage("ncverify.checks.stock") == stage("ncverify.check") == "check"
    assert stage("ncverify.values") == stage("ncverify.verdict") == stage("ncverify.context") == "base"


def test_imports_are_read_from_every_form():
    source = "from ..lower import modal_call\nfrom ..check import show\nimport ncverify.values\n\ndef f():\n    from ..read.iso import read_line\n"
    assert imports_in(source, "ncverify.checks.x") == {"ncverify.lower.modal_call", "ncverify.check", "ncverify.values", "ncverify.read.iso"}
    assert imports_in("from . import holes\n", "ncverify.checks", is_package=True) == {"ncverify.checks.holes"}
    assert imports_in(source, "ncverify.checks.x", on_load_only=True) == {"ncverify.lower.modal_call", "ncverify.check", "ncverify.values"}


def test_which_arrows_are_wrong():
    assert not _allowed("base", "interpret") and not _allowed("lower", "interpret")
    assert not _allowed("check", "lower") and not _allowed("check", "read")
    assert _allowed("report", "check") and _allowed("check", "interpret") and _allowed("lower", "read") and _allowed("read", "base")


def test_the_interpreter_sits_between_the_lowering_and_the_checker():
    """The verdicts and values sit below the interpreter; nothing in ``interpret/`` reaches
    up into the checker or back into the stages that make its input."""
    assert stage("ncverify.verdict") == stage("ncverify.values") == stage("ncverify.ir") == "base"
    interpreter = imports(PACKAGE / "interpret" / "interpreter.py")
    assert "ncverify.verdict" in interpreter and not any(stage(name) in ("read", "lower", "check", "report") for name in interpreter)
