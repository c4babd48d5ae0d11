"""XS005 version-unsupported: the header declares an OpenDRIVE version that does not exist.

## What it does
Reports a `header` whose `revMajor` is not 1 or whose `revMinor` lies outside 1 to 9,
the versions ASAM has published. The file is then checked as the nearest published
version (1.1 below, 1.9 above), and the message says which. Files declaring 1.1 to 1.3
are real versions and are not reported; railroad content in them is an XS006 finding,
since railroad elements only exist from 1.4 on.

## Why is this bad?
This rule's basis is an inference: the standard lists its versions but does not say what
a reader must do with any other. A reader cannot know which rules the author meant, and
tools disagree: some refuse the file, some guess.

## Example
```xml
  <header revMajor="1" revMinor="12" name="case"/> <!-- expect: XS005 -->
```

Use instead:
```xml
  <header revMajor="1" revMinor="9" name="case"/>
```

## Related rules
XS004 reports a version that is missing or not a number; XS005 then stays silent.

## References
- ASAM OpenDRIVE 1.7, section 2.5 "File structure", table "header"; UID `xodrlint:xodr:1.0.0:xml.version_supported`
"""

from __future__ import annotations

from collections.abc import Iterator

from xodrlint.rules import Hit, RailNetwork, Severity, rule
from xodrlint.rules.document._report import stage_hits


@rule(
    code="XS005",
    name="version-unsupported",
    uid="xodrlint:xodr:1.0.0:xml.version_supported",
    severity=Severity.WARNING,
)
def version_unsupported(network: RailNetwork) -> Iterator[Hit]:
    return stage_hits(network, "XS005")
