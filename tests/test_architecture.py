"""The layout keeps its promises: every module sits in an import contract,
docs/architecture.md names what exists and everything that exists, and the old import
paths of the flat layout still lead to the same objects."""

from __future__ import annotations

import re
import subprocess
import sys
import tomllib
import warnings
from collections.abc import Iterable, Mapping
from pathlib import Path

import pytest

from xodrlint import _moved

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


def contract_modules(config: Mapping[str, object]) -> set[str]:
    """The modules the import-linter contracts of ``config`` govern: each layer, each
    forbidden contract's sources (a package stands for everything below it)."""
    named: set[str] = set()
    contracts = config.get("contracts", [])
    assert isinstance(contracts, list)
    for contract in contracts:
        for layer in contract.get("layers", []):
            named.update(part.strip() for part in re.split(r"[|:]", layer) if part.strip())
        named.update(contract.get("source_modules", []))
    return named


def outside_every_contract(modules: Iterable[str], governed: set[str]) -> list[str]:
    return [
        module
        for module in modules
        if not any(module == name or module.startswith(name + ".") for name in governed)
    ]


def importlinter_config() -> dict[str, object]:
    with (REPO / "pyproject.toml").open("rb") as handle:
        config = tomllib.load(handle)["tool"]["importlinter"]
    assert isinstance(config, dict)
    return config


def test_every_module_sits_in_an_import_contract() -> None:
    config = importlinter_config()
    outside = outside_every_contract(package_modules(), contract_modules(config))
    assert outside == [], f"add these to a contract in pyproject.toml: {outside}"


def test_a_module_outside_the_contracts_is_found(tmp_path: Path) -> None:
    # the check above would pass vacuously if it read no layers or walked no modules
    root = tmp_path / "xodrlint"
    (root / "cli").mkdir(parents=True)
    for name in ("__init__.py", "cli/__init__.py", "cli/app.py", "engine.py", "stray.py"):
        (root / name).write_text("")
    config = {
        "contracts": [
            {"layers": ["xodrlint.cli", "xodrlint.engine | xodrlint.other"]},
            {"source_modules": ["xodrlint.formatters"]},
        ]
    }
    modules = package_modules(root)
    assert modules == ["xodrlint.cli", "xodrlint.cli.app", "xodrlint.engine", "xodrlint.stray"]
    assert outside_every_contract(modules, contract_modules(config)) == ["xodrlint.stray"]


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


@pytest.fixture(autouse=True)
def _fresh_old_paths(monkeypatch: pytest.MonkeyPatch) -> None:
    # a stand-in keeps each name it handed out (and warns once): every test starts anew
    for old in _moved.MOVED:
        monkeypatch.delitem(sys.modules, old, raising=False)


def test_no_old_path_is_shadowed_by_a_real_module() -> None:
    # the finder answers only when no real module exists: a file at an old path wins
    for old in _moved.MOVED:
        relative = Path(*old.split(".")[1:])
        assert not (PACKAGE / relative.with_suffix(".py")).exists(), old
        assert not (PACKAGE / relative / "__init__.py").exists(), old


@pytest.mark.parametrize("old", sorted(_moved.MOVED))
def test_an_old_path_hands_out_the_new_objects_with_a_warning(old: str) -> None:
    import importlib

    module = importlib.import_module(old)
    targets = [importlib.import_module(target) for target in _moved.MOVED[old]]
    public = sorted(
        {
            name
            for target in targets
            for name, value in vars(target).items()
            if not name.startswith("_") and getattr(value, "__module__", None) == target.__name__
        }
    )
    assert public, f"{old}: its new modules define nothing public"
    for name in public:
        home = next(t for t in targets if name in vars(t) and _defined_in(t, name))
        with pytest.warns(DeprecationWarning, match=re.escape(f"moved to {home.__name__}.{name}")):
            value = getattr(module, name)
        assert value is getattr(home, name)
    with warnings.catch_warnings():
        warnings.simplefilter("error")  # once per name: a second read is quiet
        getattr(module, public[0])


def _defined_in(module: object, name: str) -> bool:
    return getattr(getattr(module, name), "__module__", None) == getattr(module, "__name__", "")


def test_old_from_imports_and_submodules_work() -> None:
    with pytest.warns(DeprecationWarning, match=r"xodrlint\.validation\.store\.install_wheel"):
        from xodrlint.schemas.store import install_wheel  # type: ignore[import-not-found]
    from xodrlint.validation.store import install_wheel as moved

    assert install_wheel is moved
    with pytest.raises(ImportError):
        import xodrlint.schemas.nothing  # type: ignore[import-not-found]
    with pytest.raises(AttributeError, match="has no attribute 'nothing'"):
        import xodrlint.batch  # type: ignore[import-not-found]

        _ = xodrlint.batch.nothing


def test_python_m_on_an_old_path_runs_the_new_module(tmp_path: Path) -> None:
    done = subprocess.run(
        [sys.executable, "-m", "xodrlint.docgen"],
        cwd=tmp_path,
        capture_output=True,
        text=True,
        check=False,
        timeout=60,
    )
    assert "xodrlint.docgen moved to xodrlint.cli.docgen" in done.stderr
    # the new module ran: it refuses a folder without the rules' cases, as it always did
    assert "run from the repository root" in done.stdout + done.stderr
    assert "Traceback" not in done.stderr
