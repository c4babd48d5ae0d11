"""Partner pairs: two distinct switches of which at least one names the other as partner."""

from __future__ import annotations

from collections.abc import Iterator
from typing import NamedTuple

from xodrlint.rules import PartnerRef, RailNetwork, Switch


class PartnerPair(NamedTuple):
    first: Switch
    """The earlier switch of the pair in document order."""
    later: Switch
    partners: tuple[PartnerRef, ...]
    """The `partner` elements that name the other switch of the pair, in document order."""


def partner_of(network: RailNetwork, switch: Switch) -> Switch | None:
    """The switch a switch's `partner` names, when it names another one that exists."""
    if switch.partner is None or switch.partner.id is None:
        return None
    other = network.switch_by_id.get(switch.partner.id)
    return other if other is not None and other is not switch else None


def partner_pairs(network: RailNetwork) -> Iterator[PartnerPair]:
    """Each pair once, in the document order of its first `partner` reference (found
    once per file: PT004 and PT006 both ask, 36 ms each on a 20 MB railway)."""
    return iter(network.shared(_PartnerPairs))


class _PartnerPairs(tuple[PartnerPair, ...]):
    """Every pair of a file, as :func:`partner_pairs` gives them."""

    def __new__(cls, network: RailNetwork) -> _PartnerPairs:
        return super().__new__(cls, _found_pairs(network))


def _found_pairs(network: RailNetwork) -> Iterator[PartnerPair]:
    order = {id(switch): index for index, switch in enumerate(network.switches)}
    pairs: dict[frozenset[int], list[Switch]] = {}
    for switch in network.switches:
        other = partner_of(network, switch)
        if other is not None:
            pairs.setdefault(frozenset((id(switch), id(other))), []).append(switch)
    for namers in pairs.values():
        naming = namers[0]
        other = partner_of(network, naming)
        if other is None:
            continue
        first, later = sorted((naming, other), key=lambda sw: order[id(sw)])
        refs = tuple(sw.partner for sw in namers if sw.partner is not None)
        yield PartnerPair(first, later, refs)
