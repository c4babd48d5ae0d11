"""The linters of a run whose files fall under several configurations: one per profile
(:mod:`xodrlint.config.resolver`), each built when a file of it first needs one, in whichever
process lints the file (this one, a forked or spawned worker, a Dask worker)."""

from __future__ import annotations

from collections.abc import Sequence

from xodrlint.engine.linter import Linter, LintOptions
from xodrlint.rules.registry import Registry, load_registry


class Linters:
    """A linter per profile: ``linters[task.profile]``. Profile 0's may be given built
    (the command line's, which keeps its last document for ``map``)."""

    def __init__(
        self,
        options: Sequence[LintOptions],
        *,
        first: Linter | None = None,
        registry: Registry | None = None,
    ) -> None:
        if not options:
            raise ValueError("a run has at least one profile")
        self.options = tuple(options)
        self._registry = registry or (first.registry if first is not None else None)
        self._built: dict[int, Linter] = {0: first} if first is not None else {}

    @classmethod
    def of(cls, linter: Linter) -> Linters:
        """One profile, linted by ``linter``."""
        return cls([linter.options], first=linter)

    def __getitem__(self, profile: int) -> Linter:
        linter = self._built.get(profile)
        if linter is None:
            if self._registry is None:
                self._registry = load_registry()
            linter = Linter(self._registry, self.options[profile])
            self._built[profile] = linter
        return linter

    def __len__(self) -> int:
        return len(self.options)

    def built(self) -> list[Linter]:
        """Every profile's linter, each built now if it was not."""
        return [self[profile] for profile in range(len(self.options))]
