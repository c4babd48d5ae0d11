"""Rule selection: which rules ``select`` and ``ignore`` (and ``per-file-ignores``, and
suppressions) name, by code prefix, name or UID; the more specific entry wins."""

from __future__ import annotations

from collections.abc import Iterable, Sequence
from typing import TYPE_CHECKING

if TYPE_CHECKING:
    from xodrlint.rules import Rule
    from xodrlint.rules.registry import Registry


class SelectorError(ValueError):
    """A ``--select``/``--ignore`` entry that names no rule."""


def select_rules(registry: Registry, select: Sequence[str], ignore: Sequence[str]) -> list[Rule]:
    """The rules ``select`` picks and ``ignore`` does not; the more specific entry wins.

    An entry is ``ALL``, a code prefix (``SW``, ``SW00``, ``SW001``), a rule name or one of
    a rule's UIDs. When a select and an ignore entry are equally specific, ignore wins.
    An opt-in rule is picked only by an entry that names its family or more (``XL``,
    ``XL001``, its name or a UID), never by ``ALL``.
    """
    for token in (*select, *ignore):
        if not any(specificity(token, r) is not None for r in registry.rules):
            raise SelectorError(f"'{token}' matches no rule code, name or UID")
    chosen = []
    for candidate in registry.rules:
        selected = _best(select, candidate)
        ignored = _best(ignore, candidate)
        if selected is not None and (ignored is None or selected > ignored):
            chosen.append(candidate)
    return chosen


def _best(tokens: Iterable[str], candidate: Rule) -> int | None:
    scores = [s for t in tokens if (s := specificity(t, candidate)) is not None]
    return max(scores, default=None)


def specificity(token: str, candidate: Rule) -> int | None:
    """How closely ``token`` names the rule (``None``: not at all); suppressions and
    per-file-ignores match with it too, so ``ALL`` there leaves an opt-in rule alone."""
    meta = candidate.meta
    if token.upper() == "ALL":
        score = 0
    elif token in meta.uids or token.lower() == meta.name:
        score = len(meta.code)
    elif token and meta.code.startswith(token.upper()):
        score = len(token)
    else:
        return None
    if meta.opt_in and score < len(meta.code.rstrip("0123456789")):
        return None
    return score
