"""Tools for developers of xodrlint and of rule packs, not part of the command line:
:mod:`~xodrlint.devtools.docgen` writes the rule pages (``python -m
xodrlint.devtools.docgen``, a pack's with ``--pack``) and the generated parts of the docs,
:mod:`~xodrlint.devtools.apidoc` the rule API's reference among them."""
