"""Command line: ``ncverify check``, ``ncverify explain``, ``ncverify rules``, ``ncverify lsp``.

Exit codes: 0 nothing at or above ``--fail-on``; 1 findings at or above it (or unknown
verdicts with ``--fail-on-unknown``); 2 usage or input errors (a file that cannot be read,
is too large or is not a program), and a file whose analysis failed (an internal error, or
past its time or memory budget): never 1, so a crash does not read as findings.
"""
from __future__ import annotations

import argparse
import atexit
import gc
import json
import math
import os
import re
import sys
import threading
from pathlib import Path

# Set before the checker's modules load. OpenBLAS starts a thread per core when numpy loads,
# each spinning idle for a while: as much CPU time as the import itself, and the checks make
# no matrix product large enough to gain from threads (a value the user set is kept). The
# cycle collector would scan the objects of some 300 modules again and again while they load
# and in every full collection after, though they live as long as the process: it pauses
# while they load, and they are then frozen (left out of later collections).
os.environ.setdefault("OPENBLAS_NUM_THREADS", "1")
_COLLECTING = gc.isenabled()
gc.disable()

from . import __version__, rule_registry  # noqa: E402
from .api import FileResult, InputError, check_source, iter_program_files, project_for  # noqa: E402
from .check import RuleFileError, rule_definitions  # noqa: E402
from .rule_pages import explain_text  # noqa: E402
from .project import ConfigError  # noqa: E402
from .diagnostics import Severity, Status  # noqa: E402
from .dialect import DIALECTS, MACHINES  # noqa: E402
from .batch import FileOutcome, default_jobs, local_dispatch, run_batch  # noqa: E402
from .cluster import ClusterError  # noqa: E402
from .progress import BatchProgress  # noqa: E402
from .report import render_json, render_text, summary  # noqa: E402
from .settings import Settings  # noqa: E402
from .source import ProgramSource  # noqa: E402
from .watchdog import Budget, is_not_checked, memory_cap, run_within_budget  # noqa: E402

gc.freeze()
if _COLLECTING:
    gc.enable()

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
    check.add_argument("--format", choices=("text", "json", "jsonl", "sarif", "gitlab"), default="text")
    check.add_argument("--output", "-o", metavar="FILE", help="write the report to FILE instead of stdout")
    check.add_argument("--dialect", choices=tuple(DIALECTS), help="skip detection")
    check.add_argument("--profile", choices=DIALECTS["iso"].profiles(), help="ISO profile (default: detected, else mitsubishi-e60)")
    check.add_argument("--machine", choices=MACHINES, help="machine type where the program cannot tell")
    check.add_argument("--fail-on", choices=("error", "warning", "info", "never"), default="error")
    check.add_argument("--fail-on-unknown", action="store_true", help="unknown verdicts fail the run too")
    check.add_argument("--show-proved", action="store_true", help="list proved verdicts in the text report (they are always in JSON)")
    check.add_argument("--verbose", "-v", action="store_true", help="say on stderr why each file was read as its dialect, profile and machine type, and what its verdicts assume (the start position)")
    check.add_argument("--loop-bound", type=_bounded_int(_MAX_LOOP_BOUND), default=Settings.loop_bound, metavar="N",
                       help="iterations of one loop or repeats of one jump before the analysis gives up (default %(default)s)")
    check.add_argument("--max-paths", type=_bounded_int(_MAX_PATHS), default=Settings.max_paths, metavar="N")
    check.add_argument("--least-input-increment", type=_finite(minimum=0.0), metavar="MM",
                       help="what 1 means in a length word without a decimal point (0: a whole unit)")
    check.add_argument("--subprogram-path", action="append", default=[], metavar="DIR", help="folder searched for called programs")
    check.add_argument("--extensions", metavar="LIST", help="comma-separated extensions read in folders (default: %(default)s)",
                       default=",".join(e for e in Settings.extensions if e))
    check.add_argument("--disable", action="append", default=[], metavar="RULE", help="rule id or category to turn off")
    check.add_argument("--max-file-size", type=_positive_int, default=Settings.max_file_bytes, metavar="BYTES")
    check.add_argument("--config", metavar="FILE", help="project file (default: ncverify.toml found upward from each program)")
    check.add_argument("--rapid-path", choices=("straight", "dogleg"), default=Settings.rapid_path,
                       help="how G00 moves: interpolated straight, or each axis on its own (default %(default)s)")
    check.add_argument("--solver-timeout", type=_finite(above=0.0), default=Settings.solver_timeout_s, metavar="S", help="seconds per solver query (default %(default)s)")
    check.add_argument("--file-timeout", type=_finite(above=0.0), default=Budget.seconds, metavar="S",
                       help="wall-clock seconds for one file's analysis; past it the file is reported not checked (default %(default)s)")
    check.add_argument("--file-memory", type=_bounded_int(1 << 30), default=Budget.memory_bytes >> 20, metavar="MIB",
                       help="memory for one file's analysis in MiB; past it the file is reported not checked (default %(default)s)")
    check.add_argument("--jobs", "-j", type=_positive_int, default=None, metavar="N", help="worker processes (default: the machine's cores)")
    check.add_argument("--no-cache", action="store_true", help="verify every file again instead of reusing cached results")
    check.add_argument("--cache-dir", metavar="DIR", help="where results are cached (default: [settings] cache_dir, else the user cache folder)")
    check.add_argument("--dask", metavar="ADDRESS", help="run the checks on the Dask cluster whose scheduler is at ADDRESS (tcp://host:8786)")
    check.add_argument("--sarif-proved", action="store_true", help="SARIF: list proved verdicts as results too (code scanning shows every result as an alert)")
    check.add_argument("--sarif-category", default="ncverify", metavar="NAME", help="SARIF: the run's automationDetails category (one per analysed library)")
    check.add_argument("--plot", metavar="DIR", help="draw the toolpath of every failing file into DIR (needs ncverify[plot])")
    check.add_argument("--stock-resolution", type=_stock_resolution, default=Settings.stock_resolution, metavar="MM|auto|off",
                       help="judge rapids against the stock as cut so far, with cells of MM (default auto: from the smallest tool the program loads); "
                            "0 or off: against the raw blank")
    check.add_argument("--stock-out", metavar="FILE", help="write the workpiece the program leaves (.stl or .npz; {stem}: the program's name)")
    check.add_argument("--air-cutting", action="store_true",
                       help="report, per tool, the feed length that cut only air (sweeps every feed move through the stock model: slower)")

    plot = commands.add_parser("plot", help="draw a program's toolpath with its findings")
    plot.add_argument("program", metavar="PROGRAM")
    plot.add_argument("--output", "-o", required=True, metavar="FILE", help="the picture: .svg or .png")
    plot.add_argument("--dialect", choices=tuple(DIALECTS), help="skip detection")
    plot.add_argument("--machine", choices=MACHINES, help="machine type where the program cannot tell")

    explain = commands.add_parser("explain", help="show a rule's page")
    explain.add_argument("rule")

    rules = commands.add_parser("rules", help="list the rules")
    rules.add_argument("--where", action="store_true", help="add where each rule is implemented (module:Class, the page's constraints, or the modules that report it)")
    commands.add_parser("lsp", help="run the language server on stdin/stdout (needs the lsp extra)")
    return parser


_MAX_LOOP_BOUND = 100_000_000  # beyond this a loop bound no longer bounds the run time
_MAX_PATHS = 100_000


def _positive_int(text: str) -> int:
    try:
        value = int(text)
    except ValueError:
        raise argparse.ArgumentTypeError(f"{text!r} is not a whole number") from None
    if value < 1:
        raise argparse.ArgumentTypeError("must be at least 1")
    return value


def _bounded_int(maximum: int):
    def parse(text: str) -> int:
        value = _positive_int(text)
        if value > maximum:
            raise argparse.ArgumentTypeError(f"{value:,} is above the largest accepted value, {maximum:,}")
        return value
    return parse


def _finite(minimum: float | None = None, above: float | None = None):
    """A number option: finite, and at least ``minimum`` or above ``above``."""
    def parse(text: str) -> float:
        try:
            value = float(text)
        except ValueError:
            raise argparse.ArgumentTypeError(f"{text!r} is not a number") from None
        if not math.isfinite(value):
            raise argparse.ArgumentTypeError(f"{text!r} is not a finite number")
        if minimum is not None and value < minimum:
            raise argparse.ArgumentTypeError(f"must be at least {minimum:g}")
        if above is not None and value <= above:
            raise argparse.ArgumentTypeError(f"must be above {above:g}")
        return value
    return parse


def _stock_resolution(text: str) -> float | None:
    word = text.strip().lower()
    if word in ("auto", "off"):
        return None if word == "auto" else 0.0
    try:
        value = float(text)
    except ValueError:
        raise argparse.ArgumentTypeError(f"{text!r} is not a number, 'auto' or 'off'") from None
    if not 0.0 <= value < float("inf"):
        raise argparse.ArgumentTypeError("must be 0 or 'off' (the blank), a cell size in mm, or 'auto'")
    return value


def run() -> None:
    """The ``ncverify`` command: :func:`main`, then the process ends without tearing the
    interpreter down. Freeing every module and object one by one took about 35 ms of CPU
    time, a seventh of checking a small file, and shows nowhere outside the process. The
    output is flushed and the exit handlers run first (as the usual exit runs them: the
    worker processes' clean-up, the class-code cache); an error, a thread still running
    or output that cannot be flushed takes the usual exit."""
    code = main()
    try:
        sys.stdout.flush()
        sys.stderr.flush()
    except OSError:
        sys.exit(code)
    if threading.active_count() > 1:
        sys.exit(code)
    atexit._run_exitfuncs()
    os._exit(code)


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
        if arguments.command == "plot":
            return _plot(arguments)
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
             "--stock-resolution": "stock_resolution", "--air-cutting": "air_cutting"}
    return frozenset(setting for flag, setting in flags.items() if any(arg == flag or arg.startswith(flag + "=") for arg in argv))


def _settings(arguments) -> Settings:
    extensions = tuple(sorted({("." + e.strip().lstrip(".")).lower() for e in arguments.extensions.split(",") if e.strip()}))
    return Settings(
        dialect=arguments.dialect, profile=arguments.profile, machine=arguments.machine, loop_bound=arguments.loop_bound,
        max_paths=arguments.max_paths, least_input_increment=arguments.least_input_increment,
        subprogram_path=tuple(Path(p) for p in arguments.subprogram_path), extensions=extensions + ("",),
        fail_on=arguments.fail_on, fail_on_unknown=arguments.fail_on_unknown, disabled_rules=frozenset(arguments.disable),
        max_file_bytes=arguments.max_file_size, config=Path(arguments.config) if arguments.config else None,
        rapid_path=arguments.rapid_path, solver_timeout_s=arguments.solver_timeout,
        file_timeout_s=arguments.file_timeout, file_memory_bytes=arguments.file_memory << 20, explicit=getattr(arguments, "given", frozenset()),
        cache_dir=Path(arguments.cache_dir) if arguments.cache_dir else None,
        stock_resolution=arguments.stock_resolution, stock_out=Path(arguments.stock_out) if arguments.stock_out else None,
        air_cutting=arguments.air_cutting,
    )


def _check(arguments) -> int:
    settings = _settings(arguments)
    problem = _usage_problem(arguments, settings)
    if problem:
        print(f"ncverify: error: {problem}", file=sys.stderr)
        return EXIT_USAGE
    unknown = [name for name in settings.disabled_rules if name not in rule_definitions() and not _is_category(name)]
    if unknown:
        print(f"ncverify: error: --disable names no rule or category: {', '.join(sorted(unknown))}", file=sys.stderr)
        return EXIT_USAGE
    inputs = list(_inputs(arguments.paths, settings))
    try:
        dispatch = _dispatch(arguments)
    except ClusterError as error:
        print(f"ncverify: error: {error}", file=sys.stderr)
        return EXIT_USAGE
    with memory_cap(Budget.of(settings)):
        results, errors, texts = _run_batch(arguments, inputs, settings, dispatch)
    if arguments.format != "jsonl":
        _write(arguments, results, errors, texts)
    elif errors:
        _print_errors(errors)
    if arguments.plot:
        _plot_failing(results, settings, Path(arguments.plot))
    return _exit_code(results, errors, settings)


def _run_batch(arguments, inputs, settings: Settings, dispatch) -> tuple[list[FileResult], list[str], dict[str, str]]:
    """Check the inputs with the progress bar and, for ``--format jsonl``, a line per file
    as it finishes. A broken project file stops the run (exit 2), as before batches."""
    progress = BatchProgress(len(inputs))
    with _Lines(arguments) as lines:
        def finished(outcome: FileOutcome) -> None:
            progress.advance(outcome)
            lines.write(outcome.to_json())

        try:
            outcomes = _run_inputs(inputs, settings, dispatch, not arguments.no_cache, finished)
        finally:
            progress.close()
        broken = next((outcome for outcome in outcomes if outcome.project_file_error), None)
        if broken is not None:
            raise ConfigError(broken.error)
        results, errors, texts = _collect(outcomes, arguments.verbose)
        if not results and not errors:
            errors.append("no program files found in " + ", ".join(arguments.paths))
        lines.write({"summary": summary(results, errors)})
    return results, errors, texts


def _dispatch(arguments):
    if arguments.dask:
        from .cluster import dask_dispatch

        return dask_dispatch(arguments.dask)
    return local_dispatch(arguments.jobs or default_jobs())


def _run_inputs(inputs, settings: Settings, dispatch, use_cache: bool, finished) -> list[FileOutcome]:
    """Files through the batch (workers, cache); standard input here, at its place."""
    files = [(path, explicit) for path, explicit in inputs if path != "-"]
    outcomes = run_batch(files, settings, dispatch, use_cache, finished)
    for position, (path, _) in enumerate(inputs):
        if path == "-":
            outcome = _check_stdin(settings)
            finished(outcome)
            outcomes.insert(position, outcome)
    return outcomes


def _check_stdin(settings: Settings) -> FileOutcome:
    data = sys.stdin.buffer.read(settings.max_file_bytes + 1)
    if len(data) > settings.max_file_bytes:
        return FileOutcome("<stdin>", True, error=f"<stdin>: larger than the limit of {settings.max_file_bytes:,} bytes")
    result = run_within_budget("<stdin>", lambda: check_source(ProgramSource.from_bytes(data, "<stdin>"), settings, project_for(None, settings)),
                               Budget.of(settings))
    return FileOutcome("<stdin>", True, result, text=data.decode("utf-8", errors="replace"))


def _collect(outcomes: list[FileOutcome], verbose: bool = False) -> tuple[list[FileResult], list[str], dict[str, str]]:
    results: list[FileResult] = []
    errors: list[str] = []
    texts: dict[str, str] = {}
    for outcome in outcomes:
        if outcome.error is not None:
            errors.append(outcome.error)
            continue
        result = outcome.result
        if verbose:
            print(f"{result.path}: read as {result.dialect} ({result.dialect_confidence:g}): {result.detection_evidence or result.skipped or 'given'}",
                  file=sys.stderr)
            for assumption in result.assumptions:
                print(f"{result.path}: assumed: {assumption}", file=sys.stderr)
        if (outcome.explicit and result.skipped) or is_not_checked(result):
            errors.append(f"{outcome.result.path}: not checked: {outcome.result.skipped}")
        if outcome.text is not None:
            texts[outcome.path] = outcome.text
        results.append(outcome.result)
    return results, errors, texts


class _Lines:
    """``--format jsonl``: one JSON line per file as it finishes, then the summary line;
    for the other formats it writes nothing."""

    def __init__(self, arguments):
        self.enabled = arguments.format == "jsonl"
        self.output = arguments.output
        self.stream = None

    def __enter__(self):
        if self.enabled:
            self.stream = open(self.output, "w", encoding="utf-8") if self.output else sys.stdout
        return self

    def write(self, entry: dict) -> None:
        if self.stream is not None:
            self.stream.write(json.dumps(entry, ensure_ascii=False) + "\n")
            self.stream.flush()

    def __exit__(self, *exc):
        if self.stream is not None and self.stream is not sys.stdout:
            self.stream.close()


def _usage_problem(arguments, settings: Settings) -> str | None:
    """What makes the command line unusable before any file is read, if anything."""
    if settings.config is not None and not settings.config.is_file():
        return f"--config {settings.config}: " + ("is a folder, not a project file" if settings.config.is_dir() else "no such file")
    missing = [str(folder) for folder in settings.subprogram_path if not folder.is_dir()]
    if missing:
        return f"--subprogram-path {', '.join(missing)}: no such folder"
    if arguments.output:
        output = Path(arguments.output)
        if output.is_dir():
            return f"--output {output}: is a folder; name a file to write the report to"
        if not output.parent.is_dir():
            return f"--output {output}: the folder {output.parent} does not exist"
    return None


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
        from .sarif import render_sarif

        rendered = render_sarif(results, errors, include_proved=arguments.sarif_proved, category=arguments.sarif_category)
    elif arguments.format == "gitlab":
        from .sarif import render_gitlab

        rendered = render_gitlab(results)
    else:
        rendered = render_text(results, errors, texts, show_proved=arguments.show_proved)
    rendered = _valid_unicode(rendered, escape="\\\\" if arguments.format != "text" else "\\")
    if arguments.output:
        Path(arguments.output).write_text(rendered + "\n", encoding="utf-8")
    else:
        sys.stdout.write(rendered + "\n")
    if arguments.format != "text":
        _print_errors(errors)


def _print_errors(errors: list[str]) -> None:
    for error in errors:
        print(f"ncverify: error: {error}", file=sys.stderr)


def _plot(arguments) -> int:
    from .plot import PlotError, plot_program

    settings = Settings(dialect=arguments.dialect, machine=arguments.machine)
    try:
        plot_program(Path(arguments.program), Path(arguments.output), settings)
    except (InputError, PlotError) as error:
        print(f"ncverify: error: {error}", file=sys.stderr)
        return EXIT_USAGE
    return EXIT_OK


def _plot_failing(results: list[FileResult], settings: Settings, folder: Path) -> None:
    """``--plot DIR``: one SVG per failing file, named after its path."""
    from .plot import PlotError, plot_program

    threshold = None if settings.fail_on == "never" else Severity(settings.fail_on).rank
    folder.mkdir(parents=True, exist_ok=True)
    for result in results:
        if threshold is None or result.path == "<stdin>":
            continue
        if any(d.status is Status.VIOLATED and d.severity.rank >= threshold for d in result.diagnostics):
            target = folder / (Path(result.path).as_posix().strip("/").replace("/", "__").replace(":", "") + ".svg")
            try:
                plot_program(Path(result.path), target, settings)
            except (InputError, PlotError) as error:
                print(f"ncverify: error: {error}", file=sys.stderr)


_SURROGATE = re.compile("[\ud800-\udfff]")


def _valid_unicode(rendered: str, escape: str) -> str:
    """A file name that is not valid UTF-8 reaches Python with its stray bytes as lone
    surrogates, which cannot be written as UTF-8. Each is written ``\\xNN`` (the byte) or
    ``\\uNNNN``; ``escape`` is the backslash as the format spells it (doubled in JSON
    strings, where the names are)."""
    def spelled(match: re.Match) -> str:
        code = ord(match.group())
        return f"{escape}x{code - 0xDC00:02x}" if 0xDC80 <= code <= 0xDCFF else f"{escape}u{code:04x}"
    return _SURROGATE.sub(spelled, rendered)


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
    run()
