"""xodrlint.testing: the runner every rule pack's cases, docstrings and pages go through
(xodrlint's own in tests/rules/test_rule_cases.py and tests/test_docs.py; a third party's
through the pytest plugin). Here a small pack of its own, in a folder of the test, shows
each thing the runner must catch."""

from __future__ import annotations

import importlib
import os
import re
import subprocess
import sys
import textwrap
from pathlib import Path

import pytest

from tests.conftest import REPO
from xodrlint.devtools import docgen
from xodrlint.testing import PackError, RulePack, find_cases, read_case

CLEAN = (REPO / "examples" / "clean.xodr").read_text()
STATION = '<station name="Example Halt" id="500" type="small">'
MODULE = '''
"""AC001 station-named: a station has a name.

## What it does
Reports every station with a name.

## Why is this bad?
This pack tests the runner.

## Example
```xml
<station name="Example Halt" id="500" type="small"> <!-- expect: AC001 -->
```

Use instead:
```xml
<station id="500" type="small">
```

## Options
- `acme-prefix` (default `Ex`): what names must start with to be reported.

## References
- rule UID `acme:xodr:1.0.0:station_named`
"""

import re
from collections.abc import Iterator

from xodrlint.rules import Hit, RailNetwork, RuleOption, Settings, Severity, rule

PREFIX = RuleOption("acme-prefix", "Ex", "what names start with", kind="regex")


@rule(
    code="AC001",
    name="station-named",
    uid="acme:xodr:1.0.0:station_named",
    severity=Severity.INFO,
    options=[PREFIX],
)
def station_named(network: RailNetwork, settings: Settings) -> Iterator[Hit]:
    for station in network.stations:
        if station.name and re.match(PREFIX.text(settings), station.name):
            yield Hit(station.element, f"station '{station.name}' has a name")
'''


@pytest.fixture
def pack(tmp_path: Path, monkeypatch: pytest.MonkeyPatch) -> RulePack:
    """A one-rule pack with a valid and an invalid case and its pages written."""
    module = f"acme_{tmp_path.name.replace('-', '_')}"
    (tmp_path / f"{module}.py").write_text(MODULE)
    monkeypatch.syspath_prepend(str(tmp_path))
    # tests rewrite the module within a second, keeping its size: no stale bytecode
    monkeypatch.setattr(sys, "dont_write_bytecode", True)
    importlib.invalidate_caches()
    _case(tmp_path, "AC001/invalid_named.xodr", f"{STATION} <!-- expect: AC001 -->")
    _case(tmp_path, "AC001/valid_unnamed.xodr", '<station id="500" type="small">')
    made = RulePack([module], tmp_path)
    made.write_pages()
    return made


def _case(root: Path, name: str, station: str) -> Path:
    path = root / "rules" / name
    path.parent.mkdir(parents=True, exist_ok=True)
    path.write_text(CLEAN.replace(STATION, station))
    return path


def _line_of(path: Path, text: str) -> int:
    return next(n for n, line in enumerate(path.read_text().splitlines(), 1) if text in line)


def test_a_pack_in_order_has_no_problem(pack: RulePack) -> None:
    assert [meta.code for meta in pack.metas] == ["AC001"]
    assert [case.id for case in pack.cases] == [
        "AC001/invalid_named.xodr",
        "AC001/valid_unnamed.xodr",
    ]
    assert [problem for case in pack.cases for problem in pack.case_problems(case)] == []
    assert pack.docstring_problems(pack.metas[0]) == []
    assert pack.coverage_problems() == []
    assert pack.page_problems() == []


def test_expect_marks_at_the_end_or_alone_on_the_line_before(tmp_path: Path) -> None:
    path = tmp_path / "SW001" / "invalid_x.xodr"
    path.parent.mkdir()
    path.write_text(
        "<a>\n<b/> <!-- expect: SW001, SW002 -->\n  <!-- expect: PT001 -->\n<c/>\n</a>\n"
    )
    case = read_case(path)
    assert case.expected == ((2, "SW001"), (2, "SW002"), (4, "PT001"))
    assert case.select == ("SW001",) and case.options == {} and case.id == "SW001/invalid_x.xodr"


def test_a_case_that_differs_says_how(pack: RulePack) -> None:
    path = pack.root / "rules" / "AC001" / "invalid_wrong_line.xodr"
    path.write_text(CLEAN.replace("<OpenDRIVE>", "<OpenDRIVE> <!-- expect: AC001 -->"))
    marked, line = _line_of(path, "<OpenDRIVE>"), _line_of(path, STATION)
    assert pack.case_problems(read_case(path)) == [
        f"AC001/invalid_wrong_line.xodr: AC001 expected at line {marked}, not reported",
        f"AC001/invalid_wrong_line.xodr: AC001 at line {line} not expected: "
        "station 'Example Halt' has a name",
    ]


@pytest.mark.parametrize(
    ("name", "station", "problem"),
    [
        (
            "valid_marked.xodr",
            f"{STATION} <!-- expect: AC001 -->",
            "a valid_ case expects nothing; name it invalid_*",
        ),
        (
            "invalid_nothing.xodr",
            '<station id="500" type="small">',
            "expects no finding; name it valid_*",
        ),
        ("named_badly.xodr", STATION, "a case is named valid_* or invalid_*"),
    ],
)
def test_a_case_named_for_the_wrong_verdict(
    pack: RulePack, name: str, station: str, problem: str
) -> None:
    case = read_case(_case(pack.root, f"AC001/{name}", station))
    assert pack.case_problems(case) == [f"AC001/{name}: {problem}"]


def test_rule_toml_sets_selection_and_options(pack: RulePack) -> None:
    folder = pack.root / "rules" / "options" / "halts"
    folder.mkdir(parents=True)
    (folder / "rule.toml").write_text('select = ["AC"]\n[options]\nacme-prefix = "Central"\n')
    case = read_case(_case(pack.root, "options/halts/valid_other_prefix.xodr", STATION))
    assert case.select == ("AC",) and case.options == {"acme-prefix": "Central"}
    assert pack.case_problems(case) == []
    (folder / "rule.toml").write_text('select = ["AC001"]\n[options]\nacme-prefix = "("\n')
    [problem] = pack.case_problems(read_case(case.path))
    assert problem.startswith(f"halts/valid_other_prefix.xodr: {folder / 'rule.toml'}: ")
    assert "rule option 'acme-prefix' must be a regular expression" in problem


@pytest.mark.parametrize(
    ("text", "message"),
    [
        ("select = []\n", "'select' must be a non-empty list of rule selectors"),
        ("[options]\nx = true\n", "[options] must give numbers or strings by option name"),
        ("selekt = ['AC']\n", "unknown key 'selekt' (known: select, options, all-versions)"),
    ],
)
def test_a_rule_toml_that_cannot_be_read(tmp_path: Path, text: str, message: str) -> None:
    (tmp_path / "rules" / "fam").mkdir(parents=True)
    (tmp_path / "rules" / "fam" / "rule.toml").write_text(text)
    (tmp_path / "rules" / "fam" / "invalid_x.xodr").write_text("<x/>")
    with pytest.raises(ValueError, match=re.escape(message)):
        find_cases(tmp_path / "rules")


def test_rules_without_cases_and_cases_without_rules(pack: RulePack) -> None:
    for case in pack.cases:
        if case.is_valid:
            case.path.unlink()
    _case(pack.root, "AC002/invalid_x.xodr", STATION)
    _case(pack.root, "stray/invalid_x.xodr", STATION)
    rules = pack.root / "rules"
    assert RulePack(pack.targets, pack.root).coverage_problems() == [
        f"AC001 has no valid_* case in {rules / 'AC001'}",
        f"{rules / 'AC002'} holds cases of AC002, which is no rule of this pack",
        f"{rules / 'stray'} is named for no rule and has no rule.toml",
    ]


@pytest.mark.parametrize(
    ("old", "new", "problem"),
    [
        ("## Why is this bad?", "## Why?", "lacks '## Why is this bad?'"),
        ('"""AC001 station-named:', '"""AC001 station-name:', "its first line must read"),
        ("rule UID `acme:xodr:1.0.0:station_named`", "no UID", "'References' must name its UID"),
        (
            'id="500" type="small"> <!-- expect',
            'id="501" type="small"> <!-- expect',
            "its example is in no invalid_ case",
        ),
        (" <!-- expect: AC001 -->\n```", "\n```", "its example must mark the bad line"),
        (
            '<station id="500" type="small">\n```',
            '<station id="9" type="small">\n```',
            "its fix ('Use instead:') is in no valid_ case",
        ),
        (
            "- `acme-prefix` (default `Ex`)",
            "- prefix (default `Ex`)",
            "'Options' must name `acme-prefix`",
        ),
        ("(default `Ex`)", "(default: none)", "'Options' must give acme-prefix's default, Ex"),
        ("## Options", "## Settings", "declares options but has no 'Options' section"),
        (
            "options=[PREFIX],",
            "options=[PREFIX], defers_to=['AC009'],",
            "defers to AC009; 'Related rules' must say so",
        ),
    ],
)
def test_an_incomplete_docstring_says_what_it_lacks(
    pack: RulePack, old: str, new: str, problem: str
) -> None:
    module = pack.targets[0]
    path = pack.root / f"{module}.py"
    assert old in path.read_text()
    path.write_text(path.read_text().replace(old, new))
    sys.modules.pop(module, None)
    changed = RulePack(pack.targets, pack.root)
    problems = changed.docstring_problems(changed.metas[0])
    assert any(p.startswith(f"AC001: {problem}") for p in problems), problems


def test_stale_missing_and_stray_pages(pack: RulePack) -> None:
    page = pack.docs_root / "AC001.md"
    page.write_text(page.read_text() + "edited\n")
    (pack.docs_root / "AC404.md").write_text("# no such rule\n")
    assert pack.page_problems() == [
        "docs/rules/AC001.md is out of date",
        "docs/rules/AC404.md is the page of no rule",
        f"write them: python -m xodrlint.devtools.docgen --pack {pack.targets[0]}",
    ]
    assert pack.write_pages() == [page]
    page.unlink()
    assert pack.page_problems()[0] == "docs/rules/AC001.md is missing"


def test_a_pack_xodrlint_would_refuse_cannot_be_tested(tmp_path: Path) -> None:
    (tmp_path / "squatter_pack.py").write_text(MODULE.replace("AC001", "SW901"))
    sys.path.insert(0, str(tmp_path))
    try:
        with pytest.raises(PackError, match="uses codes reserved for xodrlint's own rules"):
            RulePack(["squatter_pack"], tmp_path).rules  # noqa: B018
    finally:
        sys.path.remove(str(tmp_path))
    with pytest.raises(PackError, match="no rule pack named"):
        RulePack([], tmp_path)


def test_docgen_writes_a_pack_s_pages(
    pack: RulePack, monkeypatch: pytest.MonkeyPatch, capsys: pytest.CaptureFixture[str]
) -> None:
    monkeypatch.chdir(pack.root)
    (pack.docs_root / "AC001.md").unlink()
    assert docgen.main(["--pack", pack.targets[0]]) == 0
    assert capsys.readouterr().out == "wrote docs/rules/AC001.md\n"
    assert pack.page_problems() == []
    assert docgen.main(["--pack"]) == 2
    assert docgen.main(["--pack", "no_such_pack_module"]) == 2
    assert "failed to load" in capsys.readouterr().err


def _pytest(project: Path, env_path: list[str]) -> subprocess.CompletedProcess[str]:
    own = [str(Path(p).resolve()) for p in os.environ.get("PYTHONPATH", "").split(os.pathsep) if p]
    return subprocess.run(
        [sys.executable, "-m", "pytest", "-p", "no:cacheprovider", "-p", "xodrlint.testing.plugin"],
        cwd=project,
        env={
            **os.environ,
            "PYTHONPATH": os.pathsep.join([*env_path, *own]),
            "PYTHONDONTWRITEBYTECODE": "1",
        },
        capture_output=True,
        text=True,
        check=False,
        timeout=300,
    )


def test_the_plugin_is_idle_in_a_project_that_does_not_use_it(tmp_path: Path) -> None:
    (tmp_path / "test_other.py").write_text("def test_other() -> None:\n    assert True\n")
    done = _pytest(tmp_path, [])
    assert done.returncode == 0, done.stdout
    assert "xodrlint:" not in done.stdout and "1 passed" in done.stdout


def test_the_plugin_says_when_no_pack_is_configured(tmp_path: Path) -> None:
    (tmp_path / "test_cases.py").write_text("from xodrlint.testing.suite import test_case\n")
    done = _pytest(tmp_path, [])
    assert done.returncode != 0
    assert "xodrlint: no rule pack named: give the module(s) its entry point names" in done.stdout
    assert "Traceback" not in done.stdout


def test_the_plugin_turns_cases_into_test_items(pack: RulePack) -> None:
    (pack.root / "pyproject.toml").write_text(
        textwrap.dedent(
            f"""\
            [tool.pytest.ini_options]
            xodrlint_packs = ["{pack.targets[0]}"]
            """
        )
    )
    (pack.root / "tests").mkdir()
    (pack.root / "tests" / "test_pack.py").write_text(
        "from xodrlint.testing.suite import *  # noqa: F403\n"
    )
    _case(pack.root, "AC001/invalid_unmarked.xodr", STATION)
    RulePack(pack.targets, pack.root).write_pages()  # only the case is wrong
    done = _pytest(pack.root, [str(pack.root)])
    assert done.returncode == 1, done.stdout
    assert f"xodrlint: rule pack {pack.targets[0]}, cases in rules/" in done.stdout
    line = _line_of(pack.root / "rules" / "AC001" / "invalid_unmarked.xodr", STATION)
    assert (
        f"AC001/invalid_unmarked.xodr: AC001 at line {line} not expected: "
        "station 'Example Halt' has a name"
    ) in done.stdout
    # each case is two items: its findings, and its fixes (none here)
    assert "1 failed, 8 passed" in done.stdout.splitlines()[-1]


def test_xodrlint_declares_no_pytest11_entry_point() -> None:
    # pytest rewrites every module of a distribution with a pytest11 entry point: all of
    # xodrlint, in every pytest session wherever it is installed, and runpy of
    # xodrlint.__main__ then fails (tests/cli/test_cli.py); packs load the plugin with -p
    import tomllib

    project = tomllib.loads((REPO / "pyproject.toml").read_text())["project"]
    assert "pytest11" not in project.get("entry-points", {})
    pack = tomllib.loads((REPO / "examples" / "rulepack" / "pyproject.toml").read_text())
    assert "-p xodrlint.testing.plugin" in pack["tool"]["pytest"]["ini_options"]["addopts"]
