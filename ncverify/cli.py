"""Command line: ``ncverify check``, ``ncverify explain``, ``ncverify rules``, ``ncverify lsp``.

Exit codes: 0 nothing at or above ``--fail-on``; 1 findings at or above it (or unknown
verdicts with ``--fail-on-unknown``); 2 usage or input errors (a file that cannot be read,
is too large or is not a program).
"""
from __future__ import annotations

import argparse
import os
import sys
from pathlib import Path

from . import __version__, rule_registry
from .api import FileResult, InputError, check_file, check_source, iter_program_files, project_for
from .check import RuleFileError, rule_definitions
from .project import ConfigError
from .diagnostics import Severity, Status
from .dialect import DIALECTS, MACHINES
from .report import render_json, render_sarif, render_text
from .settings import Settings
from .source import ProgramSource

EXIT_OK, EXIT_FINDINGS, EXIT_USAGE = 0, 1, 2


class _Parser(argparse.ArgumentParser):
    def error(self, message):
        self.print_usage(sys.stderr)
        print(f"ncverify: error: {message}", file=sys.stderr)
        raise SystemExit(EXIT_USAGE)


def build_parser() -> argparse.ArgumentParser:
    parser = _Parser(prog="ncverify", description="Verify and lint CNC part programs.")
    parser.add_argument("--version", action="version", version=f"ncverify {__version__}")
    commands = parser.add_subparsers(dest="command", required=True, parser_class=_Parser)

    check = commands.add_parser("check", help="check programs (files, folders, or - for stdin)")
    check.add_argument("paths", nargs="+", metavar="PATH")
    check.add_argument("--format", choices=("text", "json", "sarif"), default="text")
    check.add_argument("--output", "-o", metavar="FILE", help="write the report to FILE instead of stdout")
    check.add_argument("--dialect", choices=tuple(DIALECTS), help="skip detection")
    check.add_argument("--profile", choices=DIALECTS["iso"].profiles(), help="ISO profile (default: detected, else mitsubishi-e60)")
    check.add_argument("--machine", choices=MACHINES, help="machine type where the program cannot tell")
    check.add_argument("--fail-on", choices=("error", "warning", "info", "never"), default="error")
    check.add_argument("--fail-on-unknown", action="store_true", help="unknown verdicts fail the run too")
    check.add_argument("--show-proved", action="store_true", help="list proved verdicts in the text report (they are always in JSON)")
    check.add_argument("--verbose", "-v", action="store_true", help="say on stderr why each file was read as its dialect, profile and machine type")
    check.add_argument("--loop-bound", type=_positive_int, default=Settings.loop_bound, metavar="N",
                       help="iterations of one loop or repeats of one jump before the analysis gives up (default %(default)s)")
    check.add_argument("--max-paths", type=_positive_int, default=Settings.max_paths, metavar="N")
    check.add_argument("--least-input-increment", type=float, metavar="MM",
                       help="what 1 means in a length word without a decimal point (0: a whole unit)")
    check.add_argument("--subprogram-path", action="append", default=[], metavar="DIR", help="folder searched for called programs")
    check.add_argument("--extensions", metavar="LIST", help="comma-separated extensions read in folders (default: %(default)s)",
                       default=",".join(e for e in Settings.extensions if e))
    check.add_argument("--disable", action="append", default=[], metavar="RULE", help="rule id or category to turn off")
    check.add_argument("--max-file-size", type=_positive_int, default=Settings.max_file_bytes, metavar="BYTES")
    check.add_argument("--config", metavar="FILE", help="project file (default: ncverify.toml found upward from each program)")
    check.add_argument("--rapid-path", choices=("straight", "dogleg"), default=Settings.rapid_path,
                       help="how G00 moves: interpolated straight, or each axis on its own (default %(default)s)")
    check.add_argument("--solver-timeout", type=float, default=Settings.solver_timeout_s, metavar="S", help="seconds per solver query (default %(default)s)")
    check.add_argument("--stock-resolution", type=_stock_resolution, default=Settings.stock_resolution, metavar="MM|auto",
                       help="judge rapids against the stock as cut so far, with cells of MM (auto: from the smallest tool); "
                            "default 0: against the blank")
    check.add_argument("--stock-out", metavar="FILE", help="write the workpiece the program leaves (.stl or .npz; {stem}: the program's name)")

    explain = commands.add_parser("explain", help="show a rule's page")
    explain.add_argument("rule")

    rules = commands.add_parser("rules", help="list the rules")
    rules.add_argument("--where", action="store_true", help="add where each rule is implemented (module:Class, the page's constraints, or the modules that report it)")
    commands.add_parser("lsp", help="run the language server on stdin/stdout (needs the lsp extra)")
    return parser


def _positive_int(text: str) -> int:
    try:
        value = int(text)
    except ValueError:
        raise argparse.ArgumentTypeError(f"{text!r} is not a whole number") from None
    if value < 1:
        raise argparse.ArgumentTypeError("must be at least 1")
    return value


def _stock_resolution(text: str) -> float | None:
    if text.strip().lower() == "auto":
        return None
    try:
        value = float(text)
    except ValueError:
        raise argparse.ArgumentTypeError(f"{text!r} is neither a number nor 'auto'") from None
    if not 0.0 <= value < float("inf"):
        raise argparse.ArgumentTypeError("must be 0 (off), a cell size in mm, or 'auto'")
    return value


def main(argv: list[str] | None = None) -> int:
    argv = sys.argv[1:] if argv is None else argv
    arguments = build_parser().parse_args(argv)
    arguments.given = _given(argv)
    try:
        if arguments.command == "explain":
            return _explain(arguments.rule)
        if arguments.command == "rules":
            return _list_rules(arguments.where)
        if arguments.command == "lsp":
            return _serve_lsp()
        return _check(arguments)
    except RuleFileError as error:
        print(f"ncverify: broken rule definition: {error}", file=sys.stderr)
        return EXIT_USAGE
    except ConfigError as error:
        print(f"ncverify: error in the project file: {error}", file=sys.stderr)
        return EXIT_USAGE
    except KeyboardInterrupt:
        return 130
    except BrokenPipeError:
        # The reader went away (`ncverify rules | head`): stop quietly.
        devnull = os.open(os.devnull, os.O_WRONLY)
        os.dup2(devnull, sys.stdout.fileno())
        return EXIT_OK


def _given(argv: list[str]) -> frozenset[str]:
    """Which project-file settings the command line states (a value equal to the default
    still wins over the project file)."""
    flags = {"--loop-bound": "loop_bound", "--max-paths": "max_paths", "--rapid-path": "rapid_path",
             "--solver-timeout": "solver_timeout_s", "--least-input-increment": "least_input_increment",
             "--machine": "machine", "--profile": "profile", "--dialect": "dialect", "--subprogram-path": "subprogram_path",
             "--stock-resolution": "stock_resolution"}
    return frozenset(setting for flag, setting in flags.items() if any(arg == flag or arg.startswith(flag + "=") for arg in argv))


def _settings(arguments) -> Settings:
    extensions = tuple(sorted({("." + e.strip().lstrip(".")).lower() for e in arguments.extensions.split(",") if e.strip()}))
    return Settings(
        dialect=arguments.dialect, profile=arguments.profile, machine=arguments.machine, loop_bound=arguments.loop_bound,
        max_paths=arguments.max_paths, least_input_increment=arguments.least_input_increment,
        subprogram_path=tuple(Path(p) for p in arguments.subprogram_path), extensions=extensions + ("",),
        fail_on=arguments.fail_on, fail_on_unknown=arguments.fail_on_unknown, disabled_rules=frozenset(arguments.disable),
        max_file_bytes=arguments.max_file_size, config=Path(arguments.config) if arguments.config else None,
        rapid_path=arguments.rapid_path, solver_timeout_s=arguments.solver_timeout, explicit=getattr(arguments, "given", frozenset()),
        stock_resolution=arguments.stock_resolution, stock_out=Path(arguments.stock_out) if arguments.stock_out else None,
    )


def _check(arguments) -> int:
    settings = _settings(arguments)
    if settings.config is not None and not settings.config.is_file():
        print(f"ncverify: error: --config {settings.config}: no such file", file=sys.stderr)
        return EXIT_USAGE
    unknown = [name for name in settings.disabled_rules if name not in rule_definitions() and not _is_category(name)]
    if unknown:
        print(f"ncverify: error: --disable names no rule or category: {', '.join(sorted(unknown))}", file=sys.stderr)
        return EXIT_USAGE
    results: list[FileResult] = []
    errors: list[str] = []
    texts: dict[str, str] = {}
    for path, explicit in _inputs(arguments.paths, settings):
        try:
            if path == "-":
                data = sys.stdin.buffer.read(settings.max_file_bytes + 1)
                if len(data) > settings.max_file_bytes:
                    raise InputError(f"<stdin>: larger than the limit of {settings.max_file_bytes:,} bytes")
                result = check_source(ProgramSource.from_bytes(data, "<stdin>"), settings, project_for(None, settings))
                texts["<stdin>"] = data.decode("utf-8", errors="replace")
            else:
                result = check_file(path, settings)
        except InputError as error:
            errors.append(str(error))
            continue
        if arguments.verbose:
            print(f"{result.path}: read as {result.dialect} ({result.dialect_confidence:g}): {result.detection_evidence or result.skipped or 'given'}",
                  file=sys.stderr)
        if explicit and result.skipped:
            errors.append(f"{result.path}: not checked: {result.skipped}")
        results.append(result)
    if not results and not errors:
        errors.append("no program files found in " + ", ".join(arguments.paths))
    _write(arguments, results, errors, texts)
    return _exit_code(results, errors, settings)


def _inputs(paths: list[str], settings: Settings):
    for name in paths:
        if name == "-":
            yield "-", True
        elif not Path(name).exists():
            yield Path(name), True
        else:
            yield from iter_program_files([name], settings)


def _is_category(name: str) -> bool:
    from .diagnostics import CATEGORIES

    return name in CATEGORIES


def _write(arguments, results, errors, texts) -> None:
    if arguments.format == "json":
        rendered = render_json(results, errors)
    elif arguments.format == "sarif":
        rendered = render_sarif(results, errors)
    else:
        rendered = render_text(results, errors, texts, show_proved=arguments.show_proved)
    if arguments.output:
        Path(arguments.output).write_text(rendered + "\n", encoding="utf-8")
    else:
        sys.stdout.write(rendered + "\n")
    if arguments.format != "text":
        for error in errors:
            print(f"ncverify: error: {error}", file=sys.stderr)


def _exit_code(results: list[FileResult], errors: list[str], settings: Settings) -> int:
    if errors:
        return EXIT_USAGE
    threshold = None if settings.fail_on == "never" else Severity(settings.fail_on).rank
    for result in results:
        for diagnostic in result.diagnostics:
            if diagnostic.status is Status.UNKNOWN:
                if settings.fail_on_unknown:
                    return EXIT_FINDINGS
            elif diagnostic.status is Status.VIOLATED and threshold is not None and diagnostic.severity.rank >= threshold:
                return EXIT_FINDINGS
    return EXIT_OK


def explain_text(rule_id: str) -> str | None:
    """The page ``ncverify explain`` prints (Markdown), or ``None`` for an unknown rule."""
    definition = rule_definitions().get(rule_id)
    if definition is None:
        return None
    header = f"{definition.id}  [{definition.category}, {definition.severity.value}]\n{definition.summary}\n"
    return header + "\n" + definition.page


def _explain(rule_id: str) -> int:
    page = explain_text(rule_id)
    if page is None:
        close = [known for known in rule_definitions() if rule_id.split(".")[-1] in known]
        hint = f" (did you mean {', '.join(close)}?)" if close else " (see `ncverify rules`)"
        print(f"ncverify: error: no rule {rule_id!r}{hint}", file=sys.stderr)
        return EXIT_USAGE
    _print_markdown(page)
    return EXIT_OK


def _print_markdown(text: str) -> None:
    if sys.stdout.isatty():
        from rich.console import Console
        from rich.markdown import Markdown

        Console().print(Markdown(text))
    else:
        print(text)


def _serve_lsp() -> int:
    try:
        from .lsp import serve
    except ImportError as error:
        print(f"ncverify: error: the language server needs the lsp extra (pip install \"ncverify[lsp]\"): {error}", file=sys.stderr)
        return EXIT_USAGE
    serve()
    return EXIT_OK


def _list_rules(where: bool = False) -> int:
    implementations = rule_registry.implementations() if where else {}
    for definition in rule_definitions().values():
        line = f"{definition.id:34} {definition.category:16} {definition.severity.value:8} {definition.summary}"
        if where:
            line += f"  [{implementations[definition.id].where}]"
        print(line)
    return EXIT_OK


if __name__ == "__main__":
    raise SystemExit(main())
