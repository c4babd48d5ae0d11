"""Memory a large validation freed is given back to the system, not kept at the run's
high-water mark while the rules build theirs (the 20 MB railway: 528 MB to 495 MB)."""

from __future__ import annotations

import ctypes
import ctypes.util
import sys

import pytest

from tests.conftest import SHARED_SCHEMAS, needs_shared
from xodrlint.concurrency import memory
from xodrlint.document.load import load_bytes
from xodrlint.validation import libxml2
from xodrlint.validation.sets import SchemaFinder


def test_glibc_is_asked_to_give_back_its_free_pages() -> None:
    if not sys.platform.startswith("linux") or not ctypes.util.find_library("c"):
        pytest.skip("malloc_trim is glibc's")
    try:
        ctypes.CDLL(None).malloc_trim  # noqa: B018  (musl has none)
    except AttributeError:
        pytest.skip("this C library has no malloc_trim")
    assert memory.give_back_freed_memory() is True


def test_without_malloc_trim_nothing_is_done(monkeypatch: pytest.MonkeyPatch) -> None:
    memory._malloc_trim.cache_clear()
    monkeypatch.setattr(sys, "platform", "darwin")
    try:
        assert memory.give_back_freed_memory() is False
    finally:
        memory._malloc_trim.cache_clear()


def _map(roads: int) -> bytes:
    road = (
        '<road id="{0}" length="10" junction="-1"><link/><planView>'
        '<geometry s="0" x="{0}" y="0" hdg="0" length="10"><line/></geometry></planView>'
        '<lanes><laneSection s="0"><center><lane id="0" type="none" level="false"/>'
        "</center></laneSection></lanes></road>"
    )
    body = "".join(road.format(number) for number in range(roads))
    return (
        f'<?xml version="1.0"?><OpenDRIVE><header revMajor="1" revMinor="7"/>{body}</OpenDRIVE>'
    ).encode()


@needs_shared
@pytest.mark.parametrize(("roads", "given_back"), [(10, 0), (6000, 1)])
def test_a_large_documents_validation_gives_back_what_it_freed(
    monkeypatch: pytest.MonkeyPatch, roads: int, given_back: int
) -> None:
    calls: list[bool] = []

    def give_back() -> bool:
        calls.append(True)
        return True

    monkeypatch.setattr(libxml2, "give_back_freed_memory", give_back)
    data = _map(roads)
    assert (len(data) >= memory.GIVE_BACK_FROM) == bool(given_back)
    schema = SchemaFinder(SHARED_SCHEMAS).find(1, 7)
    assert schema is not None
    doc = load_bytes(data, "map.xodr")
    list(libxml2.Libxml2Validator(schema.entry).hits(doc))
    assert len(calls) == given_back
