"""Giving memory back to the system once a large piece of work has freed it.

glibc's ``malloc`` keeps what a program frees for its next allocations: a process's
resident memory stays at its high-water mark. libxml2's schema validation of a 20 MB
railway allocates and frees some 30 MB of working memory (its own thread's arena) while
the rules still build theirs; left in the arena, it adds to the run's peak.
``malloc_trim`` hands the free pages of every arena back. Elsewhere than glibc (musl,
macOS, Windows) there is no such call, and nothing is done.
"""

from __future__ import annotations

import ctypes
import functools
import sys
from collections.abc import Callable
from typing import Final

#: The size of a document (bytes) from which the memory freed by a stage of its work is
#: worth giving back: a small map's is a few pages, and each call walks the heap.
GIVE_BACK_FROM: Final = 1 << 20


@functools.cache
def _malloc_trim() -> Callable[[int], int] | None:
    if not sys.platform.startswith("linux"):
        return None
    try:
        libc = ctypes.CDLL(None)  # the process's own symbols: its C library
        trim = libc.malloc_trim
    except (OSError, AttributeError):  # another C library (musl has no malloc_trim)
        return None
    trim.argtypes = [ctypes.c_size_t]
    trim.restype = ctypes.c_int
    return trim


def give_back_freed_memory() -> bool:
    """Return the free pages of the C heap to the system; whether that could be asked.
    Not free: glibc walks every arena's free chunks, holding each arena's lock in turn
    (20 to 130 ms after validating a 20 to 40 MB map), so it is worth it only where
    the memory would otherwise add to a peak still to come."""
    trim = _malloc_trim()
    if trim is None:
        return False
    trim(0)
    return True
