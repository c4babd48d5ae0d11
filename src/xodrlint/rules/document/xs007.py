"""XS007 include-unreadable: an `include` names a file xodrlint cannot or may not read.

## What it does
Follows every `include` (`<include file="crossover.xodr"/>`): the included file's
content joins the document where the `include` stands, so a switch may name a road
another file holds, and findings inside an included file carry that file's name and
line. Reports an `include` whose file cannot be brought in:

- it does not exist, cannot be read, is no regular file, or is larger than
  `max-file-size`;
- it is not well-formed XML;
- it lies outside the folder of the file being checked (after symbolic links are
  resolved), or is a URL: xodrlint reads includes from that folder and below only, and
  never from the network;
- it includes itself, directly or through others, or lies more than 8 includes deep;
- the file being checked was not read from a folder (standard input without
  `--stdin-filename`, an object by URL), so no include of it is read.

An included file whose root element has the tag of the `include`'s parent (an
`OpenDRIVE` file included in `OpenDRIVE`) gives its children and the comments before
its root (but for a `header`: the including file's governs); any other gives its root
element. Names resolve from the folder of the file that names them, as given (a linked
map reads its includes beside the link). A file included twice joins once, so the work
is bounded by the files in the folder. The schema check judges the checked file as
written, before the included content joins it; the content of included files is judged
by the rules, not by the schema (an included fragment has no header of its own). A key
reference that an included element resolves (a `sideTrack` naming an included road) is
then not an XS006. Suppression comments keep to their own file.

## Why is this bad?
This rule's basis is an inference: OpenDRIVE allows includes "at any position" and
leaves their processing to the application. An include that cannot be followed leaves
a hole in the network: the switch, partner and station rules then report references to
elements that exist, and a simulator that follows includes sees another network than
the one checked.

## Example
```xml
  <include file="parts/missing.xml"/> <!-- expect: XS007 -->
```

Use instead:
```xml
  <include file="parts/branch.xml"/>
```

## Related rules
XS006 reports an `include` without a `file` attribute; SW004, PT001 and ST001 report
references that no file holds.

## References
- ASAM OpenDRIVE 1.7, section 2.5 "File structure" and the `t_include` type ("Location
  of the file that is to be included"); UID `xodrlint:xodr:1.0.0:xml.include_readable`
"""

from __future__ import annotations

from collections.abc import Iterator

from xodrlint.rules import Hit, RailNetwork, Severity, rule
from xodrlint.rules.document._report import stage_hits


@rule(
    code="XS007",
    name="include-unreadable",
    uid="xodrlint:xodr:1.0.0:xml.include_readable",
    severity=Severity.ERROR,
)
def include_unreadable(network: RailNetwork) -> Iterator[Hit]:
    return stage_hits(network, "XS007")
