"""Inputs by URL without a server: ``memory://`` and ``file://`` through fsspec, how URLs
are listed, read and named in reports, and what is said when fsspec or a protocol's
package is missing. The S3 tests against a real endpoint are in test_remote_s3.py."""

from __future__ import annotations

import json
import sys
import uuid
from collections.abc import Iterator
from pathlib import Path

import pytest

from tests.cli.test_cli import BROKEN, CLEAN, cli
from tests.conftest import REPO
from xodrlint import lint_file
from xodrlint.api import collect_inputs, default_registry
from xodrlint.engine.linter import Linter, LintOptions
from xodrlint.findings import relative_path
from xodrlint.inputs import remote
from xodrlint.inputs.collect import Input
from xodrlint.runners.batch import Task, lint_tasks

fsspec = pytest.importorskip("fsspec", reason="fsspec is not installed (the cloud extra)")

TWO = REPO / "examples" / "two-findings.xodr"
#: A layout with sub-folders, a file that is no map and a map name in capitals.
LAYOUT = {
    "maps/a.xodr": BROKEN,
    "maps/sub/b.xodr": TWO,
    "maps/sub/deeper/c.XODR": CLEAN,
    "maps/notes.txt": CLEAN,
    "maps/tmp/d.xodr": BROKEN,
}


@pytest.fixture
def memory() -> Iterator[str]:
    """``memory://<unique>/`` holding :data:`LAYOUT`, removed afterwards (the memory
    filesystem is one store for the whole process, and only this process's: runs over
    it lint with one job, since a fresh worker would find it empty)."""
    fs = fsspec.filesystem("memory")
    root = f"xl-{uuid.uuid4().hex[:8]}"
    for name, source in LAYOUT.items():
        fs.pipe(f"/{root}/{name}", source.read_bytes())
    yield f"memory://{root}"
    fs.rm(f"/{root}", recursive=True)


@pytest.fixture
def local(tmp_path: Path) -> Path:
    for name, source in LAYOUT.items():
        (tmp_path / name).parent.mkdir(parents=True, exist_ok=True)
        (tmp_path / name).write_bytes(source.read_bytes())
    return tmp_path


def shown(inputs: Iterator[Input]) -> list[str]:
    return [item.error or item.display for item in inputs]


# What a URL is ---------------------------------------------------------------------


@pytest.mark.parametrize(
    ("text", "url"),
    [
        ("s3://bucket/maps/a.xodr", True),
        ("gs://bucket", True),
        ("file:///home/me/a.xodr", True),
        ("memory://x/a.xodr", True),
        ("S3A://bucket/a.xodr", True),
        ("C:\\maps\\a.xodr", False),  # a Windows drive is no scheme
        ("C:/maps/a.xodr", False),
        ("c://maps/a.xodr", False),
        ("maps/a.xodr", False),
        ("-", False),
        ("http:/one-slash", False),
        ("maps/s3://a.xodr", False),
    ],
)
def test_a_url_is_a_scheme_and_two_slashes(text: str, url: bool) -> None:
    assert remote.is_url(text) is url


def test_the_path_part_of_a_url_is_what_follows_the_bucket() -> None:
    assert remote.url_path("s3://bucket/maps/tmp/a.xodr") == "maps/tmp/a.xodr"
    assert remote.url_path("file:///home/me/a.xodr") == "home/me/a.xodr"
    assert remote.url_path("s3://bucket/maps/a?b#c.xodr") == "maps/a?b#c.xodr"  # a key
    assert remote.url_path("s3://bucket") == ""


def test_a_windows_drive_path_is_a_local_path() -> None:
    (item,) = collect_inputs(["C:/no/such/folder/a.xodr"])
    assert item.url is None and item.error is not None
    assert "no such file or directory" in item.error


# Listing -------------------------------------------------------------------------


def test_a_folder_url_is_every_xodr_below_it_sorted_as_urls(memory: str) -> None:
    assert shown(collect_inputs([f"{memory}/maps"])) == [
        f"{memory}/maps/a.xodr",
        f"{memory}/maps/sub/b.xodr",
        f"{memory}/maps/sub/deeper/c.XODR",
        f"{memory}/maps/tmp/d.xodr",
    ]
    # a trailing slash names the same folder, and the URLs keep the spelling given
    assert shown(collect_inputs([f"{memory}/maps/"]))[0] == f"{memory}/maps/a.xodr"


def test_an_object_url_is_that_object_whatever_its_name(memory: str) -> None:
    (item,) = collect_inputs([f"{memory}/maps/notes.txt"])
    assert item == Input(
        f"{memory}/maps/notes.txt", url=f"{memory}/maps/notes.txt", size=CLEAN.stat().st_size
    )


@pytest.mark.parametrize(
    "pattern",
    ["maps/**/*.xodr", "maps/*/b.xodr", "maps/**", "maps/s*", "maps/*/*", "**/d.xodr"],
)
def test_a_glob_url_matches_what_the_same_local_glob_does(
    memory: str, local: Path, pattern: str, monkeypatch: pytest.MonkeyPatch
) -> None:
    monkeypatch.chdir(local)
    expected = [f"{memory}/{item.display}" for item in collect_inputs([pattern])]
    assert shown(collect_inputs([f"{memory}/{pattern}"])) == expected
    assert expected  # each pattern matches something


def test_a_glob_url_that_matches_nothing_is_no_file_matches(memory: str) -> None:
    for pattern in (f"{memory}/maps/*.json", f"{memory}/nothing/here/**/*.xodr"):
        assert shown(collect_inputs([pattern])) == [f"{pattern}: no file matches"]


def test_a_missing_object_url_is_an_error(memory: str) -> None:
    assert shown(collect_inputs([f"{memory}/maps/gone.xodr"])) == [
        f"{memory}/maps/gone.xodr: no such object"
    ]


def test_a_bucket_cannot_be_a_glob() -> None:
    assert shown(collect_inputs(["s3://*/maps/a.xodr"])) == [
        "s3://*/maps/a.xodr: the bucket or host of a URL cannot be a glob"
    ]


def test_a_url_named_twice_is_listed_once(memory: str) -> None:
    found = shown(collect_inputs([f"{memory}/maps/sub", f"{memory}/maps/sub/b.xodr"]))
    assert found == [f"{memory}/maps/sub/b.xodr", f"{memory}/maps/sub/deeper/c.XODR"]


def test_excludes_match_the_path_part_of_a_url(memory: str) -> None:
    found = shown(
        collect_inputs([f"{memory}/maps"], exclude_url=lambda part: part.startswith("maps/sub"))
    )
    assert found == [f"{memory}/maps/a.xodr", f"{memory}/maps/tmp/d.xodr"]
    result = cli("check", "--show-files", "--exclude", "tmp", f"{memory}/maps", code=0)
    assert f"{memory}/maps/tmp/d.xodr" not in result.stdout
    assert f"{memory}/maps/a.xodr" in result.stdout


def test_max_file_size_is_judged_from_the_listing_before_reading(
    memory: str, monkeypatch: pytest.MonkeyPatch
) -> None:
    def never(url: str, limit: int) -> bytes:
        raise AssertionError(f"{url} was read")

    monkeypatch.setattr(remote, "read_url", never)
    result = cli("check", "--max-file-size", "1000", f"{memory}/maps/a.xodr", code=2)
    assert result.stderr == (
        f"xodrlint: {memory}/maps/a.xodr: larger than the maximum file size"
        " (1KB, see --max-file-size)\n"
    )


def test_reading_stops_at_the_limit(memory: str) -> None:
    url = f"{memory}/maps/a.xodr"
    size = BROKEN.stat().st_size
    assert remote.read_url(url, size) == BROKEN.read_bytes()
    with pytest.raises(remote.TooLarge):
        remote.read_url(url, size - 1)
    linter = Linter(default_registry(), LintOptions())
    report = linter.lint_url(url, max_file_size=size - 1)
    assert (
        report.error
        == f"{url}: larger than the maximum file size ({size - 1}, see --max-file-size)"
    )


# Running ---------------------------------------------------------------------------


def test_reports_name_urls_as_given(memory: str) -> None:
    result = cli("check", "-f", "json", f"{memory}/maps/**/*.xodr", code=1)
    report = json.loads(result.stdout)
    assert [f["path"] for f in report["files"]] == [
        f"{memory}/maps/a.xodr",
        f"{memory}/maps/sub/b.xodr",
        f"{memory}/maps/tmp/d.xodr",
    ]
    assert {f["path"] for f in report["findings"]} == {
        f"{memory}/maps/a.xodr",
        f"{memory}/maps/sub/b.xodr",
        f"{memory}/maps/tmp/d.xodr",
    }
    text = cli("check", f"{memory}/maps/sub/b.xodr", code=1).stdout
    assert f"{memory}/maps/sub/b.xodr:26:9: PT003 [warning]" in text


def test_a_file_url_gives_the_findings_of_the_local_path(local: Path) -> None:
    by_path = cli("check", "-f", "json", local / "maps", code=1).stdout
    by_url = cli("check", "-f", "json", f"file://{local.as_posix()}/maps", code=1).stdout
    assert by_url.replace(f"file://{local.as_posix()}/", f"{local.as_posix()}/") == by_path


def test_sarif_names_a_url_by_itself(memory: str) -> None:
    fs = fsspec.filesystem("memory")
    fs.pipe(f"/{memory.removeprefix('memory://')}/maps/with space.xodr", BROKEN.read_bytes())
    result = cli("check", "-f", "sarif", f"{memory}/maps/*.xodr", code=1)
    (run,) = json.loads(result.stdout)["runs"]
    uris = {
        json.dumps(location["physicalLocation"]["artifactLocation"])
        for item in run["results"]
        for location in item["locations"]
    }
    assert uris == {
        json.dumps({"uri": f"{memory}/maps/a.xodr"}),
        json.dumps({"uri": f"{memory}/maps/with%20space.xodr"}),
    }


def test_a_url_is_no_path_below_the_root() -> None:
    assert relative_path("s3://bucket/maps/a.xodr", "/work") == "s3://bucket/maps/a.xodr"
    # a relative root once made this 's3:/bucket/maps/a.xodr'
    assert relative_path("s3://bucket/maps/a.xodr", ".") == "s3://bucket/maps/a.xodr"


def test_a_baseline_holds_urls_and_withholds_their_findings(memory: str, tmp_path: Path) -> None:
    baseline = tmp_path / "baseline.json"
    cli("check", "-j", "1", "--write-baseline", baseline, f"{memory}/maps", code=0)
    paths = {entry["path"] for entry in json.loads(baseline.read_text())["findings"]}
    assert paths == {
        f"{memory}/maps/a.xodr",
        f"{memory}/maps/sub/b.xodr",
        f"{memory}/maps/tmp/d.xodr",
    }
    cli("check", "-j", "1", "--baseline", baseline, f"{memory}/maps", code=0)


def test_per_file_ignores_match_the_path_part_of_a_url(memory: str, tmp_path: Path) -> None:
    config = tmp_path / "xodrlint.toml"
    config.write_text('[per-file-ignores]\n"maps/tmp/**" = ["ALL"]\n')
    report = json.loads(
        cli("check", "-j", "1", "--config", config, "-f", "json", f"{memory}/maps", code=1).stdout
    )
    assert f"{memory}/maps/a.xodr" in {f["path"] for f in report["findings"]}
    assert f"{memory}/maps/tmp/d.xodr" not in {f["path"] for f in report["findings"]}


def test_the_api_lints_a_url(memory: str) -> None:
    report = lint_file(f"{memory}/maps/sub/b.xodr")
    assert report.path == f"{memory}/maps/sub/b.xodr"
    assert [f.code for f in report.findings] == ["PT003", "ST004"]
    assert lint_file(f"{memory}/maps/gone.xodr").error == f"{memory}/maps/gone.xodr: no such object"


def test_a_task_by_url_is_read_where_it_is_linted(memory: str) -> None:
    url = f"{memory}/maps/sub/b.xodr"
    local = Task(TWO, "local.xodr")  # the three fields of before, by position
    by_url = Task(Path(url), url, (), url)
    linter = Linter(default_registry(), LintOptions())
    first, second = lint_tasks(linter, [local, by_url], jobs=1)
    assert [f.code for f in first.findings] == [f.code for f in second.findings]
    assert second.path == url and "read" in second.timings


# What is missing ---------------------------------------------------------------------


def test_without_fsspec_a_url_names_the_extra(monkeypatch: pytest.MonkeyPatch) -> None:
    for name in ("fsspec", "fsspec.core", "fsspec.registry"):
        monkeypatch.setitem(sys.modules, name, None)  # import fails as if not installed
    result = cli("check", "s3://bucket/maps/**/*.xodr", code=2)
    assert result.stderr == (
        "xodrlint: s3://bucket/maps/**/*.xodr: reading URLs needs fsspec"
        " (pip install 'xodrlint[cloud]')\n"
    )


def test_a_protocol_fsspec_does_not_know_is_one_line() -> None:
    result = cli("check", "nosuch://bucket/a.xodr", code=2)
    assert result.stderr == (
        "xodrlint: nosuch://bucket/a.xodr: no installed fsspec package reads nosuch:// URLs\n"
    )


def test_a_protocol_whose_package_is_missing_names_it() -> None:
    try:
        import gcsfs  # type: ignore[import-not-found, unused-ignore]  # noqa: F401
    except ImportError:
        pass
    else:
        pytest.skip("gcsfs is installed here")
    result = cli("check", "gs://bucket/maps/a.xodr", code=2)
    assert result.stderr == (
        "xodrlint: gs://bucket/maps/a.xodr: reading gs:// URLs needs the package gcsfs"
        " (pip install gcsfs)\n"
    )


# How failures read ------------------------------------------------------------------


class FakeClientError(Exception):
    """botocore's ClientError as s3fs sees it: a ``response`` with the store's code."""

    def __init__(self, code: str) -> None:
        super().__init__(f"An error occurred ({code})")
        self.response = {"Error": {"Code": code, "Message": "..."}}


class EndpointConnectionError(Exception):
    def __init__(self) -> None:
        super().__init__("Could not connect")
        self.kwargs = {"endpoint_url": "http://127.0.0.1:9/bucket/a.xodr"}


class ReadTimeoutError(Exception):
    pass


def caused(outer: Exception, inner: BaseException) -> Exception:
    outer.__cause__ = inner
    return outer


@pytest.mark.parametrize(
    ("error", "reason"),
    [
        (caused(FileNotFoundError("gone"), FakeClientError("NoSuchBucket")), "no such bucket"),
        (caused(FileNotFoundError("x"), FakeClientError("NoSuchKey")), "no such object"),
        (caused(PermissionError("x"), FakeClientError("AccessDenied")), "access denied"),
        (
            caused(PermissionError("x"), FakeClientError("InvalidAccessKeyId")),
            "access denied: the credentials were refused (InvalidAccessKeyId)",
        ),
        (
            caused(EndpointConnectionError(), ConnectionRefusedError(111, "refused")),
            "connection refused to 127.0.0.1:9",
        ),
        (EndpointConnectionError(), "cannot connect to 127.0.0.1:9"),
        (ReadTimeoutError("read timeout"), "timed out waiting for an answer"),
        (TimeoutError(), "timed out waiting for an answer"),
        (PermissionError("nope"), "access denied"),
        (ValueError("odd\nthing  here"), "ValueError: odd thing here"),
    ],
)
def test_a_failure_is_one_line_that_says_why(error: Exception, reason: str) -> None:
    assert remote.reason(error) == reason


def test_xodrlint_bounds_s3_waits_and_fsspec_config_overrides_them(
    monkeypatch: pytest.MonkeyPatch,
) -> None:
    from fsspec.config import conf

    for name in ("AWS_MAX_ATTEMPTS", "AWS_RETRY_MODE"):
        monkeypatch.delenv(name, raising=False)
    monkeypatch.delitem(conf, "s3", raising=False)
    assert remote.storage_options("s3") == remote.S3_DEFAULTS
    assert remote.storage_options("memory") == {}
    monkeypatch.setitem(conf, "s3", {"config_kwargs": {"read_timeout": 2}, "anon": True})
    assert remote.storage_options("s3") == {
        "config_kwargs": {
            "connect_timeout": 5,
            "read_timeout": 2,
            "retries": {"total_max_attempts": 3, "mode": "standard"},
        },
        "anon": True,
    }
    monkeypatch.setenv("AWS_MAX_ATTEMPTS", "7")  # botocore's own setting then decides
    assert "retries" not in remote.storage_options("s3")["config_kwargs"]


def test_a_task_by_url_is_scheduled_by_its_listed_size() -> None:
    from xodrlint.runners import batch

    url = "s3://bucket/maps/a.xodr"
    assert batch.task_size(Task(Path(url), url, (), url, 12345)) == 12345
    assert batch.task_size(Task(Path(url), url, (), url)) == 0  # unknown: never asked for


def test_an_empty_object_reads_as_empty(memory: str) -> None:
    fsspec.filesystem("memory").pipe(f"/{memory.removeprefix('memory://')}/maps/empty.xodr", b"")
    assert remote.read_url(f"{memory}/maps/empty.xodr", 100) == b""


def test_jsonl_streams_the_findings_of_urls(memory: str) -> None:
    result = cli("check", "-f", "jsonl", f"{memory}/maps/sub", code=1)
    lines = [json.loads(line) for line in result.stdout.splitlines()]
    assert {line["path"] for line in lines} == {f"{memory}/maps/sub/b.xodr"}
    assert [line["code"] for line in lines] == ["PT003", "ST004"]


# -- issue 30, item 10: URLs get the checks local paths get -----------------------------


@pytest.mark.parametrize("kind", ["device", "fifo"])
def test_a_file_url_to_a_device_or_fifo_is_refused_unread(tmp_path: Path, kind: str) -> None:
    import os

    if kind == "fifo":
        target = tmp_path / "pipe.xodr"
        os.mkfifo(target)  # reading it would wait for a writer for ever
        what = "a FIFO"
    else:
        target, what = Path("/dev/zero"), "a character device"
    url = f"file://{target.as_posix()}"
    result = cli("check", url, code=2)
    assert result.stderr == f"xodrlint: {url}: is {what}, not a regular file\n"


@pytest.mark.loopback  # port 9 of the loopback interface: refused
def test_credentials_in_a_url_are_in_no_report() -> None:
    url = "http://someone:s3cret@127.0.0.1:9/maps/a.xodr"
    for kind in ("text", "json", "sarif", "gitlab", "jsonl", "junit"):
        result = cli("check", "-f", kind, url, code=2)
        assert "s3cret" not in result.stdout + result.stderr and "someone" not in result.stdout
    assert remote.shown_url(url) == "http://127.0.0.1:9/maps/a.xodr"
    assert remote.shown_url("s3://bucket/a@b.xodr") == "s3://bucket/a@b.xodr"  # a key's @


@pytest.mark.loopback
def test_a_refused_connection_is_said_so() -> None:
    result = cli("check", "http://127.0.0.1:9/maps/a.xodr", code=2)
    assert result.stderr.startswith("xodrlint: http://127.0.0.1:9/maps/a.xodr: connection refused")


@pytest.mark.parametrize("kind", ["sarif", "gitlab", "jsonl", "text"])
def test_a_name_that_is_not_utf8_by_url_is_one_error(tmp_path: Path, kind: str) -> None:
    import os

    (tmp_path / "maps").mkdir()
    (tmp_path / "maps" / "ok.xodr").write_bytes(CLEAN.read_bytes())
    (tmp_path / "maps" / os.fsdecode(b"caf\xe9.xodr")).write_bytes(CLEAN.read_bytes())
    result = cli("check", "-f", kind, f"file://{tmp_path.as_posix()}/maps", code=2)
    assert "maps/caf\\xe9.xodr: the file name is not valid UTF-8" in result.stderr
    result.stdout.encode("utf-8")  # carried whole: no lone surrogate, no raw byte
    if kind == "jsonl":
        assert all(json.loads(line) for line in result.stdout.splitlines())


def test_anchored_excludes_match_file_urls_as_the_files_they_name(
    local: Path, monkeypatch: pytest.MonkeyPatch
) -> None:
    monkeypatch.chdir(local)
    (local / "xodrlint.toml").write_text('exclude = ["/maps/tmp/*"]\n')
    by_path = cli("check", "--show-files", "maps", code=0).stdout
    by_url = cli("check", "--show-files", f"file://{local.as_posix()}/maps", code=0).stdout
    assert "d.xodr" not in by_path and "d.xodr" not in by_url
    assert by_url.count("file://") == len(by_path.splitlines()) == 3
