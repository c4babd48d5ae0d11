"""How a run is set up: its settings, where they come from, and the installation's caches
and plugins.

- :mod:`~xodrlint.config.settings`: the settings of ``xodrlint.toml``, ``.xodrlint.toml``
  and ``[tool.xodrlint]``, read and checked;
- :mod:`~xodrlint.config.discovery`: which configuration file a folder has, and whether
  it may be trusted;
- :mod:`~xodrlint.config.sizes`: sizes and durations as settings write them;
- :mod:`~xodrlint.config.resolver`: which configuration governs each file of a run;
- :mod:`~xodrlint.config.cache`: the user cache folder, and what may be taken from it;
- :mod:`~xodrlint.config.plugins`: the installed plugins (rule packs, formatters).
"""
