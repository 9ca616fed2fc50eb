"""Pipelines and program libraries: code scanning SARIF, GitLab Code Quality, JSON lines,
worker processes, the result cache, the progress bar, Dask, pre-commit and the plot."""
from __future__ import annotations

import io
import json
import os
import re
import shutil
import socket
import subprocess
import sys
import time
from pathlib import Path

import numpy as np
import pytest

from ncverify.batch import FileOutcome, local_dispatch, run_batch
from ncverify.cli import main
from ncverify.pool import WorkerFailure, run_in_workers
from ncverify.settings import Settings

ROOT = Path(__file__).resolve().parents[1]
SCHEMA = ROOT.parent / "shared" / "schemas" / "sarif-schema-2.1.0.json"
GOOD = "O1000\nG21 G90 G17\nT1 M6\nG43 H1 Z50.\nS1000 M3\nG0 X0. Y0.\nG1 X10. F100.\nG0 Z50.\nM30\n"
BAD = "N10 G21 G90\nN20 G01 X10. Y5.\nN30 M30\n"
MAIN_CALLING = "O1000\nG21 G90 G17\nT1 M6\nG43 H1 Z50.\nS1000 M3\nM98 P2000\nM30\n"
SUBPROGRAM = "O2000\nG01 X10. Y5.\nM99\n"


def run(capsys, *arguments) -> tuple[int, str, str]:
    code = main([str(argument) for argument in arguments])
    captured = capsys.readouterr()
    return code, captured.out, captured.err


@pytest.fixture(autouse=True)
def private_cache(tmp_path, monkeypatch):
    monkeypatch.setenv("XDG_CACHE_HOME", str(tmp_path / "user-cache"))
    monkeypatch.chdir(tmp_path)


def library(folder: Path, count: int = 6) -> Path:
    folder.mkdir(parents=True, exist_ok=True)
    for number in range(count):
        (folder / f"p{number}.nc").write_text(BAD if number % 2 else GOOD)
    return folder


# --------------------------------------------------------------------------- SARIF


def sarif(capsys, *arguments) -> dict:
    _, out, _ = run(capsys, "check", "--format", "sarif", *arguments)
    return json.loads(out)


def test_sarif_for_code_scanning_validates_and_has_what_github_reads(tmp_path, capsys):
    jsonschema = pytest.importorskip("jsonschema")
    Path("lib").mkdir()
    Path("lib/bad.nc").write_text(BAD)
    document = sarif(capsys, "lib/bad.nc")
    if SCHEMA.is_file():
        jsonschema.validate(document, json.loads(SCHEMA.read_text()))
    run_ = document["runs"][0]
    assert run_["automationDetails"]["id"] == "ncverify/"
    [feed] = [r for r in run_["results"] if r["ruleId"] == "core.feed-missing"]
    artifact = feed["locations"][0]["physicalLocation"]["artifactLocation"]
    assert artifact == {"uri": "lib/bad.nc", "uriBaseId": "SRCROOT"}
    assert run_["originalUriBaseIds"]["SRCROOT"]["uri"] == tmp_path.resolve().as_uri() + "/"
    assert feed["partialFingerprints"]["primaryLocationLineHash"].endswith(":1")
    rule = run_["tool"]["driver"]["rules"][feed["ruleIndex"]]
    assert rule["id"] == "core.feed-missing"
    assert rule["help"]["markdown"].startswith("## What it checks") and rule["help"]["text"]
    assert rule["shortDescription"]["text"] and rule["fullDescription"]["text"]
    assert rule["defaultConfiguration"]["level"] == "error" and "feed" in rule["properties"]["tags"]


def fingerprints(document) -> dict:
    return {(r["ruleId"], r["partialFingerprints"]["primaryLocationLineHash"]) for r in document["runs"][0]["results"]}


def test_fingerprints_survive_renumbering_and_edits_elsewhere(tmp_path, capsys):
    path = tmp_path / "bad.nc"
    path.write_text(BAD)
    before = fingerprints(sarif(capsys, path))
    path.write_text("(A NEW HEADER COMMENT)\nN100 G21 G90\nN200  G01 X10. Y5.\nN300 M30\n")
    after = fingerprints(sarif(capsys, path))
    assert before == after and before
    path.write_text("N10 G21 G90\nN20 G01 X12. Y5.\nN30 M30\n")  # the finding's own line changed
    assert fingerprints(sarif(capsys, path)) != before


def test_identical_lines_get_distinct_fingerprints(tmp_path):
    from ncverify.sarif import Fingerprints

    path = tmp_path / "twice.nc"
    path.write_text("G21 G90\nN10 G01 X10. Y5.\nG0 X0 Y0\nN20 G01 X10.  Y5.\nM30\n")
    hashes = Fingerprints()
    first, second = hashes.line_hash(str(path), "core.feed-missing", 2), hashes.line_hash(str(path), "core.feed-missing", 4)
    assert first.split(":")[0] == second.split(":")[0] and (first[-2:], second[-2:]) == (":1", ":2")


def test_proved_verdicts_are_uploaded_only_on_request(tmp_path, capsys):
    parametric = ROOT / "corpus" / "iso"
    program = next(p for p in sorted(parametric.glob("*.nc"))
                   if any(d["status"] == "proved" for d in json.loads(main_json(capsys, p))["files"][0]["diagnostics"]))
    statuses = {r["properties"]["status"] for r in sarif(capsys, program)["runs"][0]["results"]}
    assert "proved" not in statuses
    statuses = {r["properties"]["status"] for r in sarif(capsys, "--sarif-proved", program)["runs"][0]["results"]}
    assert "proved" in statuses


def main_json(capsys, path) -> str:
    _, out, _ = run(capsys, "check", "--format", "json", path)
    return out


def test_a_finding_in_a_subprogram_file_names_its_call_site(tmp_path, capsys):
    (tmp_path / "main.nc").write_text(MAIN_CALLING)
    (tmp_path / "O2000.nc").write_text(SUBPROGRAM)
    results = sarif(capsys, "main.nc")["runs"][0]["results"]
    [feed] = [r for r in results if r["ruleId"] == "core.feed-missing"]
    assert feed["locations"][0]["physicalLocation"]["artifactLocation"]["uri"] == "O2000.nc"
    [related] = feed["relatedLocations"]
    assert related["physicalLocation"]["artifactLocation"]["uri"] == "main.nc"
    assert related["physicalLocation"]["region"]["startLine"] == 6


def test_gitlab_code_quality_report(tmp_path, capsys):
    Path("bad.nc").write_text(BAD)
    code, out, _ = run(capsys, "check", "--format", "gitlab", "bad.nc")
    issues = json.loads(out)
    assert code == 1
    [feed] = [i for i in issues if i["check_name"] == "core.feed-missing"]
    assert feed["description"].startswith("core.feed-missing: ")
    assert feed["severity"] == "major" and feed["location"] == {"path": "bad.nc", "lines": {"begin": 2}}
    assert len({i["fingerprint"] for i in issues}) == len(issues)


# --------------------------------------------------------------------------- batches


def test_jobs_give_the_same_report_in_input_order(tmp_path, capsys):
    folder = ROOT / "corpus" / "iso"
    _, one, _ = run(capsys, "check", "--format", "json", "--no-cache", "--jobs", "1", folder)
    _, two, _ = run(capsys, "check", "--format", "json", "--no-cache", "--jobs", "2", folder)
    assert one == two
    paths = [entry["path"] for entry in json.loads(one)["files"]]
    assert paths == sorted(paths) and len(paths) > 5


def test_jsonl_writes_a_line_per_file_then_the_summary(tmp_path, capsys):
    library(tmp_path / "lib")
    (tmp_path / "lib" / "broken.nc").write_bytes(b"\x00\x01\x02" * 100)
    code, out, _ = run(capsys, "check", "--format", "jsonl", "--jobs", "2", "lib", "lib/gone.nc")
    lines = [json.loads(line) for line in out.splitlines()]
    assert code == 2
    assert len(lines) == 9 and lines[-1]["summary"]["files"] == 7
    assert {entry["path"] for entry in lines[:-1]} == {f"lib/p{n}.nc" for n in range(6)} | {"lib/broken.nc", "lib/gone.nc"}
    assert [entry for entry in lines if entry.get("path") == "lib/gone.nc"][0]["error"]


def fail_on_crash_file(task):
    path, _ = task
    if path.name == "crash.nc":
        os._exit(3)
    if path.name == "hang.nc":
        time.sleep(60)
    if path.name == "raise.nc":
        raise RuntimeError("boom")
    return path.name


def test_a_crashing_or_hanging_worker_costs_only_its_file():
    names = ["a.nc", "crash.nc", "b.nc", "hang.nc", "raise.nc", "c.nc"]
    tasks = [(Path(name), Settings()) for name in names]
    started = time.monotonic()
    values = dict(run_in_workers(fail_on_crash_file, tasks, jobs=2, timeout=3))
    assert time.monotonic() - started < 40
    assert [values[0], values[2], values[5]] == ["a.nc", "b.nc", "c.nc"]
    assert "stopped unexpectedly (exit code 3)" in values[1].reason
    assert "no result within 3 s" in values[3].reason
    assert isinstance(values[4], WorkerFailure) and "RuntimeError: boom" in values[4].reason


def test_a_failed_worker_is_an_input_error_and_the_batch_goes_on(tmp_path):
    folder = library(tmp_path / "lib", 3)
    (folder / "crash.nc").write_text(GOOD)

    def dispatch(tasks):
        for index, (path, settings) in enumerate(tasks):
            yield index, WorkerFailure("the worker process stopped unexpectedly (exit code -11)") if path.name == "crash.nc" else \
                local_dispatch(1)([(path, settings)]).__next__()[1]

    inputs = [(path, False) for path in sorted(folder.iterdir())]
    outcomes = run_batch(inputs, Settings(), dispatch, use_cache=False)
    assert [o.path for o in outcomes] == [str(p) for p, _ in inputs]
    [crashed] = [o for o in outcomes if o.error]
    assert crashed.path.endswith("crash.nc") and "exit code -11" in crashed.error
    assert sum(1 for o in outcomes if o.result is not None) == 3


# --------------------------------------------------------------------------- cache


def test_the_second_run_comes_from_the_cache_and_changes_invalidate_it(tmp_path):
    (tmp_path / "main.nc").write_text(MAIN_CALLING)
    (tmp_path / "O2000.nc").write_text(SUBPROGRAM)
    settings = Settings(cache_dir=tmp_path / "cache")
    inputs = [(tmp_path / "main.nc", True)]
    dispatch = local_dispatch(1)
    first = run_batch(inputs, settings, dispatch)[0]
    second = run_batch(inputs, settings, dispatch)[0]
    assert not first.cached and second.cached
    assert first.result.to_json() == second.result.to_json()
    (tmp_path / "O2000.nc").write_text(SUBPROGRAM.replace("G01 X10. Y5.", "G01 X10. Y5. F100."))
    third = run_batch(inputs, settings, dispatch)[0]
    assert not third.cached
    assert "core.feed-missing" not in {d.rule for d in third.result.diagnostics}
    assert not run_batch(inputs, settings, dispatch, use_cache=False)[0].cached


def test_a_subprogram_appearing_later_invalidates_the_entry(tmp_path):
    (tmp_path / "main.nc").write_text(MAIN_CALLING)
    settings = Settings(cache_dir=tmp_path / "cache")
    inputs = [(tmp_path / "main.nc", True)]
    first = run_batch(inputs, settings, local_dispatch(1))[0]
    assert "core.program-not-found" in {d.rule for d in first.result.diagnostics}
    (tmp_path / "O2000.nc").write_text(SUBPROGRAM)
    second = run_batch(inputs, settings, local_dispatch(1))[0]
    assert not second.cached and "core.program-not-found" not in {d.rule for d in second.result.diagnostics}


def test_a_broken_entry_is_ignored_and_rewritten(tmp_path):
    (tmp_path / "bad.nc").write_text(BAD)
    settings = Settings(cache_dir=tmp_path / "cache")
    inputs = [(tmp_path / "bad.nc", True)]
    expected = run_batch(inputs, settings, local_dispatch(1))[0].result.to_json()
    [entry] = list((tmp_path / "cache").rglob("*.json"))
    entry.write_text('{"key": "trunc')
    again = run_batch(inputs, settings, local_dispatch(1))[0]
    assert not again.cached and again.result.to_json() == expected
    assert json.loads(entry.read_text())["result"]
    assert run_batch(inputs, settings, local_dispatch(1))[0].cached


def test_a_batch_indexes_the_library_folder_once(tmp_path, monkeypatch):
    from ncverify.library import SubprogramLibrary

    builds = []
    original = SubprogramLibrary._build_index
    monkeypatch.setattr(SubprogramLibrary, "_build_index", lambda self: builds.append(1) or original(self))
    for number in range(3):
        (tmp_path / f"main{number}.nc").write_text(MAIN_CALLING)
    (tmp_path / "O2000.nc").write_text(SUBPROGRAM)
    inputs = [(path, False) for path in sorted(tmp_path.glob("main*.nc"))]
    outcomes = run_batch(inputs, Settings(), local_dispatch(1), use_cache=False)
    assert len(builds) == 1
    assert all("core.program-not-found" not in {d.rule for d in o.result.diagnostics} for o in outcomes)
    time.sleep(0.01)
    (tmp_path / "O3000.nc").write_text(SUBPROGRAM.replace("O2000", "O3000"))  # the folder changed: indexed again
    run_batch(inputs[:1], Settings(), local_dispatch(1), use_cache=False)
    assert len(builds) == 2


def test_cache_dir_from_the_project_file(tmp_path, capsys):
    (tmp_path / "ncverify.toml").write_text('[settings]\ncache_dir = "results"\n')
    (tmp_path / "bad.nc").write_text(BAD)
    run(capsys, "check", "bad.nc")
    assert list((tmp_path / "results").rglob("*.json"))


# --------------------------------------------------------------------------- progress


def test_no_progress_bar_when_not_a_terminal(tmp_path, capsys):
    library(tmp_path / "lib")
    _, _, err = run(capsys, "check", "--jobs", "1", "lib")
    assert "checking" not in err


def test_the_progress_bar_on_a_terminal():
    from rich.console import Console

    from ncverify.batch import FileOutcome
    from ncverify.progress import BatchProgress

    stream = io.StringIO()
    progress = BatchProgress(3, Console(file=stream, force_terminal=True, width=120), show_after_s=0)
    progress.advance(FileOutcome("a.nc", error="a.nc: cannot read"))
    progress.advance(FileOutcome("b.nc", error="b.nc: cannot read"))
    progress.close()
    assert "2/3" in stream.getvalue() and "2 failing" in stream.getvalue()


# --------------------------------------------------------------------------- Dask


def test_dask_local_cluster_gives_the_local_results(tmp_path, capsys):
    distributed = pytest.importorskip("distributed") if os.environ.get("CI") != "true" else __import__("distributed")
    folder = library(tmp_path / "lib")
    (folder / "main.nc").write_text(MAIN_CALLING)
    (folder / "O2000.nc").write_text(SUBPROGRAM)
    _, local, _ = run(capsys, "check", "--format", "json", "--no-cache", "--jobs", "1", folder)
    with distributed.LocalCluster(n_workers=2, threads_per_worker=1, processes=True, dashboard_address=None) as cluster:
        _, remote, _ = run(capsys, "check", "--format", "json", "--no-cache", "--dask", cluster.scheduler_address, folder)
        with distributed.Client(cluster) as client:
            import dask.bag

            from ncverify.cluster import check_bag

            paths = [str(folder / name) for name in ("main.nc", "p1.nc")]
            outcomes = check_bag(dask.bag.from_sequence(paths, npartitions=2)).compute(scheduler=client.get)
    assert local == remote
    assert "O2000.nc" in json.dumps(json.loads(local))  # the subprogram's finding, found through the library
    assert [o.path for o in outcomes] == paths and all(isinstance(o, FileOutcome) and o.result for o in outcomes)


def test_an_unreachable_scheduler_is_a_clear_error(tmp_path, capsys):
    if os.environ.get("CI") != "true":
        pytest.importorskip("distributed")
    from ncverify.cluster import ClusterError, connect

    with socket.socket() as probe:
        probe.bind(("127.0.0.1", 0))
        port = probe.getsockname()[1]
    started = time.monotonic()
    with pytest.raises(ClusterError, match="cannot reach the Dask scheduler"):
        connect(f"tcp://127.0.0.1:{port}", timeout_s=2)
    assert time.monotonic() - started < 20


# --------------------------------------------------------------------------- pre-commit


def test_pre_commit_hook_passes_a_good_program_and_fails_a_bad_one(tmp_path):
    if shutil.which("git") is None:
        pytest.skip("no git")
    repository = tmp_path / "programs"
    repository.mkdir()
    (repository / "good.nc").write_text(GOOD)
    (repository / "bad.nc").write_text(BAD)
    (repository / "notes.md").write_text("not a program\n")
    environment = dict(os.environ, PRE_COMMIT_HOME=str(tmp_path / "pre-commit-home"), GIT_AUTHOR_NAME="t", GIT_AUTHOR_EMAIL="t@t",
                       GIT_COMMITTER_NAME="t", GIT_COMMITTER_EMAIL="t@t")
    for command in (["git", "init", "-q"], ["git", "add", "."]):
        subprocess.run(command, cwd=repository, check=True, env=environment)

    hook = subprocess.run([sys.executable, "-m", "pre_commit", "try-repo", str(ROOT), "ncverify", "--files", "good.nc", "bad.nc", "notes.md"],
                          cwd=repository, env=environment, capture_output=True, text=True, timeout=900)
    assert hook.returncode == 1, hook.stdout + hook.stderr
    assert re.search(r"^bad\.nc:2:\d+: error core\.feed-missing", hook.stdout, re.MULTILINE), hook.stdout
    assert "good.nc:" not in hook.stdout.replace("good.nc: note", "")  # the good program has no finding
    assert "notes.md" not in hook.stdout  # not a program extension: not handed to the hook


# --------------------------------------------------------------------------- plot


def test_plot_draws_the_toolpath_and_the_findings(tmp_path, capsys):
    if os.environ.get("CI") != "true":
        pytest.importorskip("matplotlib")
    code, _, err = run(capsys, "plot", ROOT / "corpus" / "iso" / "quickstart-bracket.nc", "-o", "bracket.svg")
    assert code == 0, err
    picture = Path("bracket.svg").read_text()
    assert "quickstart-bracket.nc" in picture and "1  line 14  core.comp-on-arc" in picture
    for label in ("cutting move", "rapid", "stock", "tool change", "finding (numbered as listed below)"):
        assert label in picture


def test_check_plots_every_failing_file(tmp_path, capsys):
    if os.environ.get("CI") != "true":
        pytest.importorskip("matplotlib")
    library(tmp_path / "lib", 4)
    run(capsys, "check", "--jobs", "1", "--plot", "pictures", "lib")
    assert sorted(p.name for p in Path("pictures").iterdir()) == ["lib__p1.nc.svg", "lib__p3.nc.svg"]


def test_plot_refuses_an_unknown_picture_type(tmp_path, capsys):
    code, _, err = run(capsys, "plot", ROOT / "corpus" / "iso" / "quickstart-bracket.nc", "-o", "out.gif")
    assert code == 2 and ".svg or .png" in err


def test_decimation_bounds_the_points_and_keeps_every_change_of_move():
    from ncverify.plot import decimate

    kinds = np.ones(1_000_001, dtype=np.int8)
    kinds[[10, 500_000, 999_999]] = 0
    points = np.random.default_rng(1).random((len(kinds), 3))
    drawn, drawn_kinds = decimate(points, kinds, limit=50_000)
    assert len(drawn) < 60_000 and (drawn_kinds == 0).sum() == 3


def test_plotting_a_long_program_takes_seconds(tmp_path):
    if os.environ.get("CI") != "true":
        pytest.importorskip("matplotlib")
    sys.path.insert(0, str(ROOT / "benchmarks"))
    from generate import write_program

    from ncverify.plot import plot_program

    write_program(200_000, tmp_path / "long.nc")
    started = time.monotonic()
    plot_program(tmp_path / "long.nc", tmp_path / "long.png")
    assert time.monotonic() - started < 60
    assert (tmp_path / "long.png").stat().st_size > 10_000
