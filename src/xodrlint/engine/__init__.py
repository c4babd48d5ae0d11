"""Stage 5, engine: a document's rules run, their findings judged and stamped.

- :mod:`~xodrlint.engine.linter`: the :class:`Linter` of a run's options, which lints
  one document (validation beside the model and the rules);
- :mod:`~xodrlint.engine.guard`: what a rule may do to a run (nothing but yield hits);
- :mod:`~xodrlint.engine.suppressions`: inline suppressions read from the tree;
- :mod:`~xodrlint.engine.baseline`: findings a team has accepted;
- :mod:`~xodrlint.engine.profiles`: one linter per configuration of a run.
"""
