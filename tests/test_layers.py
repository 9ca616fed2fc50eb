"""The import directions between the stages: read -> lower -> interpret -> check -> report,
with the shared vocabulary (values, verdicts, IR, source, context, tables ...) below them all.

A module may import its own stage, the stages before it and the base; the rules (check)
read the trace, never the text or its lowering, so they import neither ``read`` nor
``lower``. Imports inside functions count: they are dependencies too.
"""
from __future__ import annotations

import ast
from pathlib import Path

import ncverify

PACKAGE = Path(ncverify.__file__).parent
STAGES = ("base", "read", "lower", "interpret", "check", "report")
_INTERPRET = {"ncverify.interpret", "ncverify.control_flow", "ncverify.cycles"}  # with the ncverify.interpret package
_CHECK = {"ncverify.check", "ncverify.rule_registry"}
_REPORT = {"ncverify", "ncverify.api", "ncverify.cli", "ncverify.report", "ncverify.lsp"}

# Arrows that point the wrong way today, each to be removed by the change named beside it;
# this list may only shrink.
KNOWN_WRONG = {
    # the interpreter judges hazards with the checker's verdict functions (they move below it)
    ("ncverify.interpret", "ncverify.check"),
    # the run-time halves of the dialects still live in lower/ (they move to interpret/)
    ("ncverify.lower.heidenhain_run", "ncverify.interpret"),
    ("ncverify.lower.heidenhain_run", "ncverify.control_flow"),
    ("ncverify.lower.heidenhain_run", "ncverify.cycles"),
    ("ncverify.lower.heidenhain_contour", "ncverify.control_flow"),
    ("ncverify.lower.fagor_cycles", "ncverify.cycles"),
    ("ncverify.lower.sinumerik_cycles", "ncverify.cycles"),
    # rules reading facts of the lowering (they become dialect table data)
    ("ncverify.checks.cycle_hazards", "ncverify.lower.modal_call"),
    ("ncverify.checks.tools", "ncverify.lower.modal_call"),
    ("ncverify.checks.heidenhain_special", "ncverify.lower.heidenhain_run"),
    ("ncverify.checks.sinumerik", "ncverify.lower.sinumerik_cycles"),
    ("ncverify.checks.sinumerik_milling", "ncverify.lower.sinumerik_cycles"),
    ("ncverify.checks.sinumerik_tools", "ncverify.lower.sinumerik"),
    # the project file checks rule ids against the rule definitions
    ("ncverify.project", "ncverify.check"),
    # once the run-time code is in the interpret package: the lowering still installs its
    # dialect's runtime and uses the modal-call helper of the interpreter
    ("ncverify.lower.heidenhain", "ncverify.interpret.heidenhain.runtime"),
    ("ncverify.lower.fagor", "ncverify.interpret.modal_call"),
    ("ncverify.lower.sinumerik", "ncverify.interpret.modal_call"),
    ("ncverify.lower.modal_call", "ncverify.interpret.modal_call"),
}


def stage(module: str) -> str:
    if module.startswith("ncverify.read."):
        return "read"
    if module.startswith("ncverify.lower."):
        return "lower"
    if module in _INTERPRET or module.startswith("ncverify.interpret."):
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


def imports(path: Path) -> set[str]:
    return imports_in(path.read_text(encoding="utf-8"), _module_name(path), path.name == "__init__.py")


def imports_in(source: str, module: str, is_package: bool = False) -> set[str]:
    """The ncverify modules ``source`` (the text of ``module``) imports, anywhere in it."""
    package = module if is_package else module.rsplit(".", 1)[0]
    found = set()
    for node in ast.walk(ast.parse(source)):
        if isinstance(node, ast.ImportFrom):
            base = package.split(".")[: len(package.split(".")) - node.level + 1] if node.level else []
            target = ".".join(base + ([node.module] if node.module else []))
            found |= {_resolve(f"{target}.{alias.name}") for alias in node.names if target.startswith("ncverify")}
        elif isinstance(node, ast.Import):
            found |= {_resolve(alias.name) for alias in node.names if alias.name.startswith("ncverify")}
    return found - {module}


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


def test_no_new_import_points_against_the_pipeline():
    assert wrong_arrows() - KNOWN_WRONG == set()


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
    assert stage("ncverify.interpret") == stage("ncverify.interpret.runtime") == stage("ncverify.control_flow") == "interpret"
    assert stage("ncverify.checks.stock") == stage("ncverify.check") == "check"
    assert stage("ncverify.values") == stage("ncverify.verdict") == stage("ncverify.context") == "base"


def test_imports_are_read_from_every_form():
    source = "from ..lower import modal_call\nfrom ..check import show\nimport ncverify.values\n\ndef f():\n    from ..read.iso import read_line\n"
    assert imports_in(source, "ncverify.checks.x") == {"ncverify.lower.modal_call", "ncverify.check", "ncverify.values", "ncverify.read.iso"}
    assert imports_in("from . import holes\n", "ncverify.checks", is_package=True) == {"ncverify.checks.holes"}


def test_which_arrows_are_wrong():
    assert not _allowed("base", "interpret") and not _allowed("lower", "interpret")
    assert not _allowed("check", "lower") and not _allowed("check", "read")
    assert _allowed("report", "check") and _allowed("check", "interpret") and _allowed("lower", "read") and _allowed("read", "base")
