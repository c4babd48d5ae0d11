"""XS004 version-undefined: the header does not state the OpenDRIVE version.

## What it does
Reports a `header` whose `revMajor` or `revMinor` is missing or is not a non-negative
integer. One finding per bad attribute.

## Why is this bad?
The version decides which schema and which rules of the standard apply. xodrlint cannot
pick a schema for the file: the schema check is skipped, the railroad rules still run.

## Example
```xml
  <header revMajor="1" name="case"/> <!-- expect: XS004 -->
```

Use instead:
```xml
  <header revMajor="1" revMinor="7" name="case"/>
```

## Related rules
XS003 reports a missing header; XS005 a version that was never published.

## References
- ASAM OpenDRIVE 1.7, section 2.5 "File structure", table "header"; rule UID `asam.net:xodr:1.0.0:xml.version_is_defined`
"""

from __future__ import annotations

from collections.abc import Iterator

from xodrlint.rules import Hit, RailNetwork, Severity, rule
from xodrlint.rules.document._report import stage_hits


@rule(
    code="XS004",
    name="version-undefined",
    uid="asam.net:xodr:1.0.0:xml.version_is_defined",
    severity=Severity.ERROR,
)
def version_undefined(network: RailNetwork) -> Iterator[Hit]:
    return stage_hits(network, "XS004")
