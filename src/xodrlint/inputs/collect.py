"""Input collection: the paths ``xodrlint check`` takes (files, folders, globs, URLs, ``-``)
become the inputs of a run, each a file to lint or why it cannot be one.

Folders are walked for ``*.xodr`` (sorted, symbolic links not followed) leaving out what
:mod:`xodrlint.inputs.walk` excludes; a glob is expanded when no such path exists; a URL
is listed through :mod:`xodrlint.inputs.remote`. Reports list the inputs in this order.
"""

from __future__ import annotations

import errno
import glob
import os
import stat
from collections.abc import Callable, Iterable, Iterator
from pathlib import Path
from typing import Final, NamedTuple

from xodrlint.config.sizes import DEFAULT_MAX_FILE_SIZE, too_large
from xodrlint.inputs.files import os_reason, special_kind
from xodrlint.inputs.remote import is_url
from xodrlint.inputs.walk import IgnoreFiles, WalkRules

STDIN: Final = "-"
XODR_SUFFIX: Final = ".xodr"
#: Why a glob may match nothing where the shell would find files.
IGNORED_HINT: Final = (
    " (outside what .gitignore and .ignore files exclude; --no-respect-gitignore lints that too)"
)


class Input(NamedTuple):
    """One thing to lint: a file, standard input, or a path that cannot be linted.

    ``error`` says why a path cannot be linted (exit 2); ``skipped`` why a file met in a
    folder or a glob is left out without failing the run (a FIFO, a device). An input by
    URL has ``url`` (what its worker reads) and ``size`` (from the listing), no ``path``.
    """

    display: str
    path: Path | None = None
    error: str | None = None
    is_stdin: bool = False
    skipped: str | None = None
    url: str | None = None
    size: int | None = None
    root: Path | None = None
    """The folder a walk or a glob found the file in (``None``: named as such); ``--fix``
    writes through no link that leads out of it."""

    @property
    def lintable(self) -> bool:
        """Whether an engine lints this input: a file, or an object by URL, that no
        error kept out (standard input is read by the command itself)."""
        return self.error is None and (self.path is not None or self.url is not None)


def collect_inputs(
    paths: Iterable[str],
    exclude: Callable[[Path], bool] | None = None,
    max_file_size: int = DEFAULT_MAX_FILE_SIZE,
    *,
    respect_gitignore: bool = True,
    exclude_url: Callable[[str], bool] | None = None,
) -> Iterator[Input]:
    """Files as given, folders walked for ``*.xodr`` (sorted, symlinks not followed), and
    glob patterns (``maps/**/*.xodr``) expanded when no such path exists. ``exclude``
    drops files, found or given, that it matches.

    A URL (``s3://bucket/maps/**/*.xodr``) is listed the same way through fsspec
    (:mod:`xodrlint.inputs.remote`): an object, every ``*.xodr`` below a "folder", or a glob's
    matches as full URLs; ``exclude_url`` drops those whose path part (``maps/a.xodr``)
    it matches. Ignore files do not apply to URLs.

    A walk leaves out hidden names and, with ``respect_gitignore``, what ``.gitignore``,
    ``.ignore`` and ``info/exclude`` exclude (:mod:`xodrlint.inputs.walk`); a file named as
    such is always taken. An ignore file or line that cannot be used comes back as a
    ``skipped`` note.

    Nothing is opened here, but every file is looked at: what could not be read safely
    (larger than ``max_file_size``, a FIFO or device that would block or never end, a
    name that is not UTF-8 and so cannot be reported) comes back with ``error`` or
    ``skipped`` set, before any linting starts.
    """
    # a file named several ways (f, ./f, its absolute path, a link to it) is linted once
    seen: set[tuple[int, int]] = set()
    seen_urls: set[str] = set()
    ignore_files = IgnoreFiles() if respect_gitignore else None
    links_out: list[str] = []  # file links a walk did not follow, said once at the end
    for raw in paths:
        if raw == STDIN:
            yield Input(STDIN, is_stdin=True)
            continue
        if is_url(raw):
            excluded = _url_excluder(exclude, exclude_url)
            for item in _expand_url(raw, max_file_size, excluded):
                if item.error is None and item.url is not None:
                    if item.url in seen_urls:
                        continue
                    seen_urls.add(item.url)
                yield item
            continue
        for item in _expand(raw, max_file_size, ignore_files, links_out):
            if item.path is not None and exclude is not None and exclude(item.path):
                continue
            identity = _identity(item)
            if identity is not None:
                if identity in seen:
                    continue
                seen.add(identity)
            yield item
    if links_out:
        yield _links_out_note(links_out)


def _links_out_note(links: list[str]) -> Input:
    """One note for the file links the walks of a run did not follow."""
    shown = ", ".join(links[:3]) + (f" and {len(links) - 3} more" if len(links) > 3 else "")
    what = "a file link" if len(links) == 1 else f"{len(links)} file links"
    return Input(
        shown,
        skipped=printable_path(
            f"skipped {what} leading out of the folder walked ({shown}): a walk follows no "
            "link out of its folder; name the file on the command line to lint it"
        ),
    )


def _identity(item: Input) -> tuple[int, int] | None:
    if item.path is None or item.error is not None:
        return None
    try:
        status = item.path.stat()
    except OSError:
        return None
    return status.st_dev, status.st_ino


def _expand(
    raw: str, max_file_size: int, ignore_files: IgnoreFiles | None, links_out: list[str]
) -> Iterator[Input]:
    path = Path(raw)
    try:
        status = path.stat()
    except OSError as error:
        if glob.has_magic(raw) and error.errno == errno.ENOENT:
            walked = _glob(raw, max_file_size, ignore_files, links_out)
            yield from _noted(walked, ignore_files)
        else:
            yield Input(printable_path(raw), error=f"{printable_path(raw)}: {os_reason(error)}")
        return
    if stat.S_ISDIR(status.st_mode):
        yield from _noted(_walk(path, max_file_size, ignore_files, links_out), ignore_files)
    else:
        yield _checked(raw, path, status, max_file_size, named=True)


def _noted(walked: Iterator[Input], ignore_files: IgnoreFiles | None) -> Iterator[Input]:
    """The inputs of a walk, after a note for each ignore file or line it could not use
    (each said once in a run)."""
    found = list(walked)
    if ignore_files is not None:
        for note in ignore_files.notes:
            yield Input(printable_path(note), skipped=printable_path(note))
        ignore_files.notes.clear()
    yield from found


def _glob(
    pattern: str, max_file_size: int, ignore_files: IgnoreFiles | None, links_out: list[str]
) -> Iterator[Input]:
    """The files a glob names, walked from its folder before the first wildcard with
    :func:`os.walk` (folder links not followed: a link loop cannot make it endless) and
    matched in linear time. A folder it names is walked for ``*.xodr``; names starting
    with a dot are left out unless the pattern names them so, as the shell does, and so
    is what ignore files exclude (:class:`~xodrlint.inputs.walk.WalkRules`)."""
    from xodrlint.inputs.globs import glob_matches

    normalised = pattern.replace("\\", "/")
    parts = normalised.split("/")
    fixed = next(i for i, part in enumerate(parts) if glob.has_magic(part))
    root = "/".join(parts[:fixed]) or ("/" if normalised.startswith("/") else ".")
    rules = WalkRules(root, ignore_files, hidden="/." in "/" + normalised)
    # without "**" the pattern reaches so many folders below its fixed part, no deeper
    depth = None if "**" in parts[fixed:] else len(parts) - fixed - 1
    found: list[Path] = []
    for current, folders, files in os.walk(root, followlinks=False):
        rules.enter(current, files)
        below = len(Path(current).relative_to(root).parts)
        kept = [f for f in folders if rules.keeps_folder(current, f)]
        if depth is not None and below == depth:  # deeper only into a folder it names
            kept = [
                f
                for f in kept
                if glob_matches(
                    normalised,
                    _shown_as_given(Path(current, f), root, parts[:fixed]),
                    whole=True,
                    anywhere=False,
                )
            ]
        folders[:] = sorted(kept)
        for name in files:
            shown = _shown_as_given(Path(current, name), root, parts[:fixed])
            if (
                glob_matches(normalised, shown, whole=True, anywhere=False)
                or (
                    name.lower().endswith(XODR_SUFFIX)
                    and glob_matches(normalised, shown, anywhere=False)
                )
            ) and rules.keeps_file(current, name):
                found.append(Path(shown))
    if not found:
        yield Input(
            pattern, error=f"{pattern}: no file matches" + (IGNORED_HINT if rules.excluded else "")
        )
    inside = _inside(root)
    for path in sorted(found):
        if inside(path, links_out):
            yield _found(path, max_file_size)._replace(root=Path(root))


def _url_excluder(
    exclude: Callable[[Path], bool] | None, exclude_url: Callable[[str], bool] | None
) -> Callable[[str], bool]:
    """Whether a URL is excluded: a ``file://`` URL as the local file it names (anchored
    globs included), any other by its path part (``maps/a.xodr`` of
    ``s3://bucket/maps/a.xodr``)."""
    from xodrlint.inputs.remote import local_path, url_path

    def excluded(url: str) -> bool:
        local = local_path(url)
        if local is not None and exclude is not None:
            return exclude(Path(local))
        return exclude_url is not None and exclude_url(url_path(url))

    return excluded


def _expand_url(raw: str, max_file_size: int, excluded: Callable[[str], bool]) -> Iterator[Input]:
    """The objects a URL names, listed once here; they are read where they are linted.
    Reports show each URL without its credentials (:func:`~xodrlint.inputs.remote.shown_url`)."""
    from xodrlint.inputs.globs import glob_matches
    from xodrlint.inputs.remote import RemoteError, list_below, list_url, shown_url

    shown = printable_path(shown_url(raw))
    scheme, rest = raw.split("://", 1)
    parts = rest.split("/")
    fixed = next((i for i, part in enumerate(parts) if glob.has_magic(part)), None)
    if fixed == 0:
        yield Input(shown, error=f"{shown}: the bucket or host of a URL cannot be a glob")
        return
    listed_url = raw if fixed is None else f"{scheme}://{'/'.join(parts[:fixed])}"
    try:
        listed = list_url(raw) if fixed is None else list_below(listed_url)
    except RemoteError as error:
        if fixed is None or not error.missing:
            yield Input(shown, error=f"{shown}: {error}")
            return
        listed = []  # nothing below a glob's folder: as for a local glob, no match
    if fixed is None:
        named = len(listed) == 1 and listed[0].url == raw  # one object, whatever its name
        found = listed if named else [o for o in listed if _is_xodr(o.url)]
    else:
        pattern = "/".join(parts[fixed:])
        found = [
            o
            for o in listed
            for below in [o.url[len(listed_url) :].lstrip("/")]
            if o.url.startswith(listed_url)
            and (
                glob_matches(pattern, below, whole=True, anywhere=False)
                or (_is_xodr(o.url) and glob_matches(pattern, below, anywhere=False))
            )
        ]
        if not found:
            yield Input(shown, error=f"{shown}: no file matches")
    for item in found:
        if excluded(item.url):
            continue
        display = shown_url(item.url)
        printable = printable_path(display)
        if printable != display:  # reports could not carry it (as for a local file)
            yield Input(printable, error=f"{printable}: the file name is not valid UTF-8")
        elif item.size is not None and item.size > max_file_size:
            yield Input(display, url=item.url, error=too_large(display, max_file_size))
        else:
            yield Input(display, url=item.url, size=item.size)


def _is_xodr(name: str) -> bool:
    return name.lower().endswith(XODR_SUFFIX)


def _shown_as_given(path: Path, root: str, fixed: list[str]) -> str:
    """``path`` spelt as the pattern spells its folder (``./`` dropped, as glob does)."""
    posix = path.as_posix()
    return posix[2:] if root == "." and not fixed and posix.startswith("./") else posix


def _walk(
    folder: Path, max_file_size: int, ignore_files: IgnoreFiles | None, links_out: list[str]
) -> Iterator[Input]:
    found: list[tuple[Path, Input | None]] = []

    def unlistable(error: OSError) -> None:
        # os.walk passes over a folder it cannot list; that must not pass in silence
        where = Path(error.filename or folder)
        shown = printable_path(where.as_posix())
        found.append((where, Input(shown, error=f"{shown}: cannot list: {os_reason(error)}")))

    top = str(folder)
    rules = WalkRules(top, ignore_files)
    for current, folders, files in os.walk(top, followlinks=False, onerror=unlistable):
        rules.enter(current, files)
        folders[:] = sorted(f for f in folders if rules.keeps_folder(current, f))
        found.extend(
            (Path(current, name), None)
            for name in files
            if name.lower().endswith(XODR_SUFFIX) and rules.keeps_file(current, name)
        )
    inside = _inside(top)
    for path, problem in sorted(found, key=lambda item: item[0]):
        if problem is not None:
            yield problem
        elif inside(path, links_out):
            yield _found(path, max_file_size)._replace(root=folder)


def _inside(top: str) -> Callable[[Path, list[str]], bool]:
    """Whether a file a walk of ``top`` met is in it: not a symbolic link to a file
    elsewhere (``/proc/self/environ``, a secret beside the checkout), which a repository
    could hold to have its content printed (``--show-source``) or sent on (a report).
    A link that leaves is added to ``links_out``."""
    real_top = os.path.realpath(top)

    def inside(path: Path, links_out: list[str]) -> bool:
        if not path.is_symlink():
            return True
        target = os.path.realpath(path)
        if os.path.commonpath([real_top, target]) == real_top:
            return True
        links_out.append(path.as_posix())
        return False

    return inside


def _found(path: Path, max_file_size: int) -> Input:
    """A file met in a folder or a glob (a symbolic link is followed to what it names)."""
    shown = path.as_posix()
    try:
        status = path.stat()
    except OSError as error:
        return Input(
            printable_path(shown), path=path, error=f"{printable_path(shown)}: {os_reason(error)}"
        )
    return _checked(shown, path, status, max_file_size, named=False)


def _checked(
    shown: str, path: Path, status: os.stat_result, max_file_size: int, *, named: bool
) -> Input:
    """``path`` as an input, or why it cannot be one; a special file named on the command
    line is an error, one met in a folder walk is skipped with a note."""
    printable = printable_path(shown)
    if printable != shown:
        return Input(printable, path=path, error=f"{printable}: the file name is not valid UTF-8")
    kind = special_kind(status.st_mode)
    if kind is not None:
        if named:
            return Input(shown, path=path, error=f"{shown}: is {kind}, not a regular file")
        return Input(shown, path=path, skipped=f"{shown}: skipped, {kind} is not a regular file")
    if status.st_size > max_file_size:
        return Input(shown, path=path, error=too_large(shown, max_file_size))
    return Input(shown, path=path)


def printable_path(name: str) -> str:
    """``name`` as reports can carry it: bytes that are not UTF-8 (kept by Python as lone
    surrogates) written as ``\\xff`` escapes."""
    try:
        name.encode("utf-8")
    except UnicodeEncodeError:
        return os.fsencode(name).decode("utf-8", "backslashreplace")
    return name
