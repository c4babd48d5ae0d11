"""HY: rules that never end (issue 30, item 5), one the rule clock can stop and one it
cannot; a folder's configuration selects the one a test wants."""

from __future__ import annotations

import signal
from collections.abc import Iterator

from xodrlint.findings import Hit, Severity
from xodrlint.model import RailNetwork
from xodrlint.rules import rule


@rule(code="HY001", name="spins", uid="test:hostile:HY001", severity=Severity.WARNING)
def spins(network: RailNetwork) -> Iterator[Hit]:
    """Runs for ever in Python: the rule clock stops it (where it can run at all)."""
    while True:
        pass
    yield  # pragma: no cover


@rule(code="HY002", name="blocks-the-clock", uid="test:hostile:HY002", severity=Severity.WARNING)
def blocks_the_clock(network: RailNetwork) -> Iterator[Hit]:
    """Runs for ever where no signal reaches it: as a stage in C that never returns."""
    signal.pthread_sigmask(signal.SIG_BLOCK, {signal.SIGALRM, signal.SIGINT})
    while True:
        pass
    yield  # pragma: no cover
