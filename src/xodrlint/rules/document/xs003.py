"""XS003 header-missing: `OpenDRIVE` does not start with a `header`.

## What it does
Reports an `OpenDRIVE` root whose first child element is not `header` (comments before it
are fine).

## Why is this bad?
The header declares the OpenDRIVE version the file follows; without it no reader knows
which schema or which semantics apply. xodrlint then cannot pick a schema: the schema
check is skipped, the railroad rules still run.

## Example
```xml
<OpenDRIVE> <!-- expect: XS003 -->
  <road name="main" length="100" id="1" junction="-1">
```

Use instead:
```xml
<OpenDRIVE>
  <!-- a comment may come first -->
  <header revMajor="1" revMinor="7" name="case"/>
  <road name="main" length="100" id="1" junction="-1">
```

## Related rules
XS004 checks the version attributes of a header that is there.

## References
- ASAM OpenDRIVE 1.7, section 2.5 "File structure"; rule UID `asam.net:xodr:1.0.0:xml.fileheader_is_present`
"""

from __future__ import annotations

from collections.abc import Iterator

from xodrlint.rules import Hit, RailNetwork, Severity, rule
from xodrlint.rules.document._report import stage_hits


@rule(
    code="XS003",
    name="header-missing",
    uid="asam.net:xodr:1.0.0:xml.fileheader_is_present",
    severity=Severity.ERROR,
)
def header_missing(network: RailNetwork) -> Iterator[Hit]:
    return stage_hits(network, "XS003")
