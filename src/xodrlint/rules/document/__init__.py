"""The document rule pack (XS, XL): well-formedness, root, header, version and schema,
and suppression comments that withhold nothing.

These rules report what the load, schema and suppression stages found; they read it off
``RailNetwork.problems`` so that selection, severity and suppression treat them like
every other rule.
"""
