"""Validation through libxml2's C API gives the findings lxml's error log gives, without
working out an XPath per error (which walks the siblings: quadratic in a large map)."""

from __future__ import annotations

import sys
from pathlib import Path

import pytest

from tests.conftest import CORPUS_RAIL, REPO, SHARED, SHARED_SCHEMAS, needs_shared
from tests.test_benchmarks import RAILWAY
from xodrlint.api import default_registry
from xodrlint.engine.linter import Linter, LintOptions
from xodrlint.validation import libxml2, libxml2_direct

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


@needs_shared
def test_a_run_with_the_official_schema_takes_the_direct_route(
    monkeypatch: pytest.MonkeyPatch,
) -> None:
    # which route a run took: a future lxml whose structures fail the self-check would
    # validate through lxml again, right but quadratic in the errors, and say nothing
    if sys.implementation.name != "cpython":
        pytest.skip("direct validation needs CPython")
    routes: list[bool] = []
    real = libxml2.Libxml2Validator._validate

    def recorded(self: libxml2.Libxml2Validator, tree: object) -> object:
        routes.append(self._direct is not None)
        return real(self, tree)  # type: ignore[arg-type]

    monkeypatch.setattr(libxml2.Libxml2Validator, "_validate", recorded)
    linter = Linter(default_registry(), LintOptions(schema=SHARED_SCHEMAS, select=("XS",)))
    linter.lint_path(REPO / "examples" / "broken.xodr")
    assert routes == [True]


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


@needs_shared
def test_a_schema_is_freed_with_its_validator(monkeypatch: pytest.MonkeyPatch) -> None:
    # an API caller's linters come and go with their options: each compile is 1.5 MB
    import gc

    from lxml import etree

    freed: list[tuple[int | None, int | None]] = []
    real = libxml2_direct._free

    def recorded(library: object, schema: int | None, copy: int | None) -> None:
        freed.append((schema, copy))
        real(library, schema, copy)  # type: ignore[arg-type]

    monkeypatch.setattr(libxml2_direct, "_free", recorded)
    entry = etree.parse(str(SHARED_SCHEMAS / "1.7.0" / "opendrive_17_core.xsd"))
    schema = libxml2_direct.direct_schema(entry.getroot())
    assert schema is not None
    broken = etree.fromstring(
        b"<xs:schema xmlns:xs='http://www.w3.org/2001/XMLSchema'><xs:element/></xs:schema>"
    )
    assert libxml2_direct.direct_schema(broken) is None  # its copy is freed too
    del schema
    gc.collect()
    assert len(freed) == 2
    assert all(copy for _, copy in freed) and freed[0][0] is None and freed[1][0]


def test_a_validation_without_a_verdict_is_an_error(monkeypatch: pytest.MonkeyPatch) -> None:
    # libxml2 answers -1 (an internal error) with no error reported: not a valid document
    from lxml import etree

    library = libxml2_direct._libxml2()
    if library is None:
        pytest.skip("direct validation does not run here")
    schema = libxml2_direct.direct_schema(
        etree.fromstring(
            b"<xs:schema xmlns:xs='http://www.w3.org/2001/XMLSchema'>"
            b"<xs:element name='a'/></xs:schema>"
        )
    )
    assert schema is not None
    assert schema.validate(etree.ElementTree(etree.fromstring(b"<a/>"))) == []
    real = library.xmlSchemaValidateDoc
    monkeypatch.setattr(library, "xmlSchemaValidateDoc", lambda context, doc: -1)
    with pytest.raises(RuntimeError, match="could not validate"):
        schema.validate(etree.ElementTree(etree.fromstring(b"<a/>")))
    monkeypatch.setattr(library, "xmlSchemaValidateDoc", real)


_EXIT_WHILE_VALIDATING = """
import sys, threading, time
sys.path.insert(0, sys.argv[2])
from lxml import etree
from railway import railway
from xodrlint.validation import libxml2_direct

schema = libxml2_direct.direct_schema(etree.parse(sys.argv[1]).getroot())
assert schema is not None
tree = etree.fromstring("".join(railway(8 * 1024 * 1024, 7)).encode()).getroottree()
started = threading.Event()

def validate(schema=schema, tree=tree):  # held by the thread, as concurrency.background does
    started.set()
    schema.validate(tree)

threading.Thread(target=validate, daemon=True).start()
started.wait()
time.sleep(0.05)
sys.exit(0)  # while libxml2 still validates with the schema
"""


@needs_shared
def test_exiting_while_a_validation_runs_does_not_free_its_schema(tmp_path: Path) -> None:
    # weakref.finalize ran at exit and freed the schema under the daemon validation thread:
    # SIGSEGV in 7 of 10 runs (issue 29)
    import subprocess

    script = tmp_path / "exit_while_validating.py"
    script.write_text(_EXIT_WHILE_VALIDATING, encoding="utf-8")
    core = SHARED_SCHEMAS / "1.7.0" / "opendrive_17_core.xsd"
    for _ in range(3):
        done = subprocess.run(
            [sys.executable, str(script), str(core), str(REPO / "benchmarks")],
            capture_output=True,
            text=True,
            timeout=120,
            check=False,
        )
        assert done.returncode == 0, (done.returncode, done.stderr[-2000:])


_WITH_ENTITIES = """<?xml version="1.0"?>
<!DOCTYPE OpenDRIVE [<!ENTITY t "track one">]>
<OpenDRIVE>
  <header revMajor="1" revMinor="{minor}"><userData code="a" value="b">&t; and more</userData></header>
  <road name="a" length="100" id="1" junction="-1">
    <planView><geometry s="0" x="0" y="0" hdg="0" length="100"><line/></geometry></planView>
    <lanes><laneSection s="0"><center><lane id="0" type="none" level="false"/></center>
    <right><lane id="-1" type="rail" level="false"><width sOffset="0" a="1.5" b="0" c="0" d="0"/></lane></right>
    </laneSection></lanes>
    <railroad><switch name="W" id="5" position="sideways">&t;<mainTrack id="1" s="5" dir="+"/>
    <sideTrack id="1" s="0" dir="+"/></switch></railroad>
  </road>
  <road name="x" length="oops" id="2" junction="-1">
    <planView><geometry s="0" x="0" y="0" hdg="0" length="100"><line/></geometry></planView>
  </road>
</OpenDRIVE>
"""


@needs_shared
@pytest.mark.parametrize("minor", [7, 8])
def test_validation_goes_past_entity_references(
    tmp_path: Path, minor: int, monkeypatch: pytest.MonkeyPatch
) -> None:
    # libxml2 stopped at the first entity reference: one "internal error" and nothing after
    # it validated (the direct route), or "All checks passed" and exit 3 (lxml's route)
    path = tmp_path / "entities.xodr"
    path.write_text(_WITH_ENTITIES.format(minor=minor), encoding="utf-8")
    direct = _findings(path, direct=True, monkeypatch=monkeypatch)
    assert direct == _findings(path, direct=False, monkeypatch=monkeypatch)
    schema = [(line, str(message)) for line, code, message, _ in direct if code == "XS006"]
    assert [line for line, message in schema if "entity reference '&t;'" in message] == [4, 10]
    assert any(line == 10 and "'sideways'" in message for line, message in schema)
    assert any(line == 13 and "'oops'" in message for line, message in schema)  # after both
    assert not any("internal error" in message for _, message in schema)


def test_the_builtin_schema_goes_past_entity_references(tmp_path: Path) -> None:
    path = tmp_path / "entities.xodr"
    path.write_text(_WITH_ENTITIES.format(minor=7), encoding="utf-8")
    report = Linter(default_registry(), LintOptions(select=("XS",))).lint_path(path)
    assert (
        not report.internal_errors
    )  # lxml raised XMLSchemaValidateError: an internal error, exit 3
    found = [(f.line, f.message) for f in report.findings]
    assert any(line == 10 and "entity reference '&t;'" in message for line, message in found)
    assert any(line == 10 and "'sideways'" in message for line, message in found)
    # the built-in schema validates railroad elements alone: the header's reference is not its
    assert not any(line == 4 for line, _ in found)


_ENTITY_CHILDREN = """<?xml version="1.0"?>
<!DOCTYPE OpenDRIVE [<!ENTITY mt '<mainTrack id="1" s="5" dir="+"/>'>
<!ENTITY pv '<planView><geometry s="0" x="0" y="0" hdg="0" length="100"><line/></geometry></planView>'>]>
<OpenDRIVE>
  <header revMajor="1" revMinor="7"/>
  <road name="a" length="100" id="1" junction="-1">&pv;
    <lanes><laneSection s="0"><center><lane id="0" type="none" level="false"/></center>
    <right><lane id="-1" type="rail" level="false"><width sOffset="0" a="1.5" b="0" c="0" d="0"/></lane></right>
    </laneSection></lanes>
    <railroad><switch name="W" id="5" position="dynamic">&mt;<sideTrack id="1" s="0" dir="+"/></switch></railroad>
  </road>
</OpenDRIVE>
"""


@pytest.mark.parametrize("official", [True, False])
def test_an_entity_standing_for_children_gives_no_finding_about_them(
    tmp_path: Path, official: bool
) -> None:
    # validated without what the reference stands for, a road lacked its planView and a
    # switch its mainTrack: findings of the copy, not of the file
    if official and not SHARED_SCHEMAS.is_dir():
        pytest.skip("../shared (official ASAM schemas) is absent")
    path = tmp_path / "children.xodr"
    path.write_text(_ENTITY_CHILDREN, encoding="utf-8")
    options = LintOptions(schema=SHARED_SCHEMAS if official else None, select=("XS", "SW"))
    found = [
        (f.line, f.code, f.message)
        for f in Linter(default_registry(), options).lint_path(path).findings
    ]
    references = [line for line, _, message in found if "entity reference" in message]
    assert references == ([6, 10] if official else [10])
    assert all("entity reference" in message for _, _, message in found), found
