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


def test_generation_is_deterministic(tmp_path: Path) -> None:
    one, two = tmp_path / "a.xodr", tmp_path / "b.xodr"
    GENERATE.write_network(one, 40_000)
    GENERATE.write_network(two, 40_000)
    assert one.read_bytes() == two.read_bytes()
