"""Helpers the Klartext run-time modules share (:mod:`.runtime`, :mod:`.special`): the
path's Klartext state, the working plane, cycle levels and the cycle's own feed."""
from __future__ import annotations

from ... import values


def put(state, **changes) -> None:
    """Change the path's Klartext state (a new value: a forked path keeps its own). Asked on
    every positioning block, mostly to set what is already set: then nothing is copied."""
    current = state.klartext
    for name, value in changes.items():
        if getattr(current, name) is not value:
            state.klartext = current.changed(changes)
            return


def plane(state):
    return state.plane_axes


def numbers(params: dict) -> dict:
    """The parameters rules compare: keyword values (FMAX, AUTO, PREDEF) and strings left out."""
    return {name: value for name, value in params.items() if not isinstance(value, str)}


def levels(params: dict, depth_name: str = "Q201"):
    """Set-up clearance level, bottom and retract level of a hole or pocket cycle, and the
    direction (reference A §6.0); None where a parameter is missing or not a number."""
    depth, surface, clearance = params.get(depth_name), params.get("Q203"), params.get("Q200")
    second = params.get("Q204", 0.0)
    if any(value is None or isinstance(value, str) for value in (depth, surface, clearance)):
        return None
    if isinstance(second, str):
        second = 0.0
    direction = 1.0 if type(depth) is float and depth > 0 else -1.0
    set_up = values.sub(surface, values.mul(direction, clearance))
    bottom = values.add(surface, depth)
    if type(second) is float and type(clearance) is float:
        retract_height = max(second, clearance)
    else:
        retract_height = second
    retract = values.sub(surface, values.mul(direction, retract_height))
    return set_up, bottom, retract, direction


def pitch_feed(state, pitch):
    speed = state.spindle_speed
    if speed is None:
        return values.fresh("S*Q239", 0.0)
    return values.absolute(values.mul(speed, pitch))


class cycle_feed:
    """The cycle cuts at its own feed (Q206, else Q207); the programmed feed is back after it."""

    def __init__(self, state, params):
        self.state = state
        feed = params.get("Q206", params.get("Q207"))
        if feed is None and "Q239" in params and not isinstance(params["Q239"], str):
            feed = pitch_feed(state, params["Q239"])  # rigid tapping: S x pitch (seed L3887-3898)
        self.feed = feed if feed is not None and not isinstance(feed, str) else (state.klartext.tool_feed if feed == "AUTO" else None)

    def __enter__(self):
        self.saved = self.state.feed
        if self.feed is not None:
            self.state.feed = self.feed

    def __exit__(self, *exc):
        self.state.feed = self.saved
        return False


def offset_surface(params: dict, shift, surface_offset) -> None:
    """CYCL CALL POS's tool-axis value and a pattern point's Z act on top of Q203."""
    for extra in (shift, surface_offset):
        if extra is not None and "Q203" in params and not isinstance(params["Q203"], str):
            params["Q203"] = values.add(params["Q203"], extra)
