"""Bounded fuzzing in the suite: valid maps mutated byte by byte and with hostile XML
spliced in never make an exception escape, and every result is well formed. (Attribute
and element mutations are in test_robustness.py; long runs use tests/fuzz/fuzz_lint.py.)

Also the inputs the atheris harness found, as regression tests."""

from __future__ import annotations

from pathlib import Path

from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st

from xodrlint.api import lint_bytes

from .test_robustness import LINTER, SOURCES
from .wellformed import assert_well_formed

FUZZ = settings(
    max_examples=150,
    deadline=None,
    suppress_health_check=[HealthCheck.too_slow, HealthCheck.data_too_large],
)
HOSTILE_MARKUP = (
    b'<!DOCTYPE OpenDRIVE [<!ENTITY a "&#38;#60;"><!ENTITY x SYSTEM "file:///etc/passwd">]>',
    b"&a;",
    b"&x;",
    b"&#0;",
    b"&#x110000;",
    b"<![CDATA[<road id='1'/>]]>",
    b"<?xml version='1.0'?>",
    b"<?pi <road/>?>",
    b"<!-- <switch id='9'> -- -->",
    b"<!-- xodrlint: ignore[",
    b'<x:road xmlns:x="urn:x" id="1"/>',
    b"</road>",
    b"<road>",
    b"\x00",
    b"\xef\xbb\xbf",
    b"\xff\xfe",
    b"\r",
    b"\xc2\x85\xe2\x80\xa8",
    b'id="1" id="1"',
    b'="\x7f\x9b[31m"',
)

byte_edit = st.tuples(
    st.sampled_from(["flip", "insert", "delete", "splice", "cut"]),
    st.integers(min_value=0, max_value=1 << 20),
    st.binary(min_size=1, max_size=8),
    st.sampled_from(HOSTILE_MARKUP),
)


def _edit(data: bytes, change: tuple[str, int, bytes, bytes]) -> bytes:
    kind, where, noise, markup = change
    at = where % (len(data) + 1)
    if kind == "flip" and data:
        at %= len(data)
        return data[:at] + bytes([data[at] ^ noise[0]]) + data[at + 1 :]
    if kind == "insert":
        return data[:at] + noise + data[at:]
    if kind == "delete":
        return data[:at] + data[at + len(noise) :]
    if kind == "splice":  # hostile markup where a tag starts, or anywhere
        tag = data.find(b"<", at)
        at = tag if tag >= 0 else at
        return data[:at] + markup + data[at:]
    return data[:at]


@FUZZ
@given(source=st.sampled_from(SOURCES), changes=st.lists(byte_edit, min_size=1, max_size=5))
def test_byte_level_mutations_never_escape(
    source: Path, changes: list[tuple[str, int, bytes, bytes]]
) -> None:
    data = source.read_bytes()
    for change in changes:
        data = _edit(data, change)
    assert_well_formed(LINTER.lint_bytes(data, source.name))


@FUZZ
@given(data=st.binary(max_size=2048))
def test_arbitrary_bytes_never_escape(data: bytes) -> None:
    assert_well_formed(LINTER.lint_bytes(data, "noise.xodr"))


# Found by tests/fuzz/fuzz_lint.py ------------------------------------------------------

HEADER = '<header revMajor="1" revMinor="7"/>'


def test_a_parser_message_quoting_several_lines_stays_one_line() -> None:
    """libxml2 quotes the comment it failed on, line breaks and all."""
    data = f"<OpenDRIVE>{HEADER}\n<!-- expect -- \n  </planView>\n  <lanes>\n-->\n</OpenDRIVE>"
    report = lint_bytes(data.encode(), "comment.xodr")
    assert_well_formed(report)
    [finding] = report.findings
    assert finding.message == "double hyphen within comment: <!-- expect"


def test_control_characters_in_quoted_values_are_escaped() -> None:
    """A schema message quoted a value of DEL characters; a C1 CSI could steer a terminal."""
    data = (
        f'<OpenDRIVE>{HEADER}<road id="1" length="10"><railroad>'
        '<switch name="W\u2028" id="7" position="dyn\x7f\x9b[2J">'
        '<mainTrack id="1" s="0" dir="+"/><sideTrack id="1" s="0" dir="+"/></switch>'
        "</railroad></road></OpenDRIVE>"
    )
    report = lint_bytes(data.encode(), "controls.xodr")
    assert_well_formed(report)
    [position] = [f for f in report.findings if "position" in f.message]
    assert "'dyn\\x7f\\x9b[2J'" in position.message
