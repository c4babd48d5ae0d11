"""``xodrlint schemas fetch`` where the package index cannot be reached: the message names
the index xodrlint gave pip and where that is (host and port), from the URL itself,
whatever words the installed pip uses for the failure."""

from __future__ import annotations

import socket
import subprocess
from pathlib import Path
from typing import Any

import pytest

from xodrlint.validation import store
from xodrlint.validation.store import StoreError, index_address, redacted


@pytest.mark.parametrize(
    ("url", "address"),
    [
        ("https://pypi.org/simple", "pypi.org:443"),
        ("http://mirror.example/simple/", "mirror.example:80"),
        ("HTTPS://Mirror.Example:8443/pypi/simple", "mirror.example:8443"),
        ("http://[::1]:3141/root/pypi/+simple/", "[::1]:3141"),
        ("http://user:secret@127.0.0.1:8080/simple", "127.0.0.1:8080"),
        ("file:///opt/pypi/simple", None),
        ("/opt/pypi/simple", None),
        ("http://127.0.0.1:99999/simple", None),
        ("http://127.0.0.1:port/simple", None),
    ],
)
def test_the_address_of_an_index_comes_from_its_url(url: str, address: str | None) -> None:
    assert index_address(url) == address


@pytest.mark.parametrize(
    ("url", "shown"),
    [
        ("https://pypi.org/simple", "https://pypi.org/simple"),
        ("https://user:secret@host.example/simple", "https://user:****@host.example/simple"),
        ("https://token@host.example/simple", "https://****@host.example/simple"),
        ("https://a@b:c@host.example:81/s", "https://a@b:****@host.example:81/s"),
    ],
)
def test_the_secret_of_an_index_url_is_not_shown(url: str, shown: str) -> None:
    assert redacted(url) == shown


def _unreachable_pip(monkeypatch: pytest.MonkeyPatch, stderr: str) -> list[list[str]]:
    """pip as a stand-in that fails with ``stderr``; the commands it was given."""
    commands: list[list[str]] = []

    def run(command: list[str], **kwargs: Any) -> subprocess.CompletedProcess[str]:
        commands.append(command)
        raise subprocess.CalledProcessError(1, command, "", stderr)

    monkeypatch.setattr(subprocess, "run", run)  # as the store module calls it
    monkeypatch.setenv("PIP_INDEX_URL", "http://user:secret@mirror.invalid:3141/root/+simple/")
    return commands


@pytest.mark.parametrize(
    "stderr",
    [
        # pip 23.2's words: no host or port in them
        "WARNING: Retrying (Retry(total=0, connect=None, read=None, redirect=None, "
        "status=None)) after connection broken by 'NewConnectionError('<pip._vendor.urllib3"
        ".connection.HTTPConnection object at 0x7f>: Failed to establish a new connection: "
        "[Errno 111] Connection refused')': /root/+simple/asam-qc-opendrive/\n"
        "ERROR: No matching distribution found for asam-qc-opendrive==1.0.0",
        # words naming another host and port than the index: not the ones said
        "connection broken by NewConnectionError(host='elsewhere', port=1)",
    ],
)
def test_an_unreachable_index_is_named_by_the_url_given_to_pip(
    tmp_path: Path, monkeypatch: pytest.MonkeyPatch, stderr: str
) -> None:
    commands = _unreachable_pip(monkeypatch, stderr)
    with pytest.raises(StoreError) as caught:
        store.fetch(tmp_path / "schemas")
    [command] = commands
    index = command[command.index("--index-url") + 1]
    assert index == "http://user:secret@mirror.invalid:3141/root/+simple/"
    assert str(caught.value) == (
        "pip could not reach the package index http://user:****@mirror.invalid:3141/root/+simple/ "
        "(mirror.invalid:3141); without a network, 'xodrlint schemas add' takes an ASAM download "
        "(a folder or a zip)"
    )


def _free_port() -> int:
    with socket.socket() as probe:  # a port on the loopback interface that nobody serves
        probe.bind(("127.0.0.1", 0))
        port: int = probe.getsockname()[1]
    return port


def test_the_index_of_pips_download_section_is_given_and_named(
    tmp_path: Path, monkeypatch: pytest.MonkeyPatch
) -> None:
    """The real pip, configured by a file: its ``download`` section outranks ``global``,
    as in pip itself, and xodrlint hands pip that index."""
    ports = _free_port(), _free_port()
    config = tmp_path / "pip.conf"
    config.write_text(
        f"[global]\nindex-url = http://127.0.0.1:{ports[0]}/global\n"
        f"[download]\nindex-url = http://127.0.0.1:{ports[1]}/download\n",
        "utf-8",
    )
    monkeypatch.setenv("PIP_CONFIG_FILE", str(config))
    for name in ("PIP_INDEX_URL", "PIP_FIND_LINKS", "PIP_EXTRA_INDEX_URL", "PIP_NO_INDEX"):
        monkeypatch.delenv(name, raising=False)
    with pytest.raises(StoreError) as caught:
        store.fetch(tmp_path / "schemas")
    said = str(caught.value)
    assert said.startswith(
        f"pip could not reach the package index http://127.0.0.1:{ports[1]}/download "
        f"(127.0.0.1:{ports[1]}); "
    ), said
