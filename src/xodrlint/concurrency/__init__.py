"""Work that runs beside the calling process, knowing nothing of linting.

- :mod:`~xodrlint.concurrency.background`: one task in a thread or a forked child while
  the caller goes on (schema validation beside the rules); knows nothing of linting but
  hits;
- :mod:`~xodrlint.concurrency.forkpool`: a pool of forked workers, each handed its next
  piece by the parent; knows nothing of linting at all.

Both sit below the pipeline: validation uses ``background``, the runners ``forkpool``.
"""
