"""A rule's cases: complete small OpenDRIVE files under ``rules/<CODE>/``, named
``valid_*`` (nothing to report) or ``invalid_*``, each line that must be reported marked.

A line that must be reported carries ``<!-- expect: CODE -->`` at its end (several codes
separated by commas), or the comment stands alone on the line before. A case runs with
only its folder's rule selected and its options at their defaults, unless a
``rule.toml`` in the folder says otherwise: ``select = ["SW", "PT"]`` for folders that pin
down how several rules share a defect, ``[options]`` for cases of other option values
(``platform-min-length = 60``), ``all-versions = true`` for cases of files older than a
rule applies from that the rule judges anyway (``--all-versions``).
"""

from __future__ import annotations

import re
from collections.abc import Mapping
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any, Final, NamedTuple

EXPECT: Final = re.compile(r"<!--\s*expect:\s*(?P<codes>[A-Z0-9,\s]+?)\s*-->")
#: A folder's rules other than its name's (``select = [...]``), its option values
#: (``[options]``) and whether every rule judges every version (``all-versions``).
SELECTION_FILE: Final = "rule.toml"
_KEYS: Final = ("select", "options", "all-versions")
CASE_SUFFIX: Final = ".xodr"
#: An invalid case's expected output once fixed sits beside it: ``invalid_x.fixed.xodr``.
FIXED_SUFFIX: Final = ".fixed.xodr"


def is_case(path: Path) -> bool:
    """Whether ``path`` is a case (a fixed case's expected output is none)."""
    return path.name.endswith(CASE_SUFFIX) and not path.name.endswith(FIXED_SUFFIX)


def fixed_output(case: Path) -> Path:
    """Where a case's expected output once fixed stands."""
    return case.with_name(case.name.removesuffix(CASE_SUFFIX) + FIXED_SUFFIX)


@dataclass(frozen=True, slots=True)
class RuleCase:
    """One case file and what it expects."""

    path: Path
    code: str
    """The folder's name: the rule's code (or, with a ``rule.toml``, a name of its own)."""
    expected: tuple[tuple[int, str], ...]
    """(line, code) pairs, sorted."""
    select: tuple[str, ...]
    """The rules the case runs with."""
    options: Mapping[str, float | str] = field(default_factory=dict)
    """Rule options by name; the others keep their defaults."""
    all_versions: bool = False
    """Every rule judges the case, whatever version it declares (``--all-versions``)."""

    @property
    def is_valid(self) -> bool:
        return self.path.name.startswith("valid_")

    @property
    def id(self) -> str:
        """``SW001/invalid_x.xodr``: how a test names the case."""
        return f"{self.code}/{self.path.name}"


def case_text(path: Path) -> str:
    """A case's text: UTF-16 or UTF-32 where the file is (a case of an encoding), else
    UTF-8; every line break a newline."""
    from xodrlint.document.positions import decode_wide, wide_encoding

    data = path.read_bytes()
    wide = wide_encoding(data)
    text = decode_wide(data, wide) if wide is not None else data.decode("utf-8-sig", "replace")
    return text.replace("\r\n", "\n").replace("\r", "\n")


def read_case(path: Path) -> RuleCase:
    """The case in ``path``; its selection from the folder's ``rule.toml`` if any."""
    expected: list[tuple[int, str]] = []
    lines = case_text(path).splitlines()
    for number, text in enumerate(lines, start=1):
        for match in EXPECT.finditer(text):
            alone = text[: match.start()].strip() == ""
            line = number + 1 if alone else number
            codes = [c.strip() for c in match["codes"].split(",") if c.strip()]
            expected.extend((line, code) for code in codes)
    settings = case_settings(path.parent)
    return RuleCase(
        path,
        path.parent.name,
        tuple(sorted(expected)),
        settings.select,
        settings.options,
        settings.all_versions,
    )


class CaseSettings(NamedTuple):
    """What a folder's cases run with."""

    select: tuple[str, ...]
    options: dict[str, float | str]
    all_versions: bool = False


def folder_settings(folder: Path) -> tuple[tuple[str, ...], dict[str, float | str]]:
    """The selectors a folder's cases run with (its ``rule.toml``'s, or its name) and the
    option values they set."""
    settings = case_settings(folder)
    return settings.select, settings.options


def case_settings(folder: Path) -> CaseSettings:
    """Everything a folder's ``rule.toml`` sets (selectors, option values, whether every
    rule judges every version), or the defaults without one."""
    settings = folder / SELECTION_FILE
    if not settings.is_file():
        return CaseSettings((folder.name,), {})
    import tomllib

    table: dict[str, Any] = tomllib.loads(settings.read_text(encoding="utf-8"))
    select = table.pop("select", [folder.name])
    options = table.pop("options", {})
    all_versions = table.pop("all-versions", False)
    if not isinstance(select, list) or not select or not all(isinstance(s, str) for s in select):
        raise ValueError(f"{settings}: 'select' must be a non-empty list of rule selectors")
    if not isinstance(options, dict) or not all(
        isinstance(v, int | float | str) and not isinstance(v, bool) for v in options.values()
    ):
        raise ValueError(f"{settings}: [options] must give numbers or strings by option name")
    if not isinstance(all_versions, bool):
        raise ValueError(f"{settings}: 'all-versions' must be true or false")
    if table:
        known = ", ".join(_KEYS)
        raise ValueError(f"{settings}: unknown key '{next(iter(table))}' (known: {known})")
    return CaseSettings(tuple(select), dict(options), all_versions)


def folder_selection(folder: Path) -> tuple[str, ...]:
    """The selectors a folder's cases run with."""
    return folder_settings(folder)[0]


def cases_in(folder: Path) -> list[RuleCase]:
    """The cases of one folder, by name."""
    return [read_case(path) for path in sorted(folder.glob(f"*{CASE_SUFFIX}")) if is_case(path)]


def find_cases(root: Path) -> list[RuleCase]:
    """Every case below ``root`` (``rules/``), folder by folder."""
    return [read_case(path) for path in sorted(root.rglob(f"*{CASE_SUFFIX}")) if is_case(path)]
