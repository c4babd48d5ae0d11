"""Checker-bundle mode for the ASAM Quality Checker framework: ``xodrlint qc``.

The framework starts each registered bundle with its configuration file (``-c``) in the
run's working folder; the bundle reads ``InputFile``, its own ``CheckerBundle`` entry
(``application="xodrlintBundle"``: a ``resultFile`` and ``Checker`` entries whose
``minLevel``/``maxLevel`` pick what runs and which issues are kept) and writes the result
file there. Without a configuration the input file is an argument.

A bundle registers through a module manifest (JSON) that tells the framework how to start
it; ``xodrlint qc --manifest FILE`` writes one for this installation.
"""

from __future__ import annotations

import json
import shlex
import sys
from collections.abc import Mapping
from pathlib import Path
from typing import Final, NamedTuple, TextIO

from lxml import etree

from xodrlint.document import hardened_parser
from xodrlint.formatters.xqar import BUNDLE_NAME, LevelRange, XqarFormatter, checker_id
from xodrlint.output import STDOUT, error_line, write_output
from xodrlint.registry import Registry

#: The result file a bundle writes when its configuration names none.
DEFAULT_RESULT: Final = f"{BUNDLE_NAME}.xqar"
#: The framework reserves this name for its own pooled result.
POOLED_RESULT: Final = "Result.xqar"
#: A checker without levels keeps every issue: errors (1) to information (3).
ALL_LEVELS: Final = (1, 3)


class QcError(ValueError):
    """A configuration the bundle cannot run with: exit 2 with this one line."""


class QcRun(NamedTuple):
    input_file: str
    result_file: str
    params: tuple[tuple[str, str], ...] = ()
    """The configuration's global and bundle parameters, copied into the result."""
    levels: Mapping[str, LevelRange] | None = None
    """(maxLevel, minLevel) by rule code of each configured checker; ``None``: all rules."""


def read_config(path: Path, registry: Registry) -> QcRun:
    """The run a framework configuration file asks of this bundle."""
    try:
        root = etree.parse(str(path), hardened_parser()).getroot()
    except (OSError, etree.XMLSyntaxError) as error:
        raise QcError(f"{path}: cannot read the configuration: {error}") from None
    if root.tag != "Config":
        raise QcError(f"{path}: the root element is '{root.tag}', not 'Config'")
    params = _params(root)
    bundles = [b for b in root.iterchildren("CheckerBundle") if b.get("application") == BUNDLE_NAME]
    if len(bundles) > 1:
        raise QcError(f"{path}: more than one CheckerBundle is named '{BUNDLE_NAME}'")
    own = _params(bundles[0]) if bundles else []
    input_file = dict(params).get("InputFile")
    if not input_file:
        raise QcError(f"{path}: no Param named 'InputFile'")
    result_file = dict(own).get("resultFile") or DEFAULT_RESULT
    _check_result_name(result_file, path)
    levels = _levels(bundles[0], registry, path) if bundles else None
    return QcRun(input_file, result_file, tuple(params + own), levels)


def _params(holder: etree._Element) -> list[tuple[str, str]]:
    return [(p.get("name", ""), p.get("value", "")) for p in holder.iterchildren("Param")]


def _check_result_name(name: str, path: Path) -> None:
    if not name.endswith(".xqar") or Path(name).name != name:
        raise QcError(f"{path}: resultFile '{name}' must be a file name ending in .xqar")
    if name == POOLED_RESULT:
        raise QcError(f"{path}: resultFile '{POOLED_RESULT}' is the framework's own")


def _levels(bundle: etree._Element, registry: Registry, path: Path) -> dict[str, LevelRange]:
    """The configured checkers by rule code; none configured means every rule runs."""
    by_id = {checker_id(rule.meta): rule.code for rule in registry.rules}
    levels: dict[str, LevelRange] = {}
    for checker in bundle.iterchildren("Checker"):
        given = checker.get("checkerId", "")
        code = by_id.get(given) or (given.upper() if given.upper() in registry.by_code else None)
        if code is None:
            raise QcError(f"{path}: '{given}' is no checker of {BUNDLE_NAME} (see xodrlint rules)")
        levels[code] = (_level(checker, "maxLevel", 1, path), _level(checker, "minLevel", 3, path))
    return levels


def _level(checker: etree._Element, name: str, default: int, path: Path) -> int:
    text = (checker.get(name) or "").strip()
    if not text:
        return default
    if text not in ("1", "2", "3"):
        raise QcError(f"{path}: {name}='{text}' of '{checker.get('checkerId')}' is not 1, 2 or 3")
    return int(text)


def run_qc(
    config: Path | None, input_file: str | None, output: str | None, manifest: str | None
) -> int:
    """The ``qc`` command: 0 once the result file is written, whatever it holds (the
    framework reads a bundle's failure from its exit code); 2 for a configuration or an
    input the bundle cannot run with."""
    if manifest is not None:
        write_output(None if manifest == STDOUT else manifest, _write_manifest)
        return 0
    from xodrlint.api import default_registry
    from xodrlint.cli.check import CheckRequest, run_check

    try:
        run = _run_for(config, input_file, output, default_registry())
    except QcError as error:
        error_line(str(error))
        return 2
    request = CheckRequest(
        paths=(run.input_file,),
        output=run.result_file,
        jobs=1,
        exit_zero=True,
        select=tuple(run.levels) if run.levels else None,
    )
    return run_check(request, XqarFormatter(params=run.params, levels=run.levels))


def _run_for(
    config: Path | None, input_file: str | None, output: str | None, registry: Registry
) -> QcRun:
    if config is not None and input_file is not None:
        raise QcError("give the input file in the configuration or as an argument, not both")
    if config is not None:
        run = read_config(config, registry)
    elif input_file is not None:
        run = QcRun(input_file, DEFAULT_RESULT, (("InputFile", input_file),))
    else:
        raise QcError("qc needs a configuration (-c config.xml) or an input file")
    return run._replace(result_file=output) if output else run


def module_manifest() -> dict[str, object]:
    """The module manifest that registers this installation with the framework."""
    command = (
        f"cd $ASAM_QC_FRAMEWORK_WORKING_DIR && {shlex.quote(sys.executable)} -m xodrlint "
        "qc -c $ASAM_QC_FRAMEWORK_CONFIG_FILE"
    )
    module = {
        "name": BUNDLE_NAME,
        "exec_type": "executable",
        "module_type": "checker_bundle",
        "exec_command": command,
    }
    return {"module": [module]}


def manifest_text() -> str:
    return json.dumps(module_manifest(), indent=2) + "\n"


def _write_manifest(stream: TextIO) -> None:
    stream.write(manifest_text())
