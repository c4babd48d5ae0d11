"""Validation through libxml2's C API gives the findings lxml's error log gives, without
working out an XPath per error (which walks the siblings: quadratic in a large map)."""

from __future__ import annotations

import sys
from pathlib import Path

import pytest

from xodrlint.api import default_registry
from xodrlint.engine import Linter, LintOptions
from xodrlint.validation import libxml2, libxml2_direct

from .conftest import CORPUS_RAIL, REPO, SHARED, SHARED_SCHEMAS, needs_shared
from .test_benchmarks import RAILWAY

LARGE = SHARED / "corpus" / "large"


def _findings(
    path: Path, *, direct: bool, monkeypatch: pytest.MonkeyPatch
) -> list[tuple[object, ...]]:
    with monkeypatch.context() as patch:
        if not direct:
            patch.setattr(libxml2, "direct_schema", lambda root: None)
        linter = Linter(default_registry(), LintOptions(schema=SHARED_SCHEMAS))
        report = linter.lint_path(path)
    return [(f.line, f.code, f.message, f.xpath) for f in report.findings]


def test_the_direct_route_runs_here() -> None:
    # CPython with lxml's PyPI wheel: if this fails, large maps with many schema errors
    # are quadratic again
    if sys.implementation.name != "cpython":
        pytest.skip("direct validation needs CPython")
    assert libxml2_direct._libxml2() is not None


def _cases() -> list[Path]:
    cases = sorted(CORPUS_RAIL.glob("*.xodr")) if CORPUS_RAIL.is_dir() else []
    cases += [LARGE / "CARLA_Town03.xodr", LARGE / "Atlatec_KA-Suedtangente.xodr"]
    cases += sorted((REPO / "rules" / "XS006").glob("*.xodr"))
    return cases


@needs_shared
@pytest.mark.parametrize("path", _cases(), ids=lambda p: p.name)
def test_same_findings_as_lxml(path: Path, monkeypatch: pytest.MonkeyPatch) -> None:
    direct = _findings(path, direct=True, monkeypatch=monkeypatch)
    assert direct == _findings(path, direct=False, monkeypatch=monkeypatch)


@needs_shared
@pytest.mark.parametrize("minor", [4, 5, 6, 7, 8])
def test_same_findings_on_a_broken_railway(
    tmp_path: Path, minor: int, monkeypatch: pytest.MonkeyPatch
) -> None:
    path = tmp_path / f"broken-1.{minor}.xodr"
    text = "".join(RAILWAY.railway(minor=minor, blocks=20, defects=True))
    # more defects of other kinds: an unknown attribute, a missing one, an element out of
    # place, a duplicate key, a dangling reference
    text = text.replace('<road name="track 11"', '<road name="track 11" colour="red"', 1)
    text = text.replace('junction="-1">\n    <link>', 'junction="-1">\n    <link/><link>', 1)
    text = text.replace('id="21" junction="-1"', 'id="1" junction="-1"', 1)
    text = text.replace('<mainTrack id="31"', '<mainTrack id="9999"', 1)
    text = text.replace('<segment roadId="1" ', "<segment ", 1)
    path.write_text(text)
    direct = _findings(path, direct=True, monkeypatch=monkeypatch)
    assert len(direct) >= 2 * 3 * 20
    assert direct == _findings(path, direct=False, monkeypatch=monkeypatch)
