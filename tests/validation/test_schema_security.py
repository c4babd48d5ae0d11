"""Issue 30, items 2 and 4: a schema set is hostile input. It may come from a folder
xodrlint was merely opened in (a workspace's ``xodrlint.toml`` names it), so no file of it
pulls another file's content into a message, reaches outside the set's folder, blocks
the run or fills the memory; libxml2 compiles exactly the bytes xodrlint checked."""

from __future__ import annotations

import os
import subprocess
import sys
from pathlib import Path

import pytest

from xodrlint.api import default_registry
from xodrlint.engine.linter import Linter, LintOptions
from xodrlint.validation import libxml2
from xodrlint.validation.sets import MAX_SCHEMA_FILE_BYTES, SchemaLoadError
from xodrlint.validation.source import SchemaSource, read_schema_source

SECRET = "TOPSECRET-4711"

ENTRY = """<xs:schema xmlns:xs="http://www.w3.org/2001/XMLSchema">
  <xs:include schemaLocation="{location}"/>
  <xs:element name="OpenDRIVE"><xs:complexType><xs:sequence>
    <xs:any processContents="skip" minOccurs="0" maxOccurs="unbounded"/>
  </xs:sequence><xs:attribute name="kind" type="t_kind"/></xs:complexType></xs:element>
</xs:schema>
"""
PART = """<?xml version="1.0"?>
{doctype}<xs:schema xmlns:xs="http://www.w3.org/2001/XMLSchema">
  <xs:simpleType name="t_kind"><xs:restriction base="xs:string">
    <xs:enumeration value="{value}"/>
  </xs:restriction></xs:simpleType>
</xs:schema>
"""
#: The reviewer's exploit: a parameter entity from a DTD of the attacker's, which
#: declares a general entity holding a local file's content.
LEAKING_DOCTYPE = '<!DOCTYPE xs:schema [<!ENTITY % p SYSTEM "evil.dtd"> %p;]>\n'
EVIL_DTD = """<!ENTITY % s SYSTEM "file://{secret}">
<!ENTITY % d "<!ENTITY leak '%s;'>">
%d;
"""
MAP = '<?xml version="1.0"?>\n<OpenDRIVE kind="x"><header revMajor="1" revMinor="7"/></OpenDRIVE>\n'


def _cli(
    *args: str, cwd: Path | None = None, timeout: float = 120
) -> subprocess.CompletedProcess[str]:
    return subprocess.run(
        [sys.executable, "-m", "xodrlint", *args],
        check=False,
        capture_output=True,
        text=True,
        cwd=cwd,
        timeout=timeout,
        env={**os.environ, "XODRLINT_SCHEMA_PATH": "", "XODRLINT_FORK": "0"},
    )


def _leaking_set(folder: Path) -> Path:
    secret = folder / "secret.txt"
    secret.write_text(SECRET)
    (folder / "evil.dtd").write_text(EVIL_DTD.format(secret=secret))
    (folder / "part.xsd").write_text(PART.format(doctype=LEAKING_DOCTYPE, value="&leak;"))
    entry = folder / "core.xsd"
    entry.write_text(ENTRY.format(location="part.xsd"))
    (folder / "m.xodr").write_text(MAP)
    return entry


def _refused(done: subprocess.CompletedProcess[str], *words: str) -> str:
    assert done.returncode == 2, (done.stdout, done.stderr)
    assert SECRET not in done.stdout + done.stderr
    (line,) = done.stderr.splitlines()
    assert "Traceback" not in line
    for word in words:
        assert word in line, line
    return line


def test_an_include_with_a_doctype_cannot_pull_a_local_file_into_a_message(
    tmp_path: Path,
) -> None:
    entry = _leaking_set(tmp_path)
    done = _cli("check", "--schema", str(entry), str(tmp_path / "m.xodr"))
    _refused(done, str(tmp_path / "part.xsd"), "DOCTYPE")


def test_a_workspace_config_naming_such_a_set_is_refused_the_same(tmp_path: Path) -> None:
    _leaking_set(tmp_path)
    (tmp_path / "xodrlint.toml").write_text('schema = "core.xsd"\n')
    done = _cli("check", "m.xodr", cwd=tmp_path)
    _refused(done, "DOCTYPE")


def test_a_doctype_in_the_entry_itself_is_refused(tmp_path: Path) -> None:
    entry = tmp_path / "core.xsd"
    entry.write_text(
        '<?xml version="1.0"?>\n<!DOCTYPE xs:schema [<!ENTITY x "y">]>\n'
        + ENTRY.format(location="part.xsd")
    )
    (tmp_path / "part.xsd").write_text(PART.format(doctype="", value="a"))
    (tmp_path / "m.xodr").write_text(MAP)
    _refused(_cli("check", "--schema", str(entry), str(tmp_path / "m.xodr")), "DOCTYPE")


@pytest.mark.parametrize(
    "location",
    [
        "{outside}/part.xsd",
        "file://{outside}/part.xsd",
        "../outside/part.xsd",
        "http://127.0.0.1:9/part.xsd",
        "link/part.xsd",
    ],
    ids=["absolute", "file-url", "dotdot", "http", "symlink-out"],
)
def test_a_set_reads_only_files_inside_its_own_folder(tmp_path: Path, location: str) -> None:
    outside = tmp_path / "outside"
    outside.mkdir()
    (outside / "part.xsd").write_text(PART.format(doctype="", value="a"))
    inside = tmp_path / "set"
    inside.mkdir()
    (inside / "link").symlink_to(outside)
    entry = inside / "core.xsd"
    entry.write_text(ENTRY.format(location=location.format(outside=outside)))
    (tmp_path / "m.xodr").write_text(MAP)
    line = _refused(_cli("check", "--schema", str(entry), str(tmp_path / "m.xodr")))
    assert "own folder" in line and str(inside) in line


def test_a_set_may_include_files_of_its_subfolders(tmp_path: Path) -> None:
    (tmp_path / "parts").mkdir()
    (tmp_path / "parts" / "part.xsd").write_text(PART.format(doctype="", value="x"))
    entry = tmp_path / "core.xsd"
    entry.write_text(ENTRY.format(location="parts/part.xsd"))
    (tmp_path / "m.xodr").write_text(MAP)
    done = _cli("check", "--schema", str(entry), str(tmp_path / "m.xodr"), "--select", "XS")
    assert done.returncode == 0, done.stdout + done.stderr


def test_libxml2_compiles_the_bytes_that_were_checked(
    tmp_path: Path, monkeypatch: pytest.MonkeyPatch
) -> None:
    # the include is swapped for the leaking one between xodrlint's read and libxml2's
    # compile: what is compiled is still what was read and checked
    (tmp_path / "part.xsd").write_text(PART.format(doctype="", value="x"))
    entry = tmp_path / "core.xsd"
    entry.write_text(ENTRY.format(location="part.xsd"))
    (tmp_path / "m.xodr").write_text(MAP)
    read = read_schema_source

    def read_then_swap(path: Path) -> SchemaSource:
        source = read(path)
        _leaking_set(tmp_path)
        return source

    monkeypatch.setattr("xodrlint.validation.libxml2.read_schema_source", read_then_swap)
    linter = Linter(default_registry(), LintOptions(select=("XS",), schema=entry))
    # kind="x" is valid by the bytes read; by the swapped file it would be an XS006
    # naming the secret
    assert linter.lint_path(tmp_path / "m.xodr").findings == ()


def test_an_include_of_a_device_is_refused_without_reading_it(tmp_path: Path) -> None:
    entry = tmp_path / "core.xsd"
    entry.write_text(ENTRY.format(location="zero.xsd"))
    (tmp_path / "zero.xsd").symlink_to("/dev/zero")  # inside the folder by name only
    (tmp_path / "m.xodr").write_text(MAP)
    _refused(_cli("check", "--schema", str(entry), str(tmp_path / "m.xodr"), timeout=60))


def test_a_fifo_named_as_the_schema_does_not_block_the_run(tmp_path: Path) -> None:
    os.mkfifo(tmp_path / "core.xsd")
    (tmp_path / "m.xodr").write_text(MAP)
    done = _cli(
        "check", "--schema", str(tmp_path / "core.xsd"), str(tmp_path / "m.xodr"), timeout=60
    )
    _refused(done, "FIFO")


def test_a_fifo_in_a_schema_folder_does_not_block_the_run(tmp_path: Path) -> None:
    schemas = tmp_path / "schemas"
    schemas.mkdir()
    os.mkfifo(schemas / "a.xsd")
    (tmp_path / "m.xodr").write_text(MAP)
    done = _cli("check", "--schema", str(schemas), str(tmp_path / "m.xodr"), timeout=60)
    assert done.returncode in (0, 1), done.stderr  # no set there: the built-in schema


def test_a_schema_file_larger_than_the_cap_is_refused(tmp_path: Path) -> None:
    huge = tmp_path / "part.xsd"
    with huge.open("wb") as stream:
        stream.truncate(MAX_SCHEMA_FILE_BYTES + 1)  # sparse: no disk spent
    entry = tmp_path / "core.xsd"
    entry.write_text(ENTRY.format(location="part.xsd"))
    with pytest.raises(SchemaLoadError, match="larger than"):
        libxml2.Libxml2Validator(entry)
