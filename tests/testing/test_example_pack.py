"""The worked example pack (examples/rulepack/) passes its own tests, the command-line ones
included, as pip would install it: a .dist-info in a folder of this test's own, on the
child's search path. Nothing is installed into the environment running the suite (other
runs share it); CI also installs the pack for real, beside the built wheel of xodrlint in
an environment of their own, and runs the same tests (.ci/run)."""

from __future__ import annotations

import os
import subprocess
import sys
import tomllib
from pathlib import Path

from tests.conftest import REPO
from xodrlint.rules.registry import ENTRY_POINT_GROUP

PACK = REPO / "examples" / "rulepack"


def _installed(tmp_path: Path) -> dict[str, str]:
    """An environment where the pack is installed as its pyproject.toml declares it."""
    project = tomllib.loads((PACK / "pyproject.toml").read_text())["project"]
    name, version = project["name"], project["version"]
    info = tmp_path / "site" / f"{name.replace('-', '_')}-{version}.dist-info"
    info.mkdir(parents=True)
    (info / "METADATA").write_text(f"Metadata-Version: 2.1\nName: {name}\nVersion: {version}\n")
    points = project["entry-points"][ENTRY_POINT_GROUP]
    lines = "".join(f"{point} = {target}\n" for point, target in points.items())
    (info / "entry_points.txt").write_text(f"[{ENTRY_POINT_GROUP}]\n{lines}")
    own = [str(Path(p).resolve()) for p in os.environ.get("PYTHONPATH", "").split(os.pathsep) if p]
    search = [str(tmp_path / "site"), str(PACK / "src"), *own]
    return {
        **os.environ,
        "PYTHONPATH": os.pathsep.join(search),
        "XODRLINT_CACHE_DIR": str(tmp_path / "cache"),
        "PYTHONDONTWRITEBYTECODE": "1",  # leave no __pycache__ in the example
    }


def test_the_example_pack_passes_its_own_tests(tmp_path: Path) -> None:
    done = subprocess.run(
        # the pack's own configuration loads the plugin (-p in its addopts)
        [sys.executable, "-m", "pytest", "-q", "-p", "no:cacheprovider"],
        cwd=PACK,
        env=_installed(tmp_path),
        capture_output=True,
        text=True,
        check=False,
        timeout=600,
    )
    assert done.returncode == 0, done.stdout + done.stderr
    summary = done.stdout.strip().splitlines()[-1]
    assert " passed" in summary and "skipped" not in summary, summary
