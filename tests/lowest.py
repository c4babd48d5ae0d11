"""The lowest versions ``pyproject.toml`` admits, as pip constraints: each direct
dependency of the package and of the extras named pinned to its floor (``>=X`` becomes
``==X``; a requirement without a floor stays free). ``.ci/run`` installs xodrlint with
them into an environment of its own and runs the tests about those libraries there, so
that a floor that is too low shows as a failure instead of on a user's machine::

    python -m tests.lowest test > constraints.txt
    pip install -c constraints.txt -e '.[test]'

Transitive dependencies resolve as pip resolves them (the "lowest-direct" strategy).
"""

from __future__ import annotations

import re
import sys
import tomllib
from collections.abc import Iterable, Iterator
from pathlib import Path

REPO = Path(__file__).resolve().parents[1]
_REQUIREMENT = re.compile(r"^\s*([A-Za-z0-9][A-Za-z0-9._-]*)\s*(?:\[[^\]]*\])?\s*(.*)$")
_FLOOR = re.compile(r">=\s*([0-9][0-9A-Za-z.]*)")


def floors(requirements: Iterable[str], project: str) -> Iterator[str]:
    """``name==floor`` for each requirement with a ``>=`` bound (not the project itself,
    which an extra may name to include another extra)."""
    seen: dict[str, str] = {}
    for requirement in requirements:
        match = _REQUIREMENT.match(requirement.split(";")[0])
        if match is None:
            raise ValueError(f"not a requirement: {requirement!r}")
        name, specifier = match.group(1).lower().replace("_", "-"), match.group(2)
        floor = _FLOOR.search(specifier)
        if name == project or floor is None:
            continue
        # one package named twice (dask in two extras): the higher floor holds for both
        if name not in seen or _key(floor.group(1)) > _key(seen[name]):
            seen[name] = floor.group(1)
    for name, version in sorted(seen.items()):
        yield f"{name}=={version}"


def _key(version: str) -> tuple[int, ...]:
    return tuple(int(part) for part in re.findall(r"\d+", version))


def constraints(extras: Iterable[str], pyproject: Path = REPO / "pyproject.toml") -> list[str]:
    project = tomllib.loads(pyproject.read_text(encoding="utf-8"))["project"]
    optional = project.get("optional-dependencies", {})
    requirements = list(project.get("dependencies", []))
    for extra in extras:
        requirements.extend(optional[extra])
    return list(floors(requirements, project["name"]))


if __name__ == "__main__":
    print("\n".join(constraints(sys.argv[1:])))
