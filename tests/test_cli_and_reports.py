"""The command line, run in-process through ``ncverify.cli.main``, and its three report
formats: exit codes, folder walking, stdin, the JSON contract and SARIF 2.1.0."""
from __future__ import annotations

import io
import json
import subprocess
import sys
import types
from pathlib import Path

import pytest

from ncverify.check import rule_definitions
from ncverify.cli import main

CLEAN = """O1000
G21 G90 G17
T1 M6
G43 H1 Z50.
S1000 M3
G0 X0. Y0.
G1 X10. F100.
G0 Z50.
M30
"""
# One error: feed-missing on line 2, columns 1-17 ("G01 X10. Y5. Z-1."), plus a spindle warning.
WITH_ERROR = "G0 G21 G90 Z1.\nG01 X10. Y5. Z-1.\nS1000 M03\nM30\n"
# Only a warning: the spindle is off while cutting.
WITH_WARNING = "G21 G90\nG0 X0. Z1.\nG1 X10. Z-1. F100.\nS1000 M03\nM30\n"
# Only an unknown verdict: the loop never ends.
WITH_UNKNOWN = "WHILE [1 EQ 1] DO1\nEND1\nM30\n"
C_HEADER = "#include <stdio.h>\n#define LIMIT 10\nint limit(void);\n"

SCHEMAS = Path(__file__).resolve().parents[2] / "shared" / "schemas"


def write(folder: Path, name: str, text: str | bytes) -> Path:
    path = folder / name
    path.parent.mkdir(parents=True, exist_ok=True)
    if isinstance(text, bytes):
        path.write_bytes(text)
    else:
        path.write_text(text, encoding="utf-8")
    return path


def run(capsys, *arguments) -> tuple[int, str, str]:
    try:
        code = main([str(argument) for argument in arguments])
    except SystemExit as exit_:
        code = exit_.code
    out, err = capsys.readouterr()
    return code, out, err


def run_json(capsys, *arguments) -> tuple[int, dict]:
    code, out, _ = run(capsys, "check", "--format", "json", *arguments)
    return code, json.loads(out)


# --------------------------------------------------------------------------- exit codes


def test_a_clean_program_exits_0(tmp_path, capsys):
    code, out, _ = run(capsys, "check", write(tmp_path, "clean.nc", CLEAN))
    assert code == 0
    assert "0 error(s)" in out


def test_a_program_with_an_error_exits_1_and_names_the_finding(tmp_path, capsys):
    code, out, _ = run(capsys, "check", write(tmp_path, "bad.nc", WITH_ERROR))
    assert code == 1
    assert "bad.nc:2:1: error core.feed-missing" in out


def test_a_missing_file_exits_2_with_a_message(tmp_path, capsys):
    code, out, err = run(capsys, "check", tmp_path / "nowhere.nc")
    assert code == 2
    assert "nowhere.nc" in out + err and "Traceback" not in out + err


def test_a_binary_file_named_explicitly_exits_2(tmp_path, capsys):
    junk = write(tmp_path, "junk.nc", bytes(range(256)) * 8)
    code, out, err = run(capsys, "check", junk)
    assert code == 2
    assert "binary" in out + err


def test_a_bad_flag_exits_2(tmp_path, capsys):
    code, _, err = run(capsys, "check", "--no-such-flag", write(tmp_path, "clean.nc", CLEAN))
    assert code == 2
    assert "--no-such-flag" in err


def test_a_bad_choice_exits_2(tmp_path, capsys):
    code, _, err = run(capsys, "check", "--format", "xml", write(tmp_path, "clean.nc", CLEAN))
    assert code == 2


def test_a_zero_loop_bound_exits_2(tmp_path, capsys):
    code, _, err = run(capsys, "check", "--loop-bound", "0", write(tmp_path, "clean.nc", CLEAN))
    assert code == 2


def test_disabling_an_unknown_rule_exits_2(tmp_path, capsys):
    code, _, err = run(capsys, "check", "--disable", "core.no-such-rule", write(tmp_path, "clean.nc", CLEAN))
    assert code == 2
    assert "core.no-such-rule" in err


def test_a_missing_file_among_good_ones_still_exits_2(tmp_path, capsys):
    code, _, _ = run(capsys, "check", write(tmp_path, "clean.nc", CLEAN), tmp_path / "gone.nc")
    assert code == 2


# --------------------------------------------------------------------------- fail-on


def test_a_warning_does_not_fail_by_default(tmp_path, capsys):
    code, _, _ = run(capsys, "check", write(tmp_path, "warn.nc", WITH_WARNING))
    assert code == 0


def test_fail_on_warning_fails_on_a_warning(tmp_path, capsys):
    code, _, _ = run(capsys, "check", "--fail-on", "warning", write(tmp_path, "warn.nc", WITH_WARNING))
    assert code == 1


def test_fail_on_never_passes_a_program_with_an_error(tmp_path, capsys):
    code, out, _ = run(capsys, "check", "--fail-on", "never", write(tmp_path, "bad.nc", WITH_ERROR))
    assert code == 0
    assert "core.feed-missing" in out


def test_an_unknown_verdict_does_not_fail_by_default(tmp_path, capsys):
    code, _, _ = run(capsys, "check", "--loop-bound", "50", write(tmp_path, "loop.nc", WITH_UNKNOWN))
    assert code == 0


def test_fail_on_unknown_fails_on_an_unknown_verdict(tmp_path, capsys):
    code, out, _ = run(capsys, "check", "--loop-bound", "50", "--fail-on-unknown", write(tmp_path, "loop.nc", WITH_UNKNOWN))
    assert code == 1
    assert "core.loop-bound" in out


def test_disabling_the_rule_that_fails_makes_the_run_pass(tmp_path, capsys):
    code, _, _ = run(capsys, "check", "--disable", "core.feed-missing", write(tmp_path, "bad.nc", WITH_ERROR))
    assert code == 0


# --------------------------------------------------------------------------- folders and stdin


def test_a_folder_is_walked_recursively_over_the_program_extensions(tmp_path, capsys):
    write(tmp_path, "top.nc", CLEAN)
    write(tmp_path, "deep/er/part.tap", CLEAN)
    write(tmp_path, "notes.md", "# not a program\n")
    write(tmp_path, ".hidden/secret.nc", WITH_ERROR)
    code, document = run_json(capsys, tmp_path)
    names = sorted(Path(entry["path"]).relative_to(tmp_path).as_posix() for entry in document["files"])
    assert names == ["deep/er/part.tap", "top.nc"]
    assert code == 0


def test_an_error_in_a_nested_file_fails_the_folder(tmp_path, capsys):
    write(tmp_path, "top.nc", CLEAN)
    write(tmp_path, "sub/bad.nc", WITH_ERROR)
    code, _, out_err = run(capsys, "check", tmp_path)
    assert code == 1


def test_a_c_header_in_a_folder_is_skipped_with_a_note_and_does_not_fail(tmp_path, capsys):
    write(tmp_path, "part.nc", CLEAN)
    write(tmp_path, "include/limits.h", C_HEADER)
    code, out, _ = run(capsys, "check", tmp_path)
    assert code == 0
    assert "limits.h: note: skipped" in out
    assert "C or C++" in out


def test_a_skipped_header_is_listed_as_skipped_in_json(tmp_path, capsys):
    write(tmp_path, "part.nc", CLEAN)
    write(tmp_path, "limits.h", C_HEADER)
    code, document = run_json(capsys, tmp_path)
    [header] = [entry for entry in document["files"] if entry["path"].endswith("limits.h")]
    assert header["dialect"] is None and header["skipped"] and header["diagnostics"] == []
    assert document["summary"]["skipped"] == 1
    assert code == 0


def test_a_c_header_named_explicitly_exits_2(tmp_path, capsys):
    code, out, err = run(capsys, "check", write(tmp_path, "limits.h", C_HEADER))
    assert code == 2
    assert "not checked" in out + err


def test_an_empty_folder_exits_2(tmp_path, capsys):
    code, out, err = run(capsys, "check", tmp_path)
    assert code == 2
    assert "no program files" in out + err


def _stdin(monkeypatch, data: bytes) -> None:
    monkeypatch.setattr(sys, "stdin", types.SimpleNamespace(buffer=io.BytesIO(data)))


def test_a_dash_reads_the_program_from_stdin(monkeypatch, capsys):
    _stdin(monkeypatch, WITH_ERROR.encode())
    code, out, _ = run(capsys, "check", "-")
    assert code == 1
    assert "<stdin>:2:1: error core.feed-missing" in out
    assert "G01 X10. Y5." in out  # the text report quotes the line from stdin


def test_a_clean_program_on_stdin_exits_0(monkeypatch, capsys):
    _stdin(monkeypatch, CLEAN.encode())
    code, _, _ = run(capsys, "check", "-")
    assert code == 0


def test_stdin_over_the_size_limit_exits_2(monkeypatch, capsys):
    _stdin(monkeypatch, CLEAN.encode() * 20)
    code, out, err = run(capsys, "check", "--max-file-size", "100", "-")
    assert code == 2
    assert "limit" in out + err


def test_the_report_goes_to_the_output_file(tmp_path, capsys):
    report = tmp_path / "report.json"
    code, out, _ = run(capsys, "check", "--format", "json", "-o", report, write(tmp_path, "bad.nc", WITH_ERROR))
    assert code == 1 and out == ""
    assert json.loads(report.read_text(encoding="utf-8"))["version"] == 1


# --------------------------------------------------------------------------- JSON contract

FILE_KEYS = {"path", "dialect", "dialect_confidence", "diagnostics", "suppressed"}
DIAGNOSTIC_KEYS = {"rule", "category", "severity", "line", "column", "end_line", "end_column", "message", "status"}


def test_json_follows_the_contract(tmp_path, capsys):
    code, document = run_json(capsys, write(tmp_path, "bad.nc", WITH_ERROR))
    assert code == 1
    assert document["version"] == 1
    [entry] = document["files"]
    assert FILE_KEYS <= set(entry)
    assert entry["path"].endswith("bad.nc")
    assert entry["dialect"] == "iso"
    assert 0.0 <= entry["dialect_confidence"] <= 1.0
    assert entry["suppressed"] == []
    assert entry["diagnostics"]
    for diagnostic in entry["diagnostics"]:
        assert DIAGNOSTIC_KEYS <= set(diagnostic)
        assert diagnostic["severity"] in ("error", "warning", "info")
        assert diagnostic["status"] in ("violated", "proved", "unknown")
        assert diagnostic["rule"] in rule_definitions()
        assert diagnostic["category"] == rule_definitions()[diagnostic["rule"]].category
        assert diagnostic["line"] >= 1 and diagnostic["column"] >= 1
        assert (diagnostic["end_line"], diagnostic["end_column"]) >= (diagnostic["line"], diagnostic["column"])


def test_json_positions_are_one_based_with_an_exclusive_end(tmp_path, capsys):
    _, document = run_json(capsys, write(tmp_path, "bad.nc", WITH_ERROR))
    [feed] = [d for d in document["files"][0]["diagnostics"] if d["rule"] == "core.feed-missing"]
    # line 2 is "G01 X10. Y5. Z-1.": seventeen characters, columns 1..17, end exclusive 18
    assert (feed["line"], feed["column"], feed["end_line"], feed["end_column"]) == (2, 1, 2, 18)
    assert (feed["severity"], feed["status"], feed["category"]) == ("error", "violated", "feed")


def test_json_columns_count_characters_after_a_chinese_comment(tmp_path, capsys):
    program = "G21 G90\n(精加工) G1 X1. F0. 5\nM30\n"
    _, document = run_json(capsys, write(tmp_path, "cn.nc", program))
    [syntax] = [d for d in document["files"][0]["diagnostics"] if d["rule"] == "core.syntax"]
    line = program.splitlines()[1]
    assert line[syntax["column"] - 1 : syntax["end_column"] - 1] == "5"


def test_json_summary_counts_the_findings(tmp_path, capsys):
    _, document = run_json(capsys, write(tmp_path, "bad.nc", WITH_ERROR), write(tmp_path, "clean.nc", CLEAN))
    summary = document["summary"]
    assert summary["files"] == 2 and summary["checked"] == 2
    assert summary["error"] == 1 and summary["warning"] == 1


def test_json_lists_unreadable_files_as_errors(tmp_path, capsys):
    code, document = run_json(capsys, write(tmp_path, "clean.nc", CLEAN), tmp_path / "gone.nc")
    assert code == 2
    assert any("gone.nc" in error for error in document["errors"])
    assert document["summary"]["unreadable"] == 1


# --------------------------------------------------------------------------- SARIF


@pytest.fixture(scope="module")
def sarif_validator():
    jsonschema = pytest.importorskip("jsonschema")
    path = SCHEMAS / "sarif-schema-2.1.0.json"
    if not path.is_file():
        pytest.skip(f"no SARIF schema at {path}")
    schema = json.loads(path.read_text(encoding="utf-8"))
    validator_class = jsonschema.validators.validator_for(schema)
    validator_class.check_schema(schema)
    return validator_class(schema)


def test_sarif_output_validates_against_the_schema(tmp_path, capsys, sarif_validator):
    program = WITH_ERROR + "G X1.\nWHILE [1 EQ 1] DO1\nEND1\n"
    code, out, _ = run(capsys, "check", "--format", "sarif", "--loop-bound", "20", write(tmp_path, "bad.nc", program))
    document = json.loads(out)
    sarif_validator.validate(document)
    assert code == 1
    results = document["runs"][0]["results"]
    rules = document["runs"][0]["tool"]["driver"]["rules"]
    assert {result["ruleId"] for result in results} == {rule["id"] for rule in rules}
    for result in results:
        assert rules[result["ruleIndex"]]["id"] == result["ruleId"]


def test_sarif_output_for_a_clean_program_validates_too(tmp_path, capsys, sarif_validator):
    code, out, _ = run(capsys, "check", "--format", "sarif", write(tmp_path, "clean.nc", CLEAN))
    document = json.loads(out)
    sarif_validator.validate(document)
    assert code == 0
    assert not [r for r in document["runs"][0]["results"] if r["properties"]["status"] == "violated"]


def test_sarif_output_with_an_unreadable_file_validates_and_says_so(tmp_path, capsys, sarif_validator):
    code, out, _ = run(capsys, "check", "--format", "sarif", tmp_path / "gone.nc")
    document = json.loads(out)
    sarif_validator.validate(document)
    assert code == 2
    invocation = document["runs"][0]["invocations"][0]
    assert invocation["executionSuccessful"] is False
    assert "gone.nc" in invocation["toolExecutionNotifications"][0]["message"]["text"]


def test_sarif_results_that_are_not_failures_have_level_none(tmp_path, capsys):
    _, out, _ = run(capsys, "check", "--format", "sarif", "--loop-bound", "20", write(tmp_path, "loop.nc", WITH_UNKNOWN))
    results = json.loads(out)["runs"][0]["results"]
    assert any(result.get("kind") == "review" for result in results)
    for result in results:
        if result.get("kind", "fail") != "fail":
            assert result.get("level", "none") == "none", result


def test_sarif_regions_match_the_json_positions(tmp_path, capsys):
    path = write(tmp_path, "bad.nc", WITH_ERROR)
    _, out, _ = run(capsys, "check", "--format", "sarif", path)
    [feed] = [r for r in json.loads(out)["runs"][0]["results"] if r["ruleId"] == "core.feed-missing"]
    region = feed["locations"][0]["physicalLocation"]["region"]
    assert (region["startLine"], region["startColumn"], region["endLine"], region["endColumn"]) == (2, 1, 2, 18)
    assert feed["level"] == "error"


# --------------------------------------------------------------------------- explain and rules


def test_explain_prints_the_rule_page(capsys):
    code, out, _ = run(capsys, "explain", "core.feed-missing")
    assert code == 0
    assert out.startswith("core.feed-missing")
    for title in ("What it checks", "Why it matters", "Example", "Use instead"):
        assert f"## {title}" in out
    assert rule_definitions()["core.feed-missing"].summary in out


def test_explain_of_an_unknown_rule_exits_2(capsys):
    code, out, err = run(capsys, "explain", "no.such")
    assert code == 2
    assert "no.such" in err and out == ""


def test_rules_lists_every_rule(capsys):
    code, out, _ = run(capsys, "rules")
    assert code == 0
    listed = [line.split()[0] for line in out.splitlines() if line.strip()]
    assert sorted(listed) == sorted(rule_definitions())


def test_version_prints_the_version(capsys):
    code, out, _ = run(capsys, "--version")
    assert code == 0 and "ncverify" in out


def test_a_closed_stdout_ends_the_listing_without_a_traceback():
    process = subprocess.Popen([sys.executable, "-m", "ncverify.cli", "rules"], stdout=subprocess.PIPE, stderr=subprocess.PIPE)
    process.stdout.close()  # the reader went away before the listing was written
    _, err = process.communicate(timeout=60)
    assert b"Traceback" not in err
