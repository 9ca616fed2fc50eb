"""Rules are asked only about programs of the dialects and machine types they judge
(``Rule.dialects``, ``Rule.machines``).

The checker leaves a HEIDENHAIN, SINUMERIK or Fagor rule out of an ISO program's dispatch
lists (and so on for each dialect), and a lathe rule out of a mill program's, which must
change no finding: every corpus program
(``corpus/`` and, beside the repository, the real-world corpus), and programs Hypothesis
draws in every dialect (the oracle's: moves, loops, calls, drilling cycles, transforms),
give the same report, word for word, with the rules scoped and with every rule asked about
every program.
"""
from __future__ import annotations

import tempfile
from pathlib import Path

import pytest
from hypothesis import HealthCheck, given, settings as hypothesis_settings, strategies as st

from ncverify import InputError, Settings, check_file
from ncverify import check as check_module
from ncverify.api import iter_program_files
from ncverify.check import Checker, in_scope, rule_classes
from ncverify.context import Machine, RuleContext
from ncverify.dialect import DIALECTS
from test_corpus import PROGRAMS, settings_for
from tests.oracle_programs import DIALECTS as ORACLE_DIALECTS, cases, project_file, write

ROOT = Path(__file__).resolve().parents[1]
REALWORLD = ROOT.parent / "shared" / "corpus-realworld"
REALWORLD_PROGRAMS = [path for path, _explicit in iter_program_files([str(REALWORLD)], Settings())] if REALWORLD.is_dir() else []


def _report(program: Path, settings: Settings) -> dict | str:
    try:
        return check_file(program, settings).to_json()
    except InputError as error:
        return f"input error: {error}"


def _same_report_scoped_and_unscoped(program: Path, settings: Settings, monkeypatch) -> None:
    scoped = _report(program, settings)
    with monkeypatch.context() as unscoped:
        unscoped.setattr(check_module, "in_scope", lambda rule_class, dialect, machine: True)
        every_rule = _report(program, settings)
    assert scoped == every_rule, program


@pytest.mark.parametrize("program", PROGRAMS, ids=lambda path: str(path.relative_to(ROOT)))
def test_corpus_program_gives_the_same_report_with_rules_scoped(program, monkeypatch):
    _same_report_scoped_and_unscoped(program, settings_for(program), monkeypatch)


@pytest.mark.skipif(not REALWORLD_PROGRAMS, reason="the real-world corpus is not beside the repository")
@pytest.mark.parametrize("program", REALWORLD_PROGRAMS, ids=lambda path: str(path.relative_to(REALWORLD)))
def test_real_world_program_gives_the_same_report_with_rules_scoped(program, monkeypatch):
    _same_report_scoped_and_unscoped(program, Settings(), monkeypatch)


@hypothesis_settings(max_examples=20, deadline=None, suppress_health_check=[HealthCheck.too_slow, HealthCheck.data_too_large])
@given(dialect=st.sampled_from(ORACLE_DIALECTS), data=st.data())
def test_a_drawn_program_gives_the_same_report_with_rules_scoped(dialect, data):
    case = data.draw(cases(dialect))
    written = write(dialect, case)
    with tempfile.TemporaryDirectory() as folder, pytest.MonkeyPatch.context() as monkeypatch:
        for name, lines in written.files.items():
            (Path(folder) / name).write_text("\n".join(lines) + "\n")
        (Path(folder) / "ncverify.toml").write_text(project_file(case))
        main = Path(folder) / next(iter(written.files))
        _same_report_scoped_and_unscoped(main, Settings(dialect=dialect), monkeypatch)


def _rule_types(dialect: str | None, machine: str | None = None) -> set[str]:
    context = RuleContext(dialect=dialect, machine=Machine(kind=machine))
    return {type(instance).__name__ for instance in Checker(Settings(), context).rules}


def test_a_rule_is_scoped_to_the_dialect_its_ids_name():
    scopes = {cls.__name__: cls.dialects for cls in rule_classes()}
    assert scopes["UsableLength"] == frozenset({"heidenhain"})
    assert scopes["CycleArguments"] == frozenset({"sinumerik"})
    assert scopes["PocketToolFit"] == frozenset({"fagor"})
    assert scopes["RapidIntoStock"] is None  # core: every dialect
    assert all(in_scope(cls, None) for cls in rule_classes())


def test_the_checker_asks_only_the_rules_of_its_dialect():
    every = _rule_types(None)
    iso, klartext = _rule_types("iso"), _rule_types("heidenhain")
    assert {"UsableLength", "CycleArguments", "PocketToolFit"} <= every
    assert "RapidIntoStock" in iso and "RapidIntoStock" in klartext
    assert not {"UsableLength", "CycleArguments", "PocketToolFit"} & iso
    assert "UsableLength" in klartext and not {"CycleArguments", "PocketToolFit"} & klartext
    for dialect in DIALECTS:
        assert _rule_types(dialect) < every


def test_a_lathe_rule_is_asked_only_on_a_lathe():
    assert "LatheArcOver180" in _rule_types("iso", "lathe")
    assert "LatheArcOver180" in _rule_types("iso")  # machine type not known: every rule
    assert "LatheArcOver180" not in _rule_types("iso", "mill")
    assert "RapidIntoStock" in _rule_types("iso", "mill")
