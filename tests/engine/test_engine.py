"""Stage 5: rule selection, plugins through entry points, stamping and one defect one finding."""

from __future__ import annotations

import gc
import sys
import textwrap
import weakref
from collections.abc import Iterator
from importlib.metadata import EntryPoint
from pathlib import Path

import pytest

from tests.conftest import REPO
from xodrlint.document.load import Document
from xodrlint.engine.linter import Linter, LintOptions
from xodrlint.findings import Hit, Severity
from xodrlint.model import RailNetwork
from xodrlint.rules import rule
from xodrlint.rules.registry import Registry, load_registry
from xodrlint.rules.selection import SelectorError, select_rules

BUILTIN_POINT = EntryPoint("document", "xodrlint.rules.document", "xodrlint.rules")


def _codes(select: tuple[str, ...], ignore: tuple[str, ...] = ()) -> list[str]:
    return [r.code for r in select_rules(load_registry([BUILTIN_POINT]), select, ignore)]


def test_selection_longest_match_wins_and_ignore_wins_ties() -> None:
    every = [meta.code for meta in load_registry([BUILTIN_POINT]).metas]
    assert _codes(("ALL",)) == [code for code in every if code != "XL001"]  # XL001 is opt-in
    assert _codes(("XS",), ("XS00",)) == []
    assert _codes(("XS006",), ("XS",)) == ["XS006"]
    assert _codes(("XS",), ("XS",)) == []
    assert _codes(("xs005",)) == ["XS005"]
    assert _codes(("schema-violation",)) == ["XS006"]
    assert _codes(("asam.net:xodr:1.0.0:xml.valid_schema",)) == ["XS006"]


def test_unknown_selector_is_an_error() -> None:
    with pytest.raises(SelectorError, match="'SW999'"):
        _codes(("SW999",))


@pytest.fixture
def plugin_pack(tmp_path: Path, monkeypatch: pytest.MonkeyPatch) -> Iterator[str]:
    """A third-party rule pack on sys.path, as an installed plugin would be."""
    package = tmp_path / "acme_rules"
    package.mkdir()
    (package / "__init__.py").write_text('"""ACME rules."""\n')
    (package / "ac001.py").write_text(
        textwrap.dedent('''
        """AC001 station-too-many: a file has more than one station.

        ## What it does
        Counts stations.
        """
        from xodrlint.findings import Hit, Severity
        from xodrlint.rules import rule

        @rule(code="AC001", name="station-too-many", uid="acme:xodr:1.0.0:stations.one",
              severity=Severity.INFO)
        def too_many(network):
            for station in network.stations[1:]:
                yield Hit(station.element, f"station '{station.id}' is one too many")
        ''')
    )
    monkeypatch.syspath_prepend(str(tmp_path))
    yield "acme_rules"
    for name in [m for m in sys.modules if m.startswith("acme_rules")]:
        del sys.modules[name]


def test_a_plugin_pack_registers_like_the_builtin_ones(plugin_pack: str, tmp_path: Path) -> None:
    registry = load_registry([BUILTIN_POINT, EntryPoint("acme", plugin_pack, "xodrlint.rules")])
    assert "AC001" in registry.by_code and registry.warnings == ()
    assert registry.by_code["AC001"].meta.summary == "a file has more than one station"
    target = tmp_path / "two.xodr"
    target.write_text(
        '<OpenDRIVE><header revMajor="1" revMinor="7"/>\n<station id="a" name="A"/>\n'
        '<station id="b" name="B"/>\n</OpenDRIVE>'
    )
    report = Linter(registry, LintOptions(select=("AC",))).lint_path(target)
    assert [(f.code, f.line, f.severity, f.xpath) for f in report.findings] == [
        ("AC001", 3, Severity.INFO, "/OpenDRIVE/station[@id='b']")
    ]


def test_a_broken_plugin_is_a_warning_not_a_crash() -> None:
    registry = load_registry(
        [BUILTIN_POINT, EntryPoint("bad", "no_such_module_xyz", "xodrlint.rules")]
    )
    # the broken pack adds nothing and takes nothing away from the built-in one
    assert registry.rules == load_registry([BUILTIN_POINT]).rules
    assert registry.warnings and "'bad'" in registry.warnings[0]


def test_a_crashing_rule_is_an_internal_error_and_the_others_still_report(tmp_path: Path) -> None:
    @rule(code="ZZ001", name="always-crashes", uid="test:crash", severity=Severity.ERROR)
    def crashes(network: RailNetwork) -> Iterator[Hit]:
        raise RuntimeError("boom")
        yield  # pragma: no cover

    builtin = load_registry([BUILTIN_POINT])
    registry = Registry((*builtin.rules, crashes))
    target = tmp_path / "v.xodr"
    target.write_text('<OpenDRIVE><header revMajor="1" revMinor="12"/></OpenDRIVE>')
    report = Linter(registry).lint_path(target)
    assert [f.code for f in report.findings] == ["XS005"]
    assert report.internal_errors and "ZZ001" in report.internal_errors[0]


def test_a_specific_rule_silences_the_deferrable_schema_error_on_its_element(
    tmp_path: Path,
) -> None:
    @rule(code="ZZ002", name="partner-check", uid="test:partner", severity=Severity.ERROR)
    def partner_check(network: RailNetwork) -> Iterator[Hit]:
        for switch in network.switches:
            if switch.partner is not None:
                yield Hit(switch.partner.element, "specific finding")

    builtin = load_registry([BUILTIN_POINT])
    registry = Registry((*builtin.rules, partner_check))
    target = tmp_path / "p.xodr"
    target.write_text((REPO / "examples" / "clean.xodr").read_text())
    report = Linter(registry).lint_path(target)
    assert {f.code for f in report.findings} == {"ZZ002"}
    # the deferral only removes deferrable schema hits: a real XS006 stays
    broken = tmp_path / "b.xodr"
    broken.write_text((REPO / "examples" / "broken.xodr").read_text())
    codes = sorted(f.code for f in Linter(registry).lint_path(broken).findings)
    assert codes == ["XS006", "XS006", "XS006", "ZZ002", "ZZ002"]


def test_not_well_formed_files_run_nothing_else(tmp_path: Path) -> None:
    target = tmp_path / "t.xodr"
    target.write_text("<OpenDRIVE><header revMajor='1'")
    report = Linter(load_registry([BUILTIN_POINT])).lint_path(target)
    assert [(f.code, f.xpath, f.column is not None) for f in report.findings] == [
        ("XS001", "/", True)
    ]


def test_unreadable_path_is_a_report_error_not_a_finding(tmp_path: Path) -> None:
    report = Linter(load_registry([BUILTIN_POINT])).lint_path(tmp_path / "missing.xodr")
    assert report.findings == () and report.error is not None
    assert "no such file" in report.error.lower()


@pytest.mark.parametrize("keep", [False, True])
def test_a_linter_keeps_only_the_last_document_and_only_when_asked(
    monkeypatch: pytest.MonkeyPatch, keep: bool
) -> None:
    # a process that exits without cleanup (the CLI) never pays for freeing the last tree
    from xodrlint import model
    from xodrlint.document import load as document
    from xodrlint.engine import linter as engine

    loaded: list[weakref.ref[Document]] = []

    def load_bytes(data: bytes, path: str) -> Document:
        doc = real_load(data, path)
        loaded.append(weakref.ref(doc))
        return doc

    networks: list[RailNetwork] = []

    def build_network(root: object) -> RailNetwork:
        networks.append(real_build(root))  # type: ignore[arg-type]
        return networks[-1]

    real_load, real_build = document.load_bytes, model.build_network
    monkeypatch.setattr(engine, "load_bytes", load_bytes)
    monkeypatch.setattr(engine, "build_network", build_network)
    linter = Linter(load_registry(), keep_last_document=keep)
    for _ in range(2):
        linter.lint_path(REPO / "examples" / "clean.xodr")
    gc.collect()
    assert [ref() is not None for ref in loaded] == [False, keep]
    # the model too: freeing a large one costs as much as its tree
    kept = linter.last_document
    if keep:
        assert kept is not None
        assert kept.document is loaded[-1]() and kept.network is networks[-1]
    else:
        assert kept is None


def test_a_kept_document_with_a_fatal_problem_has_no_model() -> None:
    linter = Linter(load_registry(), keep_last_document=True)
    linter.lint_bytes(b"<OpenDRIVE><header", "broken.xodr")
    kept = linter.last_document
    assert kept is not None and kept.network is None


def test_warm_up_compiles_the_schema_the_header_asks_for_and_validates_nothing(
    monkeypatch: pytest.MonkeyPatch,
) -> None:
    from xodrlint.validation import libxml2 as schema

    def no_validation(*_: object) -> Iterator[Hit]:
        raise AssertionError("warm-up validated a document")

    monkeypatch.setattr(schema.Libxml2Validator, "hits", no_validation)
    monkeypatch.setattr(schema.BuiltinRailroadValidator, "hits", no_validation)
    linter = Linter(load_registry([BUILTIN_POINT]), LintOptions())
    linter.warm_up(REPO / "examples" / "clean.xodr")
    compiled = linter._validators._compiled
    assert len(compiled) == 1
    (validator,) = compiled.values()
    assert isinstance(validator, schema.Libxml2Validator | schema.BuiltinRailroadValidator)


@pytest.mark.parametrize("enabled", [True, False])
def test_the_collector_is_paused_while_a_document_is_linted(
    monkeypatch: pytest.MonkeyPatch, enabled: bool
) -> None:
    # a model is millions of young objects: collecting them as they are made cost
    # time growing with the square of the map
    from xodrlint import model
    from xodrlint.engine import linter as engine

    seen: list[bool] = []

    def build_network(root: object) -> RailNetwork:
        seen.append(gc.isenabled())
        return model.build_network(root)  # type: ignore[arg-type]

    monkeypatch.setattr(engine, "build_network", build_network)
    was = gc.isenabled()
    (gc.enable if enabled else gc.disable)()
    try:
        Linter(load_registry([BUILTIN_POINT])).lint_path(REPO / "examples" / "clean.xodr")
        assert seen == [False]
        assert gc.isenabled() is enabled  # as the caller left it
    finally:
        (gc.enable if was else gc.disable)()


@pytest.mark.parametrize("keep", [True, False])
def test_a_kept_document_is_frozen_out_of_the_collectors_sight(keep: bool) -> None:
    # the first collection after a lint walked every object it made: a process that
    # keeps the last document (the command line) moves them out of its sight instead
    was = gc.isenabled()
    gc.enable()
    gc.collect()
    gc.unfreeze()
    try:
        linter = Linter(load_registry([BUILTIN_POINT]), keep_last_document=keep)
        linter.lint_path(REPO / "examples" / "broken.xodr")
        assert (gc.get_freeze_count() > 0) is keep
        assert gc.isenabled()
    finally:
        gc.unfreeze()
        (gc.enable if was else gc.disable)()
