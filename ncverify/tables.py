"""Dialect tables (``dialects/<family>/*.toml``) loaded into lookups the lowering uses."""
from __future__ import annotations

import math
from dataclasses import dataclass
from functools import cache

from .cycle_models import load_cycle_table
from .resources import data_dir, read_table


@dataclass(frozen=True)
class CodeTable:
    """G/M codes, address-letter classes and power-on modes of one profile and machine."""

    profile: str
    machine: str
    g: dict[str, dict]
    m: dict[str, dict]
    words: dict
    power_on: dict[str, str]
    settings: dict
    cycles: dict[str, dict]

    def g_code(self, number: float) -> dict | None:
        return self.g.get(code_key(number))

    def m_code(self, number: float) -> dict | None:
        return self.m.get(code_key(number))


def code_key(number: float) -> str:
    """``1.0`` -> ``"1"``, ``54.1`` -> ``"54.1"``: the key form the tables use."""
    if not math.isfinite(number):
        return str(number)  # "inf", "nan": in no table, so an unknown code, never a crash
    whole = int(number)
    return str(whole) if number == whole else f"{number:g}"


def _load(family: str, name: str) -> dict:
    return read_table(data_dir("dialects") / family / name)


@cache
def iso_table(profile: str = "mitsubishi-e60", machine: str = "mill") -> CodeTable:
    mill = _load("iso", "mill.toml")
    profiles = _load("iso", "profiles.toml")
    if profile not in profiles:
        raise KeyError(f"unknown ISO profile {profile!r}; known: {', '.join(sorted(profiles))}")
    profile_data = profiles[profile]
    g = dict(mill["g"])
    m = dict(mill["m"])
    words = dict(mill["words"])
    power_on = dict(mill["power_on"])
    if machine == "lathe":
        lathe = _load("iso", "lathe.toml")
        _overlay(g, lathe.get("g", {}), lathe.get("remove_g", []))
        words.update(lathe["words"])
        power_on.update(lathe["power_on"])
    machine_overrides = profile_data.get(machine, {})
    _overlay(g, machine_overrides.get("g", {}), machine_overrides.get("remove_g", []))
    m.update(profile_data.get("m", {}))
    settings = {key: value for key, value in profile_data.items() if not isinstance(value, dict)}
    cycles = load_cycle_table("iso")
    return CodeTable(profile, machine, g, m, words, power_on, settings, cycles)


def _overlay(codes: dict, additions: dict, removals: list) -> None:
    for key in removals:
        codes.pop(key, None)
    codes.update(additions)
