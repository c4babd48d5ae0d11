"""Positions of elements in a tree, found in time that does not grow with their siblings.

lxml's ``parent.index(child)``, ``parent[i]`` and an XPath step such as ``road[1234]``
walk the siblings every time they are asked: n findings about the children of one
parent (a city map's roads) cost n times n. :class:`TreePositions` lists each parent's
children once, the first time one of them is asked about, so every later question costs
the depth of the element. Used wherever findings cross a boundary as positions: the
libxml2 error paths of the schema stage and the child indices a forked validator sends.
"""

from __future__ import annotations

import re
from typing import Final

from lxml import etree

#: A step of a libxml2 error path that names an element by its name (no namespace
#: prefix) and, where it has siblings of that name, its 1-based occurrence among them.
_NAMED_STEP: Final = re.compile(r"([A-Za-z_][\w.\-]*)(?:\[([1-9][0-9]*)\])?")


class TreePositions:
    """Children by position and by name, indexed once per parent on first use."""

    def __init__(self) -> None:
        self._children: dict[etree._Element, list[etree._Element]] = {}
        self._index: dict[etree._Element, int] = {}
        self._named: dict[etree._Element, dict[str, list[etree._Element]]] = {}

    def children(self, parent: etree._Element) -> list[etree._Element]:
        """``list(parent)``: every child as lxml counts them (comments and processing
        instructions too), made once per parent."""
        found = self._children.get(parent)
        if found is None:
            found = self._children[parent] = list(parent)
        return found

    def index_of(self, element: etree._Element) -> int | None:
        """``element.getparent().index(element)``; ``None`` for a root."""
        index = self._index.get(element)
        if index is None:
            parent = element.getparent()
            if parent is None:
                return None
            self._index.update((child, i) for i, child in enumerate(self.children(parent)))
            index = self._index[element]
        return index

    def child(self, parent: etree._Element, index: int) -> etree._Element | None:
        """``parent[index]``, or ``None`` where there is no such child."""
        children = self.children(parent)
        return children[index] if 0 <= index < len(children) else None

    def path_from(self, root: etree._Element, steps: list[int]) -> etree._Element | None:
        """The element that ``steps`` (child indices, from ``root`` down) lead to."""
        element: etree._Element | None = root
        for index in steps:
            if element is None:
                return None
            element = self.child(element, index)
        return element

    def steps_to(self, element: etree._Element, root: etree._Element) -> list[int] | None:
        """The child indices that lead from ``root`` down to ``element``; ``None`` when
        ``element`` is not below ``root``."""
        steps: list[int] = []
        current = element
        while current is not root:
            index = self.index_of(current)
            if index is None:  # reached a root that is not ``root``: another tree
                return None
            steps.append(index)
            current = current.getparent()  # type: ignore[assignment]  # index_of: not None
        steps.reverse()
        return steps

    def libxml2_path(self, root: etree._Element, path: str) -> etree._Element | bool | None:
        """The element below ``root`` that a libxml2 error path names (its first step is
        ``root`` itself, as libxml2 writes it for the validated tree): ``False`` where a
        step is not a plain name (a namespace prefix, ``*``, ``text()``), which only an
        XPath engine reads; ``None`` where the path leads nowhere."""
        steps = path.strip("/").split("/")
        if not steps[0]:
            return None
        element = root
        for step in steps[1:]:
            match = _NAMED_STEP.fullmatch(step)
            if match is None:
                return False
            same_name = self._named_children(element).get(match[1])
            occurrence = int(match[2]) if match[2] else 1
            if same_name is None or occurrence > len(same_name):
                return None
            element = same_name[occurrence - 1]
        return element

    def _named_children(self, parent: etree._Element) -> dict[str, list[etree._Element]]:
        named = self._named.get(parent)
        if named is None:
            named = self._named[parent] = {}
            for child in self.children(parent):
                tag = child.tag
                if isinstance(tag, str) and not tag.startswith("{"):
                    named.setdefault(tag, []).append(child)
        return named
