"""Z3, imported on first use. Most programs are all numbers and never ask the solver, and
importing Z3 costs a plain check a sixth of its start-up time, so the modules that build
terms or ask the solver reach it through :data:`z3`, which imports it when one of its names
is first looked up (and then keeps that name)."""
from __future__ import annotations

import importlib


class _OnFirstUse:
    def __getattr__(self, name: str):
        value = getattr(importlib.import_module("z3"), name)
        setattr(self, name, value)
        return value


z3 = _OnFirstUse()
