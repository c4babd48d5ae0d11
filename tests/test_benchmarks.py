"""The benchmark's networks: deterministic, and clean by construction in every version."""

from __future__ import annotations

import importlib.util
import sys
from pathlib import Path
from types import ModuleType

import pytest

from xodrlint.api import default_registry
from xodrlint.engine import Linter, LintOptions

from .conftest import REPO, SHARED_SCHEMAS, needs_shared


def _generator() -> ModuleType:
    spec = importlib.util.spec_from_file_location("generate", REPO / "benchmarks" / "generate.py")
    assert spec is not None and spec.loader is not None
    module = importlib.util.module_from_spec(spec)
    sys.modules["generate"] = module
    spec.loader.exec_module(module)
    return module


GENERATE = _generator()


def _railway() -> ModuleType:
    spec = importlib.util.spec_from_file_location("railway", REPO / "benchmarks" / "railway.py")
    assert spec is not None and spec.loader is not None
    module = importlib.util.module_from_spec(spec)
    sys.modules["railway"] = module
    spec.loader.exec_module(module)
    return module


RAILWAY = _railway()


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
    from xodrlint.document import load_bytes
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


def test_each_ratio_is_the_median_of_its_rounds(capsys: pytest.CaptureFixture[str]) -> None:
    # the machine doubles its speed after two rounds: per-round ratios stay 1.5, while the
    # ratio of the medians would not
    run = _runner()
    names = [
        "xmllint 1.7", "xodrlint 1.7", "xodrlint 1.8", "xodrlint 1.7 x2",
        "python imports", "xodrlint 0.2 MB", "batch -j 1", "batch -j 2", "1.7 no geometry",
    ]  # fmt: skip
    commands = [run.Command(name, []) for name in names]
    for command in commands:
        base = 3.0 if command.name in ("xodrlint 1.8", "xodrlint 0.2 MB", "batch -j 1") else 2.0
        command.seconds = [base, base, base / 2, base / 2, base / 2]
        command.peak_kb = [100, 100, 100, 100, 100]
    figures = run.report(commands)
    assert figures["R2"] == figures["R3"] == figures["B"] == 1.5
    assert figures["G"] == 1.0
    out = capsys.readouterr().out
    assert "R2    1.50   target <= 2.0   met" in out
    assert "G     1.00   target <= 1.05   met" in out
