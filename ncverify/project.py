"""The project file ``ncverify.toml``: found upward from the program, or given with
``--config``. Unknown keys and bad values are errors that name the file and, where TOML
gives one, the line, else the key path (``[stock] box.x``); the CLI exits with code 2."""
from __future__ import annotations

import ast
import math
import re
from pathlib import Path

from .context import TOOL_KEYS, TOOL_RANGES, Assumption, canonical_tool_type, Context, Machine, Stock, Tool, tool_value_problem
from .diagnostics import CATEGORIES, Severity
from .dialect import DIALECTS, MACHINES

FILE_NAME = "ncverify.toml"
SETTINGS = {
    "loop_bound": int, "call_depth": int, "max_paths": int, "solver_timeout_s": float, "machine": str,
    "profile": str, "dialect": str, "subprogram_path": list, "rapid_path": str, "least_input_increment": float,
    "cache_dir": str,
    "stock_resolution": float, "air_cutting": bool,
}
_MAY_BE_ZERO = {"least_input_increment", "stock_resolution"}  # 0: whole units; 0: no in-process stock
_WORDS = {"stock_resolution": {"auto": None, "off": 0.0}}  # settings that take a word for a value
_CHOICES = {"machine": MACHINES, "rapid_path": ("straight", "dogleg"), "dialect": tuple(DIALECTS)}
_LARGEST = {"loop_bound": 100_000_000, "call_depth": 1000, "max_paths": 100_000}  # beyond these a bound no longer bounds the run
_AXES = ("x", "y", "z", "a", "b", "c", "u", "v", "w")


class ConfigError(ValueError):
    pass


def find_project_file(start: Path | None) -> Path | None:
    """``ncverify.toml`` in the program's folder or the nearest folder above it."""
    if start is None:
        return None
    folder = start.resolve().parent if start.is_file() or not start.exists() else start.resolve()
    for candidate in (folder, *folder.parents):
        path = candidate / FILE_NAME
        if path.exists():  # a folder of that name is reported, not passed over
            return path
    return None


def load_project(path: Path) -> Context:
    if path.is_dir():
        raise ConfigError(f"{path}: is a folder, not a project file")
    try:
        text = path.read_text(encoding="utf-8")
    except (OSError, UnicodeDecodeError) as error:
        raise ConfigError(f"{path}: cannot read: {error}") from error
    return load_project_text(text, path)


def load_project_text(text: str, path: Path) -> Context:
    """A project file's text (``path`` names it in errors and anchors relative folders)."""
    import tomllib  # here: a check without a project file does not load the parser

    try:
        data = tomllib.loads(text)
    except tomllib.TOMLDecodeError as error:
        raise ConfigError(f"{path}: {error}") from error
    except RecursionError:
        raise ConfigError(f"{path}: arrays or tables nested too deeply to read") from None
    return _Reader(path).context(data)


class _Reader:
    def __init__(self, path: Path):
        self.path = path

    def fail(self, where: str, message: str):
        raise ConfigError(f"{self.path}: {where}: {message}")

    def context(self, data: dict) -> Context:
        known = {"settings", "stock", "tools", "machine", "assume", "rules"}
        for key in data:
            if key not in known:
                self.fail(f"[{key}]", f"unknown table (known: {', '.join(sorted(known))})")
        context = Context(source=str(self.path))
        context.settings = self.settings(data.get("settings", {}))
        if "stock" in data:
            context.stock = self.stock(data["stock"])
        context.tools = {number: tool for number, tool in self.tools(data.get("tools", {}))}
        context.machine = self.machine(data.get("machine", {}))
        context.assumptions = self.assumptions(data.get("assume", {}))
        context.disabled, context.severity = self.rules(data.get("rules", {}))
        return context

    # -- tables
    def settings(self, table) -> dict:
        table = self.table(table, "[settings]")
        settings = {}
        for key, value in table.items():
            kind = SETTINGS.get(key)
            if kind is None:
                self.fail(f"[settings] {key}", f"unknown setting (known: {', '.join(sorted(SETTINGS))})")
            if kind is float and isinstance(value, int) and not isinstance(value, bool):
                value = float(value)
            if key in _WORDS and isinstance(value, str):
                if value not in _WORDS[key]:
                    self.fail(f"[settings] {key}", f"expected a number or one of {', '.join(_WORDS[key])}, got {value!r}")
                settings[key] = _WORDS[key][value]
                continue
            if not isinstance(value, kind) or (isinstance(value, bool) and kind is not bool):
                self.fail(f"[settings] {key}", f"expected a {kind.__name__}, got {value!r}")
            if key in _CHOICES and value not in _CHOICES[key]:
                self.fail(f"[settings] {key}", f"expected one of {', '.join(_CHOICES[key])}, got {value!r}")
            if kind in (int, float) and (value < 0 if key in _MAY_BE_ZERO else value <= 0):
                self.fail(f"[settings] {key}", f"must be positive, got {value!r}")
            if kind is float and not math.isfinite(value):
                self.fail(f"[settings] {key}", f"expected a finite number, got {value!r}")
            if value is not None and key in _LARGEST and value > _LARGEST[key]:
                self.fail(f"[settings] {key}", f"{value:,} is above the largest accepted value, {_LARGEST[key]:,}")
            if key == "subprogram_path":
                if not all(isinstance(item, str) for item in value):
                    self.fail(f"[settings] {key}", "expected a list of folder names")
                value = tuple((self.path.parent / item) for item in value)
            if key == "cache_dir":
                value = self.path.parent / value
            settings[key] = value
        return settings

    def stock(self, table) -> Stock:
        table = self.table(table, "[stock]")
        shapes = [key for key in table if key in ("box", "polygon", "cylinder")]
        unknown = [key for key in table if key not in ("box", "polygon", "cylinder")]
        if unknown:
            self.fail(f"[stock] {unknown[0]}", "unknown key (a stock is one of box, polygon, cylinder)")
        if len(shapes) != 1:
            self.fail("[stock]", "give exactly one of box, polygon, cylinder")
        shape = shapes[0]
        spec = self.table(table[shape], f"[stock] {shape}")
        try:
            if shape == "box":
                self.keys(spec, {"x", "y", "z"}, "[stock] box", required={"x", "y", "z"})
                return Stock.box(self.range(spec["x"], "[stock] box.x"), self.range(spec["y"], "[stock] box.y"), self.range(spec["z"], "[stock] box.z"))
            if shape == "cylinder":
                self.keys(spec, {"d", "diameter", "z"}, "[stock] cylinder", required={"z"})
                diameter = spec.get("d", spec.get("diameter"))
                return Stock.cylinder(self.number(diameter, "[stock] cylinder.d"), self.range(spec["z"], "[stock] cylinder.z"))
            self.keys(spec, {"points", "z"}, "[stock] polygon", required={"points", "z"})
            points = [self.pair(point, f"[stock] polygon.points[{index}]") for index, point in enumerate(spec["points"])]
            if len(points) < 3:
                self.fail("[stock] polygon.points", "a polygon needs at least three points")
            return Stock.polygon(points, self.range(spec["z"], "[stock] polygon.z"))
        except ValueError as error:
            if isinstance(error, ConfigError):
                raise
            self.fail(f"[stock] {shape}", str(error))

    def tools(self, table):
        table = self.table(table, "[tools]")
        for key, spec in table.items():
            where = f"[tools.{key}]"
            if not key.isdigit():
                self.fail(where, "tools are keyed by their number ([tools.1])")
            spec = self.table(spec, where)
            self.keys(spec, set(TOOL_KEYS) | {"type", "name"}, where)
            tool = Tool(int(key))
            for name, value in spec.items():
                if name == "type":
                    try:
                        tool.type = canonical_tool_type(str(value))
                    except ValueError as error:
                        self.fail(f"{where} type", str(error))
                elif name == "name":
                    tool.name = str(value)
                else:
                    number = self.number(value, f"{where} {name}", positive=name not in ("length", *TOOL_RANGES))
                    if problem := tool_value_problem(name, number):
                        self.fail(f"{where} {name}", problem)
                    setattr(tool, name, number)
            yield int(key), tool

    def machine(self, table) -> Machine:
        table = self.table(table, "[machine]")
        self.keys(table, {"travel", "work_offsets", "max_spindle", "max_feed", "type", "lathe_x", "spindle_encoder", "one_workpiece", "start", "remaps"}, "[machine]")
        machine = Machine()
        if "type" in table:
            if table["type"] not in ("mill", "lathe"):
                self.fail("[machine] type", "expected mill or lathe")
            machine.kind = table["type"]
        if "lathe_x" in table:
            if table["lathe_x"] not in ("diameter", "radius"):
                self.fail("[machine] lathe_x", "expected diameter or radius")
            machine.lathe_x = table["lathe_x"]
        if "spindle_encoder" in table:
            if not isinstance(table["spindle_encoder"], bool):
                self.fail("[machine] spindle_encoder", "expected true or false")
            machine.spindle_encoder = table["spindle_encoder"]
        if "one_workpiece" in table:
            names = table["one_workpiece"]
            if not isinstance(names, list) or not all(isinstance(name, str) for name in names):
                self.fail("[machine] one_workpiece", 'expected a list of work offsets, such as ["G54", "G55"]')
            machine.one_workpiece = frozenset(name.upper() for name in names)
        if "start" in table:
            machine.start = self.start(table["start"])
        if "remaps" in table:
            codes = table["remaps"]
            if not isinstance(codes, list) or not all(isinstance(code, str) for code in codes):
                self.fail("[machine] remaps", 'expected a list of the G codes the LinuxCNC configuration remaps, such as ["G68.2", "G69"]')
            machine.remaps = frozenset(code.strip().upper() for code in codes)
        travel = self.table(table.get("travel", {}), "[machine] travel")
        for axis, limits in travel.items():
            if axis.lower() not in _AXES:
                self.fail(f"[machine] travel.{axis}", "unknown axis")
            machine.travel[axis.upper()] = self.range(limits, f"[machine] travel.{axis}")
        offsets = self.table(table.get("work_offsets", {}), "[machine] work_offsets")
        for name, values in offsets.items():
            if not isinstance(values, list) or not values or not all(isinstance(v, (int, float)) and not isinstance(v, bool) for v in values):
                self.fail(f"[machine] work_offsets.{name}", "expected a list of numbers [x, y, z]")
            machine.work_offsets[name.upper()] = tuple(float(v) for v in values)
        for key in ("max_spindle", "max_feed"):
            if key in table:
                setattr(machine, key, self.number(table[key], f"[machine] {key}", positive=True))
        return machine

    def start(self, value) -> dict[str, float]:
        """``start = { x = 0, y = 0, z = 100 }`` (workpiece coordinates, any of the axes) or
        ``start = "unknown"``."""
        if value == "unknown":
            return {}
        if not isinstance(value, dict):
            self.fail("[machine] start", 'expected a table of axes ({ x = 0, y = 0, z = 100 }) or "unknown"')
        start = {}
        for axis, number in value.items():
            if axis.upper() not in ("X", "Y", "Z", "A", "B", "C"):
                self.fail(f"[machine] start.{axis}", "unknown axis")
            start[axis.upper()] = self.number(number, f"[machine] start.{axis}")
        return start

    def assumptions(self, table) -> list[Assumption]:
        table = self.table(table, "[assume]")
        found = []
        for name, value in table.items():
            where = f"[assume] {name!r}"
            if isinstance(value, list):
                low, high = self.range(value, where)
                text = f"{low:g} <= {name} <= {high:g}"
            elif isinstance(value, str):
                text = value
            else:
                self.fail(where, "expected [low, high] or a constraint as text")
            try:
                found.append(Assumption(text, parse_assumption(text), "project file"))
            except SyntaxError as error:
                self.fail(where, f"cannot read the constraint: {error.msg}")
        return found

    def rules(self, table):
        table = self.table(table, "[rules]")
        self.keys(table, {"disable", "severity"}, "[rules]")
        from .rule_pages import rule_definitions

        known = set(rule_definitions()) | CATEGORIES
        disabled = table.get("disable", [])
        if not isinstance(disabled, list):
            self.fail("[rules] disable", "expected a list of rule ids or categories")
        for name in disabled:
            if name not in known:
                self.fail("[rules] disable", f"no rule or category {name!r}")
        severity = self.table(table.get("severity", {}), "[rules] severity")
        for name, level in severity.items():
            if name not in known:
                self.fail(f"[rules] severity.{name}", "no rule or category of that name")
            if level not in {s.value for s in Severity}:
                self.fail(f"[rules] severity.{name}", "expected error, warning or info")
        return set(disabled), dict(severity)

    # -- values
    def table(self, value, where: str) -> dict:
        if not isinstance(value, dict):
            self.fail(where, "expected a table")
        return value

    def keys(self, table: dict, allowed: set, where: str, required: set = frozenset()) -> None:
        for key in table:
            if key not in allowed:
                self.fail(f"{where} {key}" if where.endswith("]") else f"{where}.{key}", f"unknown key (known: {', '.join(sorted(allowed))})")
        for key in required:
            if key not in table:
                self.fail(where, f"{key} is missing")

    def number(self, value, where: str, positive: bool = False) -> float:
        if isinstance(value, bool) or not isinstance(value, (int, float)) or not math.isfinite(value):
            self.fail(where, f"expected a finite number, got {value!r}")
        if positive and value <= 0:
            self.fail(where, f"must be positive, got {value!r}")
        return float(value)

    def range(self, value, where: str) -> tuple[float, float]:
        if not isinstance(value, list) or len(value) != 2:
            self.fail(where, f"expected [low, high], got {value!r}")
        low, high = (self.number(item, where) for item in value)
        if low >= high:
            self.fail(where, f"the low end {low:g} must be below the high end {high:g}")
        return low, high

    def pair(self, value, where: str) -> tuple[float, float]:
        if not isinstance(value, list) or len(value) != 2:
            self.fail(where, f"expected [x, y], got {value!r}")
        return tuple(self.number(item, where) for item in value)


# Parameter names in assumptions, made into Python identifiers for ``ast``: #1 -> __p_H_1.
_PARAMETER = re.compile(r"(#|QL|QR|Q|R|P)(\d+)")
_SAFE_PREFIX = {"#": "H", "QL": "QL", "QR": "QR", "Q": "Q", "R": "R", "P": "P"}
_PROGRAM_PREFIX = {safe: prefix for prefix, safe in _SAFE_PREFIX.items()}
_ALLOWED_NODES = (ast.Expression, ast.BoolOp, ast.And, ast.Compare, ast.BinOp, ast.UnaryOp, ast.Name, ast.Constant,
                  ast.Add, ast.Sub, ast.Mult, ast.Div, ast.USub, ast.UAdd, ast.Lt, ast.LtE, ast.Gt, ast.GtE, ast.Eq, ast.Load)


def parse_assumption(text: str) -> ast.Expression:
    """``-20 <= #1 <= -2 and #2 > 0``: ISO ``#n``, HEIDENHAIN ``Qn``, SINUMERIK ``Rn`` and Fagor
    ``Pn`` parameters; comparisons may chain; ``and`` joins them (any case)."""
    python = _PARAMETER.sub(lambda match: f"__p_{_SAFE_PREFIX[match.group(1)]}_{match.group(2)}", text)
    python = re.sub(r"(?i)\band\b", "and", python)
    tree = ast.parse(python, mode="eval")
    for node in ast.walk(tree):
        if not isinstance(node, _ALLOWED_NODES):
            raise SyntaxError(f"{type(node).__name__.lower()} is not allowed in an assumption")
        if isinstance(node, ast.Constant) and not _is_finite_number(node.value):
            raise SyntaxError(f"{ast.get_source_segment(python, node) or node.value!r} is not a finite number")
    return tree


def _is_finite_number(value) -> bool:
    try:
        return math.isfinite(float(value))
    except (OverflowError, TypeError, ValueError):
        return False


def parameter_name(identifier: str) -> str:
    """The program's own name of a parameter in a parsed assumption (``__p_H_1`` -> ``#1``)."""
    if not identifier.startswith("__p_"):
        return identifier
    prefix, _, number = identifier[4:].partition("_")
    return f"{_PROGRAM_PREFIX[prefix]}{number}"


def assumption_names(tree) -> set[str]:
    return {node.id for node in ast.walk(tree) if isinstance(node, ast.Name)}


def assumption_bounds(tree) -> dict[str, tuple[float, float]]:
    """Interval bounds an assumption states directly (``-20 <= #1 <= -2``, ``#2 > 0``)."""
    infinity = float("inf")

    def constant(node):
        if isinstance(node, ast.Constant) and isinstance(node.value, (int, float)):
            return float(node.value)
        if isinstance(node, ast.UnaryOp) and isinstance(node.op, ast.USub):
            inner = constant(node.operand)
            return None if inner is None else -inner
        return None

    bounds: dict[str, list[float]] = {}
    for compare in (node for node in ast.walk(tree) if isinstance(node, ast.Compare)):
        operands = [compare.left, *compare.comparators]
        for left, operator, right in zip(operands, compare.ops, operands[1:]):
            for name_node, value_node, flipped in ((left, right, False), (right, left, True)):
                value = constant(value_node)
                if not isinstance(name_node, ast.Name) or value is None:
                    continue
                low, high = bounds.setdefault(name_node.id, [-infinity, infinity])
                below = isinstance(operator, (ast.Lt, ast.LtE)) != flipped  # name below the value
                if isinstance(operator, ast.Eq):
                    bounds[name_node.id] = [max(low, value), min(high, value)]
                elif below:
                    bounds[name_node.id][1] = min(high, value)
                else:
                    bounds[name_node.id][0] = max(low, value)
    return {name: (low, high) for name, (low, high) in bounds.items()}
