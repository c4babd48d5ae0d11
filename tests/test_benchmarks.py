"""The benchmark's networks: deterministic, and clean by construction in every version."""

from __future__ import annotations

import importlib.util
import os
import sys
from pathlib import Path
from types import ModuleType

import pytest

from xodrlint.api import default_registry
from xodrlint.engine.linter import Linter, LintOptions

from .conftest import REPO, SHARED_SCHEMAS, needs_shared


def _benchmark_module(name: str) -> ModuleType:
    """A module of benchmarks/, registered under its own name (railway.py imports
    generate.py by that name)."""
    spec = importlib.util.spec_from_file_location(name, REPO / "benchmarks" / f"{name}.py")
    assert spec is not None and spec.loader is not None
    module = importlib.util.module_from_spec(spec)
    sys.modules[name] = module
    spec.loader.exec_module(module)
    return module


GENERATE = _benchmark_module("generate")
RAILWAY = _benchmark_module("railway")


@pytest.mark.parametrize("minor", [4, 7, 8])
def test_generated_networks_are_clean(tmp_path: Path, minor: int) -> None:
    path = tmp_path / f"n-1.{minor}.xodr"
    GENERATE.write_network(path, 60_000, minor)
    assert path.stat().st_size >= 60_000
    report = Linter(default_registry(), LintOptions()).lint_path(path)
    assert report.findings == (), [f.message for f in report.findings][:3]


@needs_shared
@pytest.mark.parametrize("minor", [4, 7])
def test_generated_networks_pass_the_official_schema(tmp_path: Path, minor: int) -> None:
    path = tmp_path / f"n-1.{minor}.xodr"
    GENERATE.write_network(path, 30_000, minor)
    report = Linter(default_registry(), LintOptions(schema=SHARED_SCHEMAS)).lint_path(path)
    assert report.findings == ()
    assert report.schema is not None and "built-in" not in report.schema


@pytest.mark.parametrize("minor", [4, 7, 8])
def test_the_railway_is_clean(tmp_path: Path, minor: int) -> None:
    path = tmp_path / f"railway-1.{minor}.xodr"
    GENERATE.write_pieces(path, RAILWAY.railway(minor=minor, blocks=70))
    report = Linter(default_registry(), LintOptions()).lint_path(path)
    assert report.findings == (), [f.message for f in report.findings][:3]


@needs_shared
@pytest.mark.parametrize("minor", [4, 7, 8])
def test_the_railway_passes_the_official_schema(tmp_path: Path, minor: int) -> None:
    path = tmp_path / f"railway-1.{minor}.xodr"
    GENERATE.write_pieces(path, RAILWAY.railway(minor=minor, blocks=70))
    report = Linter(default_registry(), LintOptions(schema=SHARED_SCHEMAS)).lint_path(path)
    assert report.findings == (), [f.message for f in report.findings][:3]
    assert report.schema is not None and "built-in" not in report.schema


def test_the_railway_is_rail_dense(tmp_path: Path) -> None:
    # every road a track: one rail lane each, linked to the next, a switch every 100-200 m
    from xodrlint.document.load import load_bytes
    from xodrlint.model import build_network

    path = tmp_path / "railway.xodr"
    GENERATE.write_pieces(path, RAILWAY.railway(minor=7, blocks=RAILWAY.BLOCKS_PER_CORRIDOR * 2))
    network = build_network(load_bytes(path.read_bytes(), "railway.xodr").root)
    assert network.roads and all(road.has_rail_lane for road in network.roads)
    assert all(len(section.rail_lanes) == 1 for r in network.roads for section in r.lane_sections)
    assert len(network.switches) == 3 * 2 * RAILWAY.BLOCKS_PER_CORRIDOR
    assert sum(bool(road.links) for road in network.roads) >= len(network.roads) // 2
    assert len(network.stations) >= 2 * (RAILWAY.BLOCKS_PER_CORRIDOR // 3) - 2


@needs_shared
def test_the_many_findings_railway_has_two_per_switch(tmp_path: Path) -> None:
    path = tmp_path / "findings.xodr"
    GENERATE.write_pieces(path, RAILWAY.railway(minor=7, blocks=40, defects=True))
    report = Linter(default_registry(), LintOptions(schema=SHARED_SCHEMAS)).lint_path(path)
    codes = [finding.code for finding in report.findings]
    assert codes.count("XS006") == codes.count("SW012") == 3 * 40
    assert len(codes) == 2 * 3 * 40


@needs_shared
def test_invalid_roads_fail_the_schema_once_each(tmp_path: Path) -> None:
    path = tmp_path / "roads.xodr"
    GENERATE.write_pieces(path, RAILWAY.invalid_roads(25))
    report = Linter(default_registry(), LintOptions(schema=SHARED_SCHEMAS)).lint_path(path)
    assert [(f.code, f.line) for f in report.findings] == [("XS006", 4 + n) for n in range(25)]


def test_generation_is_deterministic(tmp_path: Path) -> None:
    one, two = tmp_path / "a.xodr", tmp_path / "b.xodr"
    GENERATE.write_network(one, 40_000)
    GENERATE.write_network(two, 40_000)
    assert one.read_bytes() == two.read_bytes()


def _runner() -> ModuleType:
    sys.path.insert(0, str(REPO / "benchmarks"))
    try:
        spec = importlib.util.spec_from_file_location("bench_run", REPO / "benchmarks" / "run.py")
        assert spec is not None and spec.loader is not None
        module = importlib.util.module_from_spec(spec)
        sys.modules["bench_run"] = module  # dataclasses look their module up there
        spec.loader.exec_module(module)
        return module
    finally:
        sys.path.remove(str(REPO / "benchmarks"))


RUN = _runner()


def test_each_ratio_is_the_median_of_its_rounds(capsys: pytest.CaptureFixture[str]) -> None:
    # the machine doubles its speed after two rounds: per-round ratios stay 1.5, while the
    # ratio of the medians would not
    names = {name for pair in RUN.FIGURES.values() for name in pair[:2]}
    slower = {"xodrlint 1.8", "xodrlint 0.2 MB", "batch -j 1", "xodrlint rail 1.8"}
    commands = [RUN.Command(name, []) for name in sorted(names)]
    for command in commands:
        base = 3.0 if command.name in slower else 2.0
        command.seconds = [base, base, base / 2, base / 2, base / 2]
        command.peak_kb = [100, 100, 100, 100, 100]
    by = {command.name: command for command in commands}
    by["xodrlint rail 1.7"].peak_kb = [130, 130, 130, 130, 260]
    by["rail defects"].seconds = [5.0, 5.0, 2.5, 2.5, 2.5]
    # F2 is per finding: 8 times the findings in 10 times the time is 1.25 a finding
    by["findings ~40k"].seconds = [20.0, 20.0, 10.0, 10.0, 10.0]
    by["findings ~40k"].findings = 40_000
    by["findings ~5k"].findings = 5_000

    figures = RUN.report(commands)

    assert set(figures) == set(RUN.FIGURES) == set(RUN.TARGETS) - {"MR1 s", "MR1 GB"}
    assert figures["R2"] == figures["R3"] == figures["B"] == figures["R2r"] == 1.5
    assert figures["R1"] == figures["R1r"] == figures["G"] == figures["Mmix"] == 1.0
    assert figures["T"] == 1.0
    assert figures["M"] == 1.3
    assert figures["F"] == 2.5
    assert figures["F2"] == pytest.approx(1.25)
    out = capsys.readouterr().out
    assert "R2     1.50   target <= 1.2   MISSED" in out
    assert "R2r    1.50   target <= 1.35   MISSED" in out
    assert "R2r-R1r +0.50   target <= 0.05   MISSED" in out
    assert "M8r    1.00   target <= 1.3   met" in out
    assert "B      1.50   target >= 1.6   MISSED" in out
    assert "F      2.50   target <= 2.0   MISSED" in out
    assert "F2     1.25   target <= 1.3   met" in out
    assert "G      1.00   target <= 1.05   met" in out
    assert "40000" in out and "5000" in out  # the counted findings, in the table


def test_figures_leave_out_commands_that_did_not_run() -> None:
    commands = [
        RUN.Command(name, [], seconds=[3.0], peak_kb=[10])
        for name in ("xodrlint 1.7", "xmllint 1.7")
    ]
    assert RUN.figures(commands) == {"R1": 1.0, "Mmix": 1.0}


@pytest.mark.parametrize("only", ["all", "mixed", "rail", "findings", "dask"])
def test_the_commands_of_a_round(
    tmp_path: Path, monkeypatch: pytest.MonkeyPatch, only: str
) -> None:
    # the files are named, not written
    monkeypatch.setattr(RUN.Inputs, "file", lambda self, name, pieces: self.folder / name)
    monkeypatch.setattr(RUN.Inputs, "batch", lambda self: self.folder / "batch-200")
    monkeypatch.setattr(RUN.Inputs, "small_maps", lambda self: self.folder / "small-2000")
    tools = RUN.Tools(["xodrlint", "check"], ["xmllint", "--noout"], {})
    names = [command.name for command in RUN.commands(RUN.Inputs(tmp_path, 2.0), tools, only)]
    assert len(names) == len(set(names))  # a command shared by two groups runs once a round
    groups = {"mixed": ("R1", "R2", "R3", "Mmix", "S", "B", "G"), "rail": ("R1r", "R2r", "M", "T")}
    groups["findings"] = ("F", "F2")
    groups["dask"] = ("D",)
    wanted = [key for group, keys in groups.items() if only in ("all", group) for key in keys]
    for key in wanted:
        top, bottom, _ = RUN.FIGURES[key]
        assert top in names and bottom in names, key
    if only == "rail":
        assert "xodrlint 1.7" not in names and "rail defects" not in names


def test_findings_are_counted_from_the_json_report() -> None:
    script = "import json, sys; json.dump({'findings': [1, 2, 3]}, open(sys.argv[1], 'w'))"
    command = RUN.Command("counted", [sys.executable, "-c", script, os.devnull])
    assert RUN.count_findings(command) == 3


def test_a_run_past_its_time_limit_records_nothing() -> None:
    command = RUN.Command("slow", [sys.executable, "-c", "import time; time.sleep(30)"])
    assert command.run(timeout=0.3) is False
    assert command.seconds == [] and command.peak_kb == []
    assert RUN.roads_line(command, 0.3) == "MR1  slow: timed out after 0.3 s   MISSED"


def test_the_roads_line() -> None:
    command = RUN.Command(RUN._roads_name(1_000_000), [], seconds=[41.23], peak_kb=[1_953_125])
    assert RUN.roads_line(command, 900) == (
        "MR1  1M roads: 41.2 s, target <= 60 s; peak 2.00 GB, target <= 3 GB   met"
    )
    command.seconds = [61.0]
    assert RUN.roads_line(command, 900).endswith("MISSED")
    assert RUN._roads_name(20_000) == "20k roads" and RUN._roads_name(1234) == "1234 roads"


def test_the_dask_model_projects_from_the_measured_costs() -> None:
    found = RUN.cluster.Overhead(files=2001, tasks=50)
    found.wall, found.scheduler = [3.0, 3.2, 3.1], [0.5, 0.5, 0.6]
    found.client, found.workers = [0.9, 0.9, 0.9], [4.0, 4.0, 4.2]
    found.one_client, found.one_wall = [0.5, 0.5, 0.5], [1.0, 1.2, 1.1]
    lines = RUN.cluster.model(found, 2)
    # the client's start-up is its run on one file: 0.4 s more for 2,000 more files
    assert lines[0].startswith("per file: workers 2.00 ms CPU, client 0.200 ms")
    assert "scheduler 0.250 ms (10.0 ms a task, 50 tasks for 2001 files)" in lines[0]
    assert lines[0].endswith("run wall 3.10 s, on one file 1.10 s")
    one, *_, most = lines[2:]
    # one machine: 1,000,000 files at 2 ms over 2 cores, 1,000 s, and 1.1 s of start-up
    assert one == "     1 machines:      999 files/s (1,001 s, 15,660 tasks; bound by the workers)"
    # 512 workers: 25,306 tasks of at most 64 files, 253 s at 10 ms, above the client's 200 s
    assert most == "   256 machines:    3,935 files/s (254 s, 25,306 tasks; bound by the scheduler)"


def test_commands_run_with_bytecode_caches_as_users_have_them(
    monkeypatch: pytest.MonkeyPatch,
) -> None:
    monkeypatch.setenv("PYTHONDONTWRITEBYTECODE", "1")
    env = RUN.command_env({"XODRLINT_SCHEMA_PATH": "x"})
    assert "PYTHONDONTWRITEBYTECODE" not in env
    assert env["XODRLINT_SCHEMA_PATH"] == "x"
    tools = RUN.Tools(["xodrlint"], ["/bin/true"], {})
    assert "without PYTHONDONTWRITEBYTECODE" in RUN.machine(tools)
