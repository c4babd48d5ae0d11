"""``python -m xodrlint``: the command line (the framework's manifest starts it so)."""

from xodrlint.cli import main

if __name__ == "__main__":  # a spawned worker process imports this module again
    main()
