"""Loading third-party rule packs: the rule API version a pack was written for, the code
prefixes reserved for xodrlint's own rules, where each rule came from, and one warning
naming a refused pack while the run goes on."""

from __future__ import annotations

import importlib
import json
import os
import subprocess
import sys
import textwrap
from pathlib import Path

import pytest

from tests.conftest import REPO
from xodrlint.config.plugins import Plugin, installed
from xodrlint.findings import PackInfo
from xodrlint.rules import API_VERSION
from xodrlint.rules.registry import ENTRY_POINT_GROUP, load_registry

CLEAN = REPO / "examples" / "clean.xodr"
RULE = """
from collections.abc import Iterator
from xodrlint.rules import Hit, RailNetwork, Severity, rule

@rule(code="{code}", name="{name}", uid="acme:xodr:1.0.0:{name}", severity=Severity.INFO)
def check(network: RailNetwork) -> Iterator[Hit]:
    for road in network.roads[:1]:
        yield Hit(road.element, "from {module}")
"""


def _pack(folder: Path, module: str, code: str, declaration: str = "") -> Plugin:
    """A one-rule pack module ``module`` in ``folder``, as an entry point would name it."""
    name = f"acme-{module.replace('_', '-')}"
    text = declaration + "\n" + RULE.format(code=code, name=name, module=module)
    (folder / f"{module}.py").write_text(textwrap.dedent(text))
    sys.modules.pop(module, None)  # another test's module of that name
    importlib.invalidate_caches()
    return Plugin(module, module, ENTRY_POINT_GROUP, "acme-rules", "2.3")


@pytest.fixture
def packs(tmp_path: Path, monkeypatch: pytest.MonkeyPatch) -> Path:
    monkeypatch.syspath_prepend(str(tmp_path))
    return tmp_path


def _load(*points: Plugin) -> tuple[set[str], list[str]]:
    registry = load_registry([*installed(ENTRY_POINT_GROUP), *points])
    return set(registry.by_code), list(registry.warnings)


@pytest.mark.parametrize("declared", [API_VERSION, (API_VERSION[0], 0)])
def test_a_pack_for_this_rule_api_is_loaded(packs: Path, declared: tuple[int, int]) -> None:
    point = _pack(
        packs, f"api_{declared[0]}_{declared[1]}", "AC001", f"XODRLINT_RULE_API = {declared}"
    )
    codes, warnings = _load(point)
    assert "AC001" in codes and "SW001" in codes
    assert warnings == []


@pytest.mark.parametrize(
    ("declared", "remedy"),
    [
        ((API_VERSION[0] + 1, 0), "upgrade xodrlint"),
        ((API_VERSION[0], API_VERSION[1] + 1), "upgrade xodrlint"),
        ((API_VERSION[0] - 1, 9), f"install a release of the pack for rule API {API_VERSION[0]}.x"),
    ],
)
def test_a_pack_for_another_rule_api_is_refused_with_one_warning(
    packs: Path, declared: tuple[int, int], remedy: str
) -> None:
    point = _pack(packs, "other_api", "AC001", f"XODRLINT_RULE_API = {declared}")
    codes, warnings = _load(point)
    assert "AC001" not in codes and "SW001" in codes
    major, minor = declared
    assert warnings == [
        f"rule pack 'other_api' (other_api, from acme-rules 2.3) is written for rule API "
        f"{major}.{minor}, but this xodrlint has rule API "
        f"{API_VERSION[0]}.{API_VERSION[1]}: none of its rules run ({remedy})"
    ]


@pytest.mark.parametrize("declared", ["'1.0'", "1", "(1,)", "(1, 0, 0)", "(True, 0)"])
def test_a_malformed_declaration_is_refused(packs: Path, declared: str) -> None:
    point = _pack(packs, "malformed", "AC001", f"XODRLINT_RULE_API = {declared}")
    codes, warnings = _load(point)
    assert "AC001" not in codes
    [warning] = warnings
    assert warning.startswith("rule pack 'malformed' (malformed, from acme-rules 2.3) declares")
    assert warning.endswith(f"not (major, minor) such as {API_VERSION!r}: none of its rules run")


def test_a_pack_without_a_declaration_is_loaded(packs: Path) -> None:
    codes, warnings = _load(_pack(packs, "undeclared", "AC001"))
    assert "AC001" in codes and warnings == []


@pytest.mark.parametrize("code", ["SW901", "SWX001", "XS901", "XY001", "PT100", "TR999"])
def test_a_pack_using_a_reserved_prefix_is_refused(packs: Path, code: str) -> None:
    good = _pack(packs, "good", "AC001")
    bad = _pack(packs, "squatter", code)
    codes, warnings = _load(good, bad)
    assert code not in codes and "AC001" in codes
    assert warnings == [
        f"rule pack 'squatter' (squatter, from acme-rules 2.3) uses codes reserved for "
        f"xodrlint's own rules ({code}; reserved: PT, RL, ST, SW, TR, X...): none of its "
        "rules run"
    ]


OPTION_RULE = """
from collections.abc import Iterator
from xodrlint.rules import Hit, RailNetwork, RuleOption, Severity, rule

@rule(
    code="AC002",
    name="acme-option",
    uid="acme:xodr:1.0.0:option",
    severity=Severity.INFO,
    options=(RuleOption("{option}", 1.0, "what it bounds"),),
)
def check(network: RailNetwork, settings: dict[str, float]) -> Iterator[Hit]:
    yield from ()
"""


@pytest.mark.parametrize("option", ["exclude", "select", "schema"])
def test_a_pack_whose_option_is_named_as_a_setting_is_refused(packs: Path, option: str) -> None:
    # the config table and the command line are shared: 'exclude' would break --exclude
    (packs / "settings_squatter.py").write_text(textwrap.dedent(OPTION_RULE.format(option=option)))
    sys.modules.pop("settings_squatter", None)
    importlib.invalidate_caches()
    point = Plugin("settings_squatter", "settings_squatter", ENTRY_POINT_GROUP, "acme-rules", "2.3")
    codes, warnings = _load(_pack(packs, "good2", "AC001"), point)
    assert "AC002" not in codes and "AC001" in codes
    assert warnings == [
        "rule pack 'settings_squatter' (settings_squatter, from acme-rules 2.3) declares rule "
        f"options named as xodrlint's own settings ({option}): none of its rules run"
    ]


def test_each_rule_knows_its_pack(packs: Path) -> None:
    registry = load_registry([*installed(ENTRY_POINT_GROUP), _pack(packs, "house", "AC001")])
    assert registry.by_code["AC001"].meta.origin == PackInfo("house", "acme-rules", "2.3")
    switches = registry.by_code["SW001"].meta.origin
    assert switches is not None and switches.builtin and switches.name == "switches"
    assert switches.distribution == "xodrlint"


def _installed(tmp_path: Path, modules: dict[str, str]) -> dict[str, str]:
    """An environment where ``modules`` (entry-point name: module text) are installed as
    one distribution, as pip leaves it, without touching the test's own environment."""
    site = tmp_path / "site"
    info = site / "acme_rules-2.3.dist-info"
    info.mkdir(parents=True)
    (info / "METADATA").write_text("Metadata-Version: 2.1\nName: acme-rules\nVersion: 2.3\n")
    points = "".join(f"{name} = {name}\n" for name in modules)
    (info / "entry_points.txt").write_text(f"[{ENTRY_POINT_GROUP}]\n{points}")
    for name, text in modules.items():
        (site / f"{name}.py").write_text(textwrap.dedent(text))
    return {
        **os.environ,
        "PYTHONPATH": os.pathsep.join([str(site), *_absolute(os.environ.get("PYTHONPATH", ""))]),
        "XODRLINT_CACHE_DIR": str(tmp_path / "cache"),
    }


def _absolute(path: str) -> list[str]:
    """The test's own search path (``PYTHONPATH=src`` in a worktree), wherever the child
    starts."""
    return [str(Path(entry).resolve()) for entry in path.split(os.pathsep) if entry]


def _xodrlint(env: dict[str, str], *args: str | Path) -> subprocess.CompletedProcess[str]:
    return subprocess.run(
        [sys.executable, "-m", "xodrlint", *map(str, args)],
        env=env,
        capture_output=True,
        text=True,
        check=False,
        timeout=120,
    )


def test_the_command_line_warns_once_and_runs_the_other_packs(tmp_path: Path) -> None:
    future = f"XODRLINT_RULE_API = ({API_VERSION[0] + 1}, 0)\n" + RULE.format(
        code="AC002", name="acme-future", module="future"
    )
    env = _installed(
        tmp_path,
        {
            "house": RULE.format(code="AC001", name="acme-house", module="house"),
            "future": future,
        },
    )
    copies = [tmp_path / f"map{n}.xodr" for n in range(4)]
    for copy in copies:
        copy.write_bytes(CLEAN.read_bytes())
    done = _xodrlint(env, "check", "-f", "json", "-j", "2", *copies)
    assert done.returncode == 0, done.stderr
    lines = done.stderr.splitlines()
    assert [line for line in lines if "rule pack" in line] == [
        line for line in lines if line.startswith("xodrlint: warning: rule pack 'future'")
    ]
    assert len(lines) == 1, done.stderr
    findings = json.loads(done.stdout)["findings"]
    assert [(f["code"], f["message"]) for f in findings] == [("AC001", "from house")] * 4


def test_rules_lists_a_pack_under_its_name(tmp_path: Path) -> None:
    env = _installed(
        tmp_path, {"house": RULE.format(code="AC001", name="acme-house", module="house")}
    )
    done = _xodrlint(env, "rules")
    assert done.returncode == 0 and done.stderr == ""
    table, _, rest = done.stdout.partition("\n\nRule pack 'house' (acme-rules 2.3):\n")
    pack, _, footnote = rest.partition("\n\n")
    assert footnote.startswith("Off by default")
    assert pack.split() == ["AC001", "acme-house", "info", "acme:xodr:1.0.0:acme-house"]
    assert table.splitlines()[1].startswith("PT001  ")  # xodrlint's own rules first
    header = table.splitlines()[0]
    assert pack.index("acme-house") == header.index("Name")  # aligned as one table
    assert pack.index("info") == header.index("Severity")
    explained = _xodrlint(env, "explain", "AC001")
    assert explained.stdout.splitlines()[2].endswith(" · rule pack 'house' (acme-rules 2.3)")
    entry = next(
        e for e in json.loads(_xodrlint(env, "rules", "-f", "json").stdout) if e["code"] == "AC001"
    )
    assert entry["plugin"] == {
        "name": "house",
        "distribution": "acme-rules",
        "version": "2.3",
        "builtin": False,
    }


def test_the_python_api_warns_once_of_a_refused_pack(
    packs: Path, monkeypatch: pytest.MonkeyPatch
) -> None:
    from xodrlint import api

    registry = load_registry([*installed(ENTRY_POINT_GROUP), _pack(packs, "squatter", "SW901")])
    monkeypatch.setattr(api, "default_registry", lambda: registry)
    api._api_registry.cache_clear()
    api._linter.cache_clear()
    try:
        with pytest.warns(RuntimeWarning, match="xodrlint: rule pack 'squatter'") as caught:
            report = api.lint_file(CLEAN)
            api.lint_file(CLEAN, select=("SW",))  # another linter, the same registry
        assert len(caught) == 1
        assert report.findings == () and report.error is None
    finally:
        api._api_registry.cache_clear()
        api._linter.cache_clear()
