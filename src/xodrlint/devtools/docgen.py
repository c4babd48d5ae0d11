"""The developers' documentation command: ``docs/rules/``, ``docs/output-formats.md`` and
the rule API's reference in ``docs/plugins.md``.

Each rule's doc page is its docstring followed by its tested cases (see
:mod:`xodrlint.testing`), so the examples in the docs are the tested ones; the formats
page is each format's real output for one small map; the reference is made from the
code (:mod:`xodrlint.devtools.apidoc`).

Run ``python -m xodrlint.devtools.docgen`` from the repository root to regenerate both; a rule
pack runs ``python -m xodrlint.devtools.docgen --pack MODULE`` from its own root to write its
``docs/rules/`` the same way.
"""

from __future__ import annotations

import sys
from collections.abc import Iterable
from pathlib import Path
from typing import Final

from xodrlint.findings import RuleMeta, RunResult
from xodrlint.testing.cases import cases_in
from xodrlint.testing.pack import RulePack
from xodrlint.testing.pages import render_page

#: The packages of xodrlint's own rules, as a pack under test.
BUILTIN_PACK: Final = "xodrlint.rules"
__all__ = ["formats_page", "generate", "main"]


def generate(root: Path, metas: Iterable[RuleMeta]) -> dict[Path, str]:
    """Doc pages by path under ``root / "docs" / "rules"``, for each of ``metas``."""
    return {
        root / "docs" / "rules" / f"{meta.code}.md": render_page(
            meta, cases_in(root / "rules" / meta.code), root
        )
        for meta in metas
    }


FORMATS_EXAMPLE: Final = "examples/two-findings.xodr"
#: How the formats page names the checkout, so the page is the same in every clone.
SHOWN_ROOT: Final = "file:///path/to/checkout/"
FORMAT_NOTES: Final = {
    "text": "The default: for people at a terminal (colours only on a terminal). Standard "
    "output holds the report; the run's notes (what was not checked) follow on standard "
    "error, `xodrlint: note: ...`, as in every format that has no place for them. A "
    "finding `--fix` mends is marked `[*]`, and a line counts them (see "
    "[fixes.md](fixes.md)).",
    "concise": "One line per finding, for editors and grep. The run's notes (what was not "
    "checked) go to standard error, `xodrlint: note: ...`.",
    "json": "xodrlint's own report; its schema is "
    "[json-output.schema.json](json-output.schema.json). Each finding's `fix` is `null` or "
    "what `--fix` would do: its `applicability` (`safe`, or `unsafe`: only with "
    "`--unsafe-fixes`), a `message`, and its `edits`, each the `content` that replaces the "
    "text from `line`, `column` to `end_line`, `end_column` (the end excluded; numbered as "
    "the finding's line and column). See [fixes.md](fixes.md).",
    "jsonl": "JSON Lines, for pipelines: one object per line, each finding as in the JSON "
    'report, and `{"path": ..., "error": ...}` for a file that could not be read (its schema '
    "is [jsonl-output.schema.json](jsonl-output.schema.json)). Each file's lines are written "
    "and flushed as soon as the file is done, in the order files complete (input order with "
    "`--jobs 1`), and the run keeps no report once written: a reader sees the first findings "
    "while later files are linted, and memory does not grow with the findings. No summary; "
    "the notes go to standard error, as in `concise`. Exit codes are those of every format. "
    "What needs every report at once is refused (exit 2): `--statistics`, and `--report` "
    "files (for both from one run, make the other the output format: `-f sarif --report "
    "jsonl=FILE`). With `--output FILE` the file appears whole when the run ends (written "
    "beside it, then renamed); standard output, or a FIFO named by `--output`, receives "
    "each line at once. See [distributed.md](distributed.md#streaming-output).",
    "sarif": "SARIF 2.1.0 for GitHub code scanning. Shown here: the results and the "
    "invocation; the real file also describes every rule in `tool.driver.rules` (help "
    "text from the rule's page, UID, aliases, tags).\n\n"
    "GitHub rejects a run of more than 25,000 results, so a log holds at most "
    "`--sarif-max-results` (or `sarif-max-results` in the config; default 25000, 0 for no "
    "limit), the most important ones: errors, then warnings, then notes, each by path and "
    "line. Suppressed results (`--show-suppressed`) count after every unsuppressed one: a "
    "dismissed alert matters less than any open one. The kept results stay in the usual "
    "order, with the fingerprints they have without a limit. When results were left out, a "
    "warning says how many, on stderr (naming the `--report` file it is about, if it is "
    "one) and in the log (a `warning` in "
    "`invocations[0].toolExecutionNotifications`, its `properties` giving `results`, "
    "`kept` and `leftOut`). A result's `relatedLocations` are places in the file, not other "
    "results, so none points at a result left out. A result with a fix has `fixes` (SARIF "
    "3.55): one `artifactChange` of its file whose `replacements` each delete a region "
    "(empty for an insertion; `endColumn` is the column after it) and insert content; "
    "the description says whether the fix is safe or unsafe.",
    "github": "GitHub Actions workflow commands: annotations on the pull request. Each of "
    "the run's notes (what was not checked) is a `::notice` of the run, on no file.",
    "gitlab": "GitLab Code Quality: the merge request widget and diff annotations. A file "
    "that could not be read is an issue too (`xodrlint:unreadable`, severity `blocker`, "
    "line 1), so the merge request shows that it went unchecked. The run's notes go to "
    "standard error, as in `concise`.",
    "junit": "JUnit XML: one test suite per file, for GitLab's and Jenkins' test reports. "
    "A finding's test case is named by code, line, column (where known) and XPath; "
    "findings that still share a name get `#2`, `#3` in their order, so every name in a "
    "suite is unique (GitLab keeps one test case per name) and the same in every run. A "
    "rule that did not judge a file of an older OpenDRIVE version than it applies from "
    "(RL001, RL002 on 1.4 to 1.6) is a `skipped` test case `CODE not applied` saying why. "
    "The run's notes go to standard error, as in `concise`.",
    "xqar": "The ASAM Quality Checker framework's result file (see "
    "[qc-framework.md](qc-framework.md)). Shown here: the bundle and the checkers with "
    "issues; the real file has a checker for every rule, each addressing its rule UIDs; a "
    "rule that did not judge a file of an older OpenDRIVE version than it applies from is "
    "a `skipped` checker saying why. The run's notes go to standard error, as in `concise`.",
}


def formats_page(root: Path) -> str:
    """docs/output-formats.md: every built-in format's real output for one small map."""
    import io
    import json

    from xodrlint import __version__
    from xodrlint.cli.check.notes import run_notes
    from xodrlint.engine.linter import Linter, LintOptions
    from xodrlint.formatters import get_formatter
    from xodrlint.rules.registry import Registry, load_registry

    # xodrlint's own rules only: the page is the same whatever packs are installed
    own = tuple(r for r in load_registry().rules if r.meta.origin and r.meta.origin.builtin)
    registry = Registry(own)
    linter = Linter(registry, LintOptions(place_fixes=True))  # as check places them
    report = linter.lint_path(root / FORMATS_EXAMPLE, FORMATS_EXAMPLE)
    notes = run_notes([report], registry.metas)
    selected = tuple(rule.code for rule in linter.rules)  # as check says what did not run
    result = RunResult(
        (report,), registry.metas, __version__, notes=notes, root=str(root), selected=selected
    )
    lines = [
        "# Output formats",
        "",
        f"`--output-format` (`-f`) picks one; `--output FILE` writes it atomically, and "
        "`--report FORMAT=FILE` (repeatable) writes more reports of the same run. Each "
        f"example below is the real output for [`{FORMATS_EXAMPLE}`](../{FORMATS_EXAMPLE}) "
        "(two findings), regenerated by `python -m xodrlint.devtools.docgen` and checked by "
        "the tests.",
        "",
        "The CI formats (`sarif`, `github`, `gitlab`, `junit`) name files relative to the "
        "repository's top, whatever folder the run starts in, so the service can place them: "
        "GitLab's `CI_PROJECT_DIR` or GitHub's `GITHUB_WORKSPACE` when set, else the nearest "
        "folder holding `.git` above the working folder, else the working folder. A file "
        "outside that folder keeps the path it was given.",
        "",
    ]
    for name, note in FORMAT_NOTES.items():
        stream = io.StringIO()
        get_formatter(name).render(result, stream)
        text = stream.getvalue().replace(Path(root).as_uri() + "/", SHOWN_ROOT)
        language = {
            "json": "json",
            "jsonl": "json",
            "sarif": "json",
            "gitlab": "json",
            "junit": "xml",
            "xqar": "xml",
        }
        if name == "sarif":
            run = json.loads(text)["runs"][0]
            shown = {"results": run["results"], "invocations": run["invocations"]}
            text = json.dumps(shown, indent=2, ensure_ascii=False) + "\n"
        if name == "xqar":
            text = _xqar_excerpt(text)
        lines += [f"## `{name}`", "", note, "", f"```{language.get(name, 'text')}"]
        lines += [text.rstrip("\n"), "```", ""]
    lines += _statistics_section(result)
    return "\n".join(lines).rstrip("\n") + "\n"


def _statistics_section(result: RunResult) -> list[str]:
    """``--statistics`` in the formats that hold it, for the same map."""
    import io

    from xodrlint.cli.check.reports import statistics_renderer

    table, document = io.StringIO(), io.StringIO()
    statistics_renderer("text", result)(table)
    statistics_renderer("json", result)(document)
    return [
        "## `--statistics`",
        "",
        "Counts per rule instead of findings: a table in `text` and `concise`, a JSON "
        "document in `json` (its schema is "
        "[json-statistics.schema.json](json-statistics.schema.json)); the other formats "
        "cannot hold statistics and are refused (exit 2).",
        "",
        "```text",
        table.getvalue().rstrip("\n"),
        "```",
        "",
        "```json",
        document.getvalue().rstrip("\n"),
        "```",
        "",
    ]


def _xqar_excerpt(text: str) -> str:
    """The bundle and its checkers with issues; the day of the run made a placeholder."""
    import re

    from lxml import etree

    root = etree.fromstring(text.encode())
    for checker in root.iter("Checker"):
        if checker.find("Issue") is None:
            checker.getparent().remove(checker)  # type: ignore[union-attr]
    etree.indent(root, space="  ")
    shown = etree.tostring(root, encoding="unicode")
    return re.sub(r'build_date="[^"]*"', 'build_date="YYYY-MM-DD"', shown)


def main(argv: list[str] | None = None) -> int:
    """Write the pages of xodrlint's own rules and the formats page, or with ``--pack
    MODULE`` (repeatable) the pages of that pack, in the current folder."""
    args = sys.argv[1:] if argv is None else argv
    packs = [args[i + 1] for i, arg in enumerate(args[:-1]) if arg == "--pack"]
    if len(packs) * 2 != len(args):
        print("usage: python -m xodrlint.devtools.docgen [--pack MODULE]...", file=sys.stderr)
        return 2
    root = Path.cwd()
    if not (root / "rules").is_dir():
        print("run from the repository root, or a pack's (no rules/ folder here)", file=sys.stderr)
        return 2
    if not packs:
        from xodrlint.devtools.apidoc import PAGE, replace_section

        formats = root / "docs" / "output-formats.md"
        formats.write_text(formats_page(root), encoding="utf-8")
        print(f"wrote {formats.relative_to(root)}")
        guide = root / PAGE
        guide.write_text(replace_section(guide.read_text(encoding="utf-8")), encoding="utf-8")
        print(f"wrote {guide.relative_to(root)}")
    try:
        written = RulePack(packs or [BUILTIN_PACK], root).write_pages()
    except ValueError as error:  # a pack refused (PackError), a rule.toml unread
        print(f"xodrlint.devtools.docgen: {error}", file=sys.stderr)
        return 2
    for path in written:
        print(f"wrote {path.relative_to(root)}")
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
