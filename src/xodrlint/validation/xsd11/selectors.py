"""The translated assertions and type alternatives of a set, run by libxml2's XPath.

:mod:`~xodrlint.validation.xsd11.translation` turned them into XPath 1.0 when the set's
form was derived; the form's manifest keeps the text, and this module compiles it once per
process. Per asserted type, one XPath finds the elements where any of its assertions
fails or is uncertain (few, in a valid map); each of those is then asked assertion by
assertion. Neither xmlschema nor elementpath is imported here.
"""

from __future__ import annotations

from collections.abc import Iterator
from dataclasses import dataclass, field
from typing import Any, Final

from lxml import etree

#: The test that never holds: the translation writes it for an assertion that cannot fail
#: (or be uncertain), and no XPath is compiled or run for it.
FALSE: Final = "false()"


@dataclass(frozen=True, slots=True)
class _Assertion:
    test: str
    fails: etree.XPath
    uncertain: etree.XPath | None


@dataclass(frozen=True, slots=True)
class _TypeCheck:
    type_name: str
    candidates: etree.XPath
    assertions: tuple[_Assertion, ...]


@dataclass(slots=True)
class Checked:
    """What the translated assertions found in one document."""

    failed: list[tuple[etree._Element, str]] = field(default_factory=list)
    """Each element with the test of an assertion it fails, in document order."""
    uncertain: list[etree._Element] = field(default_factory=list)
    """Elements whose translated assertions only xmlschema can judge exactly."""
    marks: list[tuple[etree._Element, str]] | None = None
    """Each element a type alternative gives another type than its declared one, with
    that type's name (``None``: the alternatives do not translate)."""


class Selectors:
    """A set's translation, compiled. ``translated`` holds (type, test) of every
    assertion it runs; ``untranslated`` the others, with why they do not translate."""

    def __init__(self, translation: dict[str, Any]) -> None:
        self.translated: set[tuple[str, str]] = set()
        self.untranslated: list[tuple[str, str, str]] = []
        checks: list[_TypeCheck] = []
        for entry in translation.get("types", []):
            type_name, paths = str(entry["type"]), [str(p) for p in entry["paths"]]
            assertions: list[_Assertion] = []
            for item in entry["assertions"]:
                test = str(item["test"])
                if "fails" not in item or not paths or not type_name:
                    self.untranslated.append((type_name, test, str(item.get("why", ""))))
                    continue
                uncertain = str(item["uncertain"])
                assertions.append(
                    _Assertion(
                        test,
                        etree.XPath(f"boolean({item['fails']})"),
                        None if uncertain == FALSE else etree.XPath(f"boolean({uncertain})"),
                    )
                )
                self.translated.add((type_name, test))
            any_of = ""
            if assertions:
                any_of = " or ".join(
                    f"({item[key]})"
                    for item in entry["assertions"]
                    if "fails" in item
                    for key in ("fails", "uncertain")
                    if item[key] != FALSE
                )
            if any_of:  # (an assertion that cannot fail, such as one about a parent, has none)
                union = " | ".join(f"{path}[{any_of}]" for path in paths)
                checks.append(_TypeCheck(type_name, etree.XPath(union), tuple(assertions)))
        self._checks = tuple(checks)
        marks = translation.get("marks")
        self.why_not_marks = str(translation.get("why_not_marks", ""))
        self._marks = (
            None
            if marks is None
            else tuple((etree.XPath(str(m["path"])), str(m["type"])) for m in marks)
        )

    @property
    def marks_known(self) -> bool:
        return self._marks is not None

    def marks(self, root: etree._Element) -> list[tuple[etree._Element, str]] | None:
        """Each element a type alternative gives another type than its declared one,
        with that type's name (``None``: the alternatives do not translate)."""
        if self._marks is None:
            return None
        return [
            (element, type_name)
            for selector, type_name in self._marks
            for element in _elements(selector(root))
        ]

    def check(self, root: etree._Element, *, marks: bool = True) -> Checked:
        """Every translated assertion, and (``marks``) type alternative, run on the
        document."""
        checked = Checked(marks=self.marks(root) if marks else None)
        for type_check in self._checks:
            for element in _elements(type_check.candidates(root)):
                if any(
                    a.uncertain is not None and a.uncertain(element) for a in type_check.assertions
                ):
                    checked.uncertain.append(element)
                    continue
                checked.failed.extend(
                    (element, a.test) for a in type_check.assertions if a.fails(element)
                )
        return checked


def _elements(found: Any) -> Iterator[etree._Element]:
    if isinstance(found, list):
        yield from (item for item in found if isinstance(item, etree._Element))
