"""What every document rule does: hand on the stage's hits for its code."""

from __future__ import annotations

from collections.abc import Iterator

from xodrlint.rules import Hit, RailNetwork


def stage_hits(network: RailNetwork, code: str) -> Iterator[Hit]:
    yield from network.problems.get(code, ())
