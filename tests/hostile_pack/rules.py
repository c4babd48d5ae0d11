"""HX: rules that misbehave, one way each; HX009 behaves and must keep its finding."""

from __future__ import annotations

import sys
from collections.abc import Callable, Iterable, Iterator
from typing import Any, cast

from lxml import etree

from xodrlint.findings import Hit, Severity
from xodrlint.model import RailNetwork
from xodrlint.rules import PlainCheck, Rule, rule


def _declare(code: str, name: str) -> Callable[[Callable[[RailNetwork], Iterable[Any]]], Rule]:
    """``rule`` for checks that may yield anything (that is what is tested)."""
    declare = rule(code=code, name=name, uid=f"test:hostile:{code}", severity=Severity.ERROR)
    return lambda check: declare(cast(PlainCheck, check))


class Escape(BaseException):
    """Neither an Exception nor SystemExit."""


@_declare("HX001", "yields-none")
def yields_none(network: RailNetwork) -> Iterator[object]:
    yield None


@_declare("HX002", "yields-a-string")
def yields_a_string(network: RailNetwork) -> Iterator[object]:
    yield "a finding, as text"


@_declare("HX003", "message-not-a-string")
def message_not_a_string(network: RailNetwork) -> Iterator[Hit]:
    yield Hit(_root(network), 42)  # type: ignore[arg-type]


@_declare("HX004", "foreign-element")
def foreign_element(network: RailNetwork) -> Iterator[Hit]:
    yield Hit(etree.Element("elsewhere"), "about an element of no document")


@_declare("HX005", "exits")
def exits(network: RailNetwork) -> Iterator[Hit]:
    sys.exit(0)
    yield  # pragma: no cover


@_declare("HX006", "base-exception")
def base_exception(network: RailNetwork) -> Iterator[Hit]:
    raise Escape("out of here")
    yield  # pragma: no cover


@_declare("HX007", "prints")
def prints(network: RailNetwork) -> Iterator[Hit]:
    print("chatter from a rule")
    yield from ()


@_declare("HX008", "loops")
def loops(network: RailNetwork) -> Iterator[Hit]:
    while True:
        try:
            pass
        except Exception:  # a rule that swallows everything still gets stopped
            continue
    yield  # pragma: no cover


@_declare("HX009", "behaves")
def behaves(network: RailNetwork) -> Iterator[Hit]:
    yield Hit(_root(network), "a proper finding")


def _root(network: RailNetwork) -> etree._Element:
    road = network.roads[0].element
    return road.getroottree().getroot()
