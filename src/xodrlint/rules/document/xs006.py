"""XS006 schema-violation: the file breaks the XSD of the OpenDRIVE version it declares.

## What it does
Validates the file against the official ASAM schema of its declared version (1.1 to 1.7
with libxml2, the XSD 1.1 schemas of 1.8 and 1.9 with xmlschema) and reports each error
as one finding at the line of the element it is about: the element, the attribute, the
bad value and what the schema allows.

Without an official schema (see `xodrlint schemas`), xodrlint's built-in railroad schema
checks the `railroad` and `station` subtrees only, and the report says so once.

## Why is this bad?
The schema is the normative form of the standard's tables: a value it refuses is one
that readers of the declared version are entitled to reject or misread.

## Example
```xml
      <switch name="W1" id="101" position="sideways"> <!-- expect: XS006 -->
```

Use instead:
```xml
      <switch name="W1" id="101" position="dynamic">
```

## Related rules
An XSD key, keyref or missing-child error about a railroad element is reported once, by
the specific rule (SW004, SW007, SW008, PT001, ST001, ST002, ST003, ST007, ST009),
not as XS006. A keyed attribute that is missing gives one XS006 (the missing attribute),
not a second one for the key.

## References
- ASAM OpenDRIVE 1.7, section 2.5 "File structure" and the schema files; rule UID `asam.net:xodr:1.0.0:xml.valid_schema`
"""

from __future__ import annotations

from collections.abc import Iterator

from xodrlint.findings import Hit, Severity
from xodrlint.model import RailNetwork
from xodrlint.rules import rule
from xodrlint.rules.document._report import stage_hits


@rule(
    code="XS006",
    name="schema-violation",
    uid="asam.net:xodr:1.0.0:xml.valid_schema",
    severity=Severity.ERROR,
    defers_to=("SW004", "SW007", "SW008", "PT001", "ST001", "ST002", "ST003", "ST007", "ST009"),
)
def schema_violation(network: RailNetwork) -> Iterator[Hit]:
    return stage_hits(network, "XS006")
