"""What a check imports: Z3 only when a program has free parameters to reason about, lark
only when a block is more than plain words, rich only when a batch of several files may
show its progress bar, the SARIF writer only for SARIF; never numpy's masked arrays; and
no idle BLAS threads. Each check runs in a fresh interpreter, since the test process has
imported everything already."""
from __future__ import annotations

import json
import os
import subprocess
import sys
import textwrap

from hypothesis import given, settings
from hypothesis import strategies as st

from test_verdicts import DRILL_PROVED as PARAMETRIC  # free parameters #1, #2: proofs need the solver

PLAIN = """\
(ncverify: stock box X0:100 Y0:80 Z-20:0)
G21 G90 G17 G40 G49 G80 G54
T1 M6
G43 H1 G0 Z50.
S3000 M3
G0 X10. Y10.
G0 Z5.
G1 Z-1. F200.
G1 X40.
G1 Y40.
G0 Z50.
M30
"""


_RUN = textwrap.dedent("""
    import contextlib, io, json, os, sys
    from ncverify.cli import main
    report = io.StringIO()
    with contextlib.redirect_stdout(report):
        code = main(["check", "--format", "json", "--no-cache", sys.argv[1]])
    print(json.dumps({"code": code, "report": json.loads(report.getvalue()), "imported": sorted(m for m in ("z3", "rich", "lark", "numpy.ma", "ncverify.sarif") if m in sys.modules),
                      "threads": len(os.listdir("/proc/self/task")) if os.path.isdir("/proc/self/task") else None,
                      "blas_threads": os.environ.get("OPENBLAS_NUM_THREADS")}))
""")


def _check_in_a_fresh_process(tmp_path, text: str, **environment: str) -> dict:
    program = tmp_path / "part.nc"
    program.write_text(text)
    env = {name: value for name, value in os.environ.items() if name != "OPENBLAS_NUM_THREADS"} | environment
    done = subprocess.run([sys.executable, "-c", _RUN, str(program)], capture_output=True, text=True, timeout=300, cwd=tmp_path, env=env)
    assert done.returncode == 0, done.stderr
    return json.loads(done.stdout)


def _statuses(outcome: dict, rule: str) -> set[str]:
    [program] = outcome["report"]["files"]
    return {finding["status"] for finding in program["diagnostics"] if finding["rule"] == rule}


def test_a_plain_iso_program_is_checked_without_importing_z3_lark_rich_or_masked_arrays(tmp_path):
    outcome = _check_in_a_fresh_process(tmp_path, PLAIN)
    assert outcome["imported"] == []
    assert outcome["code"] == 0
    [program] = outcome["report"]["files"]
    assert program["dialect"] == "iso" and outcome["report"]["summary"]["blocks"] >= 11


def test_the_command_line_starts_no_idle_blas_threads(tmp_path):
    """OpenBLAS would start a thread per core when numpy loads, each spinning for a while
    (as much CPU time as the import itself); the command line asks for one thread."""
    outcome = _check_in_a_fresh_process(tmp_path, PLAIN)
    assert outcome["blas_threads"] == "1"
    if outcome["threads"] is not None:
        assert outcome["threads"] == 1


def test_the_command_line_modules_are_frozen_and_the_collector_left_as_it_was():
    """The cycle collector pauses while the checker's modules load and they are frozen,
    out of later collections; a collector the process had turned off stays off."""
    script = ("import gc, sys; gc.disable() if sys.argv[1] == 'off' else None; import ncverify.cli; "
              "print(gc.isenabled(), gc.get_freeze_count() > 10000)")
    for state, expected in (("on", ["True", "True"]), ("off", ["False", "True"])):
        done = subprocess.run([sys.executable, "-c", script, state], capture_output=True, text=True, timeout=300, check=True)
        assert done.stdout.split() == expected


def test_a_thread_count_the_user_set_is_kept(tmp_path):
    assert _check_in_a_fresh_process(tmp_path, PLAIN, OPENBLAS_NUM_THREADS="2")["blas_threads"] == "2"


def test_importing_the_package_loads_no_numerical_library():
    """The command line can settle the thread pools only if the package itself (imported
    before ``ncverify.cli`` runs) has not loaded numpy yet; its API names still load."""
    script = "import sys, ncverify; before = 'numpy' in sys.modules; from ncverify import check_text, Settings; print(before, callable(check_text), Settings.__name__)"
    done = subprocess.run([sys.executable, "-c", script], capture_output=True, text=True, timeout=300, check=True)
    assert done.stdout.split() == ["False", "True", "Settings"]


def test_a_program_with_free_parameters_still_gets_its_proofs(tmp_path):
    outcome = _check_in_a_fresh_process(tmp_path, PARAMETRIC)
    assert "z3" in outcome["imported"] and "lark" in outcome["imported"]  # #1 is an expression: the grammar reads it
    assert _statuses(outcome, "core.cycle-depth-sign") == {"proved"}
    assert _statuses(outcome, "core.cycle-r-above-initial") == {"proved"}


def test_rule_pages_are_parsed_when_first_looked_up():
    from ncverify.resources import data_dir
    from ncverify.rule_pages import RuleBook, parse_rule_file

    paths = sorted(data_dir("rules").glob("*/*.md"))
    book = RuleBook(paths)
    assert len(book) == len(paths) and "core.feed-missing" in book and "core.no-such-rule" not in book
    assert book._parsed == {}
    assert book["core.feed-missing"].summary == parse_rule_file(data_dir("rules") / "core" / "feed-missing.md").summary
    assert list(book._parsed) == ["core.feed-missing"]
    constrained = [definition.id for definition in book.constrained()]
    assert constrained and constrained == [rule_id for rule_id in book if parse_rule_file(book._paths[rule_id]).constraints]


@settings(max_examples=300)
@given(st.lists(st.sampled_from(["ncverify", "NCVERIFY", "Ncverify", "NCVerify", "NcVerify", "nCVerify", "erify", "ERIFY", "ncv", "NCV",
                                 "Verify", "(", ":", " ", "\n", "X1.", "V", "v", "ve", "VE", "V1.", "e"]), max_size=30).map("".join),
       st.sampled_from([0, (1 << 18) - 9, (1 << 18) - 5, (1 << 18) - 1]))
def test_annotation_markers_are_found_by_their_vs_as_by_each_variant(text, padding):
    """The markers are found by the V each has as its third byte (the file read in pieces
    of 256 KiB: the padding puts a marker across the seam between two)."""
    from ncverify.annotations import _MARKERS, _markers
    from ncverify.source import find_all

    buffer = b"x" * padding + text.encode()
    assert _markers(buffer) == find_all(buffer, _MARKERS)


def _command(tmp_path, *arguments: str) -> subprocess.CompletedProcess:
    env = {name: value for name, value in os.environ.items() if name != "PYTHONDONTWRITEBYTECODE"} | {"XDG_CACHE_HOME": str(tmp_path / "cache")}
    return subprocess.run([sys.executable, "-m", "ncverify.cli", *arguments], capture_output=True, text=True, timeout=300, cwd=tmp_path, env=env)


def test_the_command_ends_with_its_output_exit_code_and_exit_handlers(tmp_path, capsys):
    """The command leaves without tearing the interpreter down: its report, exit code and
    the exit handlers' work (the class-code cache written) are those of the usual exit."""
    from ncverify.cli import main

    program = tmp_path / "part.nc"
    program.write_text(PLAIN.replace("F200.", ""))  # a feed move without a feed: exit code 1
    done = _command(tmp_path, "check", "--format", "json", "--no-cache", str(program))
    assert main(["check", "--format", "json", "--no-cache", str(program)]) == done.returncode == 1
    assert done.stdout == capsys.readouterr().out
    assert list((tmp_path / "cache" / "ncverify" / "classes").glob("*.marshal"))
    report = tmp_path / "report.json"
    done = _command(tmp_path, "check", "--format", "json", "--no-cache", "--output", str(report), str(program))
    assert done.returncode == 1 and json.loads(report.read_text(encoding="utf-8"))["files"][0]["path"] == str(program)
    assert _command(tmp_path, "check", str(tmp_path / "missing.nc")).returncode == 2
