"""Analysis settings. The same names serve the CLI flags and, later, ``ncverify.toml``'s
``[settings]`` table."""
from __future__ import annotations

from dataclasses import dataclass, field, replace
from pathlib import Path


@dataclass(frozen=True)
class Settings:
    """How a check runs: the command line's options and the project file's settings."""

    dialect: str | None = None  # None: detect from the text
    profile: str | None = None  # ISO profile; None: detect, else mitsubishi-e60
    machine: str | None = None  # "mill" / "lathe"; None: detect, else mill
    loop_bound: int = 10_000  # iterations of one loop, calls of one subprogram, jumps
    call_depth: int = 16  # nested subprogram / macro calls
    max_paths: int = 64  # paths explored when a branch depends on a free parameter
    least_input_increment: float | None = None  # None: the profile's value
    subprogram_path: tuple[Path, ...] = ()
    max_file_bytes: int = 1 << 30
    max_findings_per_rule: int = 200
    extensions: tuple[str, ...] = (
        ".nc", ".ngc", ".cnc", ".tap", ".gcode", ".iso", ".txt", ".mpf", ".spf",
        ".h", ".i", ".pim", ".pit", ".min", ".eia", ".din", ".ptp", ".mpr", "",
    )
    fail_on: str = "error"
    fail_on_unknown: bool = False
    disabled_rules: frozenset[str] = field(default_factory=frozenset)
    per_block_only: bool = False  # tests: run plain blocks one by one, to compare with batches
    loop_runner: bool = True  # tests: False runs every loop pass block by block (interpret/loop_runner.py)
    solver_timeout_s: float = 5.0  # per Z3 query
    file_timeout_s: float = 600.0  # wall clock for one file's analysis (ncverify.watchdog)
    file_memory_bytes: int = 8 << 30  # memory for one file's analysis
    rapid_path: str = "straight"  # or "dogleg": each axis moves on its own at rapid
    stock_resolution: float | None = None  # the stock as cut so far: None (default) cells from the smallest tool the program loads, > 0 these cells (mm), 0 off (the blank)
    stock_memory: int = 256 << 20  # bytes the in-process stock may take
    stock_out: Path | None = None  # write the cut workpiece here (.stl or .npz; {stem}: the program's name)
    air_cutting: bool = False  # judge every feed move against the stock before it, for the share that cut only air (sweeps every cut; see Workpiece._defer)
    config: Path | None = None  # the project file; None: ncverify.toml found upward
    record_values: bool = False  # editors: keep what each assignment computes, by line (FileResult.values)
    cache_dir: Path | None = None  # None: [settings] cache_dir of the project file, else the user cache folder
    explicit: frozenset[str] = frozenset()  # settings given on the command line: the project file does not override them

    def with_(self, **changes) -> "Settings":
        return replace(self, **changes)
