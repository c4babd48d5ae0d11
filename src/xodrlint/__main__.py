"""``python -m xodrlint``: the command line (the framework's manifest starts it so)."""

from xodrlint.cli import main

main()
