"""The track map: the network drawn from its plan view, with every finding on it.

A self-contained HTML page (inline SVG, CSS and plain JavaScript read from this package's
data files) or a static SVG. The ``map`` command (:mod:`xodrlint.cli.map`) lints the file
and hands the document, its model and its findings here; only that command imports this
package.
"""
