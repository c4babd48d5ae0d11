"""HM: a careless pack rule that changes the tree it is given (issue 30, item 6)."""

from __future__ import annotations

from collections.abc import Iterator

from xodrlint.findings import Hit, Severity
from xodrlint.model import RailNetwork
from xodrlint.rules import rule

#: What happened, in order, for the test that checks when the rule ran.
EVENTS: list[str] = []


@rule(code="HM001", name="sets-attributes", uid="test:hostile:HM001", severity=Severity.WARNING)
def sets_attributes(network: RailNetwork) -> Iterator[Hit]:
    """Sets an attribute on every road and lane: libxml2, validating the same tree in
    another thread without the GIL, crashed the process when the rule ran beside it."""
    EVENTS.append("HM001")
    for road in network.roads:
        road.element.set("touched", "by a pack rule" * 4)
        for lane in road.element.iter("lane"):
            lane.set("touched", "yes")
    yield from ()
