"""Sizes as settings and the command line write them (``500MB``, ``2GiB``), and the
largest input a run reads."""

from __future__ import annotations

import re
from typing import Final

#: Larger inputs are refused before they are read: far above any real map (the largest
#: public networks are tens of MB), low enough that no input can exhaust the memory.
DEFAULT_MAX_FILE_SIZE: Final = 2 * 1024**3


_SIZE: Final = re.compile(r"(\d+)\s*([kmgt]i?)?b?", re.IGNORECASE)


_UNITS: Final = {"": 1, "k": 1000, "m": 1000**2, "g": 1000**3, "t": 1000**4}


_BINARY_UNITS: Final = {"ki": 1024, "mi": 1024**2, "gi": 1024**3, "ti": 1024**4}


def parse_size(value: object) -> int:
    """A positive size in bytes: an integer, or a string such as ``500MB`` or ``2GiB``
    (kB, MB, GB, TB are powers of 1000; KiB, MiB, GiB, TiB powers of 1024)."""
    if isinstance(value, int) and not isinstance(value, bool) and value > 0:
        return value
    found = _SIZE.fullmatch(value.strip()) if isinstance(value, str) else None
    if found is not None:
        unit = (found[2] or "").lower()
        size = int(found[1]) * {**_UNITS, **_BINARY_UNITS}[unit]
        if size > 0:
            return size
    raise TypeError("a positive size such as 500MB or 2GiB")


def format_size(size: int) -> str:
    """``size`` the way a person writes it: ``2GiB``, ``10MB``, ``1234`` (bytes)."""
    for units in (_BINARY_UNITS, _UNITS):
        for unit, factor in sorted(units.items(), key=lambda item: -item[1]):
            if factor > 1 and size % factor == 0:
                return f"{size // factor}{unit.upper().replace('I', 'i')}B"
    return str(size)


def too_large(shown: str, max_file_size: int) -> str:
    """Why an input larger than ``max_file_size`` is not read."""
    limit = format_size(max_file_size)
    return f"{shown}: larger than the maximum file size ({limit}, see --max-file-size)"
