"""What a run lints: the paths, folders, globs and URLs it is given, turned into files.

- :mod:`~xodrlint.inputs.collect`: the inputs of a run, in the order reports list them;
- :mod:`~xodrlint.inputs.walk`: which folders and files a walk leaves out, as git and
  ruff would (``.gitignore``, ``.ignore``, ``exclude``);
- :mod:`~xodrlint.inputs.globs`: the glob matching of ``exclude`` and
  ``per-file-ignores``;
- :mod:`~xodrlint.inputs.remote`: inputs by URL, through fsspec;
- :mod:`~xodrlint.inputs.files`: reading a file without blocking, and writing one whole.
"""
