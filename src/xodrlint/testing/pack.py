"""A rule pack under test: its rules, loaded as xodrlint loads an installed pack, its
cases, its doc pages, and what is wrong with each.

Each check returns its problems as lines (empty: all is well), so that any test runner
can report them; :mod:`xodrlint.testing.plugin` turns them into pytest items.
"""

from __future__ import annotations

from collections import Counter
from collections.abc import Sequence
from functools import cached_property
from pathlib import Path
from typing import TYPE_CHECKING

from xodrlint.findings import RuleMeta
from xodrlint.rules import CODE_PATTERN
from xodrlint.testing.cases import (
    CASE_SUFFIX,
    FIXED_SUFFIX,
    SELECTION_FILE,
    RuleCase,
    case_text,
    cases_in,
    find_cases,
    fixed_output,
    is_case,
)
from xodrlint.testing.docstrings import docstring_problems
from xodrlint.testing.pages import render_page

if TYPE_CHECKING:
    from xodrlint.engine.linter import Linter
    from xodrlint.findings import FileReport
    from xodrlint.rules import Rule
    from xodrlint.rules.registry import Registry


class PackError(ValueError):
    """A pack that cannot be tested: it fails to load, or xodrlint would refuse it."""


class RulePack:
    """The pack whose rules the entry-point targets ``targets`` name (``my_pack`` or
    ``my_pack.rules:RULES``), with its cases in ``root / cases`` and its doc pages in
    ``root / docs``."""

    def __init__(
        self,
        targets: Sequence[str],
        root: Path,
        *,
        cases: str = "rules",
        docs: str = "docs/rules",
    ) -> None:
        if not targets:
            raise PackError("no rule pack named: give the module(s) its entry point names")
        self.targets = tuple(targets)
        self.root = root
        self.cases_root = root / cases
        self.docs_root = root / docs

    @cached_property
    def rules(self) -> tuple[Rule, ...]:
        """The pack's rules, loaded and checked as an installed pack is (a rule API it
        was not written for, a reserved code prefix: :class:`PackError`)."""
        from xodrlint.config.plugins import Plugin
        from xodrlint.rules.registry import ENTRY_POINT_GROUP, PackRefused, load_pack

        rules: dict[str, Rule] = {}
        for target in self.targets:
            name = target.partition(":")[0]
            try:
                rules.update(
                    (r.code, r) for r in load_pack(Plugin(name, target, ENTRY_POINT_GROUP))
                )
            except PackRefused as refused:
                raise PackError(str(refused)) from None
        return tuple(sorted(rules.values(), key=lambda r: r.code))

    @property
    def metas(self) -> tuple[RuleMeta, ...]:
        return tuple(r.meta for r in self.rules)

    @cached_property
    def registry(self) -> Registry:
        """Every installed rule, with the pack's own from the tree under test over an
        installed release of it: a case may select other packs' rules too."""
        from xodrlint.rules.registry import Registry, load_registry

        by_code = {r.code: r for r in load_registry().rules}
        by_code.update((r.code, r) for r in self.rules)
        return Registry(tuple(sorted(by_code.values(), key=lambda r: r.code)))

    @cached_property
    def cases(self) -> list[RuleCase]:
        return find_cases(self.cases_root) if self.cases_root.is_dir() else []

    def lint(self, case: RuleCase) -> FileReport:
        """The case linted with its selection, as ``xodrlint check --select`` would."""
        return self._linter(case).lint_path(case.path)

    def _linter(self, case: RuleCase, *, fixing: bool = False) -> Linter:
        from xodrlint.engine.fixing import DIFF, FixPolicy
        from xodrlint.engine.linter import Linter, LintOptions

        options = LintOptions(
            select=case.select,
            rule_options=case.options,
            all_versions=case.all_versions,
            fixes=FixPolicy(mode=DIFF, unsafe=True) if fixing else FixPolicy(),
            place_fixes=fixing,
        )
        return Linter(self.registry, options)

    def fix_problems(self, case: RuleCase) -> list[str]:
        """How ``case`` fixed (every fix of its selection, unsafe ones too) differs from
        its expected output (``invalid_x.fixed.xodr``, byte for byte), and whether fixing
        that output changes it again. A case whose findings have fixes needs one; a valid
        case has none."""
        expected_path = fixed_output(case.path)
        has_output = expected_path.is_file()
        if case.is_valid:
            return [f"{case.id}: a valid_ case has no fixed output"] if has_output else []
        linter = self._linter(case, fixing=True)
        fixed, report = linter.fixed_source(case.path.read_bytes(), case.id, case.path)
        problems = [f"{case.id}: internal error: {error}" for error in report.internal_errors]
        if not has_output:
            if fixed != case.path.read_bytes():
                name = expected_path.name
                problems.append(f"{case.id}: its findings have fixes; record the output in {name}")
            return problems
        expected = expected_path.read_bytes()
        if fixed != expected:
            problems.append(
                f"{case.id}: fixed, it differs from {expected_path.name}:\n"
                + _diff(expected, fixed, expected_path.name)
            )
        again, _ = linter.fixed_source(expected, expected_path.name, expected_path)
        if again != expected:
            problems.append(f"{case.id}: fixing {expected_path.name} changes it again")
        return problems

    def case_problems(self, case: RuleCase) -> list[str]:
        """How the findings of ``case`` differ from its ``expect`` marks, line and code."""
        if not case.path.name.startswith(("valid_", "invalid_")):
            return [f"{case.id}: a case is named valid_* or invalid_*"]
        from xodrlint.rules.options import OptionError
        from xodrlint.rules.selection import SelectorError

        try:
            report = self.lint(case)
        except (OptionError, SelectorError) as error:  # the folder's rule.toml
            return [f"{case.id}: {case.path.parent / SELECTION_FILE}: {error}"]
        if report.error:
            return [f"{case.id}: {report.error}"]
        problems = [f"{case.id}: internal error: {error}" for error in report.internal_errors]
        expected = Counter(case.expected)
        found = Counter((f.line, f.code) for f in report.findings)
        for line, code in sorted((expected - found).elements()):
            problems.append(f"{case.id}: {code} expected at line {line}, not reported")
        extra = found - expected
        for finding in report.findings:  # each unexpected one with its message
            key = (finding.line, finding.code)
            if extra[key] > 0:
                extra[key] -= 1
                problems.append(
                    f"{case.id}: {finding.code} at line {finding.line} not expected: "
                    f"{finding.message}"
                )
        if case.is_valid and case.expected:
            problems.append(f"{case.id}: a valid_ case expects nothing; name it invalid_*")
        if not case.is_valid and not case.expected:
            problems.append(f"{case.id}: expects no finding; name it valid_*")
        return problems

    def docstring_problems(self, meta: RuleMeta) -> list[str]:
        """What the rule's doc page (its module docstring) lacks."""
        folder = self.cases_root / meta.code
        cases = [p for p in folder.glob(f"*{CASE_SUFFIX}") if is_case(p)]
        texts = {p.name: case_text(p) for p in cases}
        invalid = [text for name, text in texts.items() if name.startswith("invalid_")]
        valid = [text for name, text in texts.items() if name.startswith("valid_")]
        problems = docstring_problems(meta, invalid, valid)
        fixed = any(fixed_output(p).is_file() for p in cases)
        says = meta.section("Fix") is not None
        if fixed and not says:
            problems.append(f"{meta.code}: its cases have fixes; a 'Fix' section must say which")
        if says and not fixed:
            problems.append(f"{meta.code}: has a 'Fix' section but no case a fix mends")
        return problems

    def coverage_problems(self) -> list[str]:
        """Rules without a valid_ and an invalid_ case, and case folders without a rule."""
        problems = []
        for meta in self.metas:
            names = [
                p.name for p in (self.cases_root / meta.code).glob(f"*{CASE_SUFFIX}") if is_case(p)
            ]
            for kind in ("valid_", "invalid_"):
                if not any(name.startswith(kind) for name in names):
                    problems.append(
                        f"{meta.code} has no {kind}* case in {self.cases_root / meta.code}"
                    )
        if self.cases_root.is_dir():
            for output in sorted(self.cases_root.rglob(f"*{FIXED_SUFFIX}")):
                case = output.with_name(output.name.removesuffix(FIXED_SUFFIX) + CASE_SUFFIX)
                if not case.is_file():
                    problems.append(f"{output} is the fixed output of no case ({case.name})")
        codes = {meta.code for meta in self.metas}
        for folder in sorted({case.path.parent for case in self.cases}):
            if (folder / SELECTION_FILE).is_file():
                continue
            if not CODE_PATTERN.match(folder.name):  # a case folder is named as a code
                problems.append(f"{folder} is named for no rule and has no {SELECTION_FILE}")
            elif folder.name not in codes:
                problems.append(
                    f"{folder} holds cases of {folder.name}, which is no rule of this pack"
                )
        return problems

    def pages(self) -> dict[Path, str]:
        """Each rule's doc page by the path it belongs at."""
        return {
            self.docs_root / f"{meta.code}.md": render_page(
                meta, cases_in(self.cases_root / meta.code), self.root
            )
            for meta in self.metas
        }

    def page_problems(self) -> list[str]:
        """Pages missing, out of date, or of no rule of the pack."""
        pages = self.pages()
        problems = [
            f"{path.relative_to(self.root)} is {'out of date' if path.is_file() else 'missing'}"
            for path, text in pages.items()
            if not path.is_file() or path.read_text(encoding="utf-8") != text
        ]
        extra = sorted(set(self.docs_root.glob("*.md")) - set(pages))
        problems += [f"{path.relative_to(self.root)} is the page of no rule" for path in extra]
        if problems:
            problems.append(f"write them: {write_command(self)}")
        return problems

    def write_pages(self) -> list[Path]:
        """Write every page that differs; the paths written."""
        written = []
        for path, text in self.pages().items():
            if not path.is_file() or path.read_text(encoding="utf-8") != text:
                path.parent.mkdir(parents=True, exist_ok=True)
                path.write_text(text, encoding="utf-8")
                written.append(path)
        return written


def _diff(expected: bytes, found: bytes, name: str) -> str:
    import difflib

    lines = difflib.unified_diff(
        expected.decode("utf-8", "replace").splitlines(keepends=True),
        found.decode("utf-8", "replace").splitlines(keepends=True),
        fromfile=name,
        tofile="fixed",
    )
    return "".join(lines)


def write_command(pack: RulePack) -> str:
    """The command that writes ``pack``'s pages, to be run in its root."""
    targets = " ".join(f"--pack {target}" for target in pack.targets)
    return f"python -m xodrlint.devtools.docgen {targets}"
