"""Processes: work that runs beside or instead of the calling process.

- :mod:`~xodrlint.workers.background`: one task in a thread or a forked child while the
  caller goes on (schema validation beside the rules); knows nothing of linting but hits;
- :mod:`~xodrlint.workers.forkpool`: a pool of forked workers, each handed its next
  piece by the parent; knows nothing of linting at all;
- :mod:`~xodrlint.workers.batch`: many files linted over worker processes, reports in
  input order (the forked pool, or an executor where fork is unavailable).
- :mod:`~xodrlint.workers.dask`: many files linted on a Dask cluster, each report as it
  completes (imported only when a run asks for Dask).

``background`` and ``forkpool`` sit below the pipeline (validation uses ``background``);
``batch`` sits above the engine, whose linter each worker keeps, and ``dask`` above it.
"""
