"""Memory a large validation freed is given back to the system, not kept at the run's
high-water mark while the rules build theirs (the 20 MB railway: 528 MB to 495 MB)."""

from __future__ import annotations

import ctypes
import ctypes.util
import sys
import threading
import time
from collections.abc import Iterator
from types import SimpleNamespace
from typing import Any

import pytest

from tests.conftest import SHARED_SCHEMAS, needs_shared
from xodrlint.concurrency import memory
from xodrlint.document.load import Document, load_bytes
from xodrlint.findings import Hit
from xodrlint.validation import libxml2, validators
from xodrlint.validation.sets import SchemaFinder


def test_glibc_is_asked_to_give_back_its_free_pages() -> None:
    if not sys.platform.startswith("linux") or not ctypes.util.find_library("c"):
        pytest.skip("malloc_trim is glibc's")
    try:
        ctypes.CDLL(None).malloc_trim  # noqa: B018  (musl has none)
    except AttributeError:
        pytest.skip("this C library has no malloc_trim")
    assert memory.give_back_freed_memory() is True


@pytest.mark.parametrize("where", ["macOS", "musl"])
def test_without_malloc_trim_nothing_is_done(monkeypatch: pytest.MonkeyPatch, where: str) -> None:
    class Musl:  # a C library without malloc_trim: ctypes raises AttributeError
        def __getattr__(self, name: str) -> object:
            raise AttributeError(name)

    if where == "macOS":
        monkeypatch.setattr(memory, "sys", SimpleNamespace(platform="darwin"))
    else:
        monkeypatch.setattr(memory, "sys", SimpleNamespace(platform="linux"))
        fake_ctypes = SimpleNamespace(CDLL=lambda name: Musl())
        monkeypatch.setattr("xodrlint.concurrency.memory.ctypes", fake_ctypes)
    memory._malloc_trim.cache_clear()
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
@pytest.mark.parametrize(
    ("roads", "rules_still_run", "given_back"),
    [(6000, True, 1), (6000, False, 0), (10, True, 0)],
    ids=["large-while-the-rules-run", "large-once-the-caller-waits", "small"],
)
def test_validation_gives_back_what_it_freed_while_the_rules_still_run(
    monkeypatch: pytest.MonkeyPatch, roads: int, rules_still_run: bool, given_back: int
) -> None:
    # a railway: the rules outlast validation, and what it freed would add to their peak;
    # a city map: the caller already waits, and the call would only delay the end
    calls: list[bool] = []

    def give_back() -> bool:
        calls.append(True)
        return True

    monkeypatch.setattr(validators, "give_back_freed_memory", give_back)
    data = _map(roads)
    assert (len(data) >= memory.GIVE_BACK_FROM) == (roads > 10)
    doc = load_bytes(data, "map.xodr")
    started = threading.Event()
    may_end = threading.Event()
    real_hits = libxml2.Libxml2Validator.hits

    def hits(self: libxml2.Libxml2Validator, doc: Document) -> Iterator[Hit]:
        started.set()
        assert may_end.wait(30)
        return real_hits(self, doc)

    monkeypatch.setattr(libxml2.Libxml2Validator, "hits", hits)
    caller_came: list[threading.Event] = []
    real_giving_back = validators._giving_back

    def giving_back(work: Any, size: int, rules_done: threading.Event) -> Any:
        caller_came.append(rules_done)
        return real_giving_back(work, size, rules_done)

    monkeypatch.setattr(validators, "_giving_back", giving_back)
    checks = validators.SchemaValidators(SchemaFinder(SHARED_SCHEMAS))
    pending = checks.start(doc)
    assert started.wait(30)
    if rules_still_run:  # validation ends first, then the caller comes for it
        may_end.set()
        deadline = time.monotonic() + 30
        while not calls and given_back and time.monotonic() < deadline:
            time.sleep(0.001)
        check = pending.result()
    else:  # the caller waits before validation ends

        def end_once_the_caller_waits() -> None:
            assert caller_came[0].wait(30)
            may_end.set()

        waiting = threading.Thread(target=end_once_the_caller_waits)
        waiting.start()
        check = pending.result()
        waiting.join()
    assert check is not None and check.hits == ()
    assert len(calls) == given_back
