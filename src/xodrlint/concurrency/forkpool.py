"""Forked worker processes, each handed its next piece of work by the parent.

Batch runs on POSIX use this instead of ``concurrent.futures.ProcessPoolExecutor``:
importing the executor (``multiprocessing``, ``concurrent.futures``, ``logging``) cost
a batch run 11-35 ms before its first file, and its bounded call queue, fed by a thread
of the parent, made workers wait between messages. Here the parent does nothing but
hand out work, so it answers at once; and a worker that dies costs only the pieces it
held, not the whole pool, because a fresh worker takes its place.

Each worker has two pipes: pieces come in as numbers, results go out as pickles. The
parent keeps :data:`IN_FLIGHT` pieces queued at each worker so that none waits for it.
"""

from __future__ import annotations

import contextlib
import os
import selectors
import signal
import struct
from collections import deque
from collections.abc import Callable, Generator, Iterator
from typing import Final, Generic, TypeVar

_T = TypeVar("_T")

#: Pieces queued at a worker: one to work on, one waiting so it never idles.
IN_FLIGHT: Final = 2

_PIECE: Final = struct.Struct("!i")
#: piece number, outcome (a result or an exception), payload length
_HEADER: Final = struct.Struct("!iBQ")
_RESULT: Final = 0
_FAILED: Final = 1
_READ_SIZE: Final = 1 << 20


def run_pieces(
    count: int, run: Callable[[int], _T], jobs: int, deliver: Callable[[int, _T], None]
) -> list[int]:
    """Run pieces ``0 .. count-1`` in ``jobs`` forked workers, calling ``deliver`` in
    the parent with each result as it arrives; the pieces whose worker died (a crash in
    a C library, an out-of-memory kill) are returned, not run again.

    An exception ``run`` raises in a worker is raised here, as a call in the parent
    would raise it.
    """
    with contextlib.closing(stream_pieces(count, run, jobs)) as pieces:
        while True:
            try:
                number, value = next(pieces)
            except StopIteration as done:
                died: list[int] = done.value
                return died
            deliver(number, value)


def stream_pieces(
    count: int, run: Callable[[int], _T], jobs: int
) -> Generator[tuple[int, _T], None, list[int]]:
    """:func:`run_pieces` as a generator: ``(number, result)`` pairs as results arrive,
    and, as its return value (``died = yield from stream_pieces(...)``), the pieces
    whose worker died.

    Between two results the workers go on with the pieces they hold, however long the
    caller takes with one; a caller that stops early (or is interrupted) closes the
    generator, which stops every worker at once.
    """
    import pickle  # a run that never forks never needs it

    waiting = iter(range(count))
    workers: list[_Worker[_T]] = []
    died: list[int] = []
    finished = False
    try:
        with selectors.DefaultSelector() as selector:

            def start_worker() -> None:
                worker: _Worker[_T] = _Worker.fork(run, workers)
                workers.append(worker)
                selector.register(worker.results, selectors.EVENT_READ, worker)
                for _ in range(IN_FLIGHT):
                    worker.hand_out(waiting)

            for _ in range(min(jobs, count)):
                start_worker()
            while selector.get_map():
                for key, _ in selector.select():
                    worker = key.data
                    data = os.read(worker.results, _READ_SIZE)
                    if data:
                        for number, outcome, payload in worker.received(data):
                            value = pickle.loads(payload)
                            if outcome == _FAILED:
                                raise value
                            # the next piece goes out before the caller sees this one
                            worker.hand_out(waiting)
                            yield number, value
                        continue
                    selector.unregister(worker.results)  # end of file: the worker is gone
                    worker.stop(kill=False)
                    died.extend(worker.held)
                    if worker.held and not worker.out_of_work:
                        start_worker()  # the pieces not handed out yet still need a worker
        finished = True
    finally:
        for worker in workers:
            worker.stop(kill=not finished)
    return sorted(died)


class _Worker(Generic[_T]):
    """The parent's side of one worker: its pipes, its process, the pieces it holds."""

    def __init__(self, pid: int, commands: int, results: int) -> None:
        self.pid = pid
        self.commands: int | None = commands
        self.results = results
        self.held: deque[int] = deque()
        self.out_of_work = False
        self._buffer = bytearray()
        self._stopped = False

    @classmethod
    def fork(cls, run: Callable[[int], _T], others: list[_Worker[_T]]) -> _Worker[_T]:
        command_read, command_write = os.pipe()
        result_read, result_write = os.pipe()
        pid = os.fork()
        if pid == 0:
            # A pipe end left open here would keep another worker's commands from ever
            # ending, or hide this worker's death from the parent.
            for fd in (command_write, result_read, *(e for o in others for e in o.open_ends())):
                os.close(fd)
            _serve(command_read, result_write, run)
        os.close(command_read)
        os.close(result_write)
        return cls(pid, command_write, result_read)

    def hand_out(self, waiting: Iterator[int]) -> None:
        if self.commands is None:
            return
        number = next(waiting, None)
        if number is None:  # closing the pipe tells the worker to leave when done
            self.out_of_work = True
            os.close(self.commands)
            self.commands = None
            return
        self.held.append(number)
        with contextlib.suppress(BrokenPipeError):  # it died; its end of file is coming
            os.write(self.commands, _PIECE.pack(number))

    def received(self, data: bytes) -> Iterator[tuple[int, int, bytes]]:
        """The complete messages ``data`` ends, in order."""
        self._buffer += data
        while len(self._buffer) >= _HEADER.size:
            number, outcome, size = _HEADER.unpack_from(self._buffer)
            end = _HEADER.size + size
            if len(self._buffer) < end:
                return
            payload = bytes(self._buffer[_HEADER.size : end])
            del self._buffer[:end]
            self.held.remove(number)
            yield number, outcome, payload

    def open_ends(self) -> tuple[int, ...]:
        """The parent's pipe ends still open: a worker forked later must close them."""
        if self._stopped:
            return ()
        return (self.results,) if self.commands is None else (self.commands, self.results)

    def stop(self, *, kill: bool) -> None:
        if self._stopped:
            return
        self._stopped = True
        if kill:  # the run is failing or interrupted: a long file must not hold it up
            with contextlib.suppress(ProcessLookupError):
                os.kill(self.pid, signal.SIGKILL)
        if self.commands is not None:
            os.close(self.commands)
            self.commands = None
        os.close(self.results)
        os.waitpid(self.pid, 0)


def _serve(commands: int, results: int, run: Callable[[int], _T]) -> None:
    """A worker's life: run each piece it is sent, send back what came of it, and leave
    without any of the parent's clean-up (buffers, atexit handlers) when the pipe ends."""
    import pickle

    status = 0
    try:
        while (header := _read_exactly(commands, _PIECE.size)) is not None:
            (number,) = _PIECE.unpack(header)
            try:
                outcome, payload = _RESULT, pickle.dumps(run(number), pickle.HIGHEST_PROTOCOL)
            except Exception as error:  # the parent raises it
                outcome, payload = _FAILED, _pickled_error(error)
            _write_all(results, _HEADER.pack(number, outcome, len(payload)) + payload)
    except BaseException:  # interrupted, or the parent went away: leave quietly
        status = 1
    finally:
        os._exit(status)


def _pickled_error(error: Exception) -> bytes:
    import pickle

    try:
        return pickle.dumps(error)
    except Exception:  # an exception that cannot cross processes still says what it was
        return pickle.dumps(RuntimeError(f"{type(error).__name__}: {error}"))


def _read_exactly(fd: int, size: int) -> bytes | None:
    data = b""
    while len(data) < size:
        piece = os.read(fd, size - len(data))
        if not piece:
            return None
        data += piece
    return data


def _write_all(fd: int, data: bytes) -> None:
    view = memoryview(data)
    while view:
        view = view[os.write(fd, view) :]
