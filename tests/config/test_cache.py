"""The cache is input from outside the run: used only when it is the user's own, writable
by no one else and unchanged since it was written; anything else is rebuilt, said once."""

from __future__ import annotations

import json
import os
import pickle
import stat
from pathlib import Path

import pytest

from xodrlint.config import cache, plugins
from xodrlint.validation.xsd11.form import MANIFEST, full_validator, xsd10_form

NOBODY = 65534
needs_root = pytest.mark.skipif(
    not hasattr(os, "getuid") or os.getuid() != 0,
    reason="giving a file to another user takes root",
)

XSD11 = """<xs:schema xmlns:xs="http://www.w3.org/2001/XMLSchema"
    xmlns:vc="http://www.w3.org/2007/XMLSchema-versioning" vc:minVersion="1.1">
  <xs:element name="OpenDRIVE">
    <xs:complexType>
      <xs:sequence><xs:element name="header"/></xs:sequence>
      <xs:attribute name="a" type="xs:int"/>
      <xs:assert test="not(@a) or @a gt 0"/>
    </xs:complexType>
  </xs:element>
</xs:schema>
"""


@pytest.fixture(autouse=True)
def _fresh_warnings(monkeypatch: pytest.MonkeyPatch) -> None:
    monkeypatch.setattr(cache, "_warned", set())


def _entry(tmp_path: Path) -> Path:
    entry = tmp_path / "set" / "core.xsd"
    entry.parent.mkdir()
    entry.write_text(XSD11)
    return entry


def test_what_is_written_is_read_back_and_private_whatever_the_umask(tmp_path: Path) -> None:
    path = cache.root() / "deep" / "entry.bin"
    old = os.umask(0o002)
    try:
        assert cache.write(path, b"content")
    finally:
        os.umask(old)
    assert cache.read(path) == b"content"
    assert stat.S_IMODE(path.stat().st_mode) == 0o600
    assert stat.S_IMODE(path.parent.stat().st_mode) == 0o700


def test_an_altered_file_is_not_used(capsys: pytest.CaptureFixture[str]) -> None:
    path = cache.root() / "entry.bin"
    assert cache.write(path, b"content")
    path.write_bytes(path.read_bytes().replace(b"content", b"CONTENT"))
    assert cache.read(path) is None
    assert "does not hold what was written" in capsys.readouterr().err


@pytest.mark.parametrize("level", ["file", "folder", "root"])
def test_a_file_others_may_write_is_not_used(
    level: str, capsys: pytest.CaptureFixture[str]
) -> None:
    path = cache.root() / "sub" / "entry.bin"
    assert cache.write(path, b"content")
    target = {"file": path, "folder": path.parent, "root": cache.root()}[level]
    target.chmod(0o777 if target.is_dir() else 0o666)
    assert cache.read(path) is None
    assert capsys.readouterr().err.count("is writable by others") == 1
    assert cache.read(path) is None
    assert capsys.readouterr().err == ""  # said once per run


@needs_root
def test_a_file_of_another_user_is_not_used(capsys: pytest.CaptureFixture[str]) -> None:
    path = cache.root() / "entry.bin"
    assert cache.write(path, b"content")
    os.chown(path, NOBODY, NOBODY)
    assert cache.read(path) is None
    assert f"belongs to another user (uid {NOBODY})" in capsys.readouterr().err


class _Planted:
    """Unpickling this creates a file: proof that code ran."""

    def __init__(self, marker: Path) -> None:
        self.marker = marker

    def __reduce__(self) -> tuple[object, tuple[str, str]]:
        return (open, (str(self.marker), "w"))


@needs_root
def test_a_pickle_another_user_planted_is_never_unpickled(
    tmp_path: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    entry = _entry(tmp_path)
    marker = tmp_path / "code-ran"
    with xsd10_form(entry) as form:
        first = full_validator(entry, form)
        [pickled] = (cache.root() / "xsd10" / form.key).glob("*.pickle")
        # a well-formed entry, hash and all: only its owner gives it away
        assert cache.write(pickled, pickle.dumps(_Planted(marker)))
        os.chown(pickled, NOBODY, NOBODY)
        second = full_validator(entry, form)
    assert not marker.exists()
    assert type(second.schema) is type(first.schema)
    assert "belongs to another user" in capsys.readouterr().err


def test_a_pickle_of_another_type_is_built_again(
    tmp_path: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    entry = _entry(tmp_path)
    with xsd10_form(entry) as form:
        first = full_validator(entry, form)
        [pickled] = (cache.root() / "xsd10" / form.key).glob("*.pickle")
        assert cache.write(pickled, pickle.dumps({"not": "a schema"}))
        second = full_validator(entry, form)
        assert type(second.schema) is type(first.schema)
        assert "does not hold an XSD 1.1 schema model" in capsys.readouterr().err
        # and the entry is repaired: the next run unpickles it silently
        full_validator(entry, form)
    assert capsys.readouterr().err == ""


@pytest.mark.parametrize(
    "damage",
    [
        {"asserts": "many"},
        {"unsupported": [1, 2]},
        {"files": ["core.xsd"]},
        {"schema_checked": "yes"},
    ],
)
def test_a_manifest_of_another_shape_means_the_form_is_made_again(
    tmp_path: Path, damage: dict[str, object], capsys: pytest.CaptureFixture[str]
) -> None:
    entry = _entry(tmp_path)
    with xsd10_form(entry) as form:
        folder = cache.root() / "xsd10" / form.key
    manifest = json.loads((folder / MANIFEST).read_text())
    manifest.update(damage)
    (folder / MANIFEST).write_text(json.dumps(manifest))
    with xsd10_form(entry) as again:
        assert again.asserts == 1 and again.entry is not None and again.cached
    assert "manifest" not in capsys.readouterr().out
    with xsd10_form(entry):  # repaired
        pass
    assert capsys.readouterr().err == ""


def test_a_form_swapped_for_a_permissive_schema_is_not_used(
    tmp_path: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    entry = _entry(tmp_path)
    with xsd10_form(entry) as form:
        assert form.entry is not None
        strict = form.entry.read_bytes()
        form.entry.write_bytes(
            b'<xs:schema xmlns:xs="http://www.w3.org/2001/XMLSchema">'
            b'<xs:element name="OpenDRIVE"/></xs:schema>'
        )
    with xsd10_form(entry) as again:
        assert again.entry is not None and again.entry.read_bytes() == strict
    assert "does not hold what was written" in capsys.readouterr().err


def _plant_rule_packs(points: object) -> Path:
    """Rewrite this environment's entry-point cache, hash and all, so that it names
    ``points`` as the rule packs; returns the cache file."""
    plugins.installed("xodrlint.rules")
    path = plugins.cache_path()
    document = json.loads(cache.read(path) or b"")
    document["entries"][0]["groups"]["xodrlint.rules"] = points
    assert cache.write(path, json.dumps(document).encode())
    return path


def test_an_entry_point_cache_of_another_shape_is_scanned_again(
    capsys: pytest.CaptureFixture[str],
) -> None:
    _plant_rule_packs([[1, ["not", "a", "name"]]])
    names = {point.name for point in plugins.installed("xodrlint.rules")}
    assert {"switches", "tracks"} <= names
    assert "holds entries of another shape" in capsys.readouterr().err


@needs_root
def test_an_entry_point_cache_of_another_user_is_scanned_again(
    capsys: pytest.CaptureFixture[str],
) -> None:
    path = _plant_rule_packs([["evil", "os:system"]])
    os.chown(path, NOBODY, NOBODY)
    names = {point.name for point in plugins.installed("xodrlint.rules")}
    assert "evil" not in names and "switches" in names
    assert "belongs to another user" in capsys.readouterr().err
