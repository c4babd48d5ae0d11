"""Stage 2, validation: a document against the official XSD of the version it declares.

- :mod:`~xodrlint.validation.validators`: the stage itself; picks, compiles and runs the
  validator for a document (beside the rules when the document is large);
- :mod:`~xodrlint.validation.sets`: where the schema set for a version comes from
  (``--schema``, ``XODRLINT_SCHEMA_PATH``, the user data folder, the built-in schema);
- :mod:`~xodrlint.validation.source`: a set's files, read once;
- :mod:`~xodrlint.validation.store`: ``xodrlint schemas add|fetch`` fill the user folder;
- :mod:`~xodrlint.validation.libxml2`: XSD 1.0 sets (OpenDRIVE 1.1 to 1.7) in libxml2;
- :mod:`~xodrlint.validation.xsd11`: XSD 1.1 sets (OpenDRIVE 1.8 and 1.9);
- :mod:`~xodrlint.validation.messages`: validator messages a map engineer understands;
- ``builtin/``: our railroad schema, for files whose official set is not installed.

Nothing here imports the model, the rules or the engine.
"""
