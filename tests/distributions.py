"""What a release's built files must hold, checked before they are uploaded.

The wheel holds exactly the package as git tracks it under ``src/xodrlint/``: every
module and every data file (the built-in XSDs, the map's page, style and script,
``py.typed``), nothing left over from an earlier build; the sdist holds every file of the
repository (``MANIFEST.in``). Both carry the version of ``xodrlint.__version__``, and the
licence files that ``license-files`` in ``pyproject.toml`` names, as they are in the
repository and declared in the metadata (``License-File``): the sdist at their paths, the
wheel under ``.dist-info/licenses/``. A package-data glob dropped from ``pyproject.toml``
makes the wheel lack a data file, and this says which. It reads the tree it lies in, never an installed xodrlint. ``.ci/run`` runs it after ``python -m build``, as docs/releasing.md does::

    python -m tests.distributions dist
"""

from __future__ import annotations

import ast
import subprocess
import sys
import tarfile
import tomllib
import zipfile
from collections.abc import Callable, Iterable, Mapping
from email.parser import HeaderParser
from pathlib import Path

REPO = Path(__file__).resolve().parents[1]
PACKAGE = "src/xodrlint/"


def project_name(repo: Path = REPO) -> str:
    with (repo / "pyproject.toml").open("rb") as handle:
        name: str = tomllib.load(handle)["project"]["name"]
    return name


def license_files(repo: Path = REPO) -> dict[str, bytes]:
    """The files ``license-files`` names (globs, as PEP 639 has them), by their
    ``/``-separated path in the repository, with their content."""
    with (repo / "pyproject.toml").open("rb") as handle:
        patterns: list[str] = tomllib.load(handle)["project"].get("license-files", [])
    return {
        path.relative_to(repo).as_posix(): path.read_bytes()
        for pattern in patterns
        for path in sorted(repo.glob(pattern))
        if path.is_file()
    }


def _license_problems(
    label: str,
    inside: Callable[[str], bytes | None],
    metadata: bytes | None,
    prefix: str,
    licenses: Mapping[str, bytes],
) -> list[str]:
    """Each licence file missing at ``prefix + path`` (``inside`` reads an entry of the
    archive, ``None`` where there is none), differing from the repository's, or not
    declared as a ``License-File`` in ``metadata``."""
    if not licenses:
        return ["pyproject.toml: license-files names no file of the repository"]
    declared = (
        HeaderParser().parsestr(metadata.decode("utf-8")).get_all("License-File", [])
        if metadata is not None
        else []
    )
    problems = []
    for path, text in sorted(licenses.items()):
        held = inside(prefix + path)
        if held is None:
            problems.append(f"{label}: lacks the licence file {prefix}{path}")
        elif held != text:
            problems.append(f"{label}: {prefix}{path} is not the repository's {path}")
        if metadata is not None and path not in declared:
            problems.append(f"{label}: its metadata declares no License-File: {path}")
    return problems


def source_version(repo: Path = REPO) -> str:
    """``__version__`` as ``src/xodrlint/__init__.py`` assigns it (pyproject.toml reads it)."""
    module = ast.parse((repo / PACKAGE / "__init__.py").read_text("utf-8"))
    for node in module.body:
        if isinstance(node, ast.Assign) and any(
            isinstance(target, ast.Name) and target.id == "__version__" for target in node.targets
        ):
            version = ast.literal_eval(node.value)
            if isinstance(version, str):
                return version
    raise ValueError(f"{PACKAGE}__init__.py assigns no __version__ string")


def tracked_files(repo: Path = REPO) -> list[str]:
    """The repository's files as git tracks them, ``/``-separated, relative to its root."""
    listed = subprocess.run(
        ["git", "ls-files", "-z"], cwd=repo, capture_output=True, check=True
    ).stdout
    return sorted(name for name in listed.decode("utf-8").split("\0") if name)


def wheel_problems(
    wheel: Path,
    tracked: Iterable[str],
    name: str,
    version: str,
    licenses: Mapping[str, bytes] | None = None,
) -> list[str]:
    """What is wrong with ``wheel``: each file of the package it lacks or has beyond it,
    and each of ``licenses`` (default: the repository's) it lacks in its .dist-info."""
    metadata = f"{name}-{version}.dist-info/"
    licenses = license_files() if licenses is None else licenses
    with zipfile.ZipFile(wheel) as archive:
        inside = {entry for entry in archive.namelist() if not entry.endswith("/")}

        def read(entry: str) -> bytes | None:
            return archive.read(entry) if entry in inside else None

        license_problems = _license_problems(
            wheel.name, read, read(f"{metadata}METADATA"), f"{metadata}licenses/", licenses
        )
    held = {entry for entry in inside if not entry.startswith(metadata)}
    wanted = {path.removeprefix("src/") for path in tracked if path.startswith(PACKAGE)}
    problems = [f"{wheel.name}: lacks {path}" for path in sorted(wanted - held)]
    problems += [
        f"{wheel.name}: holds {path}, no file of the package" for path in sorted(held - wanted)
    ]
    if f"{metadata}METADATA" not in inside:
        problems.append(f"{wheel.name}: lacks {metadata}METADATA (not version {version}?)")
    return problems + license_problems


def sdist_problems(
    sdist: Path,
    tracked: Iterable[str],
    name: str,
    version: str,
    licenses: Mapping[str, bytes] | None = None,
) -> list[str]:
    """What is wrong with ``sdist``: each file of the repository it lacks, and each of
    ``licenses`` (default: the repository's) it lacks or holds changed."""
    top = f"{name}-{version}/"
    licenses = license_files() if licenses is None else licenses
    with tarfile.open(sdist) as archive:
        members = {member.name: member for member in archive if member.isfile()}
        inside = {entry.removeprefix(top) for entry in members}

        def read(entry: str) -> bytes | None:
            member = members.get(top + entry)
            held = archive.extractfile(member) if member is not None else None
            return held.read() if held is not None else None

        license_problems = _license_problems(sdist.name, read, read("PKG-INFO"), "", licenses)
    problems = [f"{sdist.name}: lacks {path}" for path in sorted(set(tracked) - inside)]
    if "PKG-INFO" not in inside:
        problems.append(f"{sdist.name}: lacks {top}PKG-INFO (not version {version}?)")
    return problems + license_problems


def check(folder: Path, repo: Path = REPO) -> list[str]:
    """Problems of the one wheel and the one sdist of this version in ``folder``, the
    only files there (``twine upload dist/*`` takes all)."""
    name, version, tracked = project_name(repo), source_version(repo), tracked_files(repo)
    wheel = folder / f"{name}-{version}-py3-none-any.whl"
    sdist = folder / f"{name}-{version}.tar.gz"
    problems = [f"{path}: not built" for path in (wheel, sdist) if not path.is_file()]
    others = sorted(p for p in folder.iterdir() if p not in (wheel, sdist))
    problems += [f"{other}: not of this build" for other in others]
    if wheel.is_file():
        problems += wheel_problems(wheel, tracked, name, version)
    if sdist.is_file():
        problems += sdist_problems(sdist, tracked, name, version)
    return problems


def main(argv: list[str]) -> int:
    if len(argv) != 1:
        print("usage: python -m tests.distributions DIST_FOLDER", file=sys.stderr)
        return 2
    if not Path(argv[0]).is_dir():
        print(f"distributions: {argv[0]}: no such folder (run python -m build)", file=sys.stderr)
        return 2
    problems = check(Path(argv[0]))
    for problem in problems:
        print(f"distributions: {problem}", file=sys.stderr)
    if not problems:
        print(f"distributions: {argv[0]}: the wheel and the sdist hold every file and the licence")
    return 1 if problems else 0


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))
