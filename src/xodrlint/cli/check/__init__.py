"""``xodrlint check``: its request, its inputs, the run, and its reports.

- :mod:`~xodrlint.cli.check.run`: the command's work, from the request to the exit code;
- :mod:`~xodrlint.cli.check.request`: what the command line asked for;
- :mod:`~xodrlint.cli.check.inputs`: the run's inputs and linters;
- :mod:`~xodrlint.cli.check.scheduler`, :mod:`~xodrlint.cli.check.stream`: files linted
  here, over processes or on a cluster, reports as they come;
- :mod:`~xodrlint.cli.check.reports`, :mod:`~xodrlint.cli.check.notes`,
  :mod:`~xodrlint.cli.check.verbose`: what the run prints.
"""
