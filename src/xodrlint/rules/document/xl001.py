"""XL001 unused-suppression: a suppression comment withholds no finding.

## What it does
Reports an `xodrlint: ignore[...]` or `ignore-file[...]` comment, once per comment, when
one of its entries withheld no finding in this run: the defect was fixed, the comment
stands before another element than the one it was written for, or the entry names no
rule at all (a typo). The message lists the idle entries; an empty list reports
`nothing`.

Off by default: turn it on with `--extend-select XL001` (or `extend-select = ["XL001"]`
in the configuration), or with its alias `--warn-unused-suppressions`
(`warn-unused-suppressions = true`). `ALL` does not select it; `XL`, its code, its name
and its UID do, and `--ignore XL001` turns it off again.

Only entries this run can judge count: an entry whose rules were not selected may well
be needed by a run that selects them, so it is left alone.

## Why is this bad?
A stale suppression hides the next real defect of its kind on that element, with a
reason that is no longer true.

## Example
```xml
  <!-- xodrlint: ignore[ST001] the platform is surveyed in May --> <!-- expect: XL001 -->
  <station name="Depot" id="S2" type="small">
    <platform name="Depot platform" id="P2">
      <segment roadId="1" sStart="160" sEnd="200" side="left"/>
    </platform>
  </station>
```

Use instead:
```xml
  <station name="Depot" id="S2" type="small">
    <platform name="Depot platform" id="P2">
      <segment roadId="1" sStart="160" sEnd="200" side="left"/>
    </platform>
  </station>
```

## Fix
Safe: `xodrlint check --fix` takes the idle entries out of the comment, or removes the
whole comment when no entry is left (and its line, when it stood alone there; the blanks
beside it, when it shared the line with other markup).

## Related rules
Every rule's findings can be withheld by a suppression comment; XL001 judges the entries
naming the rules that ran. An entry that names XL001 itself (`XL001`, `XL`,
`unused-suppression` or its UID) is never reported, and it keeps the XL001 finding of its
own comment, and of the comments inside the element it stands before, from being
reported: `ignore[ST001, XL001]` keeps a stale ST001 entry on purpose.
`ignore-file[XL001]`, or `XL001` in `per-file-ignores`, does so for a whole file. `ALL`
in a suppression does not cover XL001, as it does not select it.

## References
- xodrlint's inline suppressions, `docs/suppressions.md`; rule UID
  `xodrlint:xodr:1.0.0:xodrlint.unused_suppression`
"""

from __future__ import annotations

from collections.abc import Iterator

from xodrlint.rules import Hit, RailNetwork, Severity, rule
from xodrlint.rules.document._report import stage_hits


@rule(
    code="XL001",
    name="unused-suppression",
    uid="xodrlint:xodr:1.0.0:xodrlint.unused_suppression",
    severity=Severity.WARNING,
    opt_in=True,
)
def unused_suppression(network: RailNetwork) -> Iterator[Hit]:
    # The engine reads the suppression comments after every other rule has run and
    # hands their idle entries on here, so selection, severity, suppressions and
    # per-file-ignores treat XL001 like any rule.
    return stage_hits(network, "XL001")
