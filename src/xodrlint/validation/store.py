"""Fill the user data folder with official schema sets: ``xodrlint schemas add|fetch``.

``fetch`` downloads ASAM's ``asam-qc-opendrive`` wheel with pip *without installing it*
(it pins lxml < 6, xmlschema < 4 and numpy < 2), checks its pinned SHA-256 and keeps
only its XSDs. ``add`` takes an ASAM download, as a folder or a zip.
"""

from __future__ import annotations

import ast
import contextlib
import hashlib
import importlib.util
import os
import re
import shutil
import subprocess
import sys
import tempfile
import zipfile
import zlib
from collections.abc import Iterator
from dataclasses import dataclass
from pathlib import Path, PurePosixPath
from typing import IO, Final
from urllib.parse import urlsplit, urlunsplit

from xodrlint.validation.sets import entry_xsd, user_schema_dir, version_of_set

QC_WHEEL: Final = "asam_qc_opendrive-1.0.0-py3-none-any.whl"
QC_REQUIREMENT: Final = "asam-qc-opendrive==1.0.0"
QC_WHEEL_SHA256: Final = "147cf2702d61fb284d03e5485b2a76b1dec0eb6a7eb3567562d3b4e4f87a873c"
_QC_SCHEMA_PREFIX: Final = "qc_opendrive/schema/"


class StoreError(Exception):
    """Adding or fetching schemas failed; the message says why, in one line."""


@dataclass(frozen=True, slots=True)
class Installed:
    version: str
    folder: Path
    files: int


#: No schema file is larger (ASAM's largest is under 300 KB): a bigger one is a zip bomb
#: or a mistake, refused before it fills memory or the disk.
MAX_FILE_BYTES: Final = 64 * 1024 * 1024
#: What one ``schemas add`` may store in all.
MAX_TOTAL_BYTES: Final = 256 * 1024 * 1024


def add(source: Path, data_dir: Path | None = None) -> list[Installed]:
    """Copy every OpenDRIVE schema set found in ``source`` (a folder or a zip)."""
    target = data_dir or user_schema_dir()
    with _locked(target):
        if zipfile.is_zipfile(source):
            with tempfile.TemporaryDirectory() as scratch:
                _extract_xsds(source, Path(scratch))
                return _copy_sets(Path(scratch), target)
        if source.is_dir():
            return _copy_sets(source, target)
    raise StoreError(f"{source}: not a folder or a zip file")


def fetch(data_dir: Path | None = None, wheel: Path | None = None) -> list[Installed]:
    """Download (or take ``wheel``) the pinned ASAM wheel, verify it, keep its XSDs."""
    target = data_dir or user_schema_dir()
    with tempfile.TemporaryDirectory() as scratch, _locked(target):
        path = wheel or _download(Path(scratch))
        return install_wheel(path, target, QC_WHEEL_SHA256)


@contextlib.contextmanager
def _locked(target: Path) -> Iterator[None]:
    """One ``schemas add`` or ``fetch`` at a time per folder: a second one waits (two at
    once swapped the same set folder and left staging folders behind)."""
    target.parent.mkdir(parents=True, exist_ok=True)
    with (target.parent / f".{target.name}.lock").open("a") as lock:
        try:
            import fcntl
        except ImportError:  # pragma: no cover - Windows: no advisory locks here
            yield
            return
        fcntl.flock(lock, fcntl.LOCK_EX)
        try:
            yield
        finally:
            fcntl.flock(lock, fcntl.LOCK_UN)


def install_wheel(wheel: Path, target: Path, sha256: str) -> list[Installed]:
    digest = hashlib.sha256(wheel.read_bytes()).hexdigest()
    if digest != sha256:
        raise StoreError(
            f"{wheel.name}: SHA-256 {digest} does not match the pinned {sha256}; not installed"
        )
    installed = []
    with zipfile.ZipFile(wheel) as archive:
        versions: dict[str, list[zipfile.ZipInfo]] = {}
        for info in archive.infolist():
            name = PurePosixPath(info.filename)
            if info.filename.startswith(_QC_SCHEMA_PREFIX) and name.suffix == ".xsd":
                versions.setdefault(name.parent.name, []).append(info)
        for version, members in sorted(versions.items()):
            folder = target / version
            _replace_folder(
                folder, ((PurePosixPath(m.filename).name, archive.read(m)) for m in members)
            )
            installed.append(Installed(version, folder, len(members)))
    if not installed:
        raise StoreError(f"{wheel.name}: holds no OpenDRIVE schemas")
    return installed


#: What pip says when it cannot reach an index (the connection refused, no name
#: resolution, a timeout): "No matching distribution found" follows, which misleads.
#: Only whether it could not connect is read from pip's words, which change between
#: releases; where it tried to connect comes from the index xodrlint gave it.
_UNREACHABLE: Final = re.compile(
    r"connection broken by|Failed to establish a new connection|Could not fetch URL|"
    r"Name or service not known|Temporary failure in name resolution|timed out",
)
_PYPI: Final = "https://pypi.org/simple"
_DEFAULT_PORTS: Final = {"http": 80, "https": 443}


def _download(scratch: Path) -> Path:
    if not _pip_here():  # some virtual-environment tools make environments without pip
        raise StoreError(_WITHOUT_PIP)
    index = _index_url()
    command = [
        sys.executable, "-m", "pip", "download", "--no-deps", "--only-binary", ":all:",
        "--disable-pip-version-check", "--quiet", "--dest", str(scratch),
        # the index is named here, so that a failure can say which one it was
        "--index-url", index,
        # a machine without a network answers in seconds, not after pip's 98 s of retries
        "--timeout", "15", "--retries", "1", QC_REQUIREMENT,
    ]  # fmt: skip
    try:
        subprocess.run(command, check=True, capture_output=True, text=True, timeout=300)
    except FileNotFoundError as error:
        raise StoreError(f"cannot run pip: {error}") from error
    except subprocess.CalledProcessError as error:
        said = f"{error.stderr or ''}\n{error.stdout or ''}"
        if _UNREACHABLE.search(said):
            address = index_address(index)
            raise StoreError(
                f"pip could not reach the package index {redacted(index)}"
                f"{f' ({address})' if address else ''}; without a network, 'xodrlint "
                "schemas add' takes an ASAM download (a folder or a zip)"
            ) from error
        if "No module named pip" in said:
            raise StoreError(_WITHOUT_PIP) from error
        last = said.strip().splitlines()
        raise StoreError(f"pip download failed: {last[-1] if last else error}") from error
    except subprocess.TimeoutExpired as error:
        raise StoreError("pip download timed out after 300 s") from error
    wheel = scratch / QC_WHEEL
    if not wheel.is_file():
        raise StoreError(f"pip did not produce {QC_WHEEL}")
    return wheel


def index_address(url: str) -> str | None:
    """``host:port`` where a client of the index ``url`` connects: the port the URL gives,
    else its scheme's; ``None`` where the URL names no host (a ``file:`` index)."""
    try:
        parts = urlsplit(url)
        host, port = parts.hostname, parts.port or _DEFAULT_PORTS.get(parts.scheme.lower())
    except ValueError:  # a port that is no number or out of range
        return None
    if not host or port is None:
        return None
    return f"[{host}]:{port}" if ":" in host else f"{host}:{port}"


def redacted(url: str) -> str:
    """``url`` with the secret of its user part replaced by ``****``, as pip shows it: the
    password of ``user:password@``, or the whole of ``token@``."""
    parts = urlsplit(url)
    user, at, host = parts.netloc.rpartition("@")
    if not at:
        return url
    name, colon, _ = user.partition(":")
    shown = f"{name}:****" if colon else "****"
    return urlunsplit(parts._replace(netloc=f"{shown}@{host}"))


def _pip_here() -> bool:
    try:
        return importlib.util.find_spec("pip") is not None
    except (ImportError, ValueError):  # a broken or hidden pip is no pip
        return False


#: What ``fetch`` says where pip cannot run: the one download to make by hand.
_WITHOUT_PIP: Final = (
    f"pip is not installed in this environment ({sys.executable}): download {QC_WHEEL} "
    f"from https://pypi.org/project/asam-qc-opendrive/#files and run 'xodrlint schemas "
    "fetch --wheel PATH' (its SHA-256 is checked)"
)


def _index_url() -> str:
    """The index pip would ask for a download: ``PIP_INDEX_URL``, else ``index-url`` of
    pip's configuration (its ``download`` section before ``global``, as pip reads them),
    else PyPI."""
    configured = os.environ.get("PIP_INDEX_URL")
    if configured:
        return configured
    settings: dict[str, str] = {}
    with contextlib.suppress(OSError, subprocess.SubprocessError):
        done = subprocess.run(
            [sys.executable, "-m", "pip", "config", "list"],
            capture_output=True,
            text=True,
            timeout=30,
            check=False,
        )
        for line in done.stdout.splitlines() if done.returncode == 0 else ():
            name, _, value = line.partition("=")  # name='value', the value as repr() writes it
            with contextlib.suppress(ValueError, SyntaxError):
                settings[name] = str(ast.literal_eval(value))
    return settings.get("download.index-url") or settings.get("global.index-url") or _PYPI


def _extract_xsds(archive_path: Path, into: Path) -> None:
    budget = _Budget(archive_path)
    try:
        with zipfile.ZipFile(archive_path) as archive:
            for info in archive.infolist():
                name = PurePosixPath(info.filename)
                # Only plain relative member names: never write outside the scratch folder.
                if name.suffix.lower() != ".xsd" or name.is_absolute() or ".." in name.parts:
                    continue
                destination = into.joinpath(*name.parts)
                destination.parent.mkdir(parents=True, exist_ok=True)
                with archive.open(info) as member:  # read no more than the limit allows
                    destination.write_bytes(budget.read(member, info.filename))
    except (zipfile.BadZipFile, zlib.error, EOFError, NotImplementedError) as error:
        raise StoreError(f"{archive_path}: a damaged zip file ({error})") from error


class _Budget:
    """Reads schema files while they keep within :data:`MAX_FILE_BYTES` each and
    :data:`MAX_TOTAL_BYTES` in all; a declared size can lie, so the bytes are counted."""

    def __init__(self, source: Path) -> None:
        self._source = source
        self._total = 0

    def read(self, stream: IO[bytes], name: str) -> bytes:
        data = stream.read(MAX_FILE_BYTES + 1)
        if len(data) > MAX_FILE_BYTES:
            raise StoreError(
                f"{self._source}: {name} is larger than {MAX_FILE_BYTES // 2**20} MiB; "
                "no schema is: refused"
            )
        self._total += len(data)
        if self._total > MAX_TOTAL_BYTES:
            raise StoreError(
                f"{self._source}: more than {MAX_TOTAL_BYTES // 2**20} MiB of schemas; refused"
            )
        return data


def _copy_sets(source: Path, target: Path) -> list[Installed]:
    installed = []
    budget = _Budget(source)
    for folder in _folders_with_xsd(source):
        entry = entry_xsd(folder)
        if entry is None:
            continue
        version = version_of_set(entry)
        if version is None:
            raise StoreError(f"{entry}: cannot tell which OpenDRIVE version this schema is")
        label = ".".join(map(str, version))
        files = sorted(folder.glob("*.xsd"))
        contents = [(f.name, _read_inside(f, source, budget)) for f in files]
        _replace_folder(target / label, iter(contents))
        installed.append(Installed(label, target / label, len(files)))
    if not installed:
        raise StoreError(f"{source}: holds no OpenDRIVE schema (no XSD declares 'OpenDRIVE')")
    return installed


def _read_inside(path: Path, source: Path, budget: _Budget) -> bytes:
    """A schema file of the folder being added; one that is a link leading out of it
    (``zz.xsd -> /etc/shadow``) is refused, not copied where others may read it."""
    root = source.resolve()
    real = path.resolve()
    if real != root and root not in real.parents:
        raise StoreError(f"{path}: links outside {source}; refused")
    with real.open("rb") as stream:
        return budget.read(stream, path.name)


def _folders_with_xsd(source: Path) -> Iterator[Path]:
    seen = set()
    for xsd in sorted(source.rglob("*.xsd")):
        if xsd.parent not in seen:
            seen.add(xsd.parent)
            yield xsd.parent


def _replace_folder(folder: Path, files: Iterator[tuple[str, bytes]]) -> None:
    """Write a schema set whole: into a sibling temp folder, then swap it in."""
    folder.parent.mkdir(parents=True, exist_ok=True)
    staging = Path(tempfile.mkdtemp(prefix=f".{folder.name}-", dir=folder.parent))
    umask = os.umask(0)
    os.umask(umask)
    staging.chmod(0o777 & ~umask)  # mkdtemp's 0700, made what a plain mkdir makes
    for name, content in files:
        (staging / name).write_bytes(content)
    if folder.exists():
        shutil.rmtree(folder)
    staging.replace(folder)
