"""Stage 2: finding the schema of a version, validating, and messages people understand."""

from __future__ import annotations

import json
import os
import shutil
import subprocess
import sys
from pathlib import Path

import pytest

from tests.conftest import CORPUS_RAIL, REPO, SHARED_SCHEMAS, needs_shared
from xodrlint.api import default_registry
from xodrlint.engine.linter import Linter, LintOptions
from xodrlint.findings import FileReport
from xodrlint.validation.sets import (
    Origin,
    SchemaFinder,
    SchemaSet,
    builtin_set,
    entry_xsd,
    uses_xsd11,
)

MINIMAL_XSD = """<?xml version="1.0"?>
<xs:schema xmlns:xs="http://www.w3.org/2001/XMLSchema">
  <xs:element name="OpenDRIVE"><xs:complexType><xs:sequence>
    <xs:any processContents="skip" minOccurs="0" maxOccurs="unbounded"/>
  </xs:sequence></xs:complexType></xs:element>
</xs:schema>
"""
OFFICIAL_EXAMPLES = [
    "ASAM-1.6.0_Ex-Railway-Switch.xodr",
    "ASAM-1.6.1_Ex-Railway-Switch.xodr",
    "ASAM-1.7.0_Ex_Railway-Switch.xodr",
    "ASAM-1.7.0_Ex_Railway-Station.xodr",
]
STATIONS_DECLARING_1_5 = [
    "ASAM-1.6.0_Ex_Railway_station.xodr",
    "ASAM-1.6.1_Ex_Railway_station.xodr",
]


def _set(folder: Path, version: str) -> Path:
    (folder / version).mkdir(parents=True)
    (folder / version / "core.xsd").write_text(MINIMAL_XSD)
    return folder / version / "core.xsd"


def test_finder_order_option_then_environment_then_user_data(tmp_path: Path) -> None:
    option, env, data = (
        _set(tmp_path / "o", "1.7.0"),
        _set(tmp_path / "e", "1.7.0"),
        _set(tmp_path / "d", "1.7.0"),
    )
    environment = {"XODRLINT_SCHEMA_PATH": str(env.parents[1])}
    finder = SchemaFinder(option.parents[1], Origin.OPTION, environment, data.parents[1])
    assert finder.find(1, 7).origin is Origin.OPTION
    assert (
        SchemaFinder(None, Origin.OPTION, environment, data.parents[1]).find(1, 7).origin
        is Origin.ENVIRONMENT
    )
    assert (
        SchemaFinder(None, Origin.OPTION, {}, data.parents[1]).find(1, 7).origin is Origin.USER_DATA
    )
    fallback = SchemaFinder(None, Origin.OPTION, {}, tmp_path / "none").find(1, 7)
    assert fallback.is_builtin and fallback.entry == builtin_set(1, 7).entry


def test_finder_picks_newest_patch_and_falls_through_missing_versions(tmp_path: Path) -> None:
    _set(tmp_path, "1.8.0")
    newest = _set(tmp_path, "1.8.1")
    finder = SchemaFinder(tmp_path, Origin.OPTION, {}, tmp_path / "none")
    assert finder.find(1, 8).entry == newest.resolve()
    assert finder.find(1, 9).is_builtin


def test_single_file_and_single_set_serve_every_version(tmp_path: Path) -> None:
    xsd = tmp_path / "mine.xsd"
    xsd.write_text(MINIMAL_XSD)
    assert SchemaFinder(xsd, Origin.OPTION, {}, tmp_path).find(1, 4).entry == xsd.resolve()
    assert (
        SchemaFinder(tmp_path, Origin.OPTION, {}, tmp_path / "x").find(1, 9).entry == xsd.resolve()
    )


@pytest.mark.parametrize("minor", range(1, 10))
def test_builtin_schema_exists_for_every_version(minor: int) -> None:
    assert builtin_set(1, minor).entry.is_file()


def _lint(path: Path, schema: Path | None = None, select: tuple[str, ...] = ("ALL",)) -> FileReport:
    return Linter(default_registry(), LintOptions(select=select, schema=schema)).lint_path(path)


@pytest.mark.parametrize("name", [*OFFICIAL_EXAMPLES, "OpenSCENARIO-1.2_SampleDatabase.xodr"])
@pytest.mark.parametrize("official", [True, False], ids=["official", "builtin"])
@needs_shared
def test_official_examples_are_clean(name: str, official: bool) -> None:
    report = _lint(CORPUS_RAIL / name, SHARED_SCHEMAS if official else None)
    assert report.findings == ()
    assert report.schema_builtin is not official


@pytest.mark.parametrize("name", STATIONS_DECLARING_1_5)
@needs_shared
def test_stations_declaring_1_5_get_one_plain_country_code_finding(name: str) -> None:
    report = _lint(CORPUS_RAIL / name, SHARED_SCHEMAS)
    assert [(f.code, f.line) for f in report.findings] == [("XS006", 8)]
    message = report.findings[0].message
    assert "'type/@country' is 'DE'" in message
    assert "OpenDRIVE 1.5" in message and "[A-Z]{3}" in message


@needs_shared
def test_1_5_keyref_bug_is_repaired(tmp_path: Path) -> None:
    switch = (CORPUS_RAIL / "ASAM-1.7.0_Ex_Railway-Switch.xodr").read_text()
    as_1_5 = tmp_path / "switch-1.5.xodr"
    as_1_5.write_text(switch.replace('revMinor="7"', 'revMinor="5"'))
    assert _lint(as_1_5, SHARED_SCHEMAS).findings == ()
    # a side track naming no road is still caught, as a road reference
    broken = tmp_path / "broken-1.5.xodr"
    broken.write_text(
        as_1_5.read_text().replace(
            '<sideTrack id="2" s="0.0000000000000000e+00"', '<sideTrack id="77" s="0"'
        )
    )
    messages = [f.message for f in _lint(broken, SHARED_SCHEMAS, ("XS006",)).findings]
    assert messages == ["'sideTrack/@id' names '77', but no 'road' has that @id"]
    # with SW004 running, the keyref error is its finding, reported once
    findings = _lint(broken, SHARED_SCHEMAS, ("XS006", "SW004")).findings
    assert [f.code for f in findings] == ["SW004"]


@needs_shared
def test_bad_switch_position_is_xs006_at_the_switch_line(tmp_path: Path) -> None:
    source = (CORPUS_RAIL / "ASAM-1.7.0_Ex_Railway-Switch.xodr").read_text()
    bad = tmp_path / "position.xodr"
    bad.write_text(source.replace('position="dynamic"', 'position="sideways"', 1))
    line = next(i for i, text in enumerate(source.splitlines(), 1) if "<switch" in text)
    for schema in (SHARED_SCHEMAS, None):
        findings = _lint(bad, schema).findings
        assert [(f.code, f.line) for f in findings] == [("XS006", line)]
        assert (
            findings[0].message
            == "'switch/@position' is 'sideways', expected one of 'dynamic', 'straight', 'turn'"
        )


@needs_shared
def test_xsd11_schema_reports_on_the_referencing_elements() -> None:
    report = _lint(CORPUS_RAIL / "libopendrive-rs_railways.xodr", SHARED_SCHEMAS, ("XS006",))
    found = [(f.line, f.xpath) for f in report.findings]
    assert (
        found
        == [
            (7, "/OpenDRIVE/road[@id='1']/railroad/switch[@id='7']/partner"),
            (7, "/OpenDRIVE/road[@id='1']/railroad/switch[@id='7']/sideTrack"),
            (7, "/OpenDRIVE/road[@id='1']/railroad/switch[@id='9']"),
            (7, "/OpenDRIVE/road[@id='1']/railroad/switch[@id='9']/sideTrack"),
            (14, "/OpenDRIVE/station[@id='20']/platform[@id='20-1']/segment[2]"),
        ]
        or len(found) == 4
    )
    messages = " | ".join(f.message for f in report.findings)
    assert "'switch' lacks the required attribute 'name'" in messages
    assert "'segment/@side' is 'up'" in messages
    assert "evaluate to a node" not in messages and "missing key field" not in messages


def test_builtin_schema_flags_railroad_in_versions_before_1_4() -> None:
    report = _lint(REPO / "rules" / "XS006" / "invalid_railroad_in_1_3.xodr", select=("XS006",))
    assert [f.message for f in report.findings] == [
        "'railroad' does not exist in OpenDRIVE 1.3; railroad content starts with OpenDRIVE 1.4"
    ]


def test_broken_user_schema_is_a_setup_error(tmp_path: Path) -> None:
    from xodrlint.validation.sets import SchemaLoadError

    (tmp_path / "bad.xsd").write_text(
        "<xs:schema xmlns:xs='http://www.w3.org/2001/XMLSchema'><xs:element/></xs:schema>"
    )
    with pytest.raises(SchemaLoadError):
        _lint(REPO / "examples" / "clean.xodr", tmp_path / "bad.xsd")


def test_schema_paths_with_dotdot_still_compile(tmp_path: Path) -> None:
    if not SHARED_SCHEMAS.is_dir():
        pytest.skip("../shared is absent")
    copy = tmp_path / "sets"
    shutil.copytree(SHARED_SCHEMAS / "1.7.0", copy / "1.7.0")
    dotted = tmp_path / "x" / ".." / "sets"
    (tmp_path / "x").mkdir()
    assert _lint(REPO / "examples" / "clean.xodr", dotted).findings == ()


def _official(text: str, tmp_path: Path, name: str = "t.xodr") -> list[tuple[int, str]]:
    path = tmp_path / name
    path.write_text(text, "utf-8")
    return sorted((f.line, f.code) for f in _lint(path, SHARED_SCHEMAS).findings)


SWITCH_EXAMPLE = "ASAM-1.7.0_Ex_Railway-Switch.xodr"


@needs_shared
def test_a_rule_takes_over_only_its_own_schema_error(tmp_path: Path) -> None:
    source = (CORPUS_RAIL / SWITCH_EXAMPLE).read_text()
    # switch 32 gets switch 12's id and loses its side track: the duplicate id is SW007's,
    # the missing side track stays an XS006 finding on the same element
    text = source.replace('<switch name="Switch32" id="32"', '<switch name="Switch32" id="12"')
    start = text.index('<sideTrack id="2" s="3.4898261533109149e+01" dir="-"/>')
    text = text[:start] + text[start:].replace(
        '<sideTrack id="2" s="3.4898261533109149e+01" dir="-"/>', "", 1
    )
    path = tmp_path / "t.xodr"
    path.write_text(text, "utf-8")
    findings = _lint(path, SHARED_SCHEMAS).findings
    line = text[: text.index('<switch name="Switch32"')].count("\n") + 1
    assert (line, "SW007") in [(f.line, f.code) for f in findings]
    assert [f.message for f in findings if f.code == "XS006"] == [
        "'partner' is not allowed here in OpenDRIVE 1.7; expected 'sideTrack'"
    ]


@needs_shared
def test_keyref_errors_on_one_line_go_to_the_element_that_holds_the_key(tmp_path: Path) -> None:
    source = (CORPUS_RAIL / "ASAM-1.7.0_Ex_Railway-Station.xodr").read_text()
    import re

    segments = re.findall(r"<segment [^>]*/>", source)
    first, second = segments[0], segments[1]
    # the bad road id equals an attribute value of the good segment before it
    bad_second = re.sub(r'roadId="[^"]*"', 'roadId="5.1000000000000000e+01"', second)
    one_line = source.replace(first, "").replace(second, first + bad_second)
    codes = [code for _, code in _official(one_line, tmp_path)]
    assert "ST003" in codes and "XS006" not in codes  # not pinned on the good neighbour


@needs_shared
def test_station_holding_only_user_data_is_st001_only(tmp_path: Path) -> None:
    source = (CORPUS_RAIL / "ASAM-1.7.0_Ex_Railway-Station.xodr").read_text()
    start = source.index("<station ")
    head_end = source.index(">", start) + 1
    end = source.index("</station>", start)
    text = source[:head_end] + '<userData code="x" value="y"/>' + source[end:]
    line = text[:start].count("\n") + 1
    assert _official(text, tmp_path) == [(line, "ST001")]


@needs_shared
def test_keyref_errors_past_line_65535_are_taken_over(tmp_path: Path) -> None:
    source = (CORPUS_RAIL / SWITCH_EXAMPLE).read_text()
    padding = "<!-- padding -->\n" * 70_000
    text = source.replace("<road ", padding + "<road ", 1).replace(
        '<sideTrack id="2" s="0.0000000000000000e+00"', '<sideTrack id="77" s="0"'
    )
    found = _official(text, tmp_path)
    assert [code for _, code in found if code != "SW002"] == ["SW004"]
    assert all(line > 70_000 for line, _ in found)


def test_a_broken_schema_is_said_once(tmp_path: Path) -> None:
    # libxml2 prints a schema's errors to stderr unless told otherwise: only our line
    bad = tmp_path / "bad.xsd"
    bad.write_text(
        "<xs:schema xmlns:xs='http://www.w3.org/2001/XMLSchema'><xs:element/></xs:schema>"
    )
    done = subprocess.run(
        [sys.executable, "-m", "xodrlint", "check", "--schema", str(bad), str(REPO / "examples")],
        check=False,
        capture_output=True,
        text=True,
    )
    assert done.returncode == 2
    assert done.stderr.splitlines() == [
        f"xodrlint: cannot compile schema {bad}: line 1: Element "
        "'{http://www.w3.org/2001/XMLSchema}element': The attribute 'name' is required "
        "but missing."
    ]


@needs_shared
@pytest.mark.parametrize("threads", ["1", "0"])
def test_the_schema_compiles_while_the_document_is_parsed(
    monkeypatch: pytest.MonkeyPatch, threads: str
) -> None:
    # the header is read off the bytes and the compile runs in a thread beside the parse
    # (XODRLINT_FORK=0: in the caller); the findings are the same
    import threading

    from xodrlint.validation import libxml2

    monkeypatch.setenv("XODRLINT_FORK", threads)
    compiled_in: list[str] = []
    real = libxml2.Libxml2Validator.__init__

    def init(self: libxml2.Libxml2Validator, entry: Path) -> None:
        compiled_in.append(threading.current_thread().name)
        real(self, entry)

    monkeypatch.setattr(libxml2.Libxml2Validator, "__init__", init)
    report = _lint(REPO / "examples" / "broken.xodr", SHARED_SCHEMAS)
    assert compiled_in == (["xodrlint-compile"] if threads == "1" else ["MainThread"])
    assert report.schema is not None and "1.7" in report.schema
    assert [f.code for f in report.findings].count("XS006") >= 3


# -- issue 18, item 1: a single 1.8 set, by every route -------------------------------------


def _cli(*args: str, env: dict[str, str] | None = None) -> subprocess.CompletedProcess[str]:
    return subprocess.run(
        [sys.executable, "-m", "xodrlint", *args],
        check=False,
        capture_output=True,
        text=True,
        env={**os.environ, **(env or {})},
    )


@needs_shared
@pytest.mark.parametrize(
    "route",
    ["1.8.1", "1.8.0", "1.8.1/OpenDRIVE_Core.xsd", "1.9.0", "environment 1.8.1"],
)
def test_a_single_xsd11_set_validates_by_every_route(route: str) -> None:
    # the 1.8 files carry no vc:minVersion marker in their first 4 KB: their asserts, type
    # alternatives and folder name tell that they are XSD 1.1
    if route.startswith("environment"):
        schema = SHARED_SCHEMAS / route.split()[1]
        done = _cli("check", str(REPO / "examples" / "broken.xodr"), "-f", "json",
                    env={"XODRLINT_SCHEMA_PATH": str(schema)})  # fmt: skip
    else:
        done = _cli(
            "check", str(REPO / "examples" / "broken.xodr"), "-f", "json",
            "--schema", str(SHARED_SCHEMAS / route),
        )  # fmt: skip
    assert done.returncode == 1, done.stderr
    report = json.loads(done.stdout)
    assert "built-in" not in report["files"][0]["schema"]["description"]
    codes = [finding["code"] for finding in report["findings"]]
    assert codes.count("XS006") >= 3  # the official schema's verdict, not the built-in's


@needs_shared
@pytest.mark.parametrize("version", ["1.4", "1.5", "1.6.1", "1.7.0", "1.8.0", "1.8.1", "1.9.0"])
def test_a_set_is_xsd11_by_its_content_and_version(version: str) -> None:
    entry = entry_xsd(SHARED_SCHEMAS / version)
    assert entry is not None
    expected = version.startswith(("1.8", "1.9"))
    assert SchemaSet(entry, None, Origin.OPTION).is_xsd11 is expected
    # a copy in a folder without a version, under a name without one: by content alone
    assert uses_xsd11(entry) is expected


def test_xsd11_content_is_recognised_whatever_the_prefix(tmp_path: Path) -> None:
    core = tmp_path / "core.xsd"
    core.write_text(
        '<s:schema xmlns:s="http://www.w3.org/2001/XMLSchema"><s:include schemaLocation="part.xsd"/>'
        '<s:element name="OpenDRIVE"/></s:schema>'
    )
    part = tmp_path / "part.xsd"
    part.write_text(
        '<s:schema xmlns:s="http://www.w3.org/2001/XMLSchema"><s:annotation><s:documentation>'
        "an alternative to assert</s:documentation></s:annotation></s:schema>"
    )
    assert not uses_xsd11(core)
    uses_xsd11.cache_clear()
    part.write_text(
        '<s:schema xmlns:s="http://www.w3.org/2001/XMLSchema"><s:complexType name="t">'
        '<s:assert test="true()"/></s:complexType></s:schema>'
    )
    assert uses_xsd11(core)  # found through the include
    uses_xsd11.cache_clear()


def test_a_set_that_fails_to_compile_names_the_file_and_line_that_failed(tmp_path: Path) -> None:
    core = tmp_path / "core.xsd"
    core.write_text(
        '<xs:schema xmlns:xs="http://www.w3.org/2001/XMLSchema">\n'
        '  <xs:include schemaLocation="part.xsd"/>\n'
        '  <xs:element name="OpenDRIVE"/>\n'
        "</xs:schema>\n"
    )
    (tmp_path / "part.xsd").write_text(
        '<xs:schema xmlns:xs="http://www.w3.org/2001/XMLSchema">\n'
        "\n"
        '  <xs:complexType name="t"><xs:element name="x"/></xs:complexType>\n'
        "</xs:schema>\n"
    )
    done = _cli("check", "--schema", str(core), str(REPO / "examples" / "clean.xodr"))
    assert done.returncode == 2
    (line,) = done.stderr.splitlines()
    assert line.startswith(f"xodrlint: cannot compile schema {core}: {tmp_path / 'part.xsd'}:3: ")


@pytest.mark.parametrize(
    "element",
    ['<xs:assertion test="$value gt 0"/>', '<xs:openContent mode="interleave"/>',
     "<xs:defaultOpenContent/>", '<xs:override schemaLocation="x.xsd"/>'],
)  # fmt: skip
def test_other_xsd11_only_elements_make_a_set_xsd11(tmp_path: Path, element: str) -> None:
    core = tmp_path / "core.xsd"
    core.write_text(
        f'<xs:schema xmlns:xs="http://www.w3.org/2001/XMLSchema">{element}'
        '<xs:element name="OpenDRIVE"/></xs:schema>'
    )
    assert uses_xsd11(core)
    uses_xsd11.cache_clear()


def test_an_unreadable_schema_is_a_one_line_error(tmp_path: Path) -> None:
    # its version is looked for in its bytes: a read error is the compile's to say
    done = _cli("check", str(REPO / "examples" / "clean.xodr"), env={
        "XODRLINT_SCHEMA_PATH": "/proc/self/mem", "XODRLINT_DATA_DIR": str(tmp_path),
    })  # fmt: skip
    assert done.returncode == 2, done.stderr
    assert len(done.stderr.splitlines()) == 1 and "Traceback" not in done.stderr


# -- issue 18, item 2: a set given for every version, said in every report ---------------


def _declared_14(tmp_path: Path) -> Path:
    path = tmp_path / "old.xodr"
    path.write_text(
        (REPO / "examples" / "clean.xodr").read_text().replace('revMinor="7"', 'revMinor="4"')
    )
    return path


@needs_shared
def test_a_set_given_for_every_version_is_said_for_a_file_of_another(tmp_path: Path) -> None:
    old = _declared_14(tmp_path)
    single = str(SHARED_SCHEMAS / "1.7.0")
    done = _cli("check", str(old), "--schema", single, "-f", "json")
    schema = json.loads(done.stdout)["files"][0]["schema"]
    assert schema["description"].startswith("OpenDRIVE 1.7.0 schema")
    assert schema["note"] == (
        "the file declares OpenDRIVE 1.4; the OpenDRIVE 1.7.0 schema given for every "
        "version (--schema) validated it"
    )
    sarif = json.loads(_cli("check", str(old), "--schema", single, "-f", "sarif").stdout)
    run = sarif["runs"][0]
    (entry,) = run["properties"]["schemas"]
    assert entry["note"] == schema["note"]
    invocation = run["invocations"][0]
    notes = [n["message"]["text"] for n in invocation["toolConfigurationNotifications"]]
    assert any(schema["note"] in note for note in notes)
    text = _cli("check", str(old), "--schema", single).stdout.splitlines()
    assert text[0] == "All checks passed: 1 file, no findings."
    assert f"note: {old}: {schema['note']}" in text
    assert any(line.startswith("note: validated with the OpenDRIVE 1.7.0 schema") for line in text)


@needs_shared
def test_a_set_of_the_files_own_version_has_nothing_to_say(tmp_path: Path) -> None:
    old = _declared_14(tmp_path)
    for schema in (SHARED_SCHEMAS, SHARED_SCHEMAS / "1.4"):
        report = json.loads(_cli("check", str(old), "--schema", str(schema), "-f", "json").stdout)
        assert report["files"][0]["schema"]["note"] is None
    clean = _cli("check", str(REPO / "examples" / "clean.xodr"), "--schema", str(SHARED_SCHEMAS))
    # a clean text run still names the schema it used
    assert "note: validated with the OpenDRIVE 1.7.0 schema" in clean.stdout


@needs_shared
def test_the_note_names_the_declared_version_and_the_one_checked(tmp_path: Path) -> None:
    path = tmp_path / "new.xodr"
    text = (REPO / "examples" / "clean.xodr").read_text().replace('revMinor="7"', 'revMinor="10"')
    path.write_text(text)
    done = _cli("check", str(path), "--schema", str(SHARED_SCHEMAS / "1.7.0"), "-f", "json")
    note = json.loads(done.stdout)["files"][0]["schema"]["note"]
    assert note.startswith("the file declares OpenDRIVE 1.10 (checked as 1.9); the OpenDRIVE 1.7.0")


def test_a_set_of_unknown_version_says_so_once_in_its_label(tmp_path: Path) -> None:
    loose = tmp_path / "loose.xsd"
    loose.write_text(
        '<xs:schema xmlns:xs="http://www.w3.org/2001/XMLSchema">'
        '<xs:element name="OpenDRIVE"/></xs:schema>'
    )
    found = SchemaSet(loose, None, Origin.OPTION)
    assert found.label == "schema of unknown OpenDRIVE version"
    assert found.version_note((1, 4), (1, 4)) is None  # nothing tells it differs
    listed = _cli("schemas", "list", env={"XODRLINT_SCHEMA_PATH": str(loose),
                                          "XODRLINT_DATA_DIR": str(tmp_path / "data")})  # fmt: skip
    assert "(from XODRLINT_SCHEMA_PATH for every version)" in listed.stdout


# -- issue 18, item 3: VIRES' 1.1 and 1.2 sets declare a target namespace ------------------

VIRES_LIKE = """<?xml version="1.0"?>
<xsd:schema xmlns:xsd="http://www.w3.org/2001/XMLSchema" targetNamespace="www.vires.com"
    xmlns="www.vires.com" elementFormDefault="qualified">
  <xsd:element name="OpenDRIVE">
    <xsd:complexType>
      <xsd:sequence>
        <xsd:element name="header" type="header"/>
        <xsd:element name="road" type="road" maxOccurs="unbounded"/>
      </xsd:sequence>
    </xsd:complexType>
  </xsd:element>
  <xsd:complexType name="header">
    <xsd:attribute name="revMajor" type="xsd:unsignedShort"/>
    <xsd:attribute name="revMinor" type="xsd:unsignedShort"/>
  </xsd:complexType>
  <xsd:complexType name="road">
    <xsd:attribute name="length" type="xsd:double" use="required"/>
    <xsd:attribute name="id" type="xsd:string"/>
  </xsd:complexType>
</xsd:schema>
"""


@pytest.mark.parametrize("namespace", ["", ' xmlns="www.vires.com"'])
def test_a_set_with_a_target_namespace_validates_files_of_its_version(
    tmp_path: Path, namespace: str
) -> None:
    # files of 1.1 and 1.2 are read without a namespace (one in VIRES' is dropped, like
    # ASAM's old one): the set's own namespace is dropped too, so both get its verdict
    (tmp_path / "sets" / "1.1").mkdir(parents=True)
    (tmp_path / "sets" / "1.1" / "OpenDRIVE_1.1.xsd").write_text(VIRES_LIKE)
    document = tmp_path / "old.xodr"
    document.write_text(
        f'<OpenDRIVE{namespace}><header revMajor="1" revMinor="1"/>'
        '<road id="1" length="10"/>\n<road id="2"/></OpenDRIVE>'
    )
    report = _lint(document, tmp_path / "sets")
    assert report.schema is not None and "1.1" in report.schema
    assert [(f.code, f.line) for f in report.findings] == [("XS006", 2)]
    assert "length" in report.findings[0].message


# -- issue 31, item 2: a schema path that is not there is said, with where it came from ----


def test_a_schema_path_variable_naming_nothing_is_one_line_and_exit_2(tmp_path: Path) -> None:
    # a typo fell back to the built-in schema, exit 0: CI lost full validation unseen
    missing = tmp_path / "shared" / "schema"
    done = _cli("check", str(REPO / "examples" / "clean.xodr"),
                env={"XODRLINT_SCHEMA_PATH": f"{tmp_path}{os.pathsep}{missing}"})  # fmt: skip
    assert done.returncode == 2
    assert (
        done.stderr == f"xodrlint: XODRLINT_SCHEMA_PATH names {missing}: no such file or folder\n"
    )


def test_a_config_naming_no_schema_says_which_file_named_it(tmp_path: Path) -> None:
    (tmp_path / "xodrlint.toml").write_text('schema = "nope"\n')
    (tmp_path / "clean.xodr").write_bytes((REPO / "examples" / "clean.xodr").read_bytes())
    done = _cli("check", str(tmp_path / "clean.xodr"))
    assert done.returncode == 2
    assert done.stderr == (
        f"xodrlint: schema {tmp_path / 'nope'} (from {tmp_path / 'xodrlint.toml'}): "
        "no such file or folder\n"
    )


def test_the_report_names_the_config_file_that_gave_the_schema(tmp_path: Path) -> None:
    set_entry = _set(tmp_path / "sets", "1.7.0")
    (tmp_path / "xodrlint.toml").write_text('schema = "sets"\n')
    (tmp_path / "clean.xodr").write_bytes((REPO / "examples" / "clean.xodr").read_bytes())
    done = _cli("check", "-f", "json", str(tmp_path / "clean.xodr"))
    assert done.returncode == 0, done.stderr
    (described,) = [f["schema"] for f in json.loads(done.stdout)["files"]]
    assert f"({set_entry}, from {tmp_path / 'xodrlint.toml'})" in str(described)
