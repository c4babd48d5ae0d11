"""XPaths a person can read, for findings: ``road[@id='3']/railroad/switch[@id='31']``,
id predicates where elements have ids and positions only where siblings share a tag."""

from __future__ import annotations

from collections.abc import Container
from typing import Final

from lxml import etree


class ReadableXPaths:
    """XPaths a person can read: id predicates where elements have ids, positions otherwise.

    A position is only added where siblings share the tag (and id), so that
    ``road[@id='3']/railroad/switch[@id='31']/partner`` stays stable when other roads
    are added.
    """

    def __init__(self, foreign: Container[etree._Element] = ()) -> None:
        # nodes an include put into this tree belong to another file: they take no
        # position among this file's siblings
        self._foreign = foreign
        self._steps: dict[etree._Element, str] = {}
        self._children: dict[etree._Element, dict[str, etree._Element]] = {}
        # whole paths too: findings share their ancestors (a road's path is asked for by
        # every switch, lane and link below it)
        self._paths: dict[etree._Element, str] = {}

    def element_at(self, root: etree._Element, path: str) -> etree._Element | None:
        steps = _split_steps(path)
        if not steps or steps[0] != self._step(root):
            return None
        node = root
        for step in steps[1:]:
            if node not in self._children:
                self._name_children(node)
            found = self._children[node].get(step)
            if found is None:
                return None
            node = found
        return node

    def path_of(self, element: etree._Element) -> str:
        paths = self._paths
        found = paths.get(element)
        if found is not None:
            return found
        parent = element.getparent()
        above = "" if parent is None else self.path_of(parent)  # no deeper than the parser
        found = paths[element] = f"{above}/{self._step(element)}"
        return found

    def _step(self, element: etree._Element) -> str:
        step = self._steps.get(element)
        if step is None:
            parent = element.getparent()
            if parent is None:
                step = _local_name(element)
                self._steps[element] = step
            else:
                self._name_children(parent)
                step = self._steps[element]
        return step

    def _name_children(self, parent: etree._Element) -> None:
        """Name all children of ``parent`` at once, so each sibling group is scanned once."""
        foreign = self._foreign
        children = [
            (child, _local_name(child))
            for child in parent.iterchildren(etree.Element)
            if child not in foreign
        ]
        per_tag: dict[str, int] = {}
        per_id: dict[tuple[str, str], int] = {}
        for child, tag in children:
            per_tag[tag] = per_tag.get(tag, 0) + 1
            ident = _own_id(child, tag)
            if ident is not None:
                per_id[tag, ident] = per_id.get((tag, ident), 0) + 1
        seen_tag: dict[str, int] = {}
        seen_id: dict[tuple[str, str], int] = {}
        named = self._children[parent] = {}
        for child, tag in children:
            seen_tag[tag] = seen_tag.get(tag, 0) + 1
            ident = _own_id(child, tag)
            if ident is not None:
                key = (tag, ident)
                seen_id[key] = seen_id.get(key, 0) + 1
                step = f"{tag}[@id={_xpath_literal(ident)}]"
                if per_id[key] > 1:
                    step += f"[{seen_id[key]}]"
            elif per_tag[tag] > 1:
                step = f"{tag}[{seen_tag[tag]}]"
            else:
                step = tag
            self._steps[child] = step
            named[step] = child


# Elements whose @id names *another* element (a road, a switch, a signal): it does not
# identify them, so their XPath step uses a position, like any element without an id.
_REFERENCE_ELEMENTS: Final = frozenset(
    {
        "partner",
        "mainTrack",
        "sideTrack",
        "neighbor",
        "objectReference",
        "signalReference",
        "dependency",
        "reference",
        "junctionReference",
        "control",
    }
)


def _own_id(element: etree._Element, tag: str) -> str | None:
    return None if tag in _REFERENCE_ELEMENTS else element.get("id")


def _local_name(element: etree._Element) -> str:
    return etree.QName(element).localname


def _split_steps(path: str) -> list[str]:
    """The steps of an absolute XPath; a ``/`` inside a predicate's quotes is no break."""
    if not path.startswith("/"):
        return []
    steps: list[str] = []
    current: list[str] = []
    depth, quote = 0, ""
    for char in path[1:]:
        if quote:
            quote = "" if char == quote else quote
        elif char in "'\"" and depth:
            quote = char
        elif char == "[":
            depth += 1
        elif char == "]":
            depth -= 1
        elif char == "/" and not depth:
            steps.append("".join(current))
            current = []
            continue
        current.append(char)
    steps.append("".join(current))
    return steps


def _xpath_literal(value: str) -> str:
    if "'" not in value:
        return f"'{value}'"
    if '"' not in value:
        return f'"{value}"'
    parts = value.split("'")
    return "concat(" + ', "\'", '.join(f"'{part}'" for part in parts) + ")"
