"""XS002 root-not-opendrive: the root element is not `OpenDRIVE`.

## What it does
Reports a well-formed XML file whose root element is not `OpenDRIVE`, or is `OpenDRIVE`
in a namespace. Files in ASAM's old namespace
`http://code.asam.net/simulation/standard/opendrive_schema`, or in `www.vires.com` (the
namespace of the OpenDRIVE 1.1 and 1.2 schemas), are accepted and read as if they had
none.

## Why is this bad?
The file is not an OpenDRIVE map (often an OpenSCENARIO or railML file with the wrong
extension). No railroad rule can run on it, so xodrlint reports this one finding.

## Example
```xml
<OpenSCENARIO> <!-- expect: XS002 -->
```

Use instead:
```xml
<OpenDRIVE>
```

## Related rules
When XS002 reports, no other rule runs on the file.

## References
- ASAM OpenDRIVE 1.7, section 2.5 "File structure"; rule UID `asam.net:xodr:1.0.0:xml.root_tag_is_opendrive`
"""

from __future__ import annotations

from collections.abc import Iterator

from xodrlint.rules import Hit, RailNetwork, Severity, rule
from xodrlint.rules.document._report import stage_hits


@rule(
    code="XS002",
    name="root-not-opendrive",
    uid="asam.net:xodr:1.0.0:xml.root_tag_is_opendrive",
    severity=Severity.ERROR,
)
def root_not_opendrive(network: RailNetwork) -> Iterator[Hit]:
    return stage_hits(network, "XS002")
