"""``xodrlint server`` without the server extra: one line naming the extra, exit 2."""

from __future__ import annotations

import os
import subprocess
import sys
from pathlib import Path

REPO = Path(__file__).resolve().parents[2]
# pygls blocked as if not installed (None in sys.modules makes its import fail)
_RUN = """
import sys
sys.modules["pygls"] = None
sys.argv = ["xodrlint", "server"]
from xodrlint.cli import main
main()
"""


def test_server_without_pygls_names_the_extra() -> None:
    env = {**os.environ, "PYTHONPATH": str(REPO / "src")}
    done = subprocess.run(
        [sys.executable, "-c", _RUN],
        check=False,
        capture_output=True,
        text=True,
        env=env,
        timeout=60,
    )
    assert done.returncode == 2
    assert done.stderr.count("\n") == 1
    assert done.stderr.startswith("xodrlint: the language server needs pygls")
    assert "pip install 'xodrlint[server]'" in done.stderr
