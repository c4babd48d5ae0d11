"""Stage 1, document: a file's bytes become a parsed tree with positions.

- :mod:`~xodrlint.document.load`: the hardened parser, the one parse of every file read,
  and the :class:`~xodrlint.document.load.Document` with its header and version;
- :mod:`~xodrlint.document.xpaths`: XPaths a person can read, for findings;
- :mod:`~xodrlint.document.positions`: where each element is, in its tree and in its
  source;
- :mod:`~xodrlint.document.includes`: what ``<include>`` brings into a document;
- :mod:`~xodrlint.document.edits`: byte-exact edits of a source (what a fix changes).
"""
