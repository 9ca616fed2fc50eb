"""The fuzzing harness: hostile inputs through the whole command line, and what must hold.

Inputs are mutations of real programs (``corpus/`` and, when present, the third-party
programs in ``../shared/corpus-realworld``, both read at run time) and programs made of
each dialect's own statements. Each input is checked with ``ncverify check`` in this
process, in one of the report formats, with the dialect detected or forced, and must:

- end without a traceback and without an internal error reported as "not checked";
- end within the per-file wall-clock bound (the watchdog's ``--file-timeout``);
- exit with a documented code (0, 1, 2);
- write valid UTF-8; JSON and SARIF that parse, SARIF that validates against the schema;
- give the identical report when run a second time;
- stay within the watchdog's memory budget (``--file-memory``), and leave the process's resident
  memory under a bound once the input is done (what one input leaks is charged to it, and a
  single input's peak does not count against every later one).

``tests/fuzz/test_fuzz.py`` runs a short fixed-seed budget in the test suite;
``benchmarks/fuzz.py`` runs the long campaign.
"""
from __future__ import annotations

import contextlib
import io
import json
import random
import resource
import time
from dataclasses import dataclass, field
from pathlib import Path

from ncverify import cli

ROOT = Path(__file__).resolve().parents[2]
CORPUS = ROOT / "corpus"
REALWORLD = ROOT.parent / "shared" / "corpus-realworld"
SCHEMAS = ROOT.parent / "shared" / "schemas"
FORMATS = ("text", "json", "sarif")
DIALECTS = (None, "iso", "heidenhain", "sinumerik", "fagor", "linuxcnc")
EXIT_CODES = frozenset({0, 1, 2})
FILE_TIMEOUT_S = 60.0  # the watchdog's budget per input: reaching it counts as a hang (wall clock: room for a busy shared machine)
LOOP_BOUND = 20  # small, so that every input is quick and only an unbounded loop reaches the timeout
MAX_PATHS = 8
SOLVER_TIMEOUT_S = 1  # per query: hostile inputs make hard queries, and the verdict is not what is tested
MEMORY_BOUND_MIB = 3072  # resident memory of the fuzzing process after an input

# Statements of each dialect and hostile fragments spliced into programs.
TOKENS = {
    "iso": ["G00 X10. Y10.", "G01 Z-5. F100.", "G81 X0 Y0 Z-10. R2. F50.", "G80", "M98 P1000 L3", "M99", "O1000",
            "#1=[#1+1]", "WHILE [#1 LT 5] DO1", "END1", "IF [#1 GT 2] GOTO 10", "N10", "G65 P9010 A1.", "M30", "GOTO 10",
            "G02 X5. Y5. R2.", "G41 D1", "T1 M06", "G43 H1", "#100=[1/0]", "M97 P100", "G28 G91 Z0",
            "M98 P99991000", "M98 P1000 L999999999", "G81 X0 Y0 Z-10. R2. K999999999", "G81 Z-5. R1. L1E9"],
    "heidenhain": ["BEGIN PGM FZ MM", "END PGM FZ MM", "L X+10 Y+10 FMAX", "L Z-5 F100", "CALL LBL 1", "CALL LBL 2 REP 99999",
                   "LBL 1", "LBL 2", "LBL 0", "Q1 = Q1 + 1", "FN 12: IF +Q1 LT +5 GOTO LBL 1", "CYCL DEF 200 DRILLING ~",
                   "Q200=+2 ;SET-UP CLEARANCE ~", "CYCL CALL", "TOOL CALL 1 Z S1000", "BLK FORM 0.1 Z X+0 Y+0 Z-20",
                   "BLK FORM 0.2 X+100 Y+100 Z+0", "CC X+0 Y+0", "C X+10 Y+0 DR+", "FN 14: ERROR = 1000", "Q2 = (Q1",
                   "CYCL DEF 220 POLAR PATTERN ~", "Q241=+999999999 ;NR OF REPETITIONS ~", "CYCL DEF 221 CARTESIAN PATTERN ~",
                   "Q242=+999999999 ;NUMBER OF COLUMNS ~", "PATTERN DEF ~", "ROW1 (X+0 Y+0 D+1 NUMX999999999 NUMY999999999)",
                   "CYCL CALL PAT FMAX"],
    "sinumerik": ["G0 X10 Y10", "G1 Z-5 F100", "R1=R1+1", "WHILE R1<5", "ENDWHILE", "LOOP", "ENDLOOP", "IF R1>2 GOTOB MARK",
                  "MARK:", "GOTOF MARK", "REPEAT", "UNTIL R1>1000000", "FOR R2=1 TO 1000000", "ENDFOR", "CYCLE81(10,0,2,-5)",
                  "MCALL CYCLE81(10,0,2,-5)", "MCALL", "DEF REAL R9=1", 'IF $MN_AXCONF_MACHAX_NAME_TAB[0] <> "X"', "ENDIF",
                  "WORKPIECE(,,,\"BOX\",0,0,-20,-80,0,0,100,100)", "SUB1", "PROC SUB1", "M17", "$TC_DP1[1,1]=120",
                  "REPEAT MARK P=999999999", "REPEATB MARK P=999999999", "REPEAT MARK END_MARK P=5", "END_MARK:",
                  "L10 P999999999", "CALL \"SUB1\" P=999999999", "SUB1 P=3", "MCALL HOLES1(0,0,0,10,999999999)",
                  "HOLES2(0,0,50,0,10,999999999)", "CYCLE801(0,0,0,10,10,999999999,999999999)"],
    "fagor": ["G0 X10 Y10", "G1 Z-5 F100", "$IF P1 > 2", "$ENDIF", "$WHILE P1 < 5", "$ENDWHILE", "$GOTO N10", "N10",
              "(RPT N10, N20)", "N20", "#CALL SUB1", "%L SUB1", "#RET", "P1 = P1 + 1", "G81 Z2 I-20", "G80", "#MCALL SUB1",
              "#MDOFF", "$FOR P2=1,1000000,1", "$ENDFOR", "#TOOL AX [Z+]", "G160 A0 I10 K3",
              "G160 A0 I10 K999999999", "G161 A0 I10 K999999999 J10 D999999999", "G162 I100 K999999999",
              "G163 X0 Y0 I10 K999999999", "G164 X0 Y0 I999999999", "G165 X0 Y0 A0 B90 I10 K999999999",
              "#RPT [N10, N20, 999999999]", "#CALL SUB1 [999999999]", "(RPT N10, N20) N999999999"],
    "linuxcnc": ["O100 sub", "O100 endsub", "O100 call [1] [2]", "O101 while [#1 LT 5]", "O101 endwhile", "#1 = [#1 + 1]",
                 "O102 repeat [999999999]", "O102 endrepeat", "O103 if [#<x> GT 2]", "O103 else", "O103 endif", "#<x> = 3",
                 "O104 do", "O104 while [1]", "O105 return", "G0 X10 Y10", "G1 Z-5 F100", "G81 Z-5 R1 L999999999",
                 "G2 X5 Y5 I2.5 J0", "M30", "%", "O200 call", "O<named> call", "O<named> sub", "O<named> endsub"],
}
HOSTILE = ["(" * 60 + "1" + ")" * 60, "[" * 60 + "1" + "]" * 60, "+".join(["1"] * 400), "-" * 300 + "1",
           "1E400", "9" * 400, "NAN", "INF", '"', "'", ";", "(", ")", "[", "]", "\t", "\r", "\ufeff", "\x00", "\u00e9\u4e2d",
           "G", "X", "#", "=", "==", "<>", "/", "%", ":", "~", "?", "-0", "0.000000001", "-1E38"]
EXTREME_NUMBERS = ["0", "-0", "1", "-1", "0.0001", "99999999", "-99999999", "1E38", "1E400", "1e-30", "65535", "4294967296"]


@dataclass
class Failure:
    kind: str
    detail: str
    data: bytes
    options: list[str]


@dataclass
class Tally:
    inputs: int = 0
    by_format: dict = field(default_factory=dict)
    by_dialect: dict = field(default_factory=dict)
    by_exit: dict = field(default_factory=dict)
    failures: list[Failure] = field(default_factory=list)
    slowest_s: float = 0.0


def seed_programs(realworld: bool = True) -> list[tuple[str, bytes]]:
    """(name, bytes) of every corpus program, and of the third-party programs if present."""
    found = []
    folders = [CORPUS] + ([REALWORLD] if realworld and REALWORLD.is_dir() else [])
    for folder in folders:
        for path in sorted(folder.rglob("*")):
            if path.is_file() and path.suffix.lower() not in (".expect", ".md", ".tsv", ".toml", ".t", ".pnt") and path.name != "README.md":
                found.append((str(path.relative_to(folder.parent)), path.read_bytes()))
    return found


# --------------------------------------------------------------------------- inputs


def mutate(rng: random.Random, seeds: list[tuple[str, bytes]]) -> tuple[str, bytes]:
    """A mutated program: a window of a seed, then one to four mutations."""
    name, data = seeds[rng.randrange(len(seeds))]
    lines = data.split(b"\n")
    if len(lines) > 60 and rng.random() < 0.9:
        start = rng.randrange(len(lines))
        lines = lines[start:start + rng.randint(5, 60)]
    for _ in range(rng.randint(1, 4)):
        lines = rng.choice(_MUTATIONS)(rng, lines, seeds) or [b""]
    return name, b"\n".join(lines)


def _delete(rng, lines, _seeds):
    if len(lines) < 2:
        return lines
    start = rng.randrange(len(lines))
    return lines[:start] + lines[start + rng.randint(1, 8):]


def _duplicate(rng, lines, _seeds):
    start = rng.randrange(len(lines))
    piece = lines[start:start + rng.randint(1, 10)]
    at = rng.randrange(len(lines) + 1)
    return lines[:at] + piece * rng.randint(1, 3) + lines[at:]


def _swap(rng, lines, _seeds):
    if len(lines) < 2:
        return lines
    a, b = rng.randrange(len(lines)), rng.randrange(len(lines))
    lines = list(lines)
    lines[a], lines[b] = lines[b], lines[a]
    return lines


def _splice(rng, lines, seeds):
    """Lines of another program (often another dialect) inserted."""
    other = seeds[rng.randrange(len(seeds))][1].split(b"\n")
    start = rng.randrange(len(other))
    at = rng.randrange(len(lines) + 1)
    return lines[:at] + other[start:start + rng.randint(1, 15)] + lines[at:]


def _statement(rng, lines, _seeds):
    """A statement of some dialect, or a few, inserted as lines."""
    dialect = rng.choice(sorted(TOKENS))
    new = [rng.choice(TOKENS[dialect]).encode() for _ in range(rng.randint(1, 5))]
    at = rng.randrange(len(lines) + 1)
    return lines[:at] + new + lines[at:]


def _hostile(rng, lines, _seeds):
    """A hostile fragment written into a line."""
    index = rng.randrange(len(lines))
    line = lines[index]
    at = rng.randint(0, len(line))
    lines = list(lines)
    lines[index] = line[:at] + rng.choice(HOSTILE).encode("utf-8") + line[at:]
    return lines


def _number(rng, lines, _seeds):
    """A number in a line replaced by an extreme one."""
    index = rng.randrange(len(lines))
    line = lines[index]
    digits = [position for position, byte in enumerate(line) if 48 <= byte <= 57]
    if not digits:
        return lines
    at = rng.choice(digits)
    end = at
    while end < len(line) and (48 <= line[end] <= 57 or line[end] == 46):
        end += 1
    lines = list(lines)
    lines[index] = line[:at] + rng.choice(EXTREME_NUMBERS).encode() + line[end:]
    return lines


def _bytes(rng, lines, _seeds):
    """A byte flipped, removed or inserted (encodings, control characters)."""
    index = rng.randrange(len(lines))
    line = bytearray(lines[index])
    at = rng.randint(0, len(line))
    action = rng.randrange(3)
    if action == 0 and at < len(line):
        line[at] = rng.randrange(256)
    elif action == 1 and at < len(line):
        del line[at]
    else:
        line[at:at] = bytes([rng.choice((0, 9, 13, 26, 0x80, 0xC3, 0xEF, 0xFF, rng.randrange(256)))])
    lines = list(lines)
    lines[index] = bytes(line)
    return lines


def _line_ends(rng, lines, _seeds):
    """Line ends changed (CRLF, lone CR) or a byte-order mark put in front."""
    choice = rng.randrange(3)
    if choice == 0:
        return [line + b"\r" for line in lines]
    if choice == 1:
        return [b"\r".join(lines)]
    return [b"\xef\xbb\xbf" + lines[0]] + lines[1:] if lines else lines


_MUTATIONS = (_delete, _duplicate, _swap, _splice, _statement, _statement, _hostile, _number, _number, _bytes, _line_ends)


def suffix_for(name: str) -> str:
    suffix = Path(name).suffix.lower()
    return suffix if suffix in (".nc", ".h", ".mpf", ".spf", ".pim", ".ngc", ".tap") else ".nc"


# --------------------------------------------------------------------------- running


class Runner:
    """Runs inputs through the CLI in this process and records what broke."""

    def __init__(self, work: Path, repeat_every: int = 1, validate_every: int = 1):
        self.work = work
        self.work.mkdir(parents=True, exist_ok=True)
        self.validator = sarif_validator()
        self.repeat_every = repeat_every  # run every n-th input twice and compare the reports
        self.validate_every = validate_every  # validate every n-th SARIF report against the schema (all are parsed)
        self.sarif_reports = 0
        self.tally = Tally()

    def check(self, data: bytes, suffix: str, report_format: str, dialect: str | None) -> Failure | None:
        tally = self.tally
        tally.inputs += 1
        tally.by_format[report_format] = tally.by_format.get(report_format, 0) + 1
        tally.by_dialect[dialect or "detected"] = tally.by_dialect.get(dialect or "detected", 0) + 1
        program = self.work / f"input{suffix}"
        program.write_bytes(data)
        options = ["--format", report_format, "--no-cache", "--file-timeout", f"{FILE_TIMEOUT_S:g}", "--loop-bound", str(LOOP_BOUND),
                   "--max-paths", str(MAX_PATHS), "--solver-timeout", str(SOLVER_TIMEOUT_S)] + (["--dialect", dialect] if dialect else [])
        failure = self._one(data, program, options, repeat=tally.inputs % self.repeat_every == 0)
        if failure is not None:
            tally.failures.append(failure)
        return failure

    def _one(self, data: bytes, program: Path, options: list[str], repeat: bool) -> Failure | None:
        def fail(kind: str, detail: str) -> Failure:
            return Failure(kind, detail, data, options)

        first = self._run(program, options)
        if isinstance(first, Failure):
            return fail(first.kind, first.detail)
        code, output, seconds = first
        self.tally.by_exit[code] = self.tally.by_exit.get(code, 0) + 1
        self.tally.slowest_s = max(self.tally.slowest_s, seconds)
        if code not in EXIT_CODES:
            return fail("exit-code", f"exit code {code}")
        if seconds > FILE_TIMEOUT_S + 5:
            return fail("hang", f"took {seconds:.1f} s")
        try:
            text = output.decode("utf-8")
        except UnicodeDecodeError as error:
            return fail("not-utf8", str(error))
        if "internal error" in text or "ran past its budget" in text or "memory budget" in text:
            return fail("not-checked", _excerpt(text, ("internal error", "ran past its budget", "memory budget")))
        problem = self._validate(text, options[1])
        if problem:
            return fail("invalid-report", problem)
        if repeat:
            second = self._run(program, options)
            if isinstance(second, Failure):
                return fail(second.kind, "second run: " + second.detail)
            if second[0] != code or second[1] != output:
                return fail("not-deterministic", "the second run gave another report or exit code")
        resident = resident_mib()
        if resident > MEMORY_BOUND_MIB:
            return fail("memory", f"{resident:.0f} MiB resident after the input")
        return None

    def _run(self, program: Path, options: list[str]):
        report = self.work / "report.out"
        report.unlink(missing_ok=True)
        started = time.monotonic()
        with contextlib.redirect_stdout(io.StringIO()), contextlib.redirect_stderr(io.StringIO()) as errors:
            try:
                code = cli.main(["check", str(program), "--output", str(report), *options])
            except SystemExit as stop:
                code = stop.code
            except BaseException as error:  # noqa: BLE001 - a traceback is what the harness looks for
                import traceback

                return Failure("traceback", "".join(traceback.format_exception(error))[-3000:], b"", [])
        seconds = time.monotonic() - started
        if "Traceback" in errors.getvalue():
            return Failure("traceback", errors.getvalue()[-3000:], b"", [])
        output = report.read_bytes() if report.exists() else b""
        return code, output, seconds

    def _validate(self, text: str, report_format: str) -> str | None:
        if report_format == "text" or not text.strip():
            return None
        try:
            document = json.loads(text)
        except ValueError as error:
            return f"{report_format} does not parse: {error}"
        if report_format == "sarif":
            self.sarif_reports += 1
        if report_format == "sarif" and self.validator is not None and self.sarif_reports % self.validate_every == 0:
            error = next(iter(self.validator.iter_errors(document)), None)
            if error is not None:
                return f"SARIF does not validate: {error.message[:300]}"
        if report_format == "json" and not {"version", "files", "summary"} <= set(document):
            return "JSON report without version, files or summary"
        return None


def resident_mib() -> float:
    """The process's resident memory now (Linux), else its peak so far."""
    try:
        pages = int(Path("/proc/self/statm").read_text().split()[1])
    except (OSError, IndexError, ValueError):
        return resource.getrusage(resource.RUSAGE_SELF).ru_maxrss / 1024
    return pages * resource.getpagesize() / (1 << 20)


def _excerpt(text: str, needles) -> str:
    for needle in needles:
        at = text.find(needle)
        if at >= 0:
            return text[max(0, at - 200): at + 400]
    return text[:400]


def sarif_validator():
    """A validator for the OASIS SARIF 2.1.0 schema (``../shared/schemas``), or None."""
    import jsonschema

    path = SCHEMAS / "sarif-schema-2.1.0.json"
    if not path.is_file():
        return None
    schema = json.loads(path.read_text(encoding="utf-8"))
    return jsonschema.validators.validator_for(schema)(schema)


def campaign(runner: Runner, seed: int, count: int, seeds: list[tuple[str, bytes]], on_failure=None) -> Tally:
    """``count`` mutated inputs from ``seed``: formats and dialects drawn in turn."""
    rng = random.Random(seed)
    for index in range(count):
        name, data = mutate(rng, seeds)
        report_format = FORMATS[index % len(FORMATS)]
        dialect = rng.choice(DIALECTS) if rng.random() < 0.4 else None
        failure = runner.check(data, suffix_for(name), report_format, dialect)
        if failure is not None and on_failure is not None:
            on_failure(failure, name, seed, index)
    return runner.tally
