"""Stage 6, report: formatters turn a :class:`~xodrlint.findings.RunResult` into output.

Each formatter is a class with a ``render(result, stream)`` method, looked up by name
here or under the ``xodrlint.formatters`` entry points (the way a plugin adds one). One
that leaves something out of its report says so in a ``warnings`` attribute
(:func:`warnings_of`); one whose report holds the run's notes says so with
``carries_notes = True`` (:func:`carries_notes`), else the command prints them on stderr.
Formatters see findings and rule metadata only, never rules or the engine.
"""

from __future__ import annotations

import importlib
import inspect
from typing import TYPE_CHECKING, Any, Final, Protocol, TextIO, cast

from xodrlint.findings import FileReport, RunResult

if TYPE_CHECKING:
    from xodrlint.config.plugins import Plugin

ENTRY_POINT_GROUP: Final = "xodrlint.formatters"

# Imported on use, so a text run never pays for the others.
BUILTIN: Final = {
    "text": "xodrlint.formatters.text:TextFormatter",
    "json": "xodrlint.formatters.json:JsonFormatter",
    "jsonl": "xodrlint.formatters.jsonl:JsonlFormatter",
    "concise": "xodrlint.formatters.concise:ConciseFormatter",
    "github": "xodrlint.formatters.github:GithubFormatter",
    "gitlab": "xodrlint.formatters.gitlab:GitlabFormatter",
    "junit": "xodrlint.formatters.junit:JunitFormatter",
    "sarif": "xodrlint.formatters.sarif:SarifFormatter",
    "xqar": "xodrlint.formatters.xqar:XqarFormatter",
}


class Formatter(Protocol):
    def render(self, result: RunResult, stream: TextIO) -> None: ...


class StreamingFormatter(Formatter, Protocol):
    """A formatter that can write its report file by file, as files are done, so a run
    keeps no report once it is written (``jsonl``): ``write_file`` for each file, in the
    order files complete."""

    def write_file(self, report: FileReport, stream: TextIO) -> None: ...


def streaming(formatter: Formatter) -> StreamingFormatter | None:
    """``formatter`` if it writes file by file (:class:`StreamingFormatter`), else ``None``."""
    if callable(getattr(formatter, "write_file", None)):
        return cast("StreamingFormatter", formatter)
    return None


class FormatterOptions(Protocol):
    show_source: bool
    quiet: bool


def _entry_points() -> list[Plugin]:
    # the scan costs a start-up (and is cached); a built-in format never needs it
    from xodrlint.config.plugins import installed

    return installed(ENTRY_POINT_GROUP)


def available() -> list[str]:
    names = set(BUILTIN)
    names.update(point.name for point in _entry_points())
    return sorted(names)


def get_formatter(
    name: str,
    *,
    show_source: bool = False,
    quiet: bool = False,
    color: str | None = None,
    sarif_max_results: int | None = None,
    unsafe_fixes: bool = False,
) -> Formatter:
    """An instance of the formatter ``name``; ``KeyError`` if there is none.

    A factory is given the options it declares, as keywords: ``show_source`` and
    ``quiet`` (a plugin's too, when it takes them; one that takes ``**options`` gets
    both). An option of one built-in format goes to that format's factory alone, so
    plugin factories keep the keywords they were written for: ``color`` (one of
    ``output.COLOR_CHOICES``, ``None`` for "auto") to the text format,
    ``sarif_max_results`` (at most this many SARIF results, 0 for no limit, ``None`` for
    the format's default) to the SARIF one, ``unsafe_fixes`` (whether the run counts
    unsafe fixes as fixable, for its ``[*]`` marks) to the text one.
    """
    extra: dict[str, object] = {}
    if name == "text" and color is not None:
        extra["color"] = color
    if name == "text" and unsafe_fixes:
        extra["unsafe_fixes"] = True
    if name == "sarif" and sarif_max_results is not None:
        extra["max_results"] = sarif_max_results
    target = BUILTIN.get(name)
    if target is None:
        matches = [p for p in _entry_points() if p.name == name]
        if not matches:
            raise KeyError(name)
        factory: Any = matches[0].load()
    else:
        module_name, _, attribute = target.partition(":")
        factory = getattr(importlib.import_module(module_name), attribute)
    options = _declared(factory, {"show_source": show_source, "quiet": quiet})
    formatter: Formatter = factory(**options, **extra)
    return formatter


def _declared(factory: Any, options: dict[str, object]) -> dict[str, object]:
    """The ``options`` ``factory`` takes: formats take only what they use."""
    if _takes_nothing(factory):
        # inspect would parse object.__init__'s text signature, importing ``ast``: 4 ms
        # of a pre-commit run on a small map, for the answer this already knows
        return {}
    try:
        parameters = inspect.signature(factory).parameters
    except (TypeError, ValueError):  # no signature to read (a builtin): as before
        return options
    if any(p.kind is inspect.Parameter.VAR_KEYWORD for p in parameters.values()):
        return options
    return {name: value for name, value in options.items() if name in parameters}


def _takes_nothing(factory: Any) -> bool:
    """Whether ``factory`` is a class made with no arguments: neither it nor a base
    defines ``__init__`` or ``__new__`` (as the JSON format's class), nor its metaclass
    ``__call__``."""
    if not isinstance(factory, type) or type(factory).__call__ is not type.__call__:
        return False
    return not any(
        "__init__" in vars(base) or "__new__" in vars(base) for base in factory.__mro__[:-1]
    )


def carries_notes(formatter: Formatter) -> bool:
    """Whether ``formatter``'s report holds the run's notes (:attr:`RunResult.notes`,
    what the run did not check), as a ``carries_notes = True`` attribute says; the
    command says them on stderr after a report that has no place for them."""
    return getattr(formatter, "carries_notes", False) is True


def shows_fixes(formatter: Formatter) -> bool:
    """Whether ``formatter`` writes the edits of each finding's fix (``shows_fixes =
    True``): the run then places them in the source."""
    return getattr(formatter, "shows_fixes", False) is True


def says_withheld(formatter: Formatter) -> bool:
    """Whether ``formatter``'s report says how many findings the baseline withheld (a
    ``says_withheld = True`` attribute); the command says it on stderr otherwise."""
    return getattr(formatter, "says_withheld", False) is True


def warnings_of(formatter: Formatter) -> tuple[str, ...]:
    """What ``formatter`` said its last render left out of the report, one line each.

    A formatter may set a ``warnings`` tuple of strings (the SARIF one does, when it
    keeps only the most important results); the command prints each on stderr, whether
    the report went to standard output or to a file. A formatter without one says nothing.
    """
    found = getattr(formatter, "warnings", ())
    if not isinstance(found, tuple | list):
        return ()
    return tuple(line for line in found if isinstance(line, str))
