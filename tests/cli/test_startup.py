"""What a pre-commit run loads: a small clean map must not pay for what it does not use."""

from __future__ import annotations

import json
import os
import subprocess
import sys
from pathlib import Path

from .test_cli import CLEAN

#: Modules only some runs need: XSD 1.1 (OpenDRIVE 1.8 and later), terminal output,
#: worker pools (-j on many files), forking large documents, plugin scans (cache misses),
#: the other formats and commands, the table of old import paths, drawing the plan view
#: (the track-geometry rules evaluate it at switch points and joints only), reading
#: ignore files (folder walks only), Dask (--scheduler only), object storage (inputs by URL
#: only), the language server.
NOT_FOR_A_SMALL_JSON_RUN = (
    "xmlschema",
    "elementpath",
    "rich",
    "pickle",
    "multiprocessing",
    "concurrent.futures",
    "importlib.metadata",
    "xodrlint.validation.xsd11.full",
    "xodrlint.validation.xsd11.fast",
    "xodrlint.validation.xsd11.form",
    "xodrlint.formatters.sarif",
    "xodrlint.formatters.xqar",
    "xodrlint.mapview",
    "xodrlint.geometry.sampling",
    "xodrlint.cli.qc",
    "xodrlint.cli.map",
    "xodrlint.concurrency.forkpool",
    "pathspec",
    # what follows includes (a map that holds none)
    "xodrlint.document.includes",
    # a Dask cluster as the engine (--scheduler, xodrlint.distributed)
    "dask",
    "distributed",
    "xodrlint.runners.dask",
    "xodrlint.distributed",
    # object storage (inputs by URL)
    "fsspec",
    "s3fs",
    "botocore",
    "aiobotocore",
    "aiohttp",
    # the language server (xodrlint server) and its protocol library
    "xodrlint.server",
    "pygls",
    "lsprotocol",
    "asyncio",
)

_RUN = """
import json, os, sys
sys.argv = ["xodrlint", "check", "-f", "json", "-o", os.devnull, sys.argv[1]]
from xodrlint.cli import main
try:
    main()
except SystemExit as done:
    code = done.code
print(json.dumps({"code": code, "modules": sorted(sys.modules)}))
"""


def _modules_of_a_run(cache: Path) -> tuple[int, set[str]]:
    env = {**os.environ, "XODRLINT_CACHE_DIR": str(cache), "XODRLINT_FAST_EXIT": "0"}
    out = subprocess.run(
        [sys.executable, "-c", _RUN, str(CLEAN)],
        env=env,
        capture_output=True,
        text=True,
        check=False,
    )
    assert out.returncode == 0, out.stderr
    result = json.loads(out.stdout)
    return result["code"], set(result["modules"])


def test_a_small_clean_run_loads_only_what_it_uses(tmp_path: Path) -> None:
    _modules_of_a_run(tmp_path)  # the first run fills the entry-point cache
    code, modules = _modules_of_a_run(tmp_path)
    assert code == 0
    assert "lxml.etree" in modules and "xodrlint.engine.linter" in modules  # the run did run
    loaded = sorted(
        name
        for name in modules
        for heavy in NOT_FOR_A_SMALL_JSON_RUN
        if name == heavy or name.startswith(heavy + ".")
    )
    assert loaded == []


def test_value_types_are_made_without_compiling_their_annotations() -> None:
    # typing compiles each string annotation of a named tuple when the class is made
    from xodrlint import findings, model
    from xodrlint.inputs import remote

    quoted = {
        f"{module.__name__}.{name}.{field}"
        for module in (findings, model, remote)
        for name, value in vars(module).items()
        if isinstance(value, type) and issubclass(value, tuple) and hasattr(value, "_fields")
        for field, annotation in value.__annotations__.items()
        if isinstance(annotation, str)
    }
    # lxml's element type is only imported for type checking there
    assert quoted <= {"xodrlint.findings.Hit.element", "xodrlint.findings.Hit.related"}
