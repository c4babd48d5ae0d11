"""``--fix`` and ``--diff``: the fixes of a file's findings applied in passes, checked.

A pass lints the source, takes the fixes the policy allows (safe ones; unsafe ones too
with ``--unsafe-fixes``; codes ``fixable`` names and ``unfixable`` does not): every safe
one, and the unsafe ones of one rule, as many as touch no text another took. It makes
their edits and lints the result. Where the result fails, the pass makes the first half
of its fixes instead (halving while that fails): a fix that fails on its own (its result
not well-formed, or still with the finding it was made for) is rolled back and reported
as its rule's internal error; the others stay. Passes repeat while fixes apply, at most
:data:`MAX_PASSES` times: a fix that reveals another defect (an unsafe one may) gets its
own pass. Fixes that undo each other are an internal error too; fixes still to make after
the last pass stay in the report, marked fixable (another ``--fix`` makes them). The
report is the fixed source's.
"""

from __future__ import annotations

import difflib
from collections import Counter
from collections.abc import Callable, Iterable, Sequence
from typing import TYPE_CHECKING, Final, NamedTuple

from xodrlint.document.positions import lines_with_breaks
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
        ``unfixable`` does (``ALL`` names every rule, an opt-in one too). An entry that
        names no rule is a :class:`~xodrlint.rules.selection.SelectorError`, as in
        ``select``."""
        from xodrlint.rules.selection import SelectorError, specificity

        for token in (*self.fixable, *self.unfixable):
            named = token.upper() == "ALL" or any(
                specificity(token, rule) is not None or rule.code.startswith(token.upper())
                for rule in registry.rules
            )
            if not named:
                where = "fixable" if token in self.fixable else "unfixable"
                raise SelectorError(f"{where}: '{token}' matches no rule code, name or UID")

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
    first: FileReport
    """The report of the source as it was, before any fix (where the fixed bytes cannot
    be written, it is the file's)."""


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
    from xodrlint.document.edits import EditableSource

    report, source, _ = lint(data)
    first = report
    fixed = 0
    refused: set[tuple[str, str, str]] = set()  # fixes rolled back: not tried again
    crashes: list[str] = []
    seen = {data}  # every state the passes left: fixes that undo each other come back
    for _ in range(MAX_PASSES):
        chosen = _chosen(report.findings, policy, refused)
        if not chosen or not isinstance(source, EditableSource):
            break
        outcome = _pass(report, source, chosen, lint)
        for finding, reason in outcome.rolled_back:
            refused.add(_identity(finding))
            crashes.append(f"fix for {finding.code} produced {reason} on {report.path}")
        if outcome.applied == 0:
            continue  # the fix this pass tried was rolled back: try the ones left
        if outcome.data in seen:
            codes = ", ".join(sorted({finding.code for finding in chosen}))
            crashes.append(
                f"fixes for {codes} undo each other on {report.path}: stopped after {fixed} fixes"
            )
            break
        seen.add(outcome.data)
        data, report, source = outcome.data, outcome.report, outcome.source
        fixed += outcome.applied
    internal = (*report.internal_errors, *crashes)
    return Fixed(report._replace(fixed=fixed, internal_errors=internal), data, first)


def diff_of(before: bytes, after: bytes, codec: str, path: str) -> str:
    """A unified diff of ``before`` and ``after``, decoded with ``codec``, in lines as XML
    and ``patch`` count them (a line ends at "\\r\\n", "\\n" or a lone "\\r"; Python's
    ``splitlines`` also breaks at U+2028 and others, which would misnumber the hunks)."""
    old = lines_with_breaks(before.decode(codec).removeprefix("\ufeff"))
    new = lines_with_breaks(after.decode(codec).removeprefix("\ufeff"))
    lines = difflib.unified_diff(old, new, fromfile=f"a/{path}", tofile=f"b/{path}")
    return "".join(line if line.endswith(("\n", "\r")) else line + "\n" for line in lines)


def _identity(finding: Finding) -> tuple[str, str, str]:
    """What tells a finding's fix from another's across passes (two of one rule on one
    element, XS006 on two attributes, differ in their message)."""
    return finding.code, finding.xpath, finding.message


def _chosen(
    findings: Sequence[Finding], policy: FixPolicy, refused: set[tuple[str, str, str]]
) -> list[Finding]:
    """The findings whose fixes this pass makes: allowed, placed, and touching no text
    a fix before them in the report touches. Every safe fix (each mends a value, a name or
    a comment where it stands), and the unsafe fixes of one rule: one rule's fixes are
    worked out from the network as it is, and another's may change what they were worked
    out from (a side track moved to the end of a road whose length the same pass
    changes)."""
    from xodrlint.document.edits import Edit, overlapping

    allowed = [
        finding
        for finding in findings
        if finding.fix is not None
        and finding.fix.edits
        and _identity(finding) not in refused
        and (policy.unsafe or finding.fix.applicability is Applicability.SAFE)
    ]
    unsafe = [
        f for f in allowed if f.fix is not None and f.fix.applicability is Applicability.UNSAFE
    ]
    code = unsafe[0].code if unsafe else None
    taken: list[Edit] = []
    chosen: list[Finding] = []
    for finding in allowed:
        assert finding.fix is not None
        if finding.fix.applicability is Applicability.UNSAFE and finding.code != code:
            continue
        edits = [Edit(edit.start, edit.end, edit.content) for edit in finding.fix.edits]
        if overlapping([*taken, *edits]):
            continue
        taken += edits
        chosen.append(finding)
    return chosen


class _Pass(NamedTuple):
    """What a pass made (``applied`` fixes: ``data`` and its lint) and rolled back."""

    data: bytes
    report: FileReport
    source: EditableSource | str | None
    applied: int
    rolled_back: list[tuple[Finding, str]]


def _pass(report: FileReport, source: EditableSource, chosen: list[Finding], lint: Lint) -> _Pass:
    """Make ``chosen``'s fixes together; where the result fails, make the first half of
    them (halving again while that fails) and leave the rest to the next pass, which
    lints afresh. A pass so makes at least one fix, or finds the one fix that fails on its
    own and rolls it back, in at most log2(n) + 1 lints (a conflict between two fixes that
    each pass alone, as a side track moved to a road's end while the road's length
    changes, is no failure: they are made in two passes)."""
    candidates = chosen
    while True:
        result = _try(source, report, candidates, lint)
        if not isinstance(result, str):
            return _Pass(*result, len(candidates), [])
        if len(candidates) == 1:
            return _Pass(b"", report, source, 0, [(candidates[0], result)])
        candidates = candidates[: len(candidates) // 2]


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
