"""XS006 schema-violation: the file breaks the XSD of the OpenDRIVE version it declares.

## What it does
Validates the file against the official ASAM schema of its declared version (1.1 to 1.7
with libxml2; the XSD 1.1 schemas of 1.8 and 1.9 as libxml2 on their XSD 1.0 form plus
xmlschema for the asserts and type alternatives, equal to full XSD 1.1 validation) and
reports each error as one finding at the line of the element it is about: the element, the attribute, the
bad value and what the schema allows.

Without an official schema (see `xodrlint schemas`), xodrlint's built-in railroad schema
checks the `railroad` and `station` subtrees only, and the report says so once; from
OpenDRIVE 1.5 on it also keys the ids of roads and of junctions, as the official schemas
do (1.4's keys none), so a repeated road id is found with either. A repeated key is
reported on the later element, naming the line of the first.

xodrlint expands no entity (nor loads any). An entity reference in an element's content
(`&name;`, declared in the file's DOCTYPE) is a finding of its own on that element: what
it stands for is not validated; everything around it is.

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

## Fix
Safe, for one kind of error: an enumerated attribute of a railroad element
(`switch/@position`, `mainTrack/@dir`, `sideTrack/@dir`, `station/@type`,
`segment/@side`) or a lane's `@type` whose value equals exactly one allowed value when
compared without case and surrounding blanks (`position="Dynamic"`, `side=" left"`):
`xodrlint check --fix` writes that value. Every other schema error has no fix.

## Related rules
An XSD key, keyref or missing-child error about a railroad element is reported once, by
the specific rule, not as XS006: a keyref on `mainTrack`/`sideTrack` by SW004, on
`partner` by PT001, on `segment` by ST003; a duplicate key on `switch` by SW007 or
SW008, on `station` by ST007, on `platform` by ST009; a station without a platform by
ST001 and a platform without a segment by ST002 (also when the schema words it as an
unexpected child of the station or platform). Only that error is handed over: any other
schema error on the same element stays an XS006 finding. A keyed attribute that is
missing gives one XS006 (the missing attribute), not a second one for the key.

## References
- ASAM OpenDRIVE 1.7, section 2.5 "File structure" and the schema files; rule UID `asam.net:xodr:1.0.0:xml.valid_schema`
"""

from __future__ import annotations

from collections.abc import Iterator
from typing import Final

from lxml import etree

from xodrlint.rules import CHILD_KINDS, Hit, RailNetwork, Severity, rule

#: Which railroad rule reports a schema identity error better, by kind and element.
TAKEN_OVER_BY: Final = {
    ("keyref", "mainTrack"): ("SW004",),
    ("keyref", "sideTrack"): ("SW004",),
    ("keyref", "partner"): ("PT001",),
    ("keyref", "segment"): ("ST003",),
    ("duplicate", "switch"): ("SW007", "SW008"),
    ("duplicate", "station"): ("ST007",),
    ("duplicate", "platform"): ("ST009",),
}
#: A container that lacks its first required child, and the rule that reports it.
REQUIRED_CHILD: Final = {"station": ("platform", "ST001"), "platform": ("segment", "ST002")}


@rule(
    code="XS006",
    name="schema-violation",
    uid="asam.net:xodr:1.0.0:xml.valid_schema",
    severity=Severity.ERROR,
    defers_to=("SW004", "SW007", "SW008", "PT001", "ST001", "ST002", "ST003", "ST007", "ST009"),
)
def schema_violation(network: RailNetwork) -> Iterator[Hit]:
    for hit in network.problems.get("XS006", ()):
        yield _handed_over(hit)


def _handed_over(hit: Hit) -> Hit:
    """The hit, told which rule (if any) reports its defect better: only that defect."""
    element = hit.element
    if element is None:
        return hit._replace(defers_to=())
    tag = etree.QName(element).localname
    codes = TAKEN_OVER_BY.get((hit.kind, tag))
    if codes is not None:
        return hit._replace(defers_to=codes)
    if hit.kind in CHILD_KINDS:
        # libxml2 reports a station holding only userData on the userData; the defect
        # is the station's missing platform, so the finding moves to the station
        owner = element if tag in REQUIRED_CHILD else element.getparent()
        owner_tag = etree.QName(owner).localname if owner is not None else ""
        if owner is not None and owner_tag in REQUIRED_CHILD:
            child, code = REQUIRED_CHILD[owner_tag]
            if next(owner.iterchildren(child), None) is None:
                return hit._replace(element=owner, defers_to=(code,))
    return hit._replace(defers_to=())
