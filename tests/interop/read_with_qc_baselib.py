"""Read an xodrlint XQAR file with ASAM's own reader, qc-baselib, and compare it with the
findings of the same run (JSON): every finding must come back as an issue with its rule
UID, level, line and XPath.

Runs in a virtual environment of its own (qc-baselib pins lxml < 6, so it never shares
xodrlint's): ``python read_with_qc_baselib.py result.xqar findings.json``.
"""

from __future__ import annotations

import json
import sys
from pathlib import Path

from qc_baselib import Result  # type: ignore[import-not-found, unused-ignore]

LEVELS = {"error": 1, "warning": 2, "info": 3}


def asam_uid(uid: str) -> str:
    # the documented mapping: the catalogue's bare entity is written as a domain
    entity, _, rest = uid.partition(":")
    return f"xodrlint.github.io:{rest}" if entity == "xodrlint" else uid


def main(result_path: str, findings_path: str) -> int:
    result = Result()
    result.load_from_file(result_path)
    findings = json.loads(Path(findings_path).read_text("utf-8"))
    seen = []
    for bundle in result.get_checker_bundle_results():
        assert bundle.name == "xodrlintBundle", bundle.name
        for checker in bundle.checkers:
            for issue in checker.issues:
                where = issue.locations[0]
                seen.append(
                    (
                        issue.rule_uid,
                        int(issue.level),
                        where.file_location[0].row,
                        where.xml_location[0].xpath,
                    )
                )
    expected = [
        (asam_uid(f["uid"]), LEVELS[f["severity"]], f["line"], f["xpath"]) for f in findings
    ]
    missing = sorted(set(expected) - set(seen))
    extra = sorted(set(seen) - set(expected))
    if missing or extra or len(seen) != len(expected):
        print(f"missing: {missing}\nunexpected: {extra}")
        return 1
    print(f"read {len(seen)} issues in {len(result.get_checker_bundle_results())} bundles")
    return 0


if __name__ == "__main__":
    sys.exit(main(*sys.argv[1:]))
