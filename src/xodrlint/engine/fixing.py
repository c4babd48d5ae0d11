"""``--fix`` and ``--diff``: the fixes of a file's findings applied in passes, checked.

A pass lints the source, takes the fixes the policy allows (safe ones; unsafe ones too
with ``--unsafe-fixes``; codes ``fixable`` names and ``unfixable`` does not), as many as
touch no text another took, makes their edits and lints the result. A fix whose result
is not well-formed, or still has the finding it was made for, is rolled back and
reported as its rule's internal error; the others stay. Passes repeat while fixes apply,
at most :data:`MAX_PASSES` times: a fix that reveals another defect (an unsafe one may)
gets its own pass. The report is the fixed source's.
"""

from __future__ import annotations

import difflib
from collections import Counter
from collections.abc import Callable, Iterable, Sequence
from typing import TYPE_CHECKING, Final, NamedTuple

from xodrlint.findings import FileReport, Finding
from xodrlint.fixes import Applicability

if TYPE_CHECKING:
    from xodrlint.document.edits import EditableSource
    from xodrlint.rules.registry import Registry

#: At most this many passes over one file (ruff's limit is 100; fixes of a railroad map
#: seldom reveal more than one more).
MAX_PASSES: Final = 10
#: What ``--fix`` does with what it fixed: write it back, or show it as a diff.
APPLY: Final = "apply"
DIFF: Final = "diff"


class FixPolicy(NamedTuple):
    """Which fixes a run makes, and what it does with them (``mode``: none, ``apply``
    or ``diff``)."""

    mode: str = ""
    unsafe: bool = False
    fixable: tuple[str, ...] = ("ALL",)
    unfixable: tuple[str, ...] = ()

    def fixable_codes(self, registry: Registry) -> frozenset[str]:
        """The codes whose fixes count: those ``fixable`` names more closely than
        ``unfixable`` does (``ALL`` names every rule, an opt-in one too)."""
        from xodrlint.rules.selection import specificity

        def best(tokens: Iterable[str], code: str) -> int | None:
            rule = registry.by_code[code]
            scores = [0 if token.upper() == "ALL" else specificity(token, rule) for token in tokens]
            return max((score for score in scores if score is not None), default=None)

        chosen = set()
        for code in registry.by_code:
            taken, refused = best(self.fixable, code), best(self.unfixable, code)
            if taken is not None and (refused is None or taken > refused):
                chosen.add(code)
        return frozenset(chosen)


class Fixed(NamedTuple):
    """The outcome of fixing one source: the report of what it still has (with how many
    findings were fixed and the rolled-back fixes among its internal errors) and the
    fixed bytes."""

    report: FileReport
    data: bytes


class Linted(NamedTuple):
    """One lint of a source: its report with the fixes placed, the editable source they
    were placed in (``None`` where nothing was placed, or why it could not be edited),
    and, where the source is no OpenDRIVE tree, why (whatever rules were selected)."""

    report: FileReport
    source: EditableSource | str | None
    broken: str | None = None


Lint = Callable[[bytes], Linted]


def fix_source(data: bytes, lint: Lint, policy: FixPolicy) -> Fixed:
    """``data`` with every fix ``policy`` allows made, pass by pass, each checked."""
    report, source, _ = lint(data)
    fixed = 0
    refused: set[tuple[str, str]] = set()  # fixes rolled back: not tried again
    crashes: list[str] = []
    for _ in range(MAX_PASSES):
        from xodrlint.document.edits import EditableSource

        chosen = _chosen(report.findings, policy, refused)
        if not chosen or not isinstance(source, EditableSource):
            break
        outcome = _pass(data, report, source, chosen, lint)
        for finding, reason in outcome.rolled_back:
            refused.add((finding.code, finding.xpath))
            crashes.append(f"fix for {finding.code} produced {reason} on {report.path}")
        if outcome.applied == 0:
            continue  # every fix of this pass was rolled back: try the ones left
        data, report, source = outcome.data, outcome.report, outcome.source
        fixed += outcome.applied
    internal = (*report.internal_errors, *crashes)
    return Fixed(report._replace(fixed=fixed, internal_errors=internal), data)


def diff_of(before: bytes, after: bytes, codec: str, path: str) -> str:
    """A unified diff of ``before`` and ``after``, decoded with ``codec``."""
    old = before.decode(codec).removeprefix("\ufeff").splitlines(keepends=True)
    new = after.decode(codec).removeprefix("\ufeff").splitlines(keepends=True)
    lines = difflib.unified_diff(old, new, fromfile=f"a/{path}", tofile=f"b/{path}")
    return "".join(line if line.endswith(("\n", "\r")) else line + "\n" for line in lines)


def _chosen(
    findings: Sequence[Finding], policy: FixPolicy, refused: set[tuple[str, str]]
) -> list[Finding]:
    """The findings whose fixes this pass makes: allowed, placed, and touching no text
    a fix before them in the report touches."""
    from xodrlint.document.edits import Edit, overlapping

    taken: list[Edit] = []
    chosen: list[Finding] = []
    for finding in findings:
        fix = finding.fix
        if fix is None or not fix.edits or (finding.code, finding.xpath) in refused:
            continue
        if fix.applicability is Applicability.UNSAFE and not policy.unsafe:
            continue
        edits = [Edit(edit.start, edit.end, edit.content) for edit in fix.edits]
        if overlapping([*taken, *edits]):
            continue
        taken += edits
        chosen.append(finding)
    return chosen


class _Pass(NamedTuple):
    data: bytes
    report: FileReport
    source: EditableSource | str | None
    applied: int
    rolled_back: list[tuple[Finding, str]]


def _pass(
    data: bytes, report: FileReport, source: EditableSource, chosen: list[Finding], lint: Lint
) -> _Pass:
    """Make ``chosen``'s fixes together; when the result fails, find the fixes that fail
    alone, roll them back and make the rest."""
    result = _try(source, report, chosen, lint)
    if isinstance(result, tuple):
        return _Pass(*result, len(chosen), [])
    rolled_back: list[tuple[Finding, str]] = []
    kept: list[Finding] = []
    for finding in chosen:
        alone = _try(source, report, [finding], lint)
        if isinstance(alone, str):
            rolled_back.append((finding, alone))
        else:
            kept.append(finding)
    together = _try(source, report, kept, lint) if kept else "no fix"
    if isinstance(together, str):  # fine alone, failing together: make none this pass
        rolled_back += [(finding, together) for finding in kept]
        return _Pass(data, report, source, 0, rolled_back)
    return _Pass(*together, len(kept), rolled_back)


def _try(
    source: EditableSource, report: FileReport, chosen: list[Finding], lint: Lint
) -> tuple[bytes, FileReport, EditableSource | str | None] | str:
    """The fixed bytes, their report and source, or what is wrong with the result."""
    from xodrlint.document.edits import Edit, EditError

    edits = [
        Edit(edit.start, edit.end, edit.content)
        for finding in chosen
        if finding.fix is not None
        for edit in finding.fix.edits
    ]
    try:
        data = source.apply(edits)
    except EditError as error:
        return f"edits that cannot be made ({error})"
    after, placed, broken = lint(data)
    if broken is not None:
        return f"a document that is not well-formed ({broken})"
    if after.error is not None:
        return f"a document that cannot be read ({after.error})"
    before = Counter((f.code, f.xpath) for f in report.findings)
    now = Counter((f.code, f.xpath) for f in after.findings)
    wanted = Counter((f.code, f.xpath) for f in chosen)
    for key, count in wanted.items():
        if now[key] > before[key] - count:
            return f"a document that still has its finding ({key[0]} at {key[1]})"
    return data, after, placed
