"""``xodrlint server``: a Language Server Protocol server over stdio (the ``server``
extra, pygls). :mod:`.convert` turns a report into LSP diagnostics, :mod:`.folders`
finds each workspace folder's configuration, :mod:`.protocol` speaks to the editor."""
