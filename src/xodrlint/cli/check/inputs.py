"""``xodrlint check``'s inputs: what the paths on its command line name, after
``exclude`` and the ignore files, the part of them ``--shard K/N`` takes, and
``--show-files``, which lists them and stops."""

from __future__ import annotations

import os
import re
import sys
from collections.abc import Callable, Sequence
from pathlib import Path
from typing import Final, NamedTuple

from xodrlint.api import collect_inputs
from xodrlint.config.resolver import Resolver
from xodrlint.config.settings import Settings
from xodrlint.config.sizes import too_large
from xodrlint.formatters.output import error_line
from xodrlint.inputs.collect import STDIN, Input, printable_path
from xodrlint.inputs.globs import glob_matches
from xodrlint.inputs.remote import is_url, shown_url
from xodrlint.messages import one_line, plural


class InputsError(ValueError):
    """Inputs a check cannot take (``-`` twice, a ``--shard`` that names no part): exit 2
    with this one line, before linting."""


def check_stdin(paths: Sequence[str], stdin_filename: str | None) -> None:
    if stdin_filename is not None and printable_path(stdin_filename) != stdin_filename:
        shown = printable_path(stdin_filename)
        raise InputsError(f"--stdin-filename {shown}: the name is not valid UTF-8")
    if list(paths).count(STDIN) > 1:
        raise InputsError(f"{STDIN} (standard input) is given more than once")


def collect(
    paths: Sequence[str],
    settings: Settings,
    resolver: Resolver | None = None,
    stdin_filename: str | None = None,
) -> list[Input]:
    """What to lint; files a folder walk met but cannot lint (a FIFO, a device) are left
    out with a note on stderr, and a warning says when nothing at all is left (exit 0,
    as ruff: an empty folder is no error). A local file is left out by the ``exclude``
    of its own configuration, found by ``resolver`` (without one: ``settings``')."""
    inputs = []
    url_settings = settings
    if resolver is not None and any(is_url(path) for path in paths):
        url_settings = resolver.settings[resolver.working_profile()]  # as they are linted
    found = collect_inputs(
        # by name too: of a file named twice (a/x.xodr, and b/x.xodr linking to it), the
        # name kept is the same whatever the order of the paths
        sorted(paths, key=lambda path: _name_key(path, stdin_filename)),
        _excluder(settings) if resolver is None else _file_excluder(resolver),
        settings.max_file_size,
        respect_gitignore=settings.respect_gitignore,
        exclude_url=_url_excluder(url_settings),
    )
    for item in found:
        if item.skipped is not None:
            error_line(f"note: {item.skipped}")
        else:
            inputs.append(item)
    if not inputs:
        named = " ".join(printable_path(shown_url(path)) for path in paths)
        error_line(f"warning: no .xodr files found under {named}")
    # by name (standard input's from --stdin-filename), as ruff orders its files: the
    # order of the paths never changes a report
    inputs.sort(key=lambda item: _by_name(item, stdin_filename))
    return inputs


def _by_name(item: Input, stdin_filename: str | None) -> tuple[str, ...]:
    return _name_key(STDIN if item.is_stdin else item.display, stdin_filename)


def _name_key(name: str, stdin_filename: str | None) -> tuple[str, ...]:
    if name == STDIN:
        name = stdin_filename or STDIN
    return tuple(name.replace(os.sep, "/").split("/"))


def _excluder(settings: Settings) -> Callable[[Path], bool] | None:
    return settings.excludes if settings.exclude else None


def _file_excluder(resolver: Resolver) -> Callable[[Path], bool]:
    return lambda path: resolver.settings_for(path).excludes(path)


def _url_excluder(settings: Settings) -> Callable[[str], bool] | None:
    """``exclude`` for inputs by URL: its globs match the URL's path part (``maps/a.xodr``
    of ``s3://bucket/maps/a.xodr``), which lies below no local folder."""
    if not settings.exclude:
        return None
    return lambda part: any(glob_matches(pattern, part) for pattern in settings.exclude)


def show_files(inputs: list[Input], stdin_filename: str | None) -> int:
    """``--show-files``: the files a check would lint, in its order and named as its
    reports name them; what it could not read is a line on stderr and exit 2."""
    for item in inputs:
        if item.error is not None:
            error_line(one_line(item.error))
    names = [
        (stdin_filename or STDIN) if item.is_stdin else item.display
        for item in inputs
        if item.error is None
    ]
    from xodrlint.cli.check.reports import write_reports

    listed = write_reports(
        [("--show-files", None, lambda stream: stream.writelines(f"{n}\n" for n in names))]
    )
    return 2 if not listed or any(item.error for item in inputs) else 0


#: Standard input is read in pieces this large, so that a limit of gigabytes is never
#: allocated up front.
STDIN_CHUNK: Final = 1024 * 1024


def read_stdin(limit: int) -> tuple[bytes, str | None]:
    """Standard input, at most ``limit`` bytes: (contents, why it cannot be linted)."""
    if sys.stdin is None:  # started with standard input closed
        return b"", f"{STDIN}: cannot read standard input: it is closed"
    pieces: list[bytes] = []
    size = 0
    try:
        while size <= limit:
            piece = sys.stdin.buffer.read(min(STDIN_CHUNK, limit + 1 - size))
            if not piece:
                break
            pieces.append(piece)
            size += len(piece)
    except (OSError, ValueError) as error:  # a closed or unreadable stream
        return b"", f"{STDIN}: cannot read standard input: {error}"
    if size > limit:
        return b"", too_large(STDIN, limit)
    return b"".join(pieces), None


class Shard(NamedTuple):
    """``--shard K/N``: the K-th (1-based) of N parts of the inputs."""

    part: int
    parts: int

    def __str__(self) -> str:
        return f"{self.part}/{self.parts}"


_SHARD: Final = re.compile(r"([0-9]+)/([0-9]+)")


def parse_shard(given: str) -> Shard:
    """``K/N`` as a :class:`Shard`, or :class:`InputsError` saying what is wrong."""
    match = _SHARD.fullmatch(given.strip())
    if match is None:
        raise InputsError(
            f"--shard {one_line(given)}: expected K/N, the K-th of N parts (e.g. 2/4)"
        )
    index, count = int(match[1]), int(match[2])
    if count < 1:
        raise InputsError(f"--shard {one_line(given)}: N must be at least 1")
    if not 1 <= index <= count:
        raise InputsError(f"--shard {one_line(given)}: K must be from 1 to {count}")
    return Shard(index, count)


def shard_of(name: str, count: int) -> int:
    """The part (1 to ``count``) the input reported as ``name`` belongs to.

    A hash of the name's bytes (SHA-256, never Python's ``hash()``, which is salted per
    process), with ``/`` between folders on every system: the same command from the same
    folder puts every file in the same part, in every run and on every machine.
    """
    import hashlib  # only sharded runs pay for it

    posix = name.replace(os.sep, "/") if os.sep != "/" else name
    digest = hashlib.sha256(posix.encode("utf-8", "surrogateescape")).digest()
    return int.from_bytes(digest[:8], "big") % count + 1


def in_shard(inputs: list[Input], shard: Shard, stdin_filename: str | None) -> list[Input]:
    """The inputs of ``shard``, in their order, each placed by the name reports give it
    (standard input by ``--stdin-filename``, or ``-``); a warning when it holds none."""
    kept = [
        item
        for item in inputs
        if shard_of((stdin_filename or STDIN) if item.is_stdin else item.display, shard.parts)
        == shard.part
    ]
    if inputs and not kept:
        error_line(f"warning: shard {shard} holds none of the {plural(len(inputs), 'input')}")
    return kept
