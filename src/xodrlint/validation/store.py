"""Fill the user data folder with official schema sets: ``xodrlint schemas add|fetch``.

``fetch`` downloads ASAM's ``asam-qc-opendrive`` wheel with pip *without installing it*
(it pins lxml < 6, xmlschema < 4 and numpy < 2), checks its pinned SHA-256 and keeps
only its XSDs. ``add`` takes an ASAM download, as a folder or a zip.
"""

from __future__ import annotations

import hashlib
import shutil
import subprocess
import sys
import tempfile
import zipfile
from collections.abc import Iterator
from dataclasses import dataclass
from pathlib import Path, PurePosixPath
from typing import Final

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


def add(source: Path, data_dir: Path | None = None) -> list[Installed]:
    """Copy every OpenDRIVE schema set found in ``source`` (a folder or a zip)."""
    target = data_dir or user_schema_dir()
    if zipfile.is_zipfile(source):
        with tempfile.TemporaryDirectory() as scratch:
            _extract_xsds(source, Path(scratch))
            return _copy_sets(Path(scratch), target)
    if source.is_dir():
        return _copy_sets(source, target)
    raise StoreError(f"{source}: not a folder or a zip file")


def fetch(data_dir: Path | None = None, wheel: Path | None = None) -> list[Installed]:
    """Download (or take ``wheel``) the pinned ASAM wheel, verify it, keep its XSDs."""
    with tempfile.TemporaryDirectory() as scratch:
        path = wheel or _download(Path(scratch))
        return install_wheel(path, data_dir or user_schema_dir(), QC_WHEEL_SHA256)


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


def _download(scratch: Path) -> Path:
    command = [
        sys.executable, "-m", "pip", "download", "--no-deps", "--only-binary", ":all:",
        "--disable-pip-version-check", "--quiet", "--dest", str(scratch), QC_REQUIREMENT,
    ]  # fmt: skip
    try:
        subprocess.run(command, check=True, capture_output=True, text=True, timeout=300)
    except FileNotFoundError as error:
        raise StoreError(f"cannot run pip: {error}") from error
    except subprocess.CalledProcessError as error:
        last = (error.stderr or error.stdout or "").strip().splitlines()
        raise StoreError(f"pip download failed: {last[-1] if last else error}") from error
    except subprocess.TimeoutExpired as error:
        raise StoreError("pip download timed out after 300 s") from error
    wheel = scratch / QC_WHEEL
    if not wheel.is_file():
        raise StoreError(f"pip did not produce {QC_WHEEL}")
    return wheel


def _extract_xsds(archive_path: Path, into: Path) -> None:
    with zipfile.ZipFile(archive_path) as archive:
        for info in archive.infolist():
            name = PurePosixPath(info.filename)
            # Only plain relative member names: never write outside the scratch folder.
            if name.suffix.lower() != ".xsd" or name.is_absolute() or ".." in name.parts:
                continue
            destination = into.joinpath(*name.parts)
            destination.parent.mkdir(parents=True, exist_ok=True)
            destination.write_bytes(archive.read(info))


def _copy_sets(source: Path, target: Path) -> list[Installed]:
    installed = []
    for folder in _folders_with_xsd(source):
        entry = entry_xsd(folder)
        if entry is None:
            continue
        version = version_of_set(entry)
        if version is None:
            raise StoreError(f"{entry}: cannot tell which OpenDRIVE version this schema is")
        label = ".".join(map(str, version))
        files = sorted(folder.glob("*.xsd"))
        _replace_folder(target / label, ((f.name, f.read_bytes()) for f in files))
        installed.append(Installed(label, target / label, len(files)))
    if not installed:
        raise StoreError(f"{source}: holds no OpenDRIVE schema (no XSD declares 'OpenDRIVE')")
    return installed


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
    for name, content in files:
        (staging / name).write_bytes(content)
    if folder.exists():
        shutil.rmtree(folder)
    staging.replace(folder)
