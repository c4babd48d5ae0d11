"""The document rule pack (XS): well-formedness, root, header, version and schema.

These rules report what the load and schema stages found; they read it off
``RailNetwork.problems`` so that selection, severity and suppression treat them like
every other rule.
"""
