"""A pack whose import ends the interpreter, and prints on the way."""

import sys

print("importing a pack that exits")
sys.exit(0)
