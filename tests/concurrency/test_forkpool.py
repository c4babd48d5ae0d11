"""The forked worker pool: every piece once, errors raised, deaths contained, nothing left
behind (no child process, no open pipe)."""

from __future__ import annotations

import os
import time
from collections.abc import Iterator
from pathlib import Path

import pytest

from tests.conftest import record_forks
from xodrlint.concurrency.forkpool import IN_FLIGHT, run_pieces

pytestmark = pytest.mark.skipif(not hasattr(os, "fork"), reason="needs os.fork")


def _open_fds() -> set[str]:
    fds = Path("/proc/self/fd")
    return {entry.name for entry in fds.iterdir()} if fds.is_dir() else set()


@pytest.fixture(autouse=True)
def _nothing_left_behind(monkeypatch: pytest.MonkeyPatch) -> Iterator[None]:
    forked = record_forks(monkeypatch)
    before = _open_fds()
    yield
    assert _open_fds() <= before, "a pipe was left open"
    for pid in forked:  # every worker was waited for (other tests' children are theirs)
        with pytest.raises(ChildProcessError):
            os.waitpid(pid, os.WNOHANG)


def _square_with_pid(number: int) -> tuple[int, int]:
    return number * number, os.getpid()


def test_every_piece_is_run_once_in_the_workers() -> None:
    delivered: dict[int, tuple[int, int]] = {}

    def deliver(number: int, value: tuple[int, int]) -> None:
        assert number not in delivered
        delivered[number] = value

    assert run_pieces(50, _square_with_pid, 2, deliver) == []
    assert sorted(delivered) == list(range(50))
    assert all(square == number * number for number, (square, _) in delivered.items())
    workers = {pid for _, pid in delivered.values()}
    assert len(workers) == 2 and os.getpid() not in workers


def test_more_workers_than_pieces_and_no_pieces() -> None:
    delivered: list[int] = []
    assert run_pieces(2, _square_with_pid, 8, lambda n, _: delivered.append(n)) == []
    assert sorted(delivered) == [0, 1]
    assert run_pieces(0, _square_with_pid, 2, lambda n, _: delivered.append(n)) == []


def _fail_on_seven(number: int) -> int:
    if number == 7:
        raise ValueError(f"piece {number} is bad")
    return number


def test_an_exception_in_a_worker_is_raised_in_the_parent() -> None:
    with pytest.raises(ValueError, match="piece 7 is bad"):
        run_pieces(20, _fail_on_seven, 2, lambda *_: None)


class _Unpicklable(Exception):
    def __reduce__(self) -> str | tuple[object, ...]:
        raise TypeError("cannot pickle this")


def _fail_unpicklably(number: int) -> int:
    raise _Unpicklable(f"lost in transit {number}")


def test_an_exception_that_cannot_cross_processes_still_says_what_it_was() -> None:
    with pytest.raises(RuntimeError, match="_Unpicklable: lost in transit"):
        run_pieces(1, _fail_unpicklably, 1, lambda *_: None)


def _die_on_five(number: int) -> int:
    if number == 5:
        os._exit(70)  # as a crash in a C library would
    return number


def test_a_dying_worker_loses_only_the_pieces_it_held() -> None:
    delivered: list[int] = []
    died = run_pieces(30, _die_on_five, 2, lambda n, _: delivered.append(n))
    assert 5 in died
    assert len(died) <= IN_FLIGHT
    assert sorted(delivered + died) == list(range(30))  # a new worker took over the rest


def _sleep(number: int) -> int:
    time.sleep(30)
    return number


def test_an_interrupted_run_stops_its_workers_at_once() -> None:
    def interrupt(*_: object) -> None:
        raise KeyboardInterrupt

    started = time.perf_counter()
    with pytest.raises(KeyboardInterrupt):
        run_pieces(3, lambda n: n if n == 0 else _sleep(n), 2, interrupt)
    assert time.perf_counter() - started < 10
