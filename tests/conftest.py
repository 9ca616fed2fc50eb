"""Helpers the test modules share: run a program through the whole pipeline and pick the
findings a test asserts on."""
from __future__ import annotations

import os
import textwrap
from pathlib import Path

from hypothesis import settings as hypothesis_settings

from ncverify import Settings, check_text
from ncverify.diagnostics import Status
from ncverify.project import load_project_text

# CI runs the same examples every time (a fixed seed per test): a red build is then the
# change's doing, never the draw's; a developer's run keeps drawing new ones.
hypothesis_settings.register_profile("ci", derandomize=True, print_blob=True)
if os.environ.get("CI"):
    hypothesis_settings.load_profile("ci")


def project(text: str):
    """A project file's context from its text, or None for no text."""
    return load_project_text(text, Path("ncverify.toml")) if text else None


def check_program(program: str, name: str = "t.nc", project_text: str = "", **settings):
    """``check_text`` on an indented triple-quoted program, with optional project file text."""
    return check_text(textwrap.dedent(program).lstrip("\n"), name, Settings(**settings), project(project_text))


def findings(result, rule: str, status: Status | None = None) -> list:
    """The findings of one rule, of one status when given."""
    return [d for d in result.diagnostics if d.rule == rule and (status is None or d.status is status)]
