"""Inputs by URL against a real S3-compatible endpoint: moto's S3 server on 127.0.0.1
holding 50 maps (the example maps and rule cases), and endpoints that refuse, never
accept or never answer. Credentials are fake and set in each test's environment only.

The server's tests skip, saying why, where moto is not installed or 127.0.0.1 cannot be
bound; the tests of unreachable endpoints need only s3fs.
"""

from __future__ import annotations

import asyncio
import contextlib
import gc
import json
import logging
import os
import re
import shlex
import socket
import subprocess
import sys
import threading
import time
from collections.abc import Iterator
from pathlib import Path

import pytest

from tests.cli.test_cli import cli
from tests.conftest import REPO

s3fs = pytest.importorskip("s3fs", reason="s3fs is not installed (the cloud extra)")

pytestmark = pytest.mark.loopback

BUCKET = "maps"
PREFIX = "tiles"
#: The documented example server, replaced by the test's own in the commands of the docs.
DOCUMENTED_ENDPOINT = "http://127.0.0.1:9000"
SOURCES = sorted((REPO / "examples").glob("*.xodr")) + sorted(REPO.glob("rules/*/*.xodr"))
#: 50 maps, keyed below ``tiles/`` as ``<folder>/<name>``.
MAPS = {f"{p.parent.name}/{p.name}": p for p in SOURCES[:50]}
FOLDER = f"s3://{BUCKET}/{PREFIX}"
URLS = sorted(f"{FOLDER}/{name}" for name in MAPS)


def _subprocess_env(**variables: str) -> dict[str, str]:
    """This environment, with the xodrlint under test first on the path: a command run
    from another folder would not find a relative ``PYTHONPATH=src``."""
    import xodrlint

    here = str(Path(xodrlint.__file__).resolve().parents[1])
    path = os.pathsep.join(filter(None, [here, os.environ.get("PYTHONPATH")]))
    return {**os.environ, "PYTHONPATH": path, **variables}


def _loopback_bindable() -> str | None:
    try:
        with socket.socket() as probe:
            probe.bind(("127.0.0.1", 0))
    except OSError as error:
        return f"127.0.0.1 cannot be bound here: {error}"
    return None


@pytest.fixture(scope="module")
def endpoint() -> Iterator[str]:
    """moto's S3 server on 127.0.0.1 (a free port), holding :data:`MAPS`."""
    server_module = pytest.importorskip("moto.server", reason="moto[server] is not installed")
    problem = _loopback_bindable()
    if problem is not None:  # moto's thread would die on it and leave start() waiting
        pytest.skip(problem)
    werkzeug = logging.getLogger("werkzeug")
    level = werkzeug.level
    werkzeug.setLevel(logging.ERROR)  # one log line a request otherwise
    server = server_module.ThreadedMotoServer(ip_address="127.0.0.1", port=0, verbose=False)
    server.start()
    host, port = server.get_host_and_port()
    url = f"http://{host}:{port}"
    fs = s3fs.S3FileSystem(
        key="testing",
        secret="testing",
        endpoint_url=url,
        client_kwargs={"region_name": "us-east-1"},
        skip_instance_cache=True,
    )
    fs.client_kwargs = {}  # us-east-1 is the one region a bucket is made without naming
    fs.mkdir(BUCKET)
    fs.pipe({f"{BUCKET}/{PREFIX}/{name}": source.read_bytes() for name, source in MAPS.items()})
    yield url
    server.stop()
    werkzeug.setLevel(level)


@pytest.fixture(scope="module", autouse=True)
def _no_thread_outlives_the_module() -> Iterator[None]:
    """Stop the thread fsspec runs s3fs's requests on (and forget the filesystems bound
    to it), so that the tests after these find a process without threads: one with
    threads lints in fresh workers, never forked ones (runners/batch.py)."""
    yield
    import fsspec.asyn

    s3fs.S3FileSystem.clear_instance_cache()
    gc.collect()  # s3fs closes a forgotten filesystem's connections on the loop, if it runs
    loop, thread = fsspec.asyn.loop[0], fsspec.asyn.iothread[0]
    if loop is not None and thread is not None:
        # the thread that resolved host names for it, then the loop's own
        asyncio.run_coroutine_threadsafe(loop.shutdown_default_executor(), loop).result(10)
        loop.call_soon_threadsafe(loop.stop)
        thread.join(timeout=10)
        fsspec.asyn.reset_lock()  # the next user starts a loop of its own


@pytest.fixture
def aws(monkeypatch: pytest.MonkeyPatch, tmp_path: Path) -> Path:
    """An environment with fake credentials and nothing of the developer's: no AWS or
    fsspec variables, no ~/.aws files, no instance metadata; no cached S3 filesystem."""
    from fsspec.config import conf

    for name in list(os.environ):
        if name.startswith(("AWS_", "FSSPEC_")):
            monkeypatch.delenv(name)
    monkeypatch.delitem(conf, "s3", raising=False)
    monkeypatch.setenv("AWS_ACCESS_KEY_ID", "testing")
    monkeypatch.setenv("AWS_SECRET_ACCESS_KEY", "testing")
    monkeypatch.setenv("AWS_DEFAULT_REGION", "us-east-1")
    monkeypatch.setenv("AWS_EC2_METADATA_DISABLED", "true")
    monkeypatch.setenv("AWS_SHARED_CREDENTIALS_FILE", str(tmp_path / "no-credentials"))
    monkeypatch.setenv("AWS_CONFIG_FILE", str(tmp_path / "no-config"))
    # fsspec keeps one filesystem per set of options, and the endpoint and credentials
    # come from variables that each test sets anew
    s3fs.S3FileSystem.clear_instance_cache()
    monkeypatch.setattr(s3fs.S3FileSystem, "_cache", {})
    return tmp_path


@pytest.fixture
def s3(endpoint: str, aws: Path, monkeypatch: pytest.MonkeyPatch) -> str:
    monkeypatch.setenv("AWS_ENDPOINT_URL", endpoint)
    return endpoint


# Runs in this process lint with one job: workers would come from the fork server an
# earlier test may have started, with that test's environment, not this one's endpoint
# and credentials. The run over workers is a process of its own (WATCHED_RUN).

# Listing -----------------------------------------------------------------------------


@pytest.mark.parametrize(
    "named",
    [f"{FOLDER}/**/*.xodr", FOLDER, f"{FOLDER}/", f"s3://{BUCKET}/**/*.xodr"],
)
def test_a_glob_or_a_folder_lists_every_map_as_a_full_url(s3: str, named: str) -> None:
    result = cli("check", "--show-files", named, code=0)
    assert result.stdout.splitlines() == URLS
    assert len(URLS) == 50


def test_a_glob_lists_what_it_matches_and_an_object_is_itself(s3: str) -> None:
    listed = cli("check", "--show-files", f"{FOLDER}/examples/*.xodr", code=0).stdout
    assert listed.splitlines() == [u for u in URLS if "/examples/" in u]
    one = f"{FOLDER}/examples/broken.xodr"
    assert cli("check", "--show-files", one, code=0).stdout == f"{one}\n"


def test_excludes_apply_to_the_path_in_the_bucket(s3: str) -> None:
    listed = cli("check", "--show-files", "--exclude", "tiles/examples", FOLDER, code=0)
    assert listed.stdout.splitlines() == [u for u in URLS if "/examples/" not in u]


# Linting -----------------------------------------------------------------------------

#: The command line, in a process of its own, with the reading function watched: a read
#: in the process that lists is recorded (the workers, forked or fresh, read unwatched).
WATCHED_RUN = """
import json, os, sys
from xodrlint.inputs import remote
client, real, reads = os.getpid(), remote.read_url, []
def read_url(url, limit):
    if os.getpid() == client:
        reads.append(url)
    return real(url, limit)
remote.read_url = read_url
sys.argv = ["xodrlint", *sys.argv[1:]]
from xodrlint.cli import main
try:
    main()
except SystemExit as done:
    print(json.dumps({"code": done.code, "client_reads": reads}), file=sys.stderr)
"""


def _watched_run(report: Path, *engine: str) -> dict[str, object]:
    """``check ENGINE -f json -o REPORT`` over the bucket's folder, in a process of its
    own: its exit code and the URLs its own process read."""
    command = ["check", *engine, "-f", "json", "-o", str(report), FOLDER]
    run = subprocess.run(
        [sys.executable, "-c", WATCHED_RUN, *command],
        env=_subprocess_env(XODRLINT_FAST_EXIT="0"),
        capture_output=True,
        text=True,
        check=False,
        timeout=300,
    )
    outcome: dict[str, object] = json.loads(run.stderr.splitlines()[-1])
    return outcome


def _from_disk(tmp_path: Path) -> str:
    """The JSON report of the same 50 maps from local disk, named as in the bucket."""
    local = tmp_path / PREFIX
    for name, source in MAPS.items():
        (local / name).parent.mkdir(parents=True, exist_ok=True)
        (local / name).write_bytes(source.read_bytes())
    from_disk = cli("check", "--jobs", "1", "-f", "json", local, code=1).stdout
    assert json.loads(from_disk)["summary"]["files"] == 50
    return from_disk.replace(f"{local.as_posix()}/", f"{FOLDER}/")


def test_workers_read_the_maps_and_report_what_local_disk_gives(s3: str, tmp_path: Path) -> None:
    report = tmp_path / "s3.json"
    assert _watched_run(report, "--jobs", "2") == {"code": 1, "client_reads": []}
    assert report.read_text("utf-8") == _from_disk(tmp_path)


def test_dask_workers_read_the_maps_and_report_what_local_disk_gives(
    s3: str, tmp_path: Path
) -> None:
    pytest.importorskip("distributed", reason="Dask is not installed (the dask extra)")
    report = tmp_path / "s3.json"
    engine = ("--scheduler", "local", "--jobs", "2")
    assert _watched_run(report, *engine) == {"code": 1, "client_reads": []}
    assert report.read_text("utf-8") == _from_disk(tmp_path)


def test_reports_name_the_urls(s3: str) -> None:
    result = cli("check", "-j", "1", "-f", "json", f"{FOLDER}/examples/*.xodr", code=1)
    report = json.loads(result.stdout)
    assert [f["path"] for f in report["files"]] == [u for u in URLS if "/examples/" in u]
    assert {f["path"] for f in report["findings"]} <= set(URLS)
    sarif = json.loads(cli("check", "-f", "sarif", f"{FOLDER}/examples/broken.xodr", code=1).stdout)
    (location,) = {
        location["physicalLocation"]["artifactLocation"]["uri"]
        for result in sarif["runs"][0]["results"]
        for location in result["locations"]
    }
    assert location == f"{FOLDER}/examples/broken.xodr"


def test_reading_stops_at_the_limit_and_an_empty_object_is_empty(s3: str) -> None:
    from xodrlint.inputs import remote

    url = f"{FOLDER}/examples/broken.xodr"
    data = MAPS["examples/broken.xodr"].read_bytes()
    assert remote.read_url(url, len(data)) == data
    with pytest.raises(remote.TooLarge):  # an object grown since it was listed
        remote.read_url(url, len(data) - 1)
    fs = s3fs.S3FileSystem()
    fs.mkdir("scratch", exist_ok=True)
    fs.pipe("scratch/empty.xodr", b"")
    assert remote.read_url("s3://scratch/empty.xodr", 100) == b""
    result = cli("check", "-f", "json", "s3://scratch/empty.xodr", code=1)
    (finding,) = json.loads(result.stdout)["findings"]
    assert finding["path"] == "s3://scratch/empty.xodr" and finding["code"] == "XS001"


# What is not there, or not allowed ----------------------------------------------------


@pytest.mark.parametrize(
    "named", ["s3://nobucket/tiles/**/*.xodr", "s3://nobucket/tiles", "s3://nobucket/a.xodr"]
)
def test_a_missing_bucket_is_one_line_and_exit_2(s3: str, named: str) -> None:
    result = cli("check", named, code=2)
    assert result.stderr == f"xodrlint: {named}: no such bucket 'nobucket'\n"


def test_a_missing_object_is_no_match_in_a_glob_and_an_error_named(s3: str) -> None:
    pattern = f"{FOLDER}/nothing/**/*.xodr"
    assert cli("check", pattern, code=2).stderr == f"xodrlint: {pattern}: no file matches\n"
    named = f"{FOLDER}/gone.xodr"
    assert cli("check", named, code=2).stderr == f"xodrlint: {named}: no such object\n"


def test_refused_credentials_are_access_denied(s3: str, monkeypatch: pytest.MonkeyPatch) -> None:
    import moto.settings

    # moto checks credentials from this many requests on (none: every one)
    monkeypatch.setattr(moto.settings, "INITIAL_NO_AUTH_ACTION_COUNT", 0)
    result = cli("check", f"{FOLDER}/**/*.xodr", code=2)
    assert result.stderr == (
        f"xodrlint: {FOLDER}/**/*.xodr: access denied:"
        " the credentials were refused (InvalidAccessKeyId)\n"
    )
    assert cli("check", f"{FOLDER}/examples/broken.xodr", code=2).stderr == (
        f"xodrlint: {FOLDER}/examples/broken.xodr: access denied\n"
    )


def test_credentials_come_from_the_aws_files(
    s3: str, aws: Path, monkeypatch: pytest.MonkeyPatch
) -> None:
    monkeypatch.delenv("AWS_ACCESS_KEY_ID")
    monkeypatch.delenv("AWS_SECRET_ACCESS_KEY")
    assert cli("check", FOLDER, code=2).stderr == (
        f"xodrlint: {FOLDER}: no credentials found (AWS_ACCESS_KEY_ID and"
        " AWS_SECRET_ACCESS_KEY, ~/.aws/credentials, or an instance role)\n"
    )
    credentials = aws / "no-credentials"
    credentials.write_text(
        "[default]\naws_access_key_id = testing\naws_secret_access_key = testing\n"
    )
    s3fs.S3FileSystem.clear_instance_cache()
    cli("check", "-j", "1", FOLDER, code=1)


@pytest.mark.parametrize("variable", ["AWS_ENDPOINT_URL_S3", "AWS_ENDPOINT_URL"])
def test_botocore_s_endpoint_variables_name_the_server(
    endpoint: str, aws: Path, variable: str, monkeypatch: pytest.MonkeyPatch
) -> None:
    monkeypatch.setenv(variable, endpoint)
    assert cli("check", "--show-files", FOLDER, code=0).stdout.splitlines() == URLS


# Unreachable endpoints -----------------------------------------------------------------


def _closed_port() -> int:
    with socket.socket() as probe:
        probe.bind(("127.0.0.1", 0))
        port: int = probe.getsockname()[1]
    return port


def test_a_refused_connection_is_one_line_within_seconds(
    aws: Path, monkeypatch: pytest.MonkeyPatch
) -> None:
    port = _closed_port()
    monkeypatch.setenv("AWS_ENDPOINT_URL", f"http://127.0.0.1:{port}")
    started = time.monotonic()
    result = cli("check", f"{FOLDER}/**/*.xodr", code=2)
    assert result.stderr == (
        f"xodrlint: {FOLDER}/**/*.xodr: connection refused to 127.0.0.1:{port}\n"
    )
    assert time.monotonic() - started < 15  # xodrlint's own bounds, not the test's


def test_an_endpoint_that_never_accepts_times_out_connecting(
    aws: Path, monkeypatch: pytest.MonkeyPatch
) -> None:
    from fsspec.config import conf

    with socket.socket() as server:
        server.bind(("127.0.0.1", 0))
        server.listen(0)  # one connection waits to be accepted; the next gets no answer
        port = server.getsockname()[1]
        with socket.create_connection(("127.0.0.1", port)):
            monkeypatch.setenv("AWS_ENDPOINT_URL", f"http://127.0.0.1:{port}")
            monkeypatch.setitem(conf, "s3", {"config_kwargs": {"connect_timeout": 1}})
            started = time.monotonic()
            result = cli("check", f"{FOLDER}/examples/broken.xodr", code=2)
    assert result.stderr == (
        f"xodrlint: {FOLDER}/examples/broken.xodr: timed out connecting to 127.0.0.1:{port}\n"
    )
    assert time.monotonic() - started < 15  # 3 attempts of 1 s, and botocore's pauses


def test_an_endpoint_that_never_answers_times_out_waiting(
    aws: Path, monkeypatch: pytest.MonkeyPatch
) -> None:
    from fsspec.config import conf

    accepted: list[socket.socket] = []
    with socket.socket() as server:
        server.bind(("127.0.0.1", 0))
        server.listen(16)
        server.settimeout(0.2)
        port = server.getsockname()[1]
        stop = threading.Event()

        def accept() -> None:  # and never answer
            while not stop.is_set():
                with contextlib.suppress(TimeoutError):
                    accepted.append(server.accept()[0])

        listener = threading.Thread(target=accept)
        listener.start()
        monkeypatch.setenv("AWS_ENDPOINT_URL", f"http://127.0.0.1:{port}")
        monkeypatch.setitem(
            conf, "s3", {"config_kwargs": {"read_timeout": 1, "retries": {"total_max_attempts": 2}}}
        )
        try:
            result = cli("check", FOLDER, code=2)
        finally:
            stop.set()
            listener.join()
            for connection in accepted:
                connection.close()
    assert result.stderr == (
        f"xodrlint: {FOLDER}: timed out waiting for an answer to 127.0.0.1:{port}\n"
    )
    # botocore's two attempts, and no more: s3fs's retries on top are turned off
    assert len(accepted) == 2


# The commands of docs/distributed.md -------------------------------------------------

_SECTION = re.search(
    r"^## Maps in object storage\n(.*?)(?=^## |\Z)",
    (REPO / "docs" / "distributed.md").read_text("utf-8"),
    flags=re.MULTILINE | re.DOTALL,
)
assert _SECTION is not None, "docs/distributed.md lost its section 'Maps in object storage'"
#: ``[VARIABLE=value ...] xodrlint check ...`` lines of the section's console blocks
DOC_COMMANDS = re.findall(
    r"^((?:[A-Z_0-9]+=\S+ )*xodrlint check [^\n]*)$",
    "".join(re.findall(r"```console\n(.*?)```", _SECTION.group(1), re.DOTALL)),
    flags=re.MULTILINE,
)


def test_the_section_shows_an_s3_run_a_file_run_and_the_endpoint_variables() -> None:
    shown = "\n".join(DOC_COMMANDS)
    for needed in ("s3://", "file://", "AWS_ENDPOINT_URL_S3=", "FSSPEC_S3_ENDPOINT_URL="):
        assert needed in shown


@pytest.mark.parametrize("command", DOC_COMMANDS)
def test_a_documented_command_runs(
    command: str, endpoint: str, aws: Path, tmp_path: Path, monkeypatch: pytest.MonkeyPatch
) -> None:
    """Each in a process of its own: fsspec reads FSSPEC_* variables when imported."""
    for name, source in MAPS.items():
        (tmp_path / PREFIX / name).parent.mkdir(parents=True, exist_ok=True)
        (tmp_path / PREFIX / name).write_bytes(source.read_bytes())
    words = shlex.split(command.replace("$PWD", tmp_path.as_posix()))
    env = _subprocess_env(AWS_ENDPOINT_URL=endpoint)
    while "=" in words[0]:
        name, _, value = words.pop(0).partition("=")
        env[name] = value.replace(DOCUMENTED_ENDPOINT, endpoint)
        # the command's own variable must name the server: the general one names a port
        # where nothing listens (so a variable that did not work never leaves the machine)
        env["AWS_ENDPOINT_URL"] = f"http://127.0.0.1:{_closed_port()}"
    assert words[:2] == ["xodrlint", "check"]
    run = subprocess.run(
        [sys.executable, "-m", "xodrlint", *words[1:]],
        cwd=tmp_path,
        env=env,
        capture_output=True,
        text=True,
        check=False,
        timeout=300,
    )
    assert run.returncode == 1, run.stderr  # the example maps have findings
    assert "Traceback" not in run.stderr
    if "--output" in words:
        report = json.loads((tmp_path / words[words.index("--output") + 1]).read_text())
        assert report["summary"]["files"] == 50
