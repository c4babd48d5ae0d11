"""The layout keeps its promises: every module sits in an import contract,
docs/architecture.md names what exists and everything that exists, and the old import
paths of the flat layout still lead to the same objects."""

from __future__ import annotations

import ast
import importlib
import re
import subprocess
import sys
import tomllib
import warnings
from collections.abc import Iterable, Mapping
from pathlib import Path
from unittest import mock

import pytest

import xodrlint
from xodrlint import MOVED_MODULES, _moved
from xodrlint.validation import libxml2, validators
from xodrlint.validation.libxml2 import Libxml2Validator
from xodrlint.validation.sets import SchemaFinder

from .conftest import REPO
from .old_layout import OLD_PUBLIC_NAMES

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
        for layer in contract.get("layers", []):
            named.update(part.strip() for part in re.split(r"[|:]", layer) if part.strip())
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
    place of its own (``workers/``: its modules sit in different layers)."""
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


@pytest.fixture(autouse=True)
def _fresh_old_paths(monkeypatch: pytest.MonkeyPatch) -> None:
    # a stand-in warns once per name: every test starts with new ones
    for old in MOVED_MODULES:
        monkeypatch.delitem(sys.modules, old, raising=False)
    monkeypatch.setattr("xodrlint.cli._OLD_NAMES_WARNED", set())


def test_no_old_path_is_a_real_module() -> None:
    for old in MOVED_MODULES:
        relative = Path(*old.split(".")[1:])
        assert not (PACKAGE / relative.with_suffix(".py")).exists(), old
        assert not (PACKAGE / relative / "__init__.py").exists(), old


def test_a_folder_left_at_an_old_path_does_not_hide_it(
    tmp_path: Path, monkeypatch: pytest.MonkeyPatch
) -> None:
    # a checkout keeps schemas/__pycache__/ after switching branches: without the finder
    # first in line, that folder imports as an empty namespace package
    (tmp_path / "schemas" / "__pycache__").mkdir(parents=True)
    monkeypatch.setattr(xodrlint, "__path__", [*xodrlint.__path__, str(tmp_path)])
    stand_in = importlib.import_module("xodrlint.schemas")

    assert isinstance(stand_in, _moved.MovedModule)
    with pytest.warns(DeprecationWarning):
        assert stand_in.SchemaFinder is SchemaFinder


def test_the_old_modules_are_the_ones_the_flat_layout_had() -> None:
    assert set(MOVED_MODULES) | {"xodrlint.cli", "xodrlint.model"} == set(OLD_PUBLIC_NAMES)


@pytest.mark.parametrize("old", sorted(OLD_PUBLIC_NAMES))
def test_every_public_name_of_an_old_module_still_imports(old: str) -> None:
    module = importlib.import_module(old)
    for name in OLD_PUBLIC_NAMES[old]:
        with warnings.catch_warnings(record=True) as caught:
            warnings.simplefilter("always")
            value = getattr(module, name)
        home = _named_home(caught, old, name)
        if home is None:  # still where it was (xodrlint.model, xodrlint.cli's app)
            continue
        assert getattr(importlib.import_module(home), name) is value, (old, name, home)
    with warnings.catch_warnings():
        warnings.simplefilter("error")  # once per name: a second read is quiet
        for name in OLD_PUBLIC_NAMES[old]:
            getattr(module, name)


def _named_home(caught: list[warnings.WarningMessage], old: str, name: str) -> str | None:
    texts = [str(w.message) for w in caught if issubclass(w.category, DeprecationWarning)]
    if not texts:
        return None
    (text,) = texts
    found = re.fullmatch(rf"{re.escape(old)}\.{name} moved to ([\w.]+)\.{name}; .*", text)
    assert found, text
    return found.group(1)


@pytest.mark.parametrize(
    ("old", "name", "home"),
    [
        ("xodrlint.schema", "Libxml2Validator", "xodrlint.validation.libxml2"),
        ("xodrlint.schema", "SchemaValidators", "xodrlint.validation.validators"),
        ("xodrlint.run", "show_config", "xodrlint.cli.config"),
        ("xodrlint.xsd_messages", "CHILD_KINDS", "xodrlint.validation.messages"),
        ("xodrlint.profile", "lane_width", "xodrlint.model.lane_profiles"),
        ("xodrlint.cli", "FAST_EXIT_ENV", "xodrlint.cli.entry"),
        ("xodrlint.cli", "FailOn", "xodrlint.cli.commands"),
    ],
)
def test_the_warning_names_where_a_name_is_defined(old: str, name: str, home: str) -> None:
    module = importlib.import_module(old)
    with pytest.warns(DeprecationWarning) as caught:
        getattr(module, name)
    assert _named_home(list(caught), old, name) in (home, "xodrlint.findings")


def test_a_name_imported_from_elsewhere_is_named_where_it_is_defined() -> None:
    import xodrlint.run  # type: ignore[import-not-found]

    with pytest.warns(
        DeprecationWarning, match=r"resolve_settings moved to xodrlint\.cli\.check\."
    ):
        xodrlint.run.resolve_settings  # noqa: B018
    import xodrlint.profile  # type: ignore[import-not-found]

    with pytest.warns(DeprecationWarning, match=r"profile\.Road moved to xodrlint\.model\.Road;"):
        xodrlint.profile.Road  # noqa: B018


def test_old_from_imports_star_imports_and_submodules_work() -> None:
    with pytest.warns(DeprecationWarning, match=r"xodrlint\.validation\.store\.install_wheel"):
        from xodrlint.schemas.store import install_wheel  # type: ignore[import-not-found]
    from xodrlint.validation.store import install_wheel as moved

    assert install_wheel is moved
    namespace: dict[str, object] = {}
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", DeprecationWarning)
        exec("from xodrlint.batch import *", namespace)
    assert namespace["lint_tasks"] is importlib.import_module("xodrlint.workers.batch").lint_tasks
    with pytest.raises(ImportError):
        importlib.import_module("xodrlint.schemas.nothing")
    with pytest.raises(AttributeError, match="has no attribute 'nothing'"):
        xodrlint.batch.nothing  # noqa: B018
    # an old module is reachable as an attribute of the package, as it was once imported
    assert isinstance(xodrlint.forkpool, _moved.MovedModule)


def test_patching_through_an_old_path_reaches_the_code_that_reads_it(
    monkeypatch: pytest.MonkeyPatch,
) -> None:
    from xodrlint.workers import batch

    original = batch.default_jobs
    old = importlib.import_module("xodrlint.batch")
    with pytest.warns(DeprecationWarning):
        monkeypatch.setattr(old, "default_jobs", lambda: 42)
    assert batch.default_jobs() == 42
    monkeypatch.undo()
    assert batch.default_jobs is original
    with mock.patch("xodrlint.schema.Libxml2Validator") as patched:
        # the old module's one binding is read in both new modules
        assert vars(validators)["Libxml2Validator"] is patched
        assert libxml2.Libxml2Validator is patched
    assert vars(validators)["Libxml2Validator"] is libxml2.Libxml2Validator is Libxml2Validator


def test_the_old_cli_names_and_the_console_entry() -> None:
    import xodrlint.cli
    from xodrlint.cli.entry import main

    assert xodrlint.cli.main is main
    with pytest.warns(DeprecationWarning, match=r"xodrlint\.cli\.explain moved to"):
        assert callable(xodrlint.cli.explain)
    with pytest.raises(AttributeError):
        xodrlint.cli.nothing  # noqa: B018


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
