"""What a release's built files must hold, checked before they are uploaded.

The wheel holds exactly the package as git tracks it under ``src/xodrlint/``: every
module and every data file (the built-in XSDs, the map's page, style and script,
``py.typed``), nothing left over from an earlier build; the sdist holds every file of the
repository (``MANIFEST.in``). Both carry the version of ``xodrlint.__version__``. A
package-data glob dropped from ``pyproject.toml`` makes the wheel lack a data file, and
this says which. It reads the tree it lies in, never an installed xodrlint. ``.ci/run`` runs it after ``python -m build``, as docs/releasing.md does::

    python -m tests.distributions dist
"""

from __future__ import annotations

import ast
import subprocess
import sys
import tarfile
import tomllib
import zipfile
from collections.abc import Iterable
from pathlib import Path

REPO = Path(__file__).resolve().parents[1]
PACKAGE = "src/xodrlint/"


def project_name(repo: Path = REPO) -> str:
    with (repo / "pyproject.toml").open("rb") as handle:
        name: str = tomllib.load(handle)["project"]["name"]
    return name


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


def wheel_problems(wheel: Path, tracked: Iterable[str], name: str, version: str) -> list[str]:
    """What is wrong with ``wheel``: each file of the package it lacks or has beyond it."""
    metadata = f"{name}-{version}.dist-info/"
    with zipfile.ZipFile(wheel) as archive:
        inside = {entry for entry in archive.namelist() if not entry.endswith("/")}
    held = {entry for entry in inside if not entry.startswith(metadata)}
    wanted = {path.removeprefix("src/") for path in tracked if path.startswith(PACKAGE)}
    problems = [f"{wheel.name}: lacks {path}" for path in sorted(wanted - held)]
    problems += [
        f"{wheel.name}: holds {path}, no file of the package" for path in sorted(held - wanted)
    ]
    if f"{metadata}METADATA" not in inside:
        problems.append(f"{wheel.name}: lacks {metadata}METADATA (not version {version}?)")
    return problems


def sdist_problems(sdist: Path, tracked: Iterable[str], name: str, version: str) -> list[str]:
    """What is wrong with ``sdist``: each file of the repository it lacks."""
    top = f"{name}-{version}/"
    with tarfile.open(sdist) as archive:
        inside = {member.name.removeprefix(top) for member in archive if member.isfile()}
    problems = [f"{sdist.name}: lacks {path}" for path in sorted(set(tracked) - inside)]
    if "PKG-INFO" not in inside:
        problems.append(f"{sdist.name}: lacks {top}PKG-INFO (not version {version}?)")
    return problems


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
        print(f"distributions: {argv[0]}: the wheel and the sdist hold every file")
    return 1 if problems else 0


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))
