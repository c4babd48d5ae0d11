"""Input collection, the walk's half: which folders and files a folder walk (or the walk
of a glob) leaves out, as git and ruff would.

Names starting with a dot are left out (unless a glob names them so). With ignore files
respected (the default; ``--no-respect-gitignore`` turns it off), so is what they exclude:
``.ignore`` and ``.gitignore`` in every folder from the repository's top (the nearest
folder above holding ``.git``; without one, the folder walked) down, and the repository's
``info/exclude``. As in ripgrep and ruff, ``.ignore`` files override ``.gitignore`` files,
which override ``info/exclude``; among files of one kind the deeper one wins, and within
a file the last matching line. An excluded folder is never entered, so nothing below it
can come back (as in git), and a big ignored ``build/`` costs nothing.

The patterns are pathspec's (:class:`pathspec.GitIgnoreSpec`): negation, anchoring,
folder-only patterns and ``**`` as git reads them. pathspec compiles each pattern to a
backtracking regular expression, so a line with more than :data:`MAX_WILDCARDS` ``*``
runs is left out with a note (``*a*a*a*a*a*a*a*a*c`` takes minutes on a 60-character
name: a repository's ``.gitignore`` must not be able to stall a CI job).
"""

from __future__ import annotations

import os
import re
import stat
from dataclasses import dataclass, field
from pathlib import Path
from typing import TYPE_CHECKING, Final

from xodrlint.inputs.files import os_reason

if TYPE_CHECKING:
    from pathspec import GitIgnoreSpec

#: Read in each folder, the first overriding the second (ripgrep's and ruff's order).
IGNORE_FILES: Final = (".ignore", ".gitignore")
#: More ``*`` runs than this in one line make pathspec's regular expression slow enough
#: to stall a run: its work grows with the name's length to the power of their number
#: (four: 0.2 s at worst on a 255-character name, measured; nine: minutes on 60).
MAX_WILDCARDS: Final = 4
_ESCAPED: Final = re.compile(r"\\.")
_STARS: Final = re.compile(r"\*+")
_NAMED_GROUP: Final = re.compile(r"\(\?P<[^>]*>")
#: How pathspec starts the expression of a pattern that matches at any depth.
_ANY_DEPTH: Final = "^(?:.+/)?"


@dataclass(frozen=True)
class IgnoreFile:
    """One ``.gitignore``, ``.ignore`` or ``info/exclude``: its patterns apply to paths
    below ``base`` (relative to the repository's top: ``""`` or ``"maps/"``)."""

    source: str
    base: str
    spec: GitIgnoreSpec
    folder_only: tuple[bool, ...]
    """Per pattern: whether it ends with ``/`` (it names folders only)."""
    anything: re.Pattern[str] | None
    """All patterns in one expression: a path it does not match matches none of them, so
    most paths are answered by one search instead of one per pattern."""

    def excludes_file(self, relative: str) -> bool | None:
        """True excluded, False re-included by a ``!`` line, None no line matches."""
        if self.anything is not None and self.anything.search(relative) is None:
            return None
        return self.spec.check_file(relative, separators=()).include

    def excludes_folder(self, relative: str) -> bool | None:
        """As :meth:`excludes_file`, for the folder itself (what git asks before it enters
        one): pathspec's ``check_file("d/")`` reads as "d and all below it", where a
        ``*`` line would outrank a later ``!*/``, so each pattern is asked about the
        folder's own path and the last one that matches decides."""
        if self.anything is not None and not (
            self.anything.search(relative) or self.anything.search(relative + "/")
        ):
            return None
        verdict = None
        for pattern, folder_only in zip(self.spec.patterns, self.folder_only, strict=True):
            if pattern.include is None:
                continue
            if pattern.match_file(relative + "/" if folder_only else relative) is not None:
                verdict = pattern.include
        return verdict


def read_ignore_file(path: Path, base: str, notes: list[str]) -> IgnoreFile | None:
    """The patterns of ``path``; ``None`` if it is missing, not a regular file, or has no
    pattern. What cannot be used (an unreadable file, a line git would not take either, a
    line too slow to match) is a note in ``notes``."""
    try:
        if not stat.S_ISREG(path.stat().st_mode):  # a FIFO would block the read
            return None
        data = path.read_bytes()
    except FileNotFoundError:
        return None
    except OSError as error:
        notes.append(f"{path}: cannot read: {os_reason(error)}; its patterns are not applied")
        return None
    from pathspec import GitIgnoreSpec
    from pathspec.patterns.gitignore.spec import GitIgnoreSpecPattern

    # git reads bytes: a name that is not UTF-8 is matched by the same bytes
    text = data.decode("utf-8", "surrogateescape").removeprefix("\ufeff")
    patterns, folder_only = [], []
    for number, raw in enumerate(text.split("\n"), start=1):
        line = raw.removesuffix("\r")
        if not line or line.startswith("#"):
            continue
        if len(_STARS.findall(_ESCAPED.sub("", line))) > MAX_WILDCARDS:
            notes.append(
                f"{path}:{number}: pattern left out: more than {MAX_WILDCARDS} '*' "
                "wildcards could take minutes to match"
            )
            continue
        try:
            pattern = GitIgnoreSpecPattern(line)
        except ValueError:  # GitIgnorePatternError: git skips such a line too
            notes.append(f"{path}:{number}: pattern left out: not a valid gitignore pattern")
            continue
        patterns.append(pattern)
        folder_only.append(line.rstrip(" ").endswith("/"))
    if not any(pattern.include is not None for pattern in patterns):
        return None
    spec = GitIgnoreSpec(patterns)
    return IgnoreFile(str(path), base, spec, tuple(folder_only), _anything(spec))


def _anything(spec: GitIgnoreSpec) -> re.Pattern[str] | None:
    """One expression that matches where any pattern of ``spec`` matches; ``None`` where
    it cannot be built. The names of groups are dropped (they may not repeat), and the
    patterns pathspec lets match at any depth (a name without ``/``, most lines of a
    ``.gitignore``) share that prefix: it is tried once per ``/`` of a path, not once per
    pattern (10,000 paths against 95 lines: 14 ms instead of 60)."""
    expressions = [p.regex for p in spec.patterns if p.include is not None]
    texts = []
    for expression in expressions:
        if not isinstance(expression, re.Pattern) or expression.flags != re.UNICODE:
            return None
        texts.append(_NAMED_GROUP.sub("(?:", str(expression.pattern)))
    anywhere = [text.removeprefix(_ANY_DEPTH) for text in texts if text.startswith(_ANY_DEPTH)]
    rest = [f"(?:{text})" for text in texts if not text.startswith(_ANY_DEPTH)]
    if anywhere:
        rest.append(f"{_ANY_DEPTH}(?:{'|'.join(anywhere)})")
    try:
        return re.compile("|".join(rest))
    except re.error:
        return None


@dataclass
class IgnoreFiles:
    """The ignore files read during one collection of inputs, each read once however
    many walks pass it (and its notes said once)."""

    notes: list[str] = field(default_factory=list)
    _read: dict[tuple[str, str], IgnoreFile | None] = field(default_factory=dict)

    def get(self, path: Path, base: str) -> IgnoreFile | None:
        """``path`` read for paths below ``base`` (the repository's top decides ``base``:
        one file can be met from two tops, in a repository inside another)."""
        key = os.path.abspath(path), base  # noqa: PTH100 (one spelling, no link resolved)
        if key not in self._read:
            self._read[key] = read_ignore_file(path, base, self.notes)
        return self._read[key]


#: The ignore files that apply in a folder, by kind (``.ignore``, ``.gitignore``,
#: ``info/exclude``), each kind deepest first: the order in which they are asked.
_Chain = tuple[tuple[IgnoreFile, ...], tuple[IgnoreFile, ...], tuple[IgnoreFile, ...]]
_NO_CHAIN: Final[_Chain] = ((), (), ())


class WalkRules:
    """What one walk from ``top`` leaves out. Call :meth:`enter` for each folder
    :func:`os.walk` yields (top first) before asking about what it holds, by the names
    ``os.walk`` gives: ``os.path.join(current, name)`` is the next ``current``.

    ``top`` itself was named on the command line, and a path named there is always
    linted: its name is never hidden, and where an ignore file above it excludes it
    (``xodrlint check build`` with ``build/`` in ``.gitignore``) it is walked as ripgrep
    and ruff walk it, with the ignore files inside it only."""

    def __init__(self, top: str, files: IgnoreFiles | None, *, hidden: bool = False) -> None:
        self.hidden = hidden
        self.files = files
        self.excluded = 0
        """Folders and files left out by ignore files (hidden ones not counted)."""
        self._where: dict[str, tuple[str, _Chain]] = {}
        if files is not None:
            self._where[top] = self._above(Path(top), files)

    def _above(self, top: Path, files: IgnoreFiles) -> tuple[str, _Chain]:
        """The path of ``top`` below the repository's top, and the ignore files of the
        folders above it; none where one of them excludes ``top`` or a folder above it
        (what it excludes there, every path below, was named on the command line)."""
        real = top.resolve()
        found = next((f for f in (real, *real.parents) if (f / ".git").exists()), None)
        if found is None:
            return "", _NO_CHAIN
        # notes name the files above as the command line named top: relative if it was
        root = found if top.is_absolute() else Path(os.path.relpath(found))
        chain = _repository(root, files)
        relative = ""
        for name in real.relative_to(found).parts:
            chain = _entered(chain, root / relative, relative, files)
            relative += name + "/"
            verdict = _verdict(chain, relative[:-1], folder=True)
            if verdict is not None and verdict[0]:
                chain = _NO_CHAIN
        return relative, chain

    def enter(self, current: str, names: list[str]) -> None:
        """Read the ignore files among ``names``, the files of ``current``."""
        if self.files is None or not any(name in names for name in IGNORE_FILES):
            return
        relative, chain = self._where[current]
        self._where[current] = relative, _entered(chain, Path(current), relative, self.files)

    def keeps_folder(self, current: str, name: str) -> bool:
        if not self.hidden and name.startswith("."):
            return False
        if self.files is None:
            return True
        relative, chain = self._where[current]
        path = relative + name
        if _excluded(chain, path, folder=True):
            self.excluded += 1
            return False
        # the spelling os.walk gives the folder when it enters it
        entered = os.path.join(current, name)  # noqa: PTH118
        if os.path.lexists(os.path.join(entered, ".git")):  # noqa: PTH118
            # a repository of its own: git asks its ignore files, not the outer ones
            self._where[entered] = "", _repository(Path(entered), self.files)
        else:
            self._where[entered] = path + "/", chain
        return True

    def keeps_file(self, current: str, name: str) -> bool:
        if not self.hidden and name.startswith("."):
            return False
        if self.files is None:
            return True
        relative, chain = self._where[current]
        if _excluded(chain, relative + name, folder=False):
            self.excluded += 1
            return False
        return True


def _repository(root: Path, files: IgnoreFiles) -> _Chain:
    """The ignore files that apply at the top of the repository in ``root``: its
    ``info/exclude`` (its ``.gitignore`` and ``.ignore`` are read on entering it)."""
    exclude = _info_exclude(root / ".git")
    read = files.get(exclude, "") if exclude is not None else None
    return ((), (), (read,) if read else ())


def _entered(chain: _Chain, folder: Path, relative: str, files: IgnoreFiles) -> _Chain:
    """``chain`` with the ignore files of ``folder`` (at ``relative``) in front."""
    ignore, gitignore = (files.get(folder / name, relative) for name in IGNORE_FILES)
    return (
        (ignore, *chain[0]) if ignore else chain[0],
        (gitignore, *chain[1]) if gitignore else chain[1],
        chain[2],
    )


def _verdict(chain: _Chain, path: str, *, folder: bool) -> tuple[bool, str] | None:
    """Whether the first ignore file of ``chain`` with a line for ``path`` (relative to
    the repository's top) excludes it, and that file's name; ``None`` if none has."""
    for kind in chain:
        for ignore_file in kind:
            relative = path[len(ignore_file.base) :]
            verdict = (
                ignore_file.excludes_folder(relative)
                if folder
                else ignore_file.excludes_file(relative)
            )
            if verdict is not None:
                return verdict, ignore_file.source
    return None


def _excluded(chain: _Chain, path: str, *, folder: bool) -> bool:
    if chain is _NO_CHAIN:
        return False
    verdict = _verdict(chain, path, folder=folder)
    return verdict is not None and verdict[0]


def _info_exclude(dot_git: Path) -> Path | None:
    """The repository's ``info/exclude``: in ``.git``, or for a worktree or submodule
    (``.git`` a file saying ``gitdir: ...``) in the folder it names, or its common one."""
    if dot_git.is_dir():
        return dot_git / "info" / "exclude"
    try:
        text = dot_git.read_text("utf-8", "surrogateescape")
    except OSError:
        return None
    if not text.startswith("gitdir:"):
        return None
    gitdir = (dot_git.parent / text.removeprefix("gitdir:").strip()).resolve()
    try:
        common = (gitdir / (gitdir / "commondir").read_text("utf-8").strip()).resolve()
    except OSError:
        common = gitdir
    return common / "info" / "exclude"
