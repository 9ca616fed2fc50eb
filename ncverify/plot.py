"""A picture of a program's toolpath with its findings (``ncverify plot``, ``check --plot``;
needs ``pip install "ncverify[plot]"``).

The program is checked as usual while a recording checker keeps the path: rapids dashed,
feeds solid, the stock outline, tool changes marked, each finding a numbered red marker at
its block. Two views: the plan (XY) and the side (XZ) on a mill, the ZX turning plane on a
lathe. Only the drawing is decimated (long streaks of moves keep every k-th point and
every change between rapid and feed), so a million-block program draws in seconds; the
check itself sees every block.
"""
from __future__ import annotations

import math
from bisect import bisect_right
from pathlib import Path

import numpy as np

from .api import InputError, check_source, project_for
from .check import Checker
from .diagnostics import Status
from .settings import Settings
from .source import ProgramSource

MAX_DRAWN_POINTS = 200_000
MAX_LISTED = 40  # findings listed under the picture
_AXES = ("X", "Y", "Z")
_RAPID, _FEED = 0, 1


class PlotError(Exception):
    """The picture cannot be made (matplotlib missing, an unknown file type)."""


class ToolpathRecorder:
    """The path as the interpreter produced it: arrays of points, the kind of move that
    ends at each point, and where each program line's move ended."""

    def __init__(self):
        self.chunks: list[tuple[np.ndarray, np.ndarray]] = []  # (points (n, 3), kinds (n,)) per move or run
        self.line_points: dict[int, tuple[float, float, float]] = {}  # where the first move of a line ends; a run's last line too
        self.runs: list[tuple[int, int, object, np.ndarray]] = []  # first line, last line, span(k), points
        self.tool_changes: list[tuple[int, str]] = []  # (number of points recorded so far, tool)
        self.points = 0
        self.checker: Checker | None = None

    def checker_class(self):
        recorder = self

        class RecordingChecker(Checker):
            def __init__(self, *arguments, **keywords):
                super().__init__(*arguments, **keywords)
                recorder.checker = self

            def segment(self, segment, state):
                if segment.span.path is None:
                    recorder.add_segment(segment)
                super().segment(segment, state)

            def motion_run(self, run, state):
                recorder.add_run(run)
                super().motion_run(run, state)

            def change(self, change, state):
                if change.what == "tool_change" and change.span.path is None:
                    recorder.tool_changes.append((recorder.points, _tool_name(change.new)))
                super().change(change, state)

        return RecordingChecker

    def add_segment(self, segment) -> None:
        start, end = _point(segment.start), _point(segment.end)
        points = _arc_points(segment, start, end) if segment.arc is not None else np.array([start, end])
        kind = _RAPID if segment.kind == "rapid" else _FEED
        kinds = np.full(len(points), kind, dtype=np.int8)
        kinds[0] = -1  # the start only joins the previous point; no move ends there
        self._add(points, kinds)
        self.line_points.setdefault(segment.span.line, tuple(end))

    def add_run(self, run) -> None:
        if run.arcs is not None:  # its straight stretches as runs, each arc drawn as one
            for start, stop, straight in run.pieces():
                if straight:
                    self.add_run(run.part(start, stop))
                else:
                    self.add_segment(run.segment(start))
            return
        columns = [run.axes.index(axis) if axis in run.axes else None for axis in _AXES]
        raw = np.asarray(run.points, dtype=float)
        points = np.column_stack([raw[:, c] if c is not None else np.full(len(raw), np.nan) for c in columns])
        kinds = np.concatenate([[-1], np.asarray(run.kinds, dtype=np.int8)])
        self._add(points, kinds)
        if len(run):
            last = run.span(len(run) - 1).line
            self.runs.append((run.span(0).line, last, run.span, points))
            self.line_points.setdefault(last, tuple(points[-1]))

    def _add(self, points: np.ndarray, kinds: np.ndarray) -> None:
        self.chunks.append((points, kinds))
        self.points += len(points)

    def point_of_line(self, line: int):
        """Where the move of ``line`` ends; for a block that does not move, where the
        tool was after the nearest earlier block that did (None before the first)."""
        if line in self.line_points:
            return self.line_points[line]
        for first, last, span, points in self.runs:
            if first <= line <= last:
                k = bisect_right(_LazyLines(span, len(points) - 1), line) - 1
                return tuple(points[k + 1]) if k >= 0 else None
        earlier = [known for known in self.line_points if known < line]
        return self.line_points[max(earlier)] if earlier else None

    def path(self) -> tuple[np.ndarray, np.ndarray]:
        if not self.chunks:
            return np.empty((0, 3)), np.empty(0, dtype=np.int8)
        return np.concatenate([c[0] for c in self.chunks]), np.concatenate([c[1] for c in self.chunks])


class _LazyLines:
    """``span(k).line`` as a sorted sequence for bisect, built only where it is probed."""

    def __init__(self, span, length: int):
        self.span, self.length = span, length

    def __len__(self):
        return self.length

    def __getitem__(self, k):
        return self.span(k).line


def _point(position: dict) -> list[float]:
    return [value if type(value) is float else math.nan for value in (position.get(axis) for axis in _AXES)]


def _tool_name(value) -> str:
    return f"T{value:g}" if isinstance(value, float) else str(value)


def _arc_points(segment, start, end) -> np.ndarray:
    """An arc as a polyline of up to 32 chords (a chord when its centre is not a number)."""
    arc = segment.arc
    first, second, _ = (axis.upper() for axis in arc.plane)
    if first not in _AXES or second not in _AXES:
        return np.array([start, end])
    i, j = _AXES.index(first), _AXES.index(second)
    centre = arc.centre if arc.centre is not None else _centre_from_radius(arc, (start[i], start[j]), (end[i], end[j]))
    if centre is None or any(type(c) is not float or not math.isfinite(c) for c in centre):
        return np.array([start, end])
    cx, cy = centre
    a0 = math.atan2(start[j] - cy, start[i] - cx)
    a1 = math.atan2(end[j] - cy, end[i] - cx)
    sweep = (a1 - a0) % (2 * math.pi)
    if arc.direction == "cw":
        sweep -= 2 * math.pi
    if sweep == 0:
        sweep = 2 * math.pi if arc.direction == "ccw" else -2 * math.pi
    radius = math.hypot(start[i] - cx, start[j] - cy)
    t = np.linspace(0.0, 1.0, 33)
    points = np.repeat([start], len(t), axis=0).astype(float)
    points[:, i] = cx + radius * np.cos(a0 + sweep * t)
    points[:, j] = cy + radius * np.sin(a0 + sweep * t)
    points[:, 3 - i - j] = start[3 - i - j] + (end[3 - i - j] - start[3 - i - j]) * t
    points[-1] = end
    return points


def _centre_from_radius(arc, start, end):
    """The centre of an arc given by R: on the chord's bisector, left of the chord for a
    counter-clockwise arc under 180 degrees, the other side for clockwise or R < 0."""
    radius = arc.radius_word
    if type(radius) is not float:
        return None
    dx, dy = end[0] - start[0], end[1] - start[1]
    chord = math.hypot(dx, dy)
    if not chord or not math.isfinite(chord) or chord > 2 * abs(radius) + 1e-9:
        return None
    offset = math.sqrt(max(radius * radius - chord * chord / 4, 0.0)) / chord
    side = (1.0 if arc.direction == "ccw" else -1.0) * (1.0 if radius > 0 else -1.0)
    return (start[0] + dx / 2 - side * offset * dy, start[1] + dy / 2 + side * offset * dx)


def decimate(points: np.ndarray, kinds: np.ndarray, limit: int = MAX_DRAWN_POINTS) -> tuple[np.ndarray, np.ndarray]:
    """At most about ``limit`` points: every k-th point, and always the first and last and
    each point where the kind of move changes (so no rapid is drawn as a feed)."""
    if len(points) <= limit:
        return points, kinds
    step = math.ceil(len(points) / limit)
    keep = np.zeros(len(points), dtype=bool)
    keep[::step] = True
    keep[[0, -1]] = True
    changes = np.flatnonzero(kinds[1:] != kinds[:-1])
    keep[changes] = True
    keep[changes + 1] = True
    return points[keep], kinds[keep]


def plot_program(program: Path, output: Path, settings: Settings | None = None) -> list:
    """Check ``program``, draw it into ``output`` (.svg or .png) and return the findings
    drawn. Raises :class:`InputError` for a file that cannot be read, :class:`PlotError`
    when the picture cannot be made."""
    if output.suffix.lower() not in (".svg", ".png"):
        raise PlotError(f"{output}: the picture must be .svg or .png")
    try:
        import matplotlib

        matplotlib.use("Agg")
        import matplotlib.pyplot as plt
    except ImportError:
        raise PlotError('plotting needs matplotlib: pip install "ncverify[plot]"') from None
    settings = settings or Settings()
    try:
        source = ProgramSource.open(program)
    except OSError as error:
        raise InputError(f"{program}: cannot read: {error.strerror or error}") from error
    recorder = ToolpathRecorder()
    result = check_source(source, settings, project_for(program, settings), checker_class=recorder.checker_class())
    if result.skipped:
        raise PlotError(f"{program}: not a program ncverify reads: {result.skipped}")
    findings = [d for d in result.diagnostics if d.status is Status.VIOLATED and d.span.path is None]
    lathe = result.machine == "lathe"
    views = [("Z", "X")] if lathe else [("X", "Y"), ("X", "Z")]
    figure, axes_list = plt.subplots(1, len(views), figsize=(7 * len(views), 6.5), squeeze=False)
    full_points, full_kinds = recorder.path()
    tools = [(full_points[count:], tool) for count, tool in recorder.tool_changes]
    points, kinds = decimate(full_points, full_kinds)
    stock = recorder.checker.context.stock if recorder.checker is not None else None
    for axes, (horizontal, vertical) in zip(axes_list[0], views):
        _draw_view(axes, points, kinds, horizontal, vertical, stock, tools, recorder, findings)
    figure.suptitle(f"{program.name}: {len(findings)} finding(s), {result.blocks:,} blocks", fontsize=12)
    handles, labels = axes_list[0][0].get_legend_handles_labels()
    if handles:
        figure.legend(handles, labels, loc="upper center", bbox_to_anchor=(0.5, 0.93), ncol=min(len(handles), 5), fontsize=8, frameon=False)
    listed = findings[:MAX_LISTED]
    lines = [f"{number}  line {d.span.line}  {d.rule}" for number, d in enumerate(listed, 1)]
    if len(findings) > len(listed):
        lines.append(f"... and {len(findings) - len(listed)} more")
    rows = math.ceil(len(lines) / 2) if lines else 0
    for column in range(2):
        figure.text(0.03 + 0.5 * column, 0.01, "\n".join(lines[column * rows:(column + 1) * rows]), fontsize=8, color="red",
                    va="bottom", family="monospace")
    figure.set_size_inches(figure.get_size_inches()[0], 6.5 + 0.16 * rows)
    figure.tight_layout(rect=(0, (0.16 * rows + 0.2) / (6.5 + 0.16 * rows), 1, 0.9))
    output.parent.mkdir(parents=True, exist_ok=True)
    figure.savefig(output, dpi=120)
    plt.close(figure)
    return findings


def _draw_view(axes, points, kinds, horizontal, vertical, stock, tools, recorder, findings) -> None:
    h, v = _AXES.index(horizontal), _AXES.index(vertical)
    plane = points[:, [h, v]]
    for kind, style, colour, label in ((_FEED, "-", "tab:blue", "cutting move"), (_RAPID, "--", "tab:orange", "rapid")):
        line = _polyline(plane, kinds[1:] == kind)
        axes.plot(line[:, 0], line[:, 1], linestyle=style, color=colour, linewidth=1.0, label=label, zorder=2)
    _draw_stock(axes, stock, horizontal, vertical)
    labelled = False
    for after, tool in tools:  # marked where the new tool first has a known position
        drawn = _first_finite(after, h, v)
        if drawn is not None:
            axes.plot(*drawn, marker="D", color="green", markersize=7, linestyle="none", label=None if labelled else "tool change")
            axes.annotate(tool, drawn, textcoords="offset points", xytext=(6, -10), fontsize=8, color="green")
            labelled = True
    markers: dict[tuple[float, float], list[int]] = {}
    for number, finding in enumerate(findings, 1):
        where = recorder.point_of_line(finding.span.line)
        if where is not None and math.isfinite(where[h]) and math.isfinite(where[v]):
            markers.setdefault((where[h], where[v]), []).append(number)
    for (x, y), numbers in markers.items():
        axes.plot(x, y, marker="o", color="red", markersize=13, linestyle="none", zorder=3,
                  label="finding (numbered as listed below)" if numbers[0] == min(min(n) for n in markers.values()) else None)
        axes.annotate(",".join(map(str, numbers)), (x, y), color="white", fontsize=7, ha="center", va="center", weight="bold", zorder=4)
    axes.autoscale()
    axes.set_aspect("equal", adjustable="datalim")
    axes.set_xlabel(horizontal)
    axes.set_ylabel(vertical)
    axes.set_title(f"{horizontal}{vertical} plane")
    axes.grid(True, linewidth=0.3)


def _polyline(plane: np.ndarray, chosen: np.ndarray) -> np.ndarray:
    """The chosen segments (segment k runs from point k to k + 1) as one line broken by
    NaN between streaks: one matplotlib path instead of one per segment."""
    indices = np.flatnonzero(chosen)
    if not len(indices):
        return np.empty((0, 2))
    pieces = []
    for streak in np.split(indices, np.flatnonzero(np.diff(indices) != 1) + 1):
        pieces += [plane[streak[0]:streak[-1] + 2], np.full((1, 2), np.nan)]
    return np.concatenate(pieces)


def _first_finite(points: np.ndarray, h: int, v: int):
    finite = np.flatnonzero(np.isfinite(points[:, h]) & np.isfinite(points[:, v]))
    return (points[finite[0], h], points[finite[0], v]) if len(finite) else None


def _draw_stock(axes, stock, horizontal, vertical) -> None:
    if stock is None:
        return
    ranges = {"Z": stock.z_range, "X": stock.x_range, "Y": stock.y_range}
    if stock.kind == "cylinder" and stock.diameter is not None:
        ranges["X"] = (0.0, stock.diameter / 2) if horizontal == "Z" else (-stock.diameter / 2, stock.diameter / 2)
        ranges["Y"] = (-stock.diameter / 2, stock.diameter / 2)
    if stock.outline is not None and (horizontal, vertical) == ("X", "Y"):
        x, y = stock.outline.exterior.xy
        axes.plot(x, y, color="grey", linewidth=1.2, label="stock", zorder=1)
        return
    first, second = ranges.get(horizontal), ranges.get(vertical)
    if first is None or second is None:
        return
    axes.plot([first[0], first[1], first[1], first[0], first[0]], [second[0], second[0], second[1], second[1], second[0]],
              color="grey", linewidth=1.2, label="stock", zorder=1)
