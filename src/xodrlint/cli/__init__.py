"""The command layer: the ``xodrlint`` command line, over the engine, the Python API,
the per-file configuration, the workers and the reports.

- :mod:`~xodrlint.cli.commands`: the typer app, every command declared (options, help);
- :mod:`~xodrlint.cli.entry`: the console entry point (exit codes, fast exit);
- one module per command, doing its work: :mod:`~xodrlint.cli.check.run`,
  :mod:`~xodrlint.cli.map`, :mod:`~xodrlint.cli.qc`, :mod:`~xodrlint.cli.rules`
  (``rules`` and ``explain``), :mod:`~xodrlint.cli.schemas`, :mod:`~xodrlint.cli.config`;

``app`` and ``main`` are loaded on first use, so a module that imports one command's
work (``xodrlint.cli.check.run``) does not load typer and every declaration.
"""

from typing import TYPE_CHECKING, Any

if TYPE_CHECKING:
    from xodrlint.cli.commands import app, schemas_app
    from xodrlint.cli.entry import main

__all__ = ["app", "main", "schemas_app"]


def __getattr__(name: str) -> Any:
    if name in ("app", "schemas_app"):
        from xodrlint.cli import commands

        return getattr(commands, name)
    if name == "main":
        from xodrlint.cli.entry import main

        return main
    raise AttributeError(f"module {__name__!r} has no attribute {name!r}")
