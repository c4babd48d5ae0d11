"""XS001 xml-malformed: the file is not well-formed XML.

## What it does
Reports a file that an XML parser cannot read: empty, truncated, binary, in an encoding
other than the one it declares, with an undefined entity or nested absurdly deep. The
finding carries the parser's message and its line (line 1 where it has none).

## Why is this bad?
Nothing can read the map: no simulator, no converter and no other rule. When a file is
not well-formed, xodrlint reports this one finding and runs nothing else on it.

## Example
A file cut off in the middle of a road:
```xml
      </laneSection>
    </lanes> <!-- expect: XS001 -->
```

Use instead:
```xml
      </laneSection>
    </lanes>
    <railroad>
```

## Related rules
When XS001 reports, no other rule runs on the file.

## References
- W3C XML 1.0, section 2.1 "Well-Formed XML Documents"
- ASAM OpenDRIVE 1.7, section 2.5 "File structure"; rule UID `asam.net:xodr:1.0.0:xml.valid_xml_document`
"""

from __future__ import annotations

from collections.abc import Iterator

from xodrlint.rules import Hit, RailNetwork, Severity, rule
from xodrlint.rules.document._report import stage_hits


@rule(
    code="XS001",
    name="xml-malformed",
    uid="asam.net:xodr:1.0.0:xml.valid_xml_document",
    severity=Severity.ERROR,
)
def xml_malformed(network: RailNetwork) -> Iterator[Hit]:
    return stage_hits(network, "XS001")
