"""Files crafted against XML parsers, and files that are broken or odd: each is answered
with one finding, in bounded time and memory, and nothing outside the file is read.

The attacks run the real console script in a child process with a time limit (a hang
fails the test instead of stalling the suite) and a cap on its address space (a parser
that expanded a bomb or kept a giant node would run out of it)."""

from __future__ import annotations

import codecs
import json
import os
import resource
import socket
import subprocess
import sys
from collections.abc import Iterator
from pathlib import Path
from typing import Any

import pytest
from lxml import etree

from xodrlint.api import lint_bytes
from xodrlint.document.load import load_bytes
from xodrlint.messages import MAX_MESSAGE_LENGTH

from .wellformed import assert_well_formed

CONSOLE_SCRIPT = Path(sys.executable).parent / "xodrlint"
#: Far more than a lint of a few MB needs, far less than an expanded bomb.
ADDRESS_SPACE_LIMIT = 2 * 1024**3
#: A hang guard, not a timing assertion: each attack takes well under a second.
HANG_GUARD_SECONDS = 60
SECRET = "xodrlint-test-secret-4711"
HEADER = '<header revMajor="1" revMinor="7"/>'
LIBXML2_HUGE_TEXT = 10_000_000


@pytest.fixture
def listener() -> Iterator[socket.socket]:
    """A local TCP port that records whether anything (libxml2 included) connects."""
    server = socket.socket(socket.AF_INET, socket.SOCK_STREAM)
    server.bind(("127.0.0.1", 0))
    server.listen(8)
    server.setblocking(False)
    yield server
    server.close()


def _accepted(server: socket.socket) -> bool:
    try:
        connection, _ = server.accept()
    except BlockingIOError:
        return False
    connection.close()
    return True


def _lint_in_child(path: Path) -> tuple[subprocess.CompletedProcess[str], dict[str, Any]]:
    if not CONSOLE_SCRIPT.is_file():
        pytest.skip(f"no console script at {CONSOLE_SCRIPT}")

    def cap_memory() -> None:
        resource.setrlimit(resource.RLIMIT_AS, (ADDRESS_SPACE_LIMIT, ADDRESS_SPACE_LIMIT))

    done = subprocess.run(
        [str(CONSOLE_SCRIPT), "check", "-f", "json", "--isolated", str(path)],
        capture_output=True,
        text=True,
        timeout=HANG_GUARD_SECONDS,
        check=False,
        preexec_fn=cap_memory,
    )
    return done, json.loads(done.stdout)


def _secret_file(tmp_path: Path) -> Path:
    secret = tmp_path / "secret.txt"
    secret.write_text(SECRET, "utf-8")
    return secret


def _attacks(tmp_path: Path, port: int) -> dict[str, str]:
    secret = _secret_file(tmp_path).as_uri()
    fifo = tmp_path / "blocking.dtd"
    os.mkfifo(fifo)  # were the external DTD ever opened, the child would hang on it
    dtd = tmp_path / "defaults.dtd"
    dtd.write_text(f'<!ATTLIST header name CDATA "{SECRET}">', "utf-8")
    laughs = '<!ENTITY a0 "lol">' + "".join(
        f'<!ENTITY a{i} "{f"&a{i - 1};" * 10}">' for i in range(1, 10)
    )
    body = f'<OpenDRIVE>{HEADER}<road id="1" length="1" name="&a9;"/></OpenDRIVE>'
    return {
        "xxe-file": f'<!DOCTYPE OpenDRIVE [<!ENTITY x SYSTEM "{secret}">]>\n'
        f'<OpenDRIVE>{HEADER}<road id="1" name="&x;"/></OpenDRIVE>',
        "xxe-file-in-text": f'<!DOCTYPE OpenDRIVE [<!ENTITY x SYSTEM "{secret}">]>\n'
        f"<OpenDRIVE>{HEADER}<userData>&x;</userData></OpenDRIVE>",
        "xxe-http": f'<!DOCTYPE OpenDRIVE [<!ENTITY x SYSTEM "http://127.0.0.1:{port}/x">]>\n'
        f"<OpenDRIVE>{HEADER}<userData>&x;</userData></OpenDRIVE>",
        "parameter-entity": f'<!DOCTYPE OpenDRIVE [<!ENTITY % p SYSTEM "http://127.0.0.1:{port}/p">%p;]>\n'
        f"<OpenDRIVE>{HEADER}</OpenDRIVE>",
        "external-dtd-http": f'<!DOCTYPE OpenDRIVE SYSTEM "http://127.0.0.1:{port}/d.dtd">\n'
        f"<OpenDRIVE>{HEADER}</OpenDRIVE>",
        "external-dtd-fifo": f'<!DOCTYPE OpenDRIVE SYSTEM "{fifo.as_uri()}">\n'
        f"<OpenDRIVE>{HEADER}<road/></OpenDRIVE>",
        "external-dtd-defaults": f'<!DOCTYPE OpenDRIVE SYSTEM "{dtd.as_uri()}">\n'
        f"<OpenDRIVE>{HEADER}<road/></OpenDRIVE>",
        "xinclude": '<OpenDRIVE xmlns:xi="http://www.w3.org/2001/XInclude">'
        f'{HEADER}<xi:include href="{secret}" parse="text"/>'
        f'<xi:include href="http://127.0.0.1:{port}/i.xml"/></OpenDRIVE>',
        "billion-laughs": f"<!DOCTYPE OpenDRIVE [{laughs}]>\n{body}",
        "quadratic-blowup": f'<!DOCTYPE OpenDRIVE [<!ENTITY a "{"x" * 50_000}">]>\n'
        f'<OpenDRIVE>{HEADER}<road name="{"&a;" * 50_000}"/></OpenDRIVE>',
    }


def test_attacks_are_answered_without_reading_anything_outside_the_file(
    tmp_path: Path, listener: socket.socket
) -> None:
    port = listener.getsockname()[1]
    for name, text in _attacks(tmp_path, port).items():
        path = tmp_path / f"{name}.xodr"
        path.write_text(text, "utf-8")
        done, report = _lint_in_child(path)
        assert done.returncode in (0, 1), (name, done.stderr)
        assert SECRET not in done.stdout + done.stderr, name
        assert "Traceback" not in done.stderr, name
        assert not _accepted(listener), f"{name}: something connected to the network"
        [file] = report["files"]
        assert file["error"] is None, name


@pytest.mark.parametrize("name", ["billion-laughs", "quadratic-blowup"])
def test_entity_bombs_are_one_xs001_naming_the_limit(tmp_path: Path, name: str) -> None:
    doc = load_bytes(_attacks(tmp_path, 9)[name].encode(), f"{name}.xodr")
    [hit] = doc.problems["XS001"]
    assert list(doc.problems) == ["XS001"]
    assert "entity" in hit.message and "safety limit" in hit.message, hit.message
    assert hit.line == 2


def test_unloaded_dtd_leaves_its_defaults_out(tmp_path: Path) -> None:
    """lxml reads DTD defaults on attribute access: the DTD must never have been read."""
    text = _attacks(tmp_path, 9)["external-dtd-defaults"]
    doc = load_bytes(text.encode(), "dtd.xodr")
    header = doc.root.find("header") if doc.root is not None else None
    assert header is not None and header.get("name") is None


def test_xinclude_stays_an_unexpanded_element(tmp_path: Path) -> None:
    doc = load_bytes(_attacks(tmp_path, 9)["xinclude"].encode(), "xi.xodr")
    assert doc.root is not None
    includes = doc.root.findall("{http://www.w3.org/2001/XInclude}include")
    assert len(includes) == 2
    assert SECRET not in etree.tostring(doc.root, encoding="unicode")


def _deep() -> bytes:
    return f"<OpenDRIVE>{HEADER}\n{'<a>' * 100_000}{'</a>' * 100_000}</OpenDRIVE>".encode()


def _giant_attribute() -> bytes:
    return (
        f'<OpenDRIVE>{HEADER}\n<road name="{"x" * (LIBXML2_HUGE_TEXT + 1)}"/></OpenDRIVE>'.encode()
    )


def _giant_text() -> bytes:
    return f"<OpenDRIVE>{HEADER}\n<userData>{'x' * (LIBXML2_HUGE_TEXT + 1)}</userData></OpenDRIVE>".encode()


def _giant_name() -> bytes:
    return f"<OpenDRIVE>{HEADER}\n<{'x' * 60_000}/></OpenDRIVE>".encode()


@pytest.mark.parametrize("build", [_deep, _giant_attribute, _giant_text, _giant_name])
def test_parser_limits_are_one_readable_xs001_on_their_line(build: object) -> None:
    assert callable(build)
    doc = load_bytes(build(), "huge.xodr")
    assert list(doc.problems) == ["XS001"]
    [hit] = doc.problems["XS001"]
    assert hit.line == 2
    assert "safety limit" in hit.message, hit.message
    assert "XML_PARSE_HUGE" not in hit.message and "xmlCtxt" not in hit.message
    assert len(hit.message) <= MAX_MESSAGE_LENGTH + 60 and hit.message.isprintable()


@pytest.mark.parametrize("build", [_deep, _giant_attribute, _giant_text])
def test_parser_limits_hold_in_bounded_memory(tmp_path: Path, build: object) -> None:
    assert callable(build)
    path = tmp_path / "huge.xodr"
    path.write_bytes(build())
    done, report = _lint_in_child(path)
    assert done.returncode == 1, done.stderr
    [finding] = report["findings"]
    assert (finding["code"], finding["line"]) == ("XS001", 2)


def _utf16(text: str, codec: str, bom: bytes = b"") -> bytes:
    return bom + text.encode(codec)


VALID = f'<?xml version="1.0" encoding="UTF-8"?>\n<OpenDRIVE>\n  {HEADER}\n</OpenDRIVE>\n'
UTF16_DECLARED = VALID.replace("UTF-8", "UTF-16")
# (contents, the one code expected or None for a clean file, its line)
ODD_FILES = {
    "empty": (b"", "XS001", 1),
    "whitespace only": (b" \r\n\t\n   ", "XS001", 3),
    "binary": (bytes(range(256)) * 4, "XS001", 1),
    "a csv named .xodr": (b"id,name,length\n1,main,100\n", "XS001", 1),
    "invalid utf-8 in the header": (
        VALID.replace("<header", "<header name='\xff'").encode("latin-1"),
        "XS001",
        3,
    ),
    "invalid utf-8 after the header": (
        VALID.replace("</OpenDRIVE>", "<userData>\x80\x81</userData></OpenDRIVE>").encode(
            "latin-1"
        ),
        "XS001",
        4,
    ),
    "utf-16 with a bom": (_utf16(UTF16_DECLARED, "utf-16-le", codecs.BOM_UTF16_LE), None, 0),
    "utf-16 without a bom": (_utf16(UTF16_DECLARED, "utf-16-be"), None, 0),
    "utf-16 cut in half a character": (
        _utf16(UTF16_DECLARED, "utf-16-le", codecs.BOM_UTF16_LE)[:-3],
        "XS001",
        4,
    ),
    "utf-16 with a wrong root": (
        _utf16(
            UTF16_DECLARED.replace("OpenDRIVE", "OpenSCENARIO"), "utf-16-be", codecs.BOM_UTF16_BE
        ),
        "XS002",
        2,
    ),
    "latin-1 bytes declared utf-8": (
        VALID.replace("<header", "<header name='Straße'").encode("latin-1"),
        "XS001",
        3,
    ),
    "utf-8 bytes declared utf-16": (UTF16_DECLARED.encode("utf-8"), "XS001", 1),
    "an unknown encoding declared": (VALID.replace("UTF-8", "EBCDIC-XYZ").encode(), "XS001", 1),
    "comments and a pi before the root": (
        VALID.replace("<OpenDRIVE>", "<!-- exported -->\n<?tool v=2?>\n<OpenDRIVE>").encode(),
        None,
        0,
    ),
    "a declaration after a comment": (b"<!-- c -->\n" + VALID.encode(), "XS001", 2),
    "a wrong root after comments": (
        VALID.replace("<OpenDRIVE>", "<!-- x -->\n<OpenSCENARIO>")
        .replace("</OpenDRIVE>", "</OpenSCENARIO>")
        .encode(),
        "XS002",
        3,
    ),
    "a namespaced root": (
        VALID.replace("<OpenDRIVE>", '<OpenDRIVE xmlns="urn:not-asam">').encode(),
        "XS002",
        2,
    ),
    "a prefixed root": (
        VALID.replace("<OpenDRIVE>", '<o:OpenDRIVE xmlns:o="urn:x">')
        .replace("</OpenDRIVE>", "</o:OpenDRIVE>")
        .encode(),
        "XS002",
        2,
    ),
}


@pytest.mark.parametrize(("data", "code", "line"), ODD_FILES.values(), ids=list(ODD_FILES))
def test_odd_files_give_exactly_one_finding_with_its_line(
    data: bytes, code: str | None, line: int
) -> None:
    report = lint_bytes(data, "odd.xodr")
    assert_well_formed(report)
    found = [(finding.code, finding.line) for finding in report.findings]
    assert found == ([] if code is None else [(code, line)])
