"""``xodrlint map``: the network drawn from its plan view, with every finding on it.

A self-contained HTML page (inline SVG, CSS and plain JavaScript read from this package's
data files) or a static SVG. Only the ``map`` command imports this package.
"""
