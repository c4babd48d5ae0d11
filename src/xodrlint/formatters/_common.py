"""Helpers the CI formats share: rule lookup, report paths and fingerprints."""

from __future__ import annotations

import re
from collections.abc import Iterable
from typing import Final

from xodrlint.findings import Finding, RuleMeta, RunResult, fingerprints, relative_path

#: The rule whose finding means the file could not be parsed at all.
MALFORMED: Final = "XS001"
_BREAKS: Final = re.compile(r"\s*[\r\n]+\s*")


def rules_by_code(result: RunResult) -> dict[str, RuleMeta]:
    return {meta.code: meta for meta in result.rules}


def report_path(path: str, result: RunResult) -> str:
    """The path CI systems want: relative to the run's root (the checkout) when below it."""
    return relative_path(path, result.root)


def run_fingerprints(result: RunResult, extra: Iterable[Finding] = ()) -> list[str]:
    """Fingerprints of all findings of the run in order, then of ``extra``.

    ``extra`` (suppressed findings) come last, so the fingerprints of reported findings
    are the same whether or not suppressed ones are shown.
    """
    return fingerprints([*result.findings, *extra], result.root)


def not_applied_reason(meta: RuleMeta | None, declared: str | None) -> str:
    """Why a rule did not judge a file (the formats that say so per file: JUnit, XQAR):
    ``not applied to OpenDRIVE 1.4: it applies from 1.7 on (--all-versions applies it)``."""
    since = meta.since_label if meta is not None else None
    when = f"from {since} on" if since else "to later versions only"
    return (
        f"not applied to OpenDRIVE {declared or 'of this version'}: it applies {when} "
        "(--all-versions applies it)"
    )


def single_line(text: str) -> str:
    """``text`` on one line: line breaks become spaces."""
    return _BREAKS.sub(" ", text)
