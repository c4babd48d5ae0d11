"""Message hygiene for every stage: findings quote what a map holds, and a map may hold
anything. A message is one printable line, whatever it quotes."""

from __future__ import annotations

import re
from typing import Final

# libxml2 tells a programmer which parser option lifts a limit; a user can do nothing
# with that, and lifting it is exactly what a hostile file wants.
_LIBXML2_OPTION_HINT: Final = re.compile(
    r"[,;:]?\s*(?:try|use|see)\s+(?:XML_PARSE_HUGE|xml[A-Z]\w+)(?:\s+option)?", re.IGNORECASE
)
_PARSER_LIMITS: Final = (
    "excessive depth",
    "amplification",
    "limit exceeded",
    "too long",
    "too big",
    "huge input",
)
#: Parser messages quote the offending text; past this length the quote is cut.
MAX_MESSAGE_LENGTH: Final = 200


def readable_parser_message(message: str) -> str:
    """One printable line a user can act on, however odd the text libxml2 quotes."""
    limit_hit = _LIBXML2_OPTION_HINT.search(message) is not None or any(
        word in message.lower() for word in _PARSER_LIMITS
    )
    message = _LIBXML2_OPTION_HINT.sub("", message)
    message = one_line(" ".join(message.split()))  # a quoted comment may span lines
    if len(message) > MAX_MESSAGE_LENGTH:
        message = message[: MAX_MESSAGE_LENGTH - 1] + "\u2026"
    if limit_hit:
        message += " (refused: a safety limit of the XML parser)"
    return _lowercase_first(message)


def plural(count: int, noun: str, nouns: str | None = None) -> str:
    """``count`` and its noun, singular for one: ``1 file``, ``2 files``, ``0 files``;
    ``nouns`` where the plural is not the noun and an "s" (``switches``, ``info``)."""
    return f"{count} {noun if count == 1 else nouns or noun + 's'}"


def one_line(text: str) -> str:
    """``text`` with what is not printable (line breaks, control characters) escaped as
    ``\\x85``, ``\\u2028``: a message stays one line and cannot steer a terminal."""
    if text.isprintable():
        return text
    return "".join(char if char.isprintable() else _escaped(char) for char in text)


def _escaped(char: str) -> str:
    code = ord(char)
    return (
        f"\\x{code:02x}"
        if code < 0x100
        else f"\\u{code:04x}"
        if code < 0x10000
        else f"\\U{code:08x}"
    )


def _lowercase_first(text: str) -> str:
    return text[:1].lower() + text[1:] if text[:2] != text[:2].upper() else text
