"""Glob matching for ``exclude`` and ``per-file-ignores`` patterns and for globs on the
command line: ``*`` and ``?`` within a folder name, ``**`` across folders, a pattern
without ``/`` at any depth.

Hand-written on purpose: the libraries compile globs to regular expressions, and a glob
such as ``*a*a*a*a*a*a*c`` made Python's backtracking engine (and pathspec's, which
compiles to one) take minutes on a 60-character name; a repository's configuration may
hold any pattern. Here the work is bounded by the sizes of the pattern and the path.
"""

from __future__ import annotations

from collections.abc import Sequence
from functools import cache, lru_cache
from pathlib import Path


@lru_cache(maxsize=256)
def _glob_segments(pattern: str, anywhere: bool) -> tuple[str, ...]:
    """A glob's folder segments: ``*`` and ``?`` stay within a segment, a ``**`` segment
    spans any number of folders, and (``anywhere``) a pattern without ``/`` matches a
    name at any depth (``**/`` in front)."""
    glob = pattern.strip().replace("\\", "/").rstrip("/")
    if anywhere and "/" not in glob:
        glob = "**/" + glob
    return tuple(segment for segment in glob.split("/") if segment not in ("", "."))


def glob_matches(
    pattern: str, relative: str, *, whole: bool = False, anywhere: bool = True
) -> bool:
    """Whether the POSIX path ``relative`` (or a folder above it: a pattern naming a
    folder matches everything below it; with ``whole``, the path itself only) matches
    ``pattern`` (which, ``anywhere``, matches at any depth when it has no ``/``: the
    rule for excludes, not for globs on the command line).

    No regular expression: a glob such as ``*a*a*a*a*a*a*c`` made Python's backtracking
    engine (and pathspec's, which compiles to one) take minutes on a 60-character
    name. Segments are matched by :func:`_segment_matches` and folders by a table of
    (pattern segment, path segment) pairs, so the work is bounded by the sizes of the
    two, never exponential.
    """
    wanted = _glob_segments(pattern, anywhere)
    names = [name for name in relative.split("/") if name not in ("", ".")]

    @cache
    def match(at_pattern: int, at_path: int) -> bool:
        if at_pattern == len(wanted):
            # the pattern named this path, or (unless ``whole``) a folder above it
            return at_path == len(names) if whole else at_path > 0
        segment = wanted[at_pattern]
        if segment == "**":
            if match(at_pattern + 1, at_path):
                return True
            return at_path < len(names) and match(at_pattern, at_path + 1)
        return (
            at_path < len(names)
            and _segment_matches(segment, names[at_path])
            and match(at_pattern + 1, at_path + 1)
        )

    return match(0, 0)


def _segment_matches(pattern: str, name: str) -> bool:
    """``*`` (any run) and ``?`` (one character) against one name, by the two-pointer
    method: on a mismatch only the last ``*`` is retried, one character further, which
    bounds the work by the product of the lengths."""
    at_pattern = at_name = 0
    star, star_name = -1, 0
    while at_name < len(name):
        if at_pattern < len(pattern) and pattern[at_pattern] in ("?", name[at_name]):
            at_pattern += 1
            at_name += 1
        elif at_pattern < len(pattern) and pattern[at_pattern] == "*":
            star, star_name = at_pattern, at_name
            at_pattern += 1
        elif star >= 0:
            star_name += 1
            at_pattern, at_name = star + 1, star_name
        else:
            return False
    return all(char == "*" for char in pattern[at_pattern:])


def matches(pattern: str, path: str | Path, base: Path) -> bool:
    """Whether ``path`` (a file) matches ``pattern``, relative to ``base``."""
    return any_match((pattern,), path, base)


def any_match(patterns: Sequence[str], path: str | Path, base: Path) -> bool:
    """Whether ``path`` matches one of ``patterns``; the path is resolved once."""
    candidate = Path(path)
    try:
        relative = candidate.resolve().relative_to(base.resolve()).as_posix()
    except ValueError:
        relative = candidate.as_posix()
    return any(glob_matches(pattern, relative) for pattern in patterns)
