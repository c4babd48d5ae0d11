"""The pytest plugin of rule packs.

A pack loads and configures it in ``[tool.pytest.ini_options]``::

    addopts = "-p xodrlint.testing.plugin"
    xodrlint_packs = ["my_pack"]      # what its xodrlint.rules entry point names
    xodrlint_cases = "rules"          # folders of cases, rules/<CODE>/ (the default)
    xodrlint_docs = "docs/rules"      # generated doc pages (the default)

and a test that asks for ``xodrlint_case`` runs once per case, one that asks for
``xodrlint_rule`` once per rule of the pack; ``xodrlint_pack`` is the
:class:`~xodrlint.testing.RulePack` that checks them. :mod:`xodrlint.testing.suite`
holds the tests themselves. Until a test asks, it imports nothing of xodrlint's.

It is loaded by name, not through a ``pytest11`` entry point: pytest rewrites the
assertions of every module of a distribution that declares one, which for xodrlint
would be the whole package in every pytest session of every environment it is
installed in (and ``runpy`` of ``xodrlint.__main__`` fails under that import hook).
"""

from __future__ import annotations

from pathlib import Path
from typing import TYPE_CHECKING, Final

import pytest

if TYPE_CHECKING:
    from xodrlint.testing.pack import RulePack

PACKS: Final = "xodrlint_packs"
CASES: Final = "xodrlint_cases"
DOCS: Final = "xodrlint_docs"
_PACK_KEY: Final = pytest.StashKey["RulePack"]()


def pytest_addoption(parser: pytest.Parser) -> None:
    parser.addini(PACKS, "xodrlint: the rule pack under test (entry-point targets)", "linelist")
    parser.addini(CASES, "xodrlint: the folder of rules/<CODE>/ cases", default="rules")
    parser.addini(DOCS, "xodrlint: the folder of generated doc pages", default="docs/rules")


def pytest_report_header(config: pytest.Config) -> str | None:
    targets = config.getini(PACKS)
    if not targets:
        return None
    return f"xodrlint: rule pack {', '.join(targets)}, cases in {config.getini(CASES)}/"


def pytest_generate_tests(metafunc: pytest.Metafunc) -> None:
    if "xodrlint_case" in metafunc.fixturenames:
        cases = _pack(metafunc.config).cases
        metafunc.parametrize("xodrlint_case", cases, ids=[case.id for case in cases])
    if "xodrlint_rule" in metafunc.fixturenames:
        metas = _pack(metafunc.config).metas
        metafunc.parametrize("xodrlint_rule", metas, ids=[meta.code for meta in metas])


@pytest.fixture(scope="session")
def xodrlint_pack(request: pytest.FixtureRequest) -> RulePack:
    """The rule pack ``xodrlint_packs`` names."""
    return _pack(request.config)


def _pack(config: pytest.Config) -> RulePack:
    """The pack under test, loaded once a session; a pack that cannot be loaded (or a
    ``rule.toml`` that cannot be read) is a collection error saying why, not a traceback."""
    if _PACK_KEY in config.stash:
        return config.stash[_PACK_KEY]
    from xodrlint.testing.pack import PackError, RulePack

    folder = config.inipath.parent if config.inipath else config.rootpath
    try:
        pack = RulePack(
            config.getini(PACKS),
            Path(folder),
            cases=str(config.getini(CASES)),
            docs=str(config.getini(DOCS)),
        )
        pack.rules  # noqa: B018  (loading it is the check)
        pack.cases  # noqa: B018  (and reading the cases)
    except PackError as error:
        where = config.inipath or "the pytest configuration"
        raise pytest.Collector.CollectError(f"xodrlint: {error} ({PACKS} in {where})") from None
    except ValueError as error:
        raise pytest.Collector.CollectError(f"xodrlint: {error}") from None
    config.stash[_PACK_KEY] = pack
    return pack
