"""What several rule packs share: tolerances, number formatting, duplicate detection."""

from __future__ import annotations

import math
from collections.abc import Callable, Iterable, Iterator, Sequence
from typing import Final, TypeVar

from lxml import etree

from xodrlint.rules import S_TOLERANCE, RuleOption, non_finite

__all__ = [
    "S_TOLERANCE",
    "S_TOLERANCE_OPTION",
    "below",
    "beyond",
    "degrees",
    "later_duplicates",
    "metres",
    "point",
    "quoted",
    "within",
]

_T = TypeVar("_T")

#: How far apart two s-coordinates or lengths may be and still count as the same: every
#: rule that compares a position along a road with a road's ends or with another
#: position reads it. 1e-6 m by default; data written to millimetres wants 0.0005 (a
#: side track at s="34.898" on a road 34.898262 m long is at its end).
S_TOLERANCE_OPTION: Final = RuleOption(
    name="s-tolerance",
    default=S_TOLERANCE,
    description=(
        "Largest difference between two s-coordinates or lengths that counts as none "
        "(0.0005 for data rounded to millimetres)"
    ),
)

_NONE: Final = "(none)"


def quoted(value: object) -> str:
    """``'value'`` for messages, or a word saying it is not there."""
    return _NONE if value is None else f"'{value}'"


def metres(value: float) -> str:
    """A length or s-coordinate for messages: up to six decimals, no trailing zeros."""
    text = f"{value:.6f}".rstrip("0").rstrip(".")
    return "0" if text in ("-0", "") else text


def point(x: float, y: float) -> str:
    """A plan-view position for messages, to the millimetre."""
    return f"({_millimetres(x)}, {_millimetres(y)})"


def _millimetres(value: float) -> str:
    text = f"{value:.3f}".rstrip("0").rstrip(".")
    return "0" if text in ("-0", "") else text


def degrees(radians: float) -> str:
    """A direction or angle for messages, in degrees from 0 to 360 (exclusive), to a
    hundredth: -0.1 rad reads 354.27, a full turn 0."""
    text = f"{math.degrees(radians % math.tau):.2f}".rstrip("0").rstrip(".")
    return "0" if text in ("-0", "", "360") else text


def beyond(value: float, limit: float, places: int) -> str:
    """``value`` for a message saying it exceeds ``limit``: to ``places`` decimals, or as
    many more as it takes not to read as the limit itself (0.1000011 against 0.1)."""
    for digits in range(places, 12):
        text = f"{value:.{digits}f}".rstrip("0").rstrip(".")
        if float(text) > limit:
            return text
    return repr(value)


def below(value: float, limit: float, places: int) -> str:
    """``value`` for a message saying it falls short of ``limit``: to ``places`` decimals,
    or as many more as it takes not to read as the limit itself (24.9999 against 25)."""
    for digits in range(places, 12):
        text = f"{value:.{digits}f}".rstrip("0").rstrip(".")
        if float(text) < limit:
            return text
    return repr(value)


def within(value: float, low: float, high: float, tolerance: float = S_TOLERANCE) -> bool:
    """``low <= value <= high`` with ``tolerance`` (``s-tolerance``) on both ends."""
    return low - tolerance <= value <= high + tolerance


def later_duplicates(
    items: Iterable[_T], key_of: Callable[[_T], str | None]
) -> Iterator[tuple[_T, _T]]:
    """Each item whose key an earlier item already has, with that first item."""
    first: dict[str, _T] = {}
    for item in items:
        key = key_of(item)
        if key is None:
            continue
        if key in first:
            yield item, first[key]
        else:
            first[key] = item


def first_non_finite(elements: Iterable[etree._Element], attributes: Sequence[str]) -> str | None:
    """``name=value`` of the first of ``attributes`` of ``elements`` that is an xs:double
    but no finite number (``a=INF``), as written; ``None`` when there is none."""
    for element in elements:
        for name in attributes:
            written = non_finite(element, name)
            if written is not None:
                return f"{name}={written}"
    return None
