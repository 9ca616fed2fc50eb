"""The parametric corpus programs, through the JSON of ``check_file``: which verdicts they
show (corpus/README.md, "Verdicts on parametric programs").

The ``.expect`` files list only violated and unknown findings; the ``proved`` entries and
the witnesses are checked here.
"""
from __future__ import annotations

import json
from pathlib import Path

import pytest

from ncverify import check_file, check_text
from ncverify.cli import main as cli_main
from witness_text import assumed_ranges, parameters_only, substitute

CORPUS = Path(__file__).resolve().parents[1] / "corpus" / "iso"
PROVED = CORPUS / "param-pocket-proved.nc"
VIOLATED = [CORPUS / "param-depth-violated.nc", CORPUS / "param-rapid-violated.nc"]
CONTEXT = CORPUS / "context-unknown.nc"


def entries(program: Path) -> list[dict]:
    return check_file(program).to_json()["diagnostics"]


def test_param_pocket_proved_has_proved_entries_and_no_violation():
    found = entries(PROVED)
    proved = [d for d in found if d["status"] == "proved"]
    assert {d["rule"] for d in proved} >= {"core.cycle-depth-sign", "core.cycle-zero-depth", "core.clearance-below-stock",
                                          "core.cycle-r-above-initial", "core.rapid-into-stock"}
    assert all(d["severity"] == "info" and "witness" not in d for d in proved)
    assert [d for d in found if d["status"] == "violated"] == []
    # what is left is context the corpus does not give (no ncverify.toml), each with its reason
    assert all(d.get("reason") for d in found if d["status"] == "unknown")


def test_param_pocket_proved_on_the_command_line_json(capsys):
    code = cli_main(["check", str(PROVED), "--format", "json"])
    document = json.loads(capsys.readouterr().out)
    assert code == 0
    # the retracts straight up out of the pocket (lines 19, 35) meet nothing the tool has not
    # met already: the cut stock passes them without a proof of their own
    assert document["summary"]["proved"] >= 9 and document["summary"]["error"] == 0
    assert document["files"][0]["free_parameters"] == ["#1", "#2", "#3", "#4"]


@pytest.mark.parametrize("program", VIOLATED, ids=lambda path: path.name)
def test_violated_parametric_findings_carry_a_witness_inside_the_assumed_ranges(program):
    text = program.read_text(encoding="utf-8")
    ranges = assumed_ranges(text)
    violated = [d for d in entries(program) if d["status"] == "violated"]
    assert violated
    for finding in violated:
        values = parameters_only(finding.get("witness", {}))
        assert values, f"{finding['rule']} at line {finding['line']} has no witness"
        for name, value in values.items():
            low, high = ranges[name]
            assert low <= value <= high, (finding["rule"], finding["line"], name, value)


@pytest.mark.parametrize("program", VIOLATED, ids=lambda path: path.name)
def test_every_witness_of_the_corpus_reproduces_in_the_program_text(program):
    text = program.read_text(encoding="utf-8")
    for finding in entries(program):
        assert "did not reproduce" not in finding.get("reason", "")
        if finding["status"] != "violated":
            continue
        concrete = check_text(substitute(text, parameters_only(finding["witness"])), program.name)
        assert [d for d in concrete.diagnostics
                if d.rule == finding["rule"] and d.span.line == finding["line"] and d.status.value == "violated"], finding


def test_param_depth_violated_shows_both_hazards():
    found = {(d["rule"], d["line"]) for d in entries(CORPUS / "param-depth-violated.nc") if d["status"] == "violated"}
    assert ("core.cycle-depth-sign", 17) in found  # #1 up to +3 with R2.
    assert ("core.clearance-below-stock", 27) in found  # R#2 down to -2 on a Z0 plate


def test_param_rapid_violated_shows_a_symbolic_rapid_into_the_stock():
    found = [d for d in entries(CORPUS / "param-rapid-violated.nc") if d["status"] == "violated"]
    assert {d["rule"] for d in found} == {"core.rapid-into-stock"}
    assert all("Z#5" in d["message"] for d in found)


@pytest.mark.parametrize("program", VIOLATED, ids=lambda path: path.name)
def test_corpus_witnesses_name_only_program_parameters(program):
    for finding in entries(program):
        if finding["status"] == "violated":
            assert set(finding["witness"]) <= set(assumed_ranges(program.read_text(encoding="utf-8")))


def test_context_unknown_answers_unknown_once_per_missing_context():
    found = entries(CONTEXT)
    assert found and all(d["status"] == "unknown" for d in found)
    by_rule = {}
    for d in found:
        by_rule.setdefault(d["rule"], []).append(d["reason"])
    assert all(len(reasons) == 1 for reasons in by_rule.values()), by_rule
    assert by_rule["core.rapid-into-stock"] == ["no stock defined"]
    assert by_rule["core.clearance-below-stock"] == ["no stock defined"]
    assert "travel" in by_rule["core.travel-limit"][0]
    assert "tool table" in by_rule["core.tool-not-in-table"][0]
