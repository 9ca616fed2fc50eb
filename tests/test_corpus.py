"""Every program in ``corpus/`` gives exactly the findings its ``.expect`` file lists.

A program ``NAME.nc`` (or ``.h``, ``.mpf``, ``.spf``, ``.pim``: any extension a folder walk
checks) has a sibling ``NAME.expect``: one line per finding whose status is
``violated`` or ``unknown``, written ``LINE:COLUMN RULE STATUS`` and sorted by line, column
and rule. A clean program has an empty ``.expect``. CLI settings a program needs are given
in a comment on its first line, ``(ncverify-test: --machine lathe)`` or, in a dialect whose
comments start with ``;``, ``; ncverify-test: --machine lathe``; they are read with the
CLI's own parser, so they mean what they mean on the command line.

To write (or rewrite) the ``.expect`` of a program, then review every line of it:

    python tests/test_corpus.py corpus/iso/NAME.nc            # print the findings
    python tests/test_corpus.py --write corpus/iso/NAME.nc    # write NAME.expect
"""
from __future__ import annotations

import re
import shlex
import sys
from pathlib import Path

import pytest

from ncverify import check_file
from ncverify.cli import _settings, build_parser
from ncverify.diagnostics import Status
from ncverify.settings import Settings

CORPUS = Path(__file__).resolve().parents[1] / "corpus"
_EXTENSIONS = {extension.lower() for extension in Settings().extensions}
PROGRAMS = sorted(path for path in CORPUS.rglob("*") if path.is_file() and path.suffix.lower() in _EXTENSIONS and path.suffix and not path.name.startswith("."))
_SETTINGS_COMMENT = re.compile(r"(?:\(\s*ncverify-test:\s*([^)]*)\)|;\s*ncverify-test:\s*(.*))", re.IGNORECASE)
_REPORTED = (Status.VIOLATED, Status.UNKNOWN)


def settings_for(program: Path) -> Settings:
    """The settings named in the program's first-line ``(ncverify-test: ...)`` comment."""
    with program.open(encoding="utf-8", errors="replace") as handle:
        first_line = handle.readline()
    match = _SETTINGS_COMMENT.search(first_line)
    arguments = shlex.split(match.group(1) or match.group(2)) if match else []
    return _settings(build_parser().parse_args(["check", str(program), *arguments]))


def findings(program: Path) -> list[str]:
    """``LINE:COLUMN RULE STATUS`` for each violated or unknown finding, sorted."""
    result = check_file(program, settings_for(program))
    assert result.skipped is None, f"{program.name} was not checked: {result.skipped}"
    elsewhere = [d for d in result.diagnostics if d.span.path not in (None, str(program))]
    assert not elsewhere, f"{program.name} reaches another file; corpus programs must be self-contained: {elsewhere}"
    reported = sorted((d.span.line, d.span.column, d.rule, d.status.value) for d in result.diagnostics if d.status in _REPORTED)
    return [f"{line}:{column} {rule} {status}" for line, column, rule, status in reported]


def expected(program: Path) -> list[str]:
    expect_file = program.with_suffix(".expect")
    assert expect_file.exists(), f"{program.name} has no {expect_file.name}"
    return [line.strip() for line in expect_file.read_text(encoding="utf-8").splitlines() if line.strip()]


def test_the_corpus_is_not_empty():
    assert len(PROGRAMS) >= 10


def test_every_expect_file_has_its_program():
    programs = {program.with_suffix("") for program in PROGRAMS}
    orphans = [path.name for path in CORPUS.rglob("*.expect") if path.with_suffix("") not in programs]
    assert not orphans


@pytest.mark.parametrize("program", PROGRAMS, ids=lambda path: str(path.relative_to(CORPUS)))
def test_program_gives_exactly_the_expected_findings(program):
    want = expected(program)
    assert want == sorted(set(want), key=want.index), f"{program.with_suffix('.expect').name} repeats a line"
    got = findings(program)
    assert set(got) == set(want), (
        f"\nmissing (expected, not found): {sorted(set(want) - set(got))}"
        f"\nunexpected (found, not expected): {sorted(set(got) - set(want))}"
    )


def test_clean_programs_have_no_violation():
    """A clean program may still list ``unknown`` lines: checks it lacks the context for."""
    for program in PROGRAMS:
        if program.stem.startswith("clean-"):
            violated = [line for line in expected(program) if line.endswith(" violated")]
            assert violated == [], f"{program.name} is a clean program but its .expect lists violations"


def _main(argv: list[str]) -> int:
    write = "--write" in argv
    for name in (argument for argument in argv if argument != "--write"):
        program = Path(name).resolve()
        lines = findings(program)
        if write:
            program.with_suffix(".expect").write_text("".join(line + "\n" for line in lines), encoding="utf-8")
            print(f"{program.with_suffix('.expect')}: {len(lines)} finding(s) written - review each one")
        else:
            print(f"== {program}")
            print("\n".join(lines) if lines else "(no findings)")
    return 0


if __name__ == "__main__":
    raise SystemExit(_main(sys.argv[1:]))
