"""What lints many files: over worker processes on this machine, or on a Dask cluster.

- :mod:`~xodrlint.runners.batch`: many files linted over worker processes, reports in
  input order (the forked pool of :mod:`xodrlint.concurrency.forkpool`, or an executor
  where fork is unavailable); each worker keeps the engine's linter.
- :mod:`~xodrlint.runners.dask`: many files linted on a Dask cluster, each report as it
  completes (imported only when a run asks for Dask).
"""
