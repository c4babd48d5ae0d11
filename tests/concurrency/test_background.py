"""Validation beside the rules, in a thread or a forked child: the same findings as in
one thread, a dead child costs nothing but time, and a thread's error reaches the caller."""

from __future__ import annotations

import os
import threading
from collections.abc import Callable
from pathlib import Path

import pytest

from tests.conftest import REPO, SHARED_SCHEMAS, needs_shared
from xodrlint.api import default_registry
from xodrlint.concurrency import background
from xodrlint.engine.linter import Linter, LintOptions


def test_a_task_runs_in_a_child_and_its_value_comes_back(monkeypatch: pytest.MonkeyPatch) -> None:
    monkeypatch.setattr(background, "MIN_BYTES", 0)
    parent = os.getpid()
    pending = background.start(lambda: ("pid", os.getpid()), size=1)
    kind, pid = pending.result()
    assert kind == "pid" and pid != parent  # computed in the child


def test_a_dead_child_means_the_parent_does_the_work(monkeypatch: pytest.MonkeyPatch) -> None:
    monkeypatch.setattr(background, "MIN_BYTES", 0)
    parent = os.getpid()

    def task() -> int:
        if os.getpid() != parent:
            os._exit(9)  # as a crash or an out-of-memory kill would end it
        return 42

    assert background.start(task, size=1).result() == 42


def test_a_thread_safe_task_runs_in_a_thread_of_this_process(
    monkeypatch: pytest.MonkeyPatch,
) -> None:
    monkeypatch.setattr(background, "MIN_BYTES", 0)
    caller = threading.current_thread()
    pending = background.start(
        lambda: (os.getpid(), threading.current_thread()), size=1, thread_safe=True
    )
    pid, thread = pending.result()
    assert pid == os.getpid() and thread is not caller


def test_a_threads_error_is_raised_where_the_result_is_asked_for(
    monkeypatch: pytest.MonkeyPatch,
) -> None:
    monkeypatch.setattr(background, "MIN_BYTES", 0)

    def task() -> int:
        raise ValueError("bad schema")

    pending = background.start(task, size=1, thread_safe=True)
    with pytest.raises(ValueError, match="bad schema"):
        pending.result()


def test_the_switch_keeps_the_work_in_the_caller(monkeypatch: pytest.MonkeyPatch) -> None:
    monkeypatch.setenv(background.ENV, "0")
    caller = threading.current_thread()
    pending = background.start(threading.current_thread, size=10**9, thread_safe=True)
    assert pending.result() is caller


def test_thread_safe_work_of_any_size_runs_beside_the_caller() -> None:
    # a thread costs a tenth of a millisecond: a pre-commit run's small map overlaps its
    # validation with the rules too
    caller = threading.current_thread()
    pending = background.start(threading.current_thread, size=1, thread_safe=True)
    assert pending.result() is not caller
    unsafe = background.start(threading.current_thread, size=1, thread_safe=False)
    assert unsafe.result() is caller  # too small to fork: done on demand


def test_small_documents_and_the_switch_keep_one_process(monkeypatch: pytest.MonkeyPatch) -> None:
    assert not background.can_fork(background.MIN_BYTES - 1)
    monkeypatch.setenv(background.ENV, "0")
    assert not background.can_fork(background.MIN_BYTES * 10)


@needs_shared
@pytest.mark.parametrize("name", ["broken.xodr", "two-findings.xodr", "clean.xodr"])
@pytest.mark.parametrize(
    ("schema", "beside"),
    [
        (SHARED_SCHEMAS, "thread"),  # libxml2 on the whole document releases the GIL
        (None, "fork"),  # the built-in schema validates subtrees: never in a thread
    ],
)
def test_validation_beside_the_rules_gives_the_same_findings(
    name: str, schema: Path | None, beside: str, monkeypatch: pytest.MonkeyPatch
) -> None:
    path = REPO / "examples" / name
    alone = Linter(default_registry(), LintOptions(schema=schema)).lint_path(path)
    monkeypatch.setattr(background, "MIN_BYTES", 0)
    used: list[str] = []
    in_thread, fork = background._in_thread, os.fork

    def spied_thread(task: Callable[[], object]) -> background.Pending[object]:
        used.append("thread")
        return in_thread(task)

    def spied_fork() -> int:
        used.append("fork")
        return fork()

    monkeypatch.setattr(background, "_in_thread", spied_thread)
    monkeypatch.setattr(os, "fork", spied_fork)
    if beside == "fork":
        # a validation thread of the test before may still be ending (its result given,
        # the thread not yet gone): a process with two threads rightly does not fork
        _until_single_threaded()
    beside_rules = Linter(default_registry(), LintOptions(schema=schema)).lint_path(path)
    assert used == [beside]
    assert beside_rules.findings == alone.findings
    # hits a child sent back are stamped here with their element's line and column
    assert all(f.column is not None for f in beside_rules.findings)
    assert beside_rules.schema == alone.schema


def _until_single_threaded(seconds: float = 10.0) -> None:
    import time

    deadline = time.monotonic() + seconds
    while not background.single_threaded():
        assert time.monotonic() < deadline, "threads of earlier tests are still running"
        time.sleep(0.01)


def test_no_fork_while_other_threads_run() -> None:
    import threading

    _until_single_threaded()  # a thread of the test before may still be ending
    assert background.can_fork(background.MIN_BYTES)
    release = threading.Event()
    other = threading.Thread(target=release.wait)
    other.start()
    try:
        assert not background.can_fork(background.MIN_BYTES)
    finally:
        release.set()
        other.join()


@pytest.mark.skipif(not Path("/proc/self/task").is_dir(), reason="needs Linux's /proc")
def test_no_fork_while_a_thread_python_does_not_list_runs() -> None:
    # a thread a C library starts (a BLAS pool, pyarrow's allocator) is not one of
    # threading's, yet a lock it holds stays locked in a child all the same: Python 3.12
    # and later warn of the deadlock, from the thread count the system keeps
    import _thread
    import threading
    import time

    from xodrlint.runners import batch

    _until_single_threaded()  # a thread of the test before may still be ending
    assert batch._can_fork_workers()
    release, gone = _thread.allocate_lock(), _thread.allocate_lock()
    release.acquire()
    gone.acquire()

    def wait() -> None:
        release.acquire()
        gone.release()

    _thread.start_new_thread(wait, ())
    try:
        assert threading.active_count() == 1  # threading does not see it
        assert not background.single_threaded()
        assert not background.can_fork(background.MIN_BYTES)
        assert not batch._can_fork_workers()
    finally:
        release.release()
        gone.acquire()
    deadline = time.monotonic() + 10
    while not background.single_threaded():  # the thread is gone once it has returned
        assert time.monotonic() < deadline
        time.sleep(0.01)


@pytest.mark.parametrize(
    ("attribute_type", "thread_safe"),
    [("xs:string", True), ("xs:IDREF", False), ("xs:ID", False), ("my:QName", False)],
)
def test_a_set_whose_validation_writes_into_the_document_never_runs_in_a_thread(
    tmp_path: Path, attribute_type: str, thread_safe: bool
) -> None:
    # libxml2 registers an IDREF in the document's tables through its string dictionary
    # while another thread's tag lookups read that dictionary: a crash, so a fork
    from xodrlint.validation.libxml2 import Libxml2Validator

    schema = tmp_path / "set.xsd"
    schema.write_text(
        '<xs:schema xmlns:xs="http://www.w3.org/2001/XMLSchema" xmlns:my="urn:x">'
        '<xs:element name="OpenDRIVE"><xs:complexType>'
        f'<xs:attribute name="a" type="{attribute_type.replace("my:", "xs:")}"/>'
        "</xs:complexType></xs:element></xs:schema>"
    )
    assert Libxml2Validator(schema).thread_safe is thread_safe


@needs_shared
def test_the_official_schemas_may_run_in_a_thread() -> None:
    from xodrlint.validation.libxml2 import Libxml2Validator

    entry = next((SHARED_SCHEMAS / "1.7.0").glob("*core.xsd"))
    assert Libxml2Validator(entry).thread_safe


def test_the_compile_started_while_parsing_has_ended_when_validation_starts(
    tmp_path: Path, monkeypatch: pytest.MonkeyPatch
) -> None:
    # the compile thread may not have taken its lock yet when validation compiles the set
    # itself, or may let go of it a moment before it ends: were it still running, a large
    # map's validation would not fork and the run would lose its overlap
    from xodrlint.document.load import Version, load_bytes
    from xodrlint.validation.sets import SchemaFinder
    from xodrlint.validation.validators import SchemaValidators

    doc = load_bytes((REPO / "examples" / "clean.xodr").read_bytes(), "clean.xodr")
    assert doc.effective is not None
    alone_when_started: list[bool] = []
    start_hits = background.start_hits

    def spied(*args: object, **kwargs: object) -> object:
        alone_when_started.append(background.single_threaded())
        return start_hits(*args, **kwargs)  # type: ignore[arg-type]

    monkeypatch.setattr(background, "start_hits", spied)
    _until_single_threaded()
    for _ in range(50):
        validators = SchemaValidators(SchemaFinder(None, environment={}, data_dir=tmp_path))
        validators.compile_soon(Version(doc.effective.major, doc.effective.minor))
        validators.start(doc).result()
    assert alone_when_started == [True] * 50


def test_a_hits_fix_crosses_the_fork_with_its_nodes_found_again() -> None:
    from lxml import etree

    from xodrlint.findings import Hit
    from xodrlint.fixes import Applicability, Fix, insert_element, remove_comment, set_attribute

    root = etree.fromstring("<a><!-- c --><b x='1'/><d/></a>")
    comment, b, d = list(root)
    fix = Fix(
        "mend",
        (
            set_attribute(b, "x", "2"),
            remove_comment(comment),
            insert_element(d, "e", {"f": "g"}, where="before"),
        ),
        Applicability.UNSAFE,
    )
    sent = background.send_hits([Hit(b, "m", fix=fix), Hit(d, "n")], root)
    received = background.receive_hits(sent, root)
    assert received[0].fix == fix and received[1].fix is None


@needs_shared
def test_a_lane_type_in_another_case_is_mended_with_the_official_schema(tmp_path: Path) -> None:
    from xodrlint.engine.fixing import DIFF, FixPolicy

    source = (REPO / "examples" / "clean.xodr").read_text(encoding="utf-8")
    assert 'type="rail"' in source
    target = tmp_path / "lane.xodr"
    target.write_text(source.replace('type="rail"', 'type="Rail "', 1), encoding="utf-8")
    options = LintOptions(
        select=("XS006",),
        schema=SHARED_SCHEMAS,
        fixes=FixPolicy(mode=DIFF),
        place_fixes=True,
    )
    fixed, report = Linter(default_registry(), options).fixed_source(target.read_bytes(), "l")
    assert report.fixed == 1 and report.findings == ()
    assert fixed.decode() == source
