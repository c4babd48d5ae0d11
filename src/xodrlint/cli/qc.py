"""Checker-bundle mode for the ASAM Quality Checker framework: ``xodrlint qc``.

The framework starts each registered bundle with its configuration file (``-c``) in the
run's working folder; the bundle reads ``InputFile``, its own ``CheckerBundle`` entry
(``application="xodrlintBundle"``: a ``resultFile`` and ``Checker`` entries whose
``minLevel``/``maxLevel`` pick what runs and which issues are kept) and writes the result
file where ``resultFile`` says, relative to that folder, as ASAM's own bundles do (which
open it as given, so its folder must exist). Without a configuration the input file is an
argument. Either way the bundle says on stderr where it wrote the result.

A bundle registers through a module manifest (JSON) that tells the framework how to start
it; ``xodrlint qc --manifest FILE`` writes one for this installation.
"""

from __future__ import annotations

import json
import os
import shlex
import sys
from collections.abc import Mapping
from pathlib import Path
from typing import TYPE_CHECKING, Final, NamedTuple, TextIO

from lxml import etree

from xodrlint.document.load import hardened_parser
from xodrlint.formatters.output import STDOUT, error_line, write_output
from xodrlint.formatters.xqar import BUNDLE_NAME, LevelRange, XqarFormatter, checker_id
from xodrlint.messages import one_line
from xodrlint.rules.registry import Registry

if TYPE_CHECKING:
    from xodrlint.findings import RunResult
    from xodrlint.formatters import Formatter

#: The result file a bundle writes when its configuration names none.
DEFAULT_RESULT: Final = f"{BUNDLE_NAME}.xqar"
#: The framework's pooled result: its pooling skips a bundle result of this name, in the
#: working folder where it reads every other ``*.xqar`` (docs/qc-framework.md says so;
#: a bundle may still write it, as ASAM's own may).
POOLED_RESULT: Final = "Result.xqar"
#: The bundle parameter that applies every rule to every OpenDRIVE version.
ALL_VERSIONS_PARAM: Final = "allVersions"
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
    result_named_by: str = "result file"
    """What named the result file, for messages: ``--output``, the configuration."""
    all_versions: bool | None = None
    """The bundle's ``allVersions`` parameter (``--all-versions``); ``None``: not given,
    the xodrlint configuration beside the map decides."""


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
    levels = _levels(bundles[0], registry, path) if bundles else None
    all_versions = _flag(dict(own).get(ALL_VERSIONS_PARAM), path)
    return QcRun(
        input_file, result_file, tuple(params + own), levels, f"{path}: resultFile", all_versions
    )


def _flag(value: str | None, path: Path) -> bool | None:
    if value is None:
        return None
    text = value.strip().lower()
    if text not in ("true", "false", "1", "0"):
        raise QcError(f"{path}: {ALL_VERSIONS_PARAM}='{value}' is not 'true' or 'false'")
    return text in ("true", "1")


def _params(holder: etree._Element) -> list[tuple[str, str]]:
    return [(p.get("name", ""), p.get("value", "")) for p in holder.iterchildren("Param")]


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
    config: Path | None,
    input_file: str | None,
    output: str | None,
    manifest: str | None,
    keep_alive: list[object] | None = None,
) -> int:
    """The ``qc`` command: 0 once the result file is written, whatever it holds (the
    framework reads a bundle's failure from its exit code); 2 for a configuration or an
    input the bundle cannot run with. ``keep_alive``: see ``CheckRequest.keep_alive``."""
    if manifest is not None:
        write_output(None if manifest == STDOUT else manifest, _write_manifest)
        return 0
    from xodrlint.api import default_registry
    from xodrlint.cli.check.request import CheckRequest
    from xodrlint.cli.check.run import run_check

    try:
        run = _run_for(config, input_file, output, default_registry())
        _check_result_path(run)
    except QcError as error:
        error_line(one_line(str(error)))  # it quotes the configuration's values
        return 2
    request = CheckRequest(
        paths=(run.input_file,),
        output=run.result_file,
        jobs=1,
        exit_zero=True,
        select=tuple(run.levels) if run.levels else None,
        all_versions=run.all_versions,
        keep_alive=keep_alive,
        fix=False,  # a checker bundle reports; a configuration's `fix` writes nothing here
    )
    formatter = _Noted(XqarFormatter(params=run.params, levels=run.levels))
    code = run_check(request, formatter)
    if formatter.written and run.result_file != STDOUT:
        print(one_line(f"xodrlint: wrote results to {run.result_file}"), file=sys.stderr)
    return code


class _Noted:
    """The bundle's formatter, noting that the result went out whole, so that ``qc``
    names the file it wrote and only that."""

    def __init__(self, inner: Formatter) -> None:
        self._inner = inner
        self.written = False

    def render(self, result: RunResult, stream: TextIO) -> None:
        self._inner.render(result, stream)
        stream.flush()  # a full disk fails here, before the file is said to be written
        self.written = True


def _check_result_path(run: QcRun) -> None:
    """Refuse a result file that cannot be written, or that is the input, before linting.

    ASAM's bundles open the configuration's ``resultFile`` as given, relative to the
    working folder, and do not create its folder; nor does this one, but it says so in
    one line where theirs end in a traceback.
    """
    if run.result_file == STDOUT:
        return
    from xodrlint.api import collect_inputs
    from xodrlint.inputs.files import overwrites

    target = Path(run.result_file)
    named = f"{run.result_named_by} {run.result_file}"
    if target.is_dir() or run.result_file.endswith(("/", os.sep)):
        raise QcError(f"{named}: names a folder, not a file")
    folder = target.parent
    if not folder.is_dir():
        problem = "is not a folder" if folder.exists() else "does not exist"
        raise QcError(f"{named}: its folder {folder} {problem}")
    inputs = [item.path for item in collect_inputs((run.input_file,)) if item.path is not None]
    if overwrites(target, inputs):
        which = "the input file" if len(inputs) == 1 else "one of the input files"
        raise QcError(f"{named}: is {which}; refusing to overwrite it")


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
    return run._replace(result_file=output, result_named_by="--output") if output else run


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
