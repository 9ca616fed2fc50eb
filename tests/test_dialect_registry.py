"""The one list of dialects feeds the command line, the project file and detection."""
from __future__ import annotations

import importlib
from pathlib import Path

import pytest

from ncverify.cli import build_parser
from ncverify.detect import _SIGNATURES
from ncverify.dialect import DIALECTS, MACHINES
from ncverify.project import ConfigError, load_project_text
from ncverify.resources import data_dir


def test_detection_scores_exactly_the_registered_dialects():
    assert set(_SIGNATURES) == set(DIALECTS)


def test_every_registered_dialect_has_tables_and_a_lowering():
    assert {folder.name for folder in data_dir("dialects").iterdir() if folder.is_dir()} == set(DIALECTS)
    for info in DIALECTS.values():
        assert callable(importlib.import_module(info.lowering).setup), info.id
        assert info.extensions and all(extension.startswith(".") for extension in info.extensions)
        assert set(info.machines) <= set(MACHINES)


def test_the_command_line_offers_the_registered_dialects_and_machines():
    parser = build_parser()
    assert parser.parse_args(["check", "x.nc", "--dialect", "fagor", "--machine", "lathe"]).dialect == "fagor"
    with pytest.raises(SystemExit):
        parser.parse_args(["check", "x.nc", "--dialect", "okuma"])


def test_the_project_file_refuses_a_dialect_that_is_not_registered():
    assert load_project_text('[settings]\ndialect = "sinumerik"\n', Path("ncverify.toml")).settings["dialect"] == "sinumerik"
    with pytest.raises(ConfigError, match="iso, heidenhain, sinumerik, fagor"):
        load_project_text('[settings]\ndialect = "okuma"\n', Path("ncverify.toml"))


def test_profiles_come_from_the_dialect_tables():
    assert "mitsubishi-e60" in DIALECTS["iso"].profiles() and DIALECTS["heidenhain"].profiles() == []
