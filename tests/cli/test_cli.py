"""The ``xodrlint`` command end to end: exit codes, reports, options and schema management."""

from __future__ import annotations

import hashlib
import inspect
import json
import os
import re
import stat
import subprocess
import sys
import threading
import zipfile
from pathlib import Path
from typing import Any

import jsonschema  # type: ignore[import-untyped, unused-ignore]
import pytest
from typer.testing import CliRunner, Result

from tests.conftest import REPO
from xodrlint import __version__
from xodrlint.api import default_registry
from xodrlint.cli import app
from xodrlint.cli.check.notes import FULL_VALIDATION_NOTE
from xodrlint.validation.store import install_wheel

CLEAN = REPO / "examples" / "clean.xodr"
BROKEN = REPO / "examples" / "broken.xodr"
OUTPUT_SCHEMA = json.loads((REPO / "docs" / "json-output.schema.json").read_text("utf-8"))
CONSOLE_SCRIPT = Path(sys.executable).parent / "xodrlint"
ANSI = re.compile(r"\x1b\[")
BROKEN_FINDINGS = [
    (25, "XS006", "/OpenDRIVE/road[@id='1']/railroad/switch[@id='101']"),
    (30, "XS006", "/OpenDRIVE/road[@id='1']/railroad/switch[@id='102']"),
    (32, "SW006", "/OpenDRIVE/road[@id='1']/railroad/switch[@id='102']/sideTrack"),
    (53, "RL003", "/OpenDRIVE/road[@id='2']/lanes/laneSection/right/lane[@id='-1']"),
    (62, "ST004", "/OpenDRIVE/station[@id='500']/platform[@id='501']/segment"),
    (62, "XS006", "/OpenDRIVE/station[@id='500']/platform[@id='501']/segment"),
]
#: Their columns: where the '<' of each finding's element stands on its line.
BROKEN_COLUMNS = [7, 7, 9, 11, 7, 7]
# Rich must see a pipe, never a forced terminal, whatever the developer's shell sets.
PLAIN_ENV: dict[str, str | None] = {"FORCE_COLOR": None, "TTY_COMPATIBLE": None, "NO_COLOR": None}
# A stand-in for an official ASAM OpenDRIVE schema: one global OpenDRIVE, any content.
STUB_XSD = """<xs:schema xmlns:xs="http://www.w3.org/2001/XMLSchema">
  <xs:element name="OpenDRIVE"><xs:complexType><xs:sequence>
    <xs:any processContents="skip" minOccurs="0" maxOccurs="unbounded"/>
  </xs:sequence><xs:anyAttribute processContents="skip"/></xs:complexType></xs:element>
</xs:schema>
"""


def cli(*args: str | Path, code: int, stdin: bytes | None = None, **env: str | None) -> Result:
    result = CliRunner().invoke(app, [str(a) for a in args], input=stdin, env={**PLAIN_ENV, **env})
    if result.exception is not None and not isinstance(result.exception, SystemExit):
        raise result.exception
    assert result.exit_code == code, (result.stdout, result.stderr)
    return result


def report(*args: str | Path, code: int, stdin: bytes | None = None) -> dict[str, Any]:
    """Run ``check -f json`` and return the document, checked against the public schema."""
    result = cli("check", "-f", "json", *args, code=code, stdin=stdin)
    document: dict[str, Any] = json.loads(result.stdout)
    jsonschema.validate(document, OUTPUT_SCHEMA)
    return document


def codes(document: dict[str, Any]) -> list[str]:
    return [finding["code"] for finding in document["findings"]]


def write_variant(path: Path, source: Path, old: str, new: str) -> Path:
    text = source.read_text("utf-8")
    assert old in text
    path.write_text(text.replace(old, new), "utf-8")
    return path


def test_exit_codes_for_clean_broken_and_exit_zero() -> None:
    assert "All checks passed: 1 file, no findings." in cli("check", CLEAN, code=0).stdout
    cli("check", BROKEN, code=1)
    cli("check", BROKEN, "--exit-zero", code=0)


def test_fail_on_decides_whether_a_warning_fails(tmp_path: Path) -> None:
    # A clean network declaring OpenDRIVE 1.12: one XS005 warning.
    warning_file = write_variant(tmp_path / "v.xodr", CLEAN, 'revMinor="7"', 'revMinor="12"')
    assert codes(report(warning_file, code=1)) == ["XS005"]
    cli("check", warning_file, code=1)
    cli("check", warning_file, "--fail-on", "error", code=0)
    cli("check", BROKEN, "--fail-on", "error", code=1)


def test_missing_file_is_exit_2_and_the_other_paths_are_still_linted(tmp_path: Path) -> None:
    missing = tmp_path / "missing.xodr"
    result = cli("check", missing, BROKEN, code=2)
    assert _without_notes(result.stderr) == [f"xodrlint: {missing}: no such file or directory"]
    assert "Traceback" not in result.output
    assert f"{BROKEN}:25:7: XS006 [error]" in result.stdout
    assert "1 could not be read." in result.stdout


@pytest.mark.parametrize(
    ("args", "message"),
    [
        (["--select", "XS9"], "'XS9' matches no rule code, name or UID"),
        (["--ignore", "nonsense"], "'nonsense' matches no rule code, name or UID"),
        (
            ["-f", "xml"],
            "unknown output format 'xml' (choose from concise, github, gitlab, json, jsonl, junit, sarif, text, xqar)",
        ),
        (["--schema", "/nowhere/at/all"], "--schema /nowhere/at/all: no such file or folder"),
    ],
)
def test_usage_errors_are_exit_2_with_one_line(args: list[str], message: str) -> None:
    result = cli("check", CLEAN, *args, code=2)
    assert result.stderr == f"xodrlint: {message}\n"
    assert result.stdout == ""


def test_a_schema_that_does_not_compile_is_exit_2(tmp_path: Path) -> None:
    (tmp_path / "bad.xsd").write_text("not xml at all", "utf-8")
    result = cli("check", CLEAN, "--schema", tmp_path / "bad.xsd", code=2)
    assert result.stderr.startswith(f"xodrlint: cannot read schema {tmp_path / 'bad.xsd'}")


def test_json_report_of_broken_example() -> None:
    document = report(BROKEN, code=1)
    assert [(f["line"], f["code"], f["xpath"]) for f in document["findings"]] == BROKEN_FINDINGS
    assert [f["column"] for f in document["findings"]] == BROKEN_COLUMNS
    schema_findings = [f for f in document["findings"] if f["code"] == "XS006"]
    assert {(f["column"], f["path"], f["severity"], f["uid"]) for f in schema_findings} == {
        (7, str(BROKEN), "error", "asam.net:xodr:1.0.0:xml.valid_schema")
    }
    assert document["findings"][0]["message"] == (
        "'switch/@position' is 'sideways', expected one of 'dynamic', 'straight', 'turn'"
    )
    [entry] = document["files"]
    assert entry["declared_version"] == "1.7"
    assert entry["schema"]["builtin"] is True
    assert entry["findings"] == len(BROKEN_FINDINGS)
    assert entry["error"] is None
    assert document["tool"] == {"name": "xodrlint", "version": __version__}
    assert document["summary"] == {
        "files": 1,
        "files_with_findings": 1,
        "unreadable_files": 0,
        "findings": 6,
        "by_severity": {"error": 5, "warning": 1, "info": 0},
    }
    assert document["notes"] and "xodrlint schemas fetch" in document["notes"][0]


def test_output_schema_is_valid_and_strict() -> None:
    jsonschema.Draft202012Validator.check_schema(OUTPUT_SCHEMA)
    document = report(CLEAN, code=0)
    assert document["findings"] == [] and document["summary"]["files_with_findings"] == 0
    document["files"][0]["extra"] = True
    with pytest.raises(jsonschema.ValidationError, match="'extra' was unexpected"):
        jsonschema.validate(document, OUTPUT_SCHEMA)


def test_json_report_lists_a_missing_file_and_stays_complete(tmp_path: Path) -> None:
    missing = tmp_path / "missing.xodr"
    document = report(CLEAN, missing, BROKEN, code=2)
    # files by name, whatever the order given (where the checkout lives decides whether
    # the temporary folder sorts first)
    by_name = sorted([missing, BROKEN, CLEAN], key=lambda path: path.parts)
    assert [f["path"] for f in document["files"]] == [str(path) for path in by_name]
    gone = document["files"][by_name.index(missing)]
    assert gone["error"] == f"{missing}: no such file or directory"
    assert (gone["schema"], gone["declared_version"], gone["findings"]) == (None, None, 0)
    assert document["summary"]["unreadable_files"] == 1
    assert codes(document) == [code for _, code, _ in BROKEN_FINDINGS]


def test_json_report_of_an_unparsable_file_has_a_column(tmp_path: Path) -> None:
    (tmp_path / "bad.xodr").write_text("<OpenDRIVE>", "utf-8")
    [finding] = report(tmp_path / "bad.xodr", code=1)["findings"]
    assert (finding["code"], finding["line"], finding["xpath"]) == ("XS001", 1, "/")
    assert isinstance(finding["column"], int)


def test_text_report_when_piped_is_plain_and_unwrapped(tmp_path: Path) -> None:
    value = "sideways" * 40
    long_file = write_variant(tmp_path / "long.xodr", BROKEN, "sideways", value)
    out = cli("check", long_file, code=1, NO_COLOR="1", COLUMNS="40").stdout
    message = f"'switch/@position' is '{value}', expected one of 'dynamic', 'straight', 'turn'"
    assert f"{long_file}:25:7: XS006 [error] {message}\n" in out
    assert "\n    /OpenDRIVE/road[@id='1']/railroad/switch[@id='101']\n" in out
    assert "\n    /OpenDRIVE/station[@id='500']/platform[@id='501']/segment\n" in out
    assert "Found 6 findings (5 errors, 1 warning) in 1 of 1 file.\n" in out
    assert not ANSI.search(out)
    assert not ANSI.search(cli("check", BROKEN, code=1).stdout)


def test_quiet_prints_finding_lines_and_the_note_of_what_was_not_checked(
    tmp_path: Path,
) -> None:
    # the pre-commit hook runs with --quiet: it must still say that only railroad
    # elements were validated, in one line after the findings, and print no summary
    note = f"xodrlint: note: {FULL_VALIDATION_NOTE}"
    quiet = cli("check", BROKEN, "--quiet", code=1)
    assert [line.split(" [")[0] for line in quiet.stdout.splitlines()] == [
        f"{BROKEN}:{line}:{column}: {code}"
        for (line, code, _), column in zip(BROKEN_FINDINGS, BROKEN_COLUMNS, strict=True)
    ]
    assert quiet.stderr == note + "\n"  # after the report, on stderr
    clean = cli("check", CLEAN, "-q", code=0)
    assert (clean.stdout, clean.stderr) == ("", note + "\n")
    # validated in full (here by a stand-in for the official set): nothing to say
    stub = tmp_path / "opendrive.xsd"
    stub.write_text(STUB_XSD, "utf-8")
    full = cli("check", CLEAN, "-q", "--schema", stub, code=0)
    assert (full.stdout, full.stderr) == ("", "")


def test_show_source_prints_the_source_line() -> None:
    out = cli("check", BROKEN, "--show-source", code=1).stdout
    assert '    25 |       <switch name="W1" id="101" position="sideways">\n' in out
    assert '    62 |       <segment roadId="1" sStart="60" sEnd="240" side="up"/>\n' in out


@pytest.mark.parametrize("output_format", ["text", "json"])
def test_output_writes_the_report_to_a_file(tmp_path: Path, output_format: str) -> None:
    target = tmp_path / "report.out"
    result = cli("check", BROKEN, "-f", output_format, "--output", target, code=1)
    assert result.stdout == ""
    written = target.read_text("utf-8")
    if output_format == "json":
        jsonschema.validate(json.loads(written), OUTPUT_SCHEMA)
    else:
        assert f"{BROKEN}:30:7: XS006 [error]" in written
    assert [p.name for p in tmp_path.iterdir()] == ["report.out"]  # no temp file left


def test_output_to_a_fifo_writes_into_it_and_leaves_it_a_fifo(tmp_path: Path) -> None:
    # a rename over a device or a FIFO would leave a regular file in its place (as root,
    # `-o /dev/null` replaced the machine's /dev/null)
    fifo = tmp_path / "pipe"
    os.mkfifo(fifo)
    received: list[bytes] = []
    reader = threading.Thread(target=lambda: received.append(fifo.read_bytes()))
    reader.start()
    cli("check", BROKEN, "-f", "json", "-o", fifo, code=1)
    reader.join(timeout=30)
    assert stat.S_ISFIFO(fifo.lstat().st_mode)
    jsonschema.validate(json.loads(received[0]), OUTPUT_SCHEMA)


def test_output_through_a_symlink_replaces_the_file_it_names(tmp_path: Path) -> None:
    (tmp_path / "reports").mkdir()
    real = tmp_path / "reports" / "latest.json"
    real.write_text("old", "utf-8")
    link = tmp_path / "report.json"
    link.symlink_to(real)
    cli("check", BROKEN, "-f", "json", "-o", link, code=1)
    assert link.is_symlink()
    jsonschema.validate(json.loads(real.read_text("utf-8")), OUTPUT_SCHEMA)


@pytest.mark.parametrize("as_folder", [False, True])
def test_output_refuses_to_overwrite_an_input(tmp_path: Path, as_folder: bool) -> None:
    victim = tmp_path / "map.xodr"
    victim.write_bytes(BROKEN.read_bytes())
    result = cli("check", tmp_path if as_folder else victim, "-o", victim, code=2)
    assert "is one of the inputs; refusing to overwrite it" in result.stderr
    assert victim.read_bytes() == BROKEN.read_bytes()


def test_stdin_is_reported_under_stdin_filename() -> None:
    args = ("-", "--stdin-filename", "maps/x.xodr")
    document = report(*args, code=1, stdin=BROKEN.read_bytes())
    assert [f["path"] for f in document["files"]] == ["maps/x.xodr"]
    assert {f["path"] for f in document["findings"]} == {"maps/x.xodr"}
    out = cli("check", *args, "-q", code=1, stdin=BROKEN.read_bytes()).stdout
    assert out.startswith("maps/x.xodr:25:7: XS006 [error] ")


def test_folders_are_walked_for_xodr_files_in_sorted_order(tmp_path: Path) -> None:
    root = tmp_path / "maps"
    names = ["z.xodr", "c/d/deep.xodr", "b.xodr", "a/y.xodr", "notes.txt", "a/y.xodr.bak"]
    for name in names:
        (root / name).parent.mkdir(parents=True, exist_ok=True)
        (root / name).write_bytes(CLEAN.read_bytes())
    document = report(root, code=0)
    expected = ["a/y.xodr", "b.xodr", "c/d/deep.xodr", "z.xodr"]
    assert [f["path"] for f in document["files"]] == [f"{root}/{name}" for name in expected]


@pytest.mark.parametrize(
    ("select", "ignore", "expected"),
    [
        ("ALL", "", ["XS005", "XS006", "XS006", "SW006", "RL003", "ST004", "XS006"]),
        ("ALL", "SW,ST,RL", ["XS005", "XS006", "XS006", "XS006"]),
        ("XS00", "XS006", ["XS005"]),  # the longer ignore wins
        ("XS006", "XS00", ["XS006", "XS006", "XS006"]),  # the longer select wins
        ("XS005,XS006", "XS", ["XS005", "XS006", "XS006", "XS006"]),
        ("RL,ST004", "", ["RL003", "ST004"]),
        ("XS006", "XS006", []),  # a tie: ignore wins
        ("schema-violation", "XS006", []),  # a name is as specific as its code
        ("asam.net:xodr:1.0.0:xml.valid_schema", "", ["XS006", "XS006", "XS006"]),
    ],
)
def test_select_and_ignore(tmp_path: Path, select: str, ignore: str, expected: list[str]) -> None:
    mixed = write_variant(tmp_path / "mixed.xodr", BROKEN, 'revMinor="7"', 'revMinor="12"')
    args = ["--select", select, *(["--ignore", ignore] if ignore else [])]
    document = report(mixed, *args, code=1 if expected else 0)
    assert codes(document) == expected
    if "XS006" not in expected:  # no schema stage ran, so there is nothing to note
        assert document["files"][0]["schema"] is None
        assert document["notes"] == []


def test_rules_lists_each_rule_with_its_uid_on_one_line() -> None:
    lines = cli("rules", code=0).stdout.splitlines()
    assert lines[0].split() == ["Code", "Name", "Severity", "UID"]
    metas = {meta.code: meta for meta in default_registry().metas}
    assert {f"XS00{n}" for n in range(1, 7)} <= set(metas)
    for code, meta in metas.items():
        [line] = [line for line in lines if line.startswith(f"{code} ")]
        assert line.split() == [code, meta.name, str(meta.severity), *meta.uids]


def test_rules_as_json() -> None:
    entries = json.loads(cli("rules", "-f", "json", code=0).stdout)
    by_code = {entry["code"]: entry for entry in entries}
    assert by_code["XS006"]["uid"] == "asam.net:xodr:1.0.0:xml.valid_schema"
    assert by_code["XS005"]["severity"] == "warning"
    cli("rules", "-f", "yaml", code=2)


@pytest.mark.parametrize(
    "token", ["XS006", "xs006", "schema-violation", "asam.net:xodr:1.0.0:xml.valid_schema"]
)
def test_explain_prints_the_rule_doc(token: str) -> None:
    out = cli("explain", token, code=0).stdout
    assert out.startswith("# XS006 schema-violation\n")
    assert "UID: `asam.net:xodr:1.0.0:xml.valid_schema`" in out
    assert "## Why is this bad?" in out
    assert not ANSI.search(out)


def test_explain_an_unknown_rule_is_exit_2() -> None:
    result = cli("explain", "XS999", code=2)
    assert result.stderr == "xodrlint: no rule 'XS999' (see 'xodrlint rules')\n"


def test_version() -> None:
    assert cli("--version", code=0).stdout == f"xodrlint {__version__}\n"


def stub_download(root: Path) -> Path:
    (root / "1.7.0").mkdir(parents=True)
    (root / "1.7.0" / "opendrive_core.xsd").write_text(STUB_XSD, "utf-8")
    (root / "1.7.0" / "readme.txt").write_text("not a schema", "utf-8")
    return root


def zip_of(folder: Path, archive: Path) -> Path:
    with zipfile.ZipFile(archive, "w") as handle:
        for path in sorted(folder.rglob("*")):
            if path.is_file():
                handle.write(path, path.relative_to(folder).as_posix())
    return archive


@pytest.mark.parametrize("as_zip", [False, True])
def test_schemas_add_installs_an_official_set(
    tmp_path: Path, isolated_schemas: Path, as_zip: bool
) -> None:
    source = stub_download(tmp_path / "download")
    if as_zip:
        source = zip_of(source, tmp_path / "download.zip")
    installed = isolated_schemas / "schemas" / "1.7.0"
    assert cli("schemas", "list", code=0).stdout.startswith("no official schemas found\n")
    out = cli("schemas", "add", source, code=0).stdout
    assert out == f"added OpenDRIVE 1.7.0 (1 file) to {installed}\n"
    assert [p.name for p in installed.iterdir()] == ["opendrive_core.xsd"]
    assert (installed / "opendrive_core.xsd").read_text("utf-8") == STUB_XSD

    listing = cli("schemas", "list", code=0).stdout
    [line] = [line for line in listing.splitlines() if line.startswith("OpenDRIVE 1.7.0 schema")]
    assert line.endswith(f" {installed / 'opendrive_core.xsd'}  (from user data)")
    assert "built-in railroad schemas: 1.4 (railroad-1.4.xsd)" in listing

    document = report(BROKEN, "--select", "XS", code=0)  # the stand-in schema accepts anything
    schema = document["files"][0]["schema"]
    assert schema["builtin"] is False
    assert schema["description"] == (
        f"OpenDRIVE 1.7.0 schema ({installed / 'opendrive_core.xsd'}, from user data)"
    )
    assert document["notes"] == []


@pytest.mark.parametrize("kind", ["no-opendrive", "missing", "plain-file"])
def test_schemas_add_rejects_what_holds_no_schema(
    tmp_path: Path, isolated_schemas: Path, kind: str
) -> None:
    source = tmp_path / "source"
    if kind == "no-opendrive":
        (source / "1.7.0").mkdir(parents=True)
        (source / "1.7.0" / "other.xsd").write_text(STUB_XSD.replace("OpenDRIVE", "Other"), "utf-8")
    elif kind == "plain-file":
        source.write_text("hello", "utf-8")
    result = cli("schemas", "add", source, code=2)
    assert result.stderr.startswith(f"xodrlint: {source}: ")
    assert len(result.stderr.splitlines()) == 1
    assert not (isolated_schemas / "schemas").exists()


@pytest.mark.parametrize("as_zip", [False, True])
@pytest.mark.parametrize("limit", ["MAX_FILE_BYTES", "MAX_TOTAL_BYTES"])
def test_schemas_add_refuses_more_than_a_schema_set_can_hold(
    tmp_path: Path,
    isolated_schemas: Path,
    monkeypatch: pytest.MonkeyPatch,
    as_zip: bool,
    limit: str,
) -> None:
    # the real limits are 64 MiB a file and 256 MiB in all: a 1 MB zip held a 1 GiB XSD
    from xodrlint.validation import store

    monkeypatch.setattr(store, limit, len(STUB_XSD) + 10)
    source = stub_download(tmp_path / "download")
    (source / "1.7.0" / "opendrive_extra.xsd").write_text(STUB_XSD + " " * 20, "utf-8")
    if as_zip:
        source = zip_of(source, tmp_path / "download.zip")
    result = cli("schemas", "add", source, code=2)
    assert "refused" in result.stderr and len(result.stderr.splitlines()) == 1
    assert not (isolated_schemas / "schemas" / "1.7.0").exists()


def test_schemas_add_refuses_a_link_out_of_the_folder(
    tmp_path: Path, isolated_schemas: Path
) -> None:
    secret = tmp_path / "secret.txt"
    secret.write_text("password", "utf-8")
    source = stub_download(tmp_path / "download")
    (source / "1.7.0" / "zz.xsd").symlink_to(secret)
    result = cli("schemas", "add", source, code=2)
    assert (
        result.stderr
        == f"xodrlint: {source / '1.7.0' / 'zz.xsd'}: links outside {source}; refused\n"
    )
    assert not (isolated_schemas / "schemas" / "1.7.0").exists()


def test_schemas_add_reports_a_damaged_zip_as_a_usage_error(
    tmp_path: Path, isolated_schemas: Path
) -> None:
    archive = zip_of(stub_download(tmp_path / "download"), tmp_path / "download.zip")
    data = bytearray(archive.read_bytes())
    at = data.index(b"OpenDRIVE")  # stored uncompressed: flip a byte of the member
    data[at] ^= 0x20
    archive.write_bytes(bytes(data))
    result = cli("schemas", "add", archive, code=2)
    assert "a damaged zip file" in result.stderr and "CRC" in result.stderr


def test_stored_schemas_follow_the_umask_and_concurrent_adds_wait_their_turn(
    tmp_path: Path, isolated_schemas: Path
) -> None:
    from xodrlint.validation import store

    source = stub_download(tmp_path / "download")
    target = isolated_schemas / "schemas"
    old = os.umask(0o027)
    try:
        workers = [threading.Thread(target=store.add, args=(source, target)) for _ in range(4)]
        for worker in workers:
            worker.start()
        for worker in workers:
            worker.join()
    finally:
        os.umask(old)
    assert sorted(p.name for p in target.iterdir()) == ["1.7.0"]  # no staging folder left
    assert stat.S_IMODE((target / "1.7.0").stat().st_mode) == 0o750
    assert stat.S_IMODE((target / "1.7.0" / "opendrive_core.xsd").stat().st_mode) == 0o640


def fake_wheel(tmp_path: Path) -> Path:
    with zipfile.ZipFile(tmp_path / "fake.whl", "w") as handle:
        handle.writestr("qc_opendrive/schema/1.7.0/x.xsd", STUB_XSD)
        handle.writestr("qc_opendrive/__init__.py", "")
    return tmp_path / "fake.whl"


def test_schemas_fetch_without_a_network_says_which_index_it_could_not_reach(
    isolated_schemas: Path, monkeypatch: pytest.MonkeyPatch
) -> None:
    import socket

    with socket.socket() as probe:  # a port on the loopback interface that nobody serves
        probe.bind(("127.0.0.1", 0))
        port = probe.getsockname()[1]
    index = f"http://127.0.0.1:{port}/simple"
    monkeypatch.setenv("PIP_CONFIG_FILE", os.devnull)  # the machine's own indexes stay out
    for name in ("PIP_FIND_LINKS", "PIP_EXTRA_INDEX_URL", "PIP_NO_INDEX"):
        monkeypatch.delenv(name, raising=False)
    monkeypatch.setenv("PIP_INDEX_URL", index)
    result = cli("schemas", "fetch", code=2)
    assert result.stderr == (
        f"xodrlint: pip could not reach the package index {index} (127.0.0.1:{port}); "
        "without a network, 'xodrlint schemas add' takes an ASAM download (a folder or a zip)\n"
    )


def test_schemas_fetch_refuses_a_wheel_that_does_not_match_the_pin(
    tmp_path: Path, isolated_schemas: Path
) -> None:
    result = cli("schemas", "fetch", "--wheel", fake_wheel(tmp_path), code=2)
    assert "does not match the pinned" in result.stderr
    assert result.stderr.endswith("; not installed\n")
    assert not (isolated_schemas / "schemas").exists()


def test_install_wheel_installs_the_schemas_of_a_verified_wheel(tmp_path: Path) -> None:
    wheel = fake_wheel(tmp_path)
    target = tmp_path / "schemas"
    [item] = install_wheel(wheel, target, hashlib.sha256(wheel.read_bytes()).hexdigest())
    assert (item.version, item.folder, item.files) == ("1.7.0", target / "1.7.0", 1)
    assert [p.name for p in target.iterdir()] == ["1.7.0"]
    assert (target / "1.7.0" / "x.xsd").read_text("utf-8") == STUB_XSD


def console(*args: str | Path) -> subprocess.CompletedProcess[str]:
    if not CONSOLE_SCRIPT.is_file():
        pytest.skip(f"no console script at {CONSOLE_SCRIPT}")
    command = [str(CONSOLE_SCRIPT), *map(str, args)]
    env = {name: value for name, value in os.environ.items() if name not in PLAIN_ENV}
    return subprocess.run(command, capture_output=True, text=True, timeout=60, check=False, env=env)


def test_console_script_exit_codes_and_one_line_errors(tmp_path: Path) -> None:
    broken = console("check", BROKEN, "-q")
    assert broken.returncode == 1
    assert broken.stdout.splitlines()[0].startswith(f"{BROKEN}:25:7: XS006 [error] ")
    missing = console("check", tmp_path / "missing.xodr", CLEAN)
    assert missing.returncode == 2
    assert _without_notes(missing.stderr) == [
        f"xodrlint: {tmp_path / 'missing.xodr'}: no such file or directory"
    ]
    assert console("check", CLEAN).returncode == 0


@pytest.mark.parametrize("where", ["missing-folder", "a-folder"])
def test_an_unwritable_output_is_a_usage_error(tmp_path: Path, where: str) -> None:
    target = tmp_path / "no" / "such" / "report.json" if where == "missing-folder" else tmp_path
    result = console("check", CLEAN, "--output", target)
    assert (result.returncode, result.stderr.count("\n")) == (2, 1), result.stderr
    assert "internal error" not in result.stderr


def test_summary_does_not_claim_success_when_an_input_was_unreadable(tmp_path: Path) -> None:
    result = CliRunner().invoke(app, ["check", str(tmp_path / "gone.xodr"), str(CLEAN)])
    assert result.exit_code == 2
    assert "All checks passed" not in result.stdout
    assert "No findings in 1 of 2 files. 1 could not be read." in result.stdout


def test_readme_shows_the_real_output_of_the_broken_example(
    monkeypatch: pytest.MonkeyPatch,
) -> None:
    monkeypatch.chdir(REPO)
    readme = (REPO / "README.md").read_text("utf-8")
    shown = readme.split("Output for `examples/broken.xodr`", 1)[1].split("```text\n", 1)[1]
    shown = shown.split("```", 1)[0]
    done = cli("check", "examples/broken.xodr", code=1)
    assert done.stdout + done.stderr == shown


@pytest.mark.parametrize("meta", default_registry().metas, ids=lambda m: m.code)
def test_explain_works_for_every_rule(meta: Any) -> None:
    out = cli("explain", meta.code, code=0).stdout
    assert out.startswith(f"# {meta.code} {meta.name}\n")
    assert "## What it does" in out and meta.uid in out


def _command_paths() -> list[tuple[str, ...]]:
    """Every command of the app, by the words that invoke it (``schemas add``)."""
    import typer.main

    found: list[tuple[str, ...]] = [()]
    groups: list[tuple[tuple[str, ...], Any]] = [((), typer.main.get_command(app))]
    while groups:
        path, group = groups.pop()
        for name, command in getattr(group, "commands", {}).items():
            found.append((*path, name))
            groups.append(((*path, name), command))
    return sorted(found)


def _params_of(path: tuple[str, ...]) -> list[Any]:
    import typer.main

    command: Any = typer.main.get_command(app)
    for name in path:
        command = command.commands[name]
    return list(command.params)


#: What typer and click write where a parameter names no metavar of its own: its type
#: (<str>, <int range>) or choices (<auto|always|never>), TEXT, INTEGER, {name}.
HELP_PLACEHOLDERS = re.compile(r"<[a-z][a-z |]*>|\bTEXT\b|INTEGER|\{")
#: A metavar says what to give: FILE, PATH..., CODES, NAME=VALUE, K/N.
METAVAR = re.compile(r"[A-Z][A-Z0-9_]*([=/][A-Z]+)?(\.\.\.)?")


@pytest.mark.parametrize("path", _command_paths(), ids=" ".join)
def test_help_names_every_value_by_what_it_is(path: tuple[str, ...]) -> None:
    text = cli(*path, "--help", code=0).stdout
    assert not HELP_PLACEHOLDERS.search(text), text
    # every parameter that takes a value, options added later included, names it
    for param in _params_of(path):
        if getattr(param, "is_flag", False):
            continue
        assert param.metavar is not None and METAVAR.fullmatch(param.metavar), (
            path,
            param.name,
            param.metavar,
        )
        assert param.metavar in text, (path, param.metavar)


def test_rules_lists_every_rule_and_which_are_off_by_default() -> None:
    table, _, footnote = cli("rules", code=0).stdout.partition("\n\n")
    codes = [line.split()[0] for line in table.splitlines()[1:]]
    metas = default_registry().metas
    assert codes == [meta.code for meta in metas]
    # the registry holds a rule for each rule module of the built-in packs, no more
    modules = (REPO / "src" / "xodrlint" / "rules").glob("*/[a-z][a-z][0-9][0-9][0-9].py")
    assert sorted(codes) == sorted(module.stem.upper() for module in modules)
    opt_in = [meta.code for meta in metas if meta.opt_in]
    assert "XL001" in opt_in
    assert footnote == (
        f"Off by default (turn on with --extend-select): {', '.join(opt_in)}\n\n"
        "From OpenDRIVE 1.7 on (older files with --all-versions): RL001, RL002\n"
    )


@pytest.mark.parametrize(
    "args",
    [
        ["check", "--help"],
        ["check", "--bogus", "x.xodr"],
        ["check"],
        ["qc", "--help"],
        ["rules", "-f", "bad"],
        ["explain"],
        ["schemas", "list", "--help"],
        ["--version"],
    ],
)
def test_a_command_run_alone_reads_as_in_the_whole_app(args: list[str]) -> None:
    # the console script builds only the invoked command (a faster start): help, usage
    # errors and exit codes must not tell the difference
    alone = subprocess.run(
        [str(CONSOLE_SCRIPT), *args], capture_output=True, text=True, check=False, env=_plain_env()
    )
    whole_app = "import sys; from xodrlint.cli import app; app(prog_name='xodrlint')"
    whole = subprocess.run(
        [sys.executable, "-c", whole_app, *args],
        capture_output=True,
        text=True,
        check=False,
        env=_plain_env(),
    )
    assert (alone.stdout, alone.stderr, alone.returncode) == (
        whole.stdout,
        whole.stderr,
        whole.returncode,
    )


def _plain_env() -> dict[str, str]:
    return {**{k: v for k, v in os.environ.items() if k not in PLAIN_ENV}, "COLUMNS": "80"}


def test_only_the_invoked_command_is_built() -> None:
    from xodrlint.cli.entry import _invoked_alone

    alone = _invoked_alone(["check", "maps/"])
    assert alone is not None
    assert [info.callback.__name__ for info in alone.registered_commands] == ["check"]  # type: ignore[union-attr]
    assert _invoked_alone(["schemas", "list"]) is None  # a group keeps the whole app
    assert _invoked_alone(["--version"]) is None
    assert _invoked_alone([]) is None


def test_command_annotations_are_evaluated_once_at_import() -> None:
    # typer reads them on every run; a string annotation would cost an eval each
    from xodrlint.cli import schemas_app

    commands = [*app.registered_commands, *schemas_app.registered_commands]
    assert commands
    for info in commands:
        assert info.callback is not None
        annotations = inspect.get_annotations(info.callback)
        strings = [name for name, value in annotations.items() if isinstance(value, str)]
        assert not strings, f"{info.callback.__name__}: {strings}"


def test_python_dash_m_runs_the_command_and_a_spawned_worker_does_not() -> None:
    out = subprocess.run(
        [sys.executable, "-m", "xodrlint", "--version"], capture_output=True, text=True, check=True
    )
    assert out.stdout == f"xodrlint {__version__}\n"
    import runpy

    # a spawned worker imports the parent's main module under this name
    runpy.run_module("xodrlint", run_name="__mp_main__")


def test_the_entry_point_keeps_what_check_map_and_qc_need_not_free(tmp_path: Path) -> None:
    # the command line exits without tearing down (cli.entry): the last map's tree, and
    # the linter holding it, go into the list the entry point hands each command, and
    # nowhere else (a run of the API or of a test frees them with the run)
    from xodrlint.engine.linter import Linter

    commands = (
        ["check", str(CLEAN)],
        ["map", str(CLEAN), "-o", str(tmp_path / "m.html")],
        ["qc", str(CLEAN), "-o", str(tmp_path / "r.xqar")],
    )
    for args in commands:
        kept: list[object] = []
        result = CliRunner().invoke(app, args, obj=kept, env=PLAIN_ENV)
        assert result.exit_code == 0, result.stderr
        (linter,) = kept
        assert isinstance(linter, Linter)
        last = linter.last_document
        assert last is not None and last.document.path == str(CLEAN)


def test_main_hands_its_keep_alive_list_to_the_command(monkeypatch: pytest.MonkeyPatch) -> None:
    # the real path of `xodrlint check`: main builds the one command it runs
    # (_invoked_alone) and calls it with the list as the context's object
    from xodrlint.cli import entry
    from xodrlint.cli.check import run
    from xodrlint.engine.linter import Linter

    handed: list[list[object] | None] = []
    kept_linter = run._kept_linter

    def spy(registry: Any, options: Any, keep_alive: list[object] | None) -> Any:
        linter = kept_linter(registry, options, keep_alive)
        handed.append(keep_alive)
        return linter

    monkeypatch.setattr(run, "_kept_linter", spy)
    monkeypatch.setattr(sys, "argv", ["xodrlint", "check", "-q", str(CLEAN)])
    monkeypatch.setenv(entry.FAST_EXIT_ENV, "0")
    assert entry._invoked_alone(sys.argv[1:]) is not None
    with pytest.raises(SystemExit) as done:
        entry.main()
    assert done.value.code == 0
    (keep_alive,) = handed
    assert keep_alive is not None
    (linter,) = keep_alive
    assert isinstance(linter, Linter) and linter.last_document is not None


def test_schemas_fetch_without_pip_says_how_to_fetch_by_hand(
    isolated_schemas: Path, tmp_path: Path
) -> None:
    # some virtual-environment tools make environments without pip: a one-line answer
    # naming the wheel and --wheel, not "No module named pip"
    import subprocess
    import sys

    hide_pip = tmp_path / "hide_pip"
    hide_pip.mkdir()
    (hide_pip / "sitecustomize.py").write_text(
        "import sys\n"
        "class _NoPip:\n"
        "    def find_spec(self, name, path=None, target=None):\n"
        "        if name == 'pip' or name.startswith('pip.'):\n"
        "            raise ModuleNotFoundError(\"No module named 'pip'\")\n"
        "        return None\n"
        "sys.meta_path.insert(0, _NoPip())\n"
    )
    env = {**os.environ, "PYTHONPATH": f"{hide_pip}{os.pathsep}{os.environ.get('PYTHONPATH', '')}"}
    done = subprocess.run(
        [sys.executable, "-m", "xodrlint", "schemas", "fetch"],
        capture_output=True, text=True, env=env, check=False,
    )  # fmt: skip
    assert done.returncode == 2, done.stderr
    (line,) = done.stderr.splitlines()
    assert "pip is not installed in this environment" in line
    assert "asam_qc_opendrive-1.0.0-py3-none-any.whl" in line and "--wheel PATH" in line


def test_a_19_file_without_its_set_is_told_where_the_set_comes_from() -> None:
    from xodrlint.cli.check.notes import FULL_VALIDATION_NOTE, run_notes
    from xodrlint.findings import FileReport

    old = FileReport("a.xodr", declared_version="1.7", schema="built-in", schema_builtin=True)
    new = FileReport("b.xodr", declared_version="1.9", schema="built-in", schema_builtin=True)
    assert run_notes([old]) == (FULL_VALIDATION_NOTE,)
    (note,) = run_notes([new])
    assert "OpenDRIVE 1.9" in note and "schemas add PATH" in note and "1.8.0 only" in note
    assert note.startswith("only railroad elements were validated (built-in schema)")
    assert len(run_notes([old, new])) == 2
    official = FileReport("c.xodr", declared_version="1.9", schema="OpenDRIVE 1.9.0 schema")
    assert run_notes([official]) == ()


def _without_notes(stderr: str) -> list[str]:
    """``stderr``'s lines but the run's notes (what was not checked), which the text
    format says there after its report."""
    return [line for line in stderr.splitlines() if not line.startswith("xodrlint: note: ")]
