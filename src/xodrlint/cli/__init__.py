"""The command layer: the ``xodrlint`` command line, a thin client of the engine and the
Python API.

- :mod:`~xodrlint.cli.app`: the typer app, every command declared (options and help);
- :mod:`~xodrlint.cli.entry`: the console entry point (exit codes, fast exit);
- one module per command, doing its work: :mod:`~xodrlint.cli.check`,
  :mod:`~xodrlint.cli.map`, :mod:`~xodrlint.cli.qc`, :mod:`~xodrlint.cli.rules`
  (``rules`` and ``explain``), :mod:`~xodrlint.cli.schemas`, :mod:`~xodrlint.cli.config`;
- :mod:`~xodrlint.cli.docgen`: the developers' command that writes ``docs/rules``.
"""

from xodrlint.cli.app import app, schemas_app
from xodrlint.cli.entry import main

__all__ = ["app", "main", "schemas_app"]
