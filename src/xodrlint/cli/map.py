"""``xodrlint map FILE -o map.html|map.svg``: lint the file as ``check`` would, print the
findings, and draw the network with every finding on it.

Exit codes are ``check``'s: 0 nothing at or above ``--fail-on`` (or ``--exit-zero``), 1
findings, 2 usage or input errors (one line), 3 internal errors. A file that is not an
OpenDRIVE document (XS001, XS002) gets its findings printed and no picture (exit 1).
``--quiet`` prints the findings alone: no file header, summary or "wrote" line, as
``check --quiet`` (the notes of what was not checked stay, on stderr).
"""

from __future__ import annotations

import itertools
import sys
import time
from collections.abc import Sequence
from dataclasses import dataclass
from functools import partial
from pathlib import Path
from typing import Final, TextIO

from xodrlint import __version__
from xodrlint.api import default_registry, exit_code
from xodrlint.cli.check.notes import run_notes, say_notes
from xodrlint.cli.check.request import CheckRequest, UsageError
from xodrlint.cli.check.run import prepare_linter
from xodrlint.config.settings import ConfigError
from xodrlint.document.load import Document, load_bytes
from xodrlint.findings import FileReport, Finding, RunResult
from xodrlint.formatters import get_formatter
from xodrlint.formatters.output import error_line, write_output
from xodrlint.inputs.files import os_reason, overwrites
from xodrlint.mapview.locate import Locator
from xodrlint.mapview.page import html_page, standalone_svg
from xodrlint.mapview.place import Placer
from xodrlint.mapview.scene import Scene, build_scene
from xodrlint.mapview.svg import PlacedFinding, frame_of
from xodrlint.messages import plural
from xodrlint.model import RailNetwork, build_network
from xodrlint.rules.options import OptionError
from xodrlint.rules.registry import Registry
from xodrlint.rules.selection import SelectorError
from xodrlint.validation.sets import SchemaLoadError

#: Chord tolerance of the drawing in metres: finer than the 1 cm the coordinates keep
#: would only add points.
DEFAULT_TOLERANCE: Final = 0.05
KINDS: Final = {".html": "html", ".htm": "html", ".svg": "svg"}


@dataclass(frozen=True)
class MapRequest:
    """A map of ``check.paths[0]`` to ``output``, linted with ``check``'s options."""

    check: CheckRequest
    output: str
    tolerance: float = DEFAULT_TOLERANCE


@dataclass(frozen=True)
class RenderedMap:
    text: str
    scene: Scene
    findings: tuple[PlacedFinding, ...]


def run_map(request: MapRequest) -> int:
    registry = default_registry()
    for warning in registry.warnings:
        error_line(f"warning: {warning}")
    source = Path(request.check.paths[0])
    try:
        kind = _output_kind(request.output, source)
        settings, linter = prepare_linter(registry, request.check)
        data = _read(source)
        report = linter.lint_bytes(data, request.check.paths[0], location=source)
    except (ConfigError, SelectorError, OptionError, UsageError, SchemaLoadError) as error:
        error_line(str(error))
        return 2
    _print_report(registry, report, quiet=request.check.quiet)
    # the tree and model the linter kept: a city map is not parsed and modelled twice
    kept = linter.last_document
    doc, network = (kept.document, kept.network) if kept else (load_bytes(data, report.path), None)
    if not doc.is_opendrive:
        error_line(f"no map written: {report.path} is not an OpenDRIVE document")
        return exit_code([report], settings.fail_on, request.check.exit_zero)
    started = time.perf_counter()
    rendered = render_map(doc, report.findings, kind, request.tolerance, network)
    try:
        write_output(request.output, partial(_write, rendered.text))
    except OSError as error:
        error_line(f"--output {request.output}: cannot write: {os_reason(error)}")
        return 2
    if not request.check.quiet:
        _print_written(request.output, rendered, time.perf_counter() - started)
    return exit_code([report], settings.fail_on, request.check.exit_zero)


def render_map(
    doc: Document,
    findings: Sequence[Finding],
    kind: str,
    tolerance: float,
    network: RailNetwork | None = None,
) -> RenderedMap:
    """The page (``kind`` "html") or standalone SVG of an OpenDRIVE document, whose
    model ``network`` is built here unless given."""
    assert doc.tree is not None
    if network is None:
        network = build_network(doc.root)
    placer = Placer(network)
    scene = build_scene(doc, network, placer, tolerance)
    locator = Locator(doc, network, placer)
    placed = tuple(
        PlacedFinding(
            index,
            finding,
            locator.place(finding),
            None if finding.path == doc.path else finding.path,  # an included file's
        )
        for index, finding in enumerate(findings)
    )
    markers = (item.at for item in placed if item.at is not None)
    frame = frame_of(itertools.chain(scene.points(), markers))
    if kind == "svg":
        text = standalone_svg(scene, placed, frame)
    else:
        text = html_page(doc.path, scene, placed, frame)
    return RenderedMap(text, scene, placed)


def _write(text: str, stream: TextIO) -> None:
    stream.write(text)


def _output_kind(output: str, source: Path) -> str:
    kind = KINDS.get(Path(output).suffix.lower())
    if kind is None:
        raise UsageError(f"--output {output}: name a .html or .svg file")
    target = Path(output)
    if target.is_dir():
        raise UsageError(f"--output {output}: is a folder")
    if not (target.parent if str(target.parent) else Path()).is_dir():
        raise UsageError(f"--output {output}: its folder {target.parent} does not exist")
    if overwrites(target, [source]):
        raise UsageError(f"--output {output}: is the input; refusing to overwrite it")
    return kind


def _read(source: Path) -> bytes:
    if source.is_dir():
        raise UsageError(f"{source}: is a folder; map takes one .xodr file")
    try:
        return source.read_bytes()
    except OSError as error:
        raise UsageError(f"{source}: {os_reason(error)}") from None


def _print_report(registry: Registry, report: FileReport, *, quiet: bool) -> None:
    for crash in report.internal_errors:
        error_line(f"internal error: {crash}")
    result = RunResult(
        (report,),
        registry.metas,
        __version__,
        notes=run_notes([report], registry.metas),
        root=str(Path.cwd()),
    )
    get_formatter("text", quiet=quiet).render(result, sys.stdout)
    sys.stdout.flush()
    say_notes(result.notes)  # on stderr after the report, as check says them


def _print_written(output: str, rendered: RenderedMap, seconds: float) -> None:
    scene = rendered.scene
    placed = sum(1 for item in rendered.findings if item.at is not None)
    size = len(rendered.text.encode("utf-8"))
    print(
        f"xodrlint: wrote {output} ({size / 1e6:.2f} MB in {seconds:.1f} s): "
        f"{plural(scene.road_count(), 'road')}, "
        f"{plural(len(scene.switches), 'switch', 'switches')}, "
        f"{plural(len(scene.platforms), 'platform segment')}, "
        f"{placed} of {plural(len(rendered.findings), 'finding')} placed, "
        f"{plural(len(scene.not_drawn), 'item')} not drawn",
        file=sys.stderr,
    )
