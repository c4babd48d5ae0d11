"""The layout keeps its promises: every module sits in an import contract,
docs/architecture.md names what exists and everything that exists, and importing
xodrlint leaves the import machinery alone (no finder serves old module paths)."""

from __future__ import annotations

import ast
import re
import subprocess
import sys
import tomllib
from collections.abc import Iterable, Mapping
from pathlib import Path

from .conftest import REPO

PACKAGE = REPO / "src" / "xodrlint"
ARCHITECTURE = REPO / "docs" / "architecture.md"


def package_modules(root: Path = PACKAGE) -> list[str]:
    """Every module and package under ``root``, dotted (the root package itself left out)."""
    names = []
    for path in sorted(root.rglob("*.py")):
        parts = path.relative_to(root.parent).with_suffix("").parts
        if parts[-1] == "__init__":
            parts = parts[:-1]
        if len(parts) > 1:
            names.append(".".join(parts))
    return names


def layered_modules(config: Mapping[str, object]) -> set[str]:
    """The modules the layers contracts of ``config`` place (a package stands for
    everything below it)."""
    named: set[str] = set()
    contracts = config.get("contracts", [])
    assert isinstance(contracts, list)
    for contract in contracts:
        # a contract with containers names its layers inside each container
        prefixes = [f"{container}." for container in contract.get("containers", [])] or [""]
        for layer in contract.get("layers", []):
            parts = [part.strip() for part in re.split(r"[|:]", layer) if part.strip()]
            named.update(prefix + part for prefix in prefixes for part in parts)
    return named


def contract_modules(config: Mapping[str, object]) -> set[str]:
    """Every module a contract of ``config`` names: layers and forbidden sources."""
    contracts = config.get("contracts", [])
    assert isinstance(contracts, list)
    sources = {name for contract in contracts for name in contract.get("source_modules", [])}
    return layered_modules(config) | sources


def outside_every_layer(
    modules: Iterable[str], layered: set[str], root: Path = PACKAGE
) -> list[str]:
    """Modules no layer places. A package whose ``__init__`` imports nothing needs no
    place of its own (``engine/``: its modules sit in different layers)."""
    return [
        module
        for module in modules
        if not any(module == name or module.startswith(name + ".") for name in layered)
        and not _imports_nothing(root.parent / module.replace(".", "/") / "__init__.py")
    ]


def _imports_nothing(init: Path) -> bool:
    if not init.is_file():
        return False
    tree = ast.parse(init.read_text("utf-8"))
    return not any(isinstance(node, ast.Import | ast.ImportFrom) for node in ast.walk(tree))


def importlinter_config() -> dict[str, object]:
    with (REPO / "pyproject.toml").open("rb") as handle:
        config = tomllib.load(handle)["tool"]["importlinter"]
    assert isinstance(config, dict)
    return config


def test_every_module_sits_in_an_import_contract() -> None:
    config = importlinter_config()
    outside = outside_every_layer(package_modules(), layered_modules(config))
    assert outside == [], f"give these a layer in pyproject.toml: {outside}"


def test_a_module_outside_the_contracts_is_found(tmp_path: Path) -> None:
    # the check above would pass vacuously if it read no layers or walked no modules
    root = tmp_path / "xodrlint"
    (root / "cli").mkdir(parents=True)
    (root / "workers").mkdir()
    (root / "formatters").mkdir()
    for name in ("__init__.py", "cli/__init__.py", "cli/commands.py", "engine.py", "stray.py"):
        (root / name).write_text("")
    (root / "workers" / "__init__.py").write_text('"""Processes."""\n')
    (root / "workers" / "pool.py").write_text("")
    (root / "formatters" / "__init__.py").write_text("from xodrlint import engine\n")
    config = {
        "contracts": [
            {"layers": ["xodrlint.cli", "xodrlint.engine | xodrlint.other"]},
            # a forbidden contract's source is no place in the layers
            {"source_modules": ["xodrlint.formatters", "xodrlint.workers"]},
        ]
    }
    modules = package_modules(root)
    assert "xodrlint.cli.commands" in modules and "xodrlint.workers" in modules
    assert outside_every_layer(modules, layered_modules(config), root) == [
        "xodrlint.formatters",
        "xodrlint.stray",
        "xodrlint.workers.pool",
    ]


def test_every_package_of_the_contracts_exists() -> None:
    # a layer that names a module that was moved or renamed governs nothing
    existing = set(package_modules())
    missing = sorted(contract_modules(importlinter_config()) - existing)
    assert missing == [], f"contracts name modules that do not exist: {missing}"


_PATH_IN_DOC = re.compile(r"`([a-z_0-9/]+(?:\.py|/))`")


def _doc_paths() -> list[str]:
    return _PATH_IN_DOC.findall(ARCHITECTURE.read_text("utf-8"))


def test_architecture_doc_names_only_what_exists() -> None:
    paths = _doc_paths()
    assert len(paths) > 20  # the pattern still reads the doc
    # inside the package, or a top-level folder of the repository (rules/ is both)
    missing = [p for p in paths if not (PACKAGE / p).exists() and not (REPO / p).exists()]
    assert missing == [], f"docs/architecture.md names what does not exist: {missing}"


def test_architecture_doc_names_every_package_and_top_level_module() -> None:
    named = set(_doc_paths())
    parts = [
        *(f"{p.parent.relative_to(PACKAGE)}/" for p in PACKAGE.glob("*/__init__.py")),
        *(p.name for p in PACKAGE.glob("*.py") if p.name not in ("__init__.py", "__main__.py")),
        *(
            f"{p.parent.relative_to(PACKAGE)}/"
            for p in PACKAGE.glob("*/*/__init__.py")
            if p.parts[-3] != "rules"  # rule packs: `xodrlint rules` lists them
        ),
    ]
    unnamed = sorted(part for part in parts if part not in named)
    assert unnamed == [], f"docs/architecture.md does not say where these live: {unnamed}"


def test_importing_xodrlint_leaves_the_import_machinery_alone() -> None:
    """No finder of ours in sys.meta_path (a notebook's or a Dask worker's imports pass
    through it), and the flat layout's module paths are gone, not served."""
    done = subprocess.run(
        [
            sys.executable,
            "-c",
            "import sys; before = list(sys.meta_path); import xodrlint, xodrlint.cli;"
            "assert sys.meta_path == before, sys.meta_path\n"
            "try:\n import xodrlint.batch\nexcept ModuleNotFoundError: print('gone')",
        ],
        capture_output=True,
        text=True,
        check=False,
        timeout=60,
    )
    assert (done.returncode, done.stdout, done.stderr) == (0, "gone\n", "")
