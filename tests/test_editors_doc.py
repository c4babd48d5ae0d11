"""docs/editors.md: every editor's snippet parses, and starts ``xodrlint server``."""

from __future__ import annotations

import json
import re
import tomllib
from pathlib import Path

import pytest

DOC = Path(__file__).resolve().parents[1] / "docs" / "editors.md"
_BLOCK = re.compile(r"^```(?P<lang>\w+)\n(?P<body>.*?)^```$", re.M | re.S)
COMMAND = ["xodrlint", "server"]


def _blocks(lang: str) -> list[str]:
    found = [m["body"] for m in _BLOCK.finditer(DOC.read_text("utf-8")) if m["lang"] == lang]
    assert found, f"no {lang} snippet in {DOC.name}"
    return found


def test_the_vs_code_settings_are_json_starting_the_server() -> None:
    (body,) = _blocks("json")
    settings = json.loads(body)
    assert [settings["glspc.server.command"], *settings["glspc.server.commandArguments"]] == (
        COMMAND
    )
    language = settings["files.associations"]["*.xodr"]
    assert language in settings["glspc.server.languageId"]


def test_the_helix_languages_toml_starts_the_server_for_xodr_files() -> None:
    (body,) = _blocks("toml")
    config = tomllib.loads(body)
    server = config["language-server"]["xodrlint"]
    assert [server["command"], *server["args"]] == COMMAND
    (language,) = config["language"]
    assert "xodr" in language["file-types"]
    assert language["language-servers"] == ["xodrlint"]
    # the fields Helix requires of a language
    assert {"name", "scope", "file-types", "roots"} <= set(language)


def _lua_fields(body: str, name: str) -> list[list[str]]:
    """The string lists of every ``name = { "a", "b" }`` field in the Lua ``body`` (which
    must parse: luaparser raises on a snippet that is not Lua)."""
    ast = pytest.importorskip("luaparser.ast", reason="luaparser (the test extra) is missing")
    nodes = pytest.importorskip("luaparser.astnodes")
    return [
        [item.value.s.decode() for item in node.value.fields]
        for node in ast.walk(ast.parse(body))
        if isinstance(node, nodes.Field)
        and isinstance(node.key, nodes.Name)
        and node.key.id == name
        and isinstance(node.value, nodes.Table)
    ]


#: The first line of a Neovim snippet: the versions it is for.
_FOR = re.compile(r"-- Neovim (\d+)\.(\d+)( and later| to (\d+)\.(\d+)| with nvim-lspconfig .*)?\n")


def _versions(body: str) -> tuple[tuple[int, int], tuple[int, int]]:
    """The lowest and the highest Neovim (major, minor) a snippet is for."""
    found = _FOR.match(body)
    assert found, f"a Neovim snippet says first which versions it is for: {body[:60]!r}"
    low = (int(found[1]), int(found[2]))
    if found[3] == " and later":
        return low, (99, 99)
    if found[4]:
        return low, (int(found[4]), int(found[5]))
    return low, low


def _lua_strings(body: str, name: str) -> list[str]:
    """The strings of every ``name = "..."`` field in the Lua ``body``."""
    ast = pytest.importorskip("luaparser.ast", reason="luaparser (the test extra) is missing")
    nodes = pytest.importorskip("luaparser.astnodes")
    return [
        node.value.s.decode()
        for node in ast.walk(ast.parse(body))
        if isinstance(node, nodes.Field)
        and isinstance(node.key, nodes.Name)
        and node.key.id == name
        and isinstance(node.value, nodes.String)
    ]


def test_the_neovim_lua_parses_and_starts_the_server() -> None:
    bodies = _blocks("lua")
    # vim.lsp.config, vim.lsp.start, vim.lsp.start_client, lspconfig
    assert [_versions(body)[0] for body in bodies] == [(0, 11), (0, 8), (0, 7), (0, 10)]
    for body in bodies:
        assert _lua_fields(body, "cmd") == [COMMAND]
        # the server starts for .xodr buffers: by the client's filetypes, or an autocommand's
        assert _lua_fields(body, "filetypes") == [["xodr"]] or "xodr" in _lua_strings(
            body, "pattern"
        )


def _neovim() -> tuple[int, int] | None:
    """The version of the ``nvim`` on the PATH, if any."""
    import shutil
    import subprocess

    if shutil.which("nvim") is None:
        return None
    first = subprocess.run(
        ["nvim", "--version"], capture_output=True, text=True, timeout=30, check=False
    ).stdout.partition("\n")[0]
    found = re.search(r"v(\d+)\.(\d+)", first)
    return (int(found[1]), int(found[2])) if found else None


_REPORT = (
    "lua vim.defer_fn(function() "
    "for _, d in ipairs(vim.diagnostic.get(0)) do "
    "io.stdout:write(tostring(d.code) .. ' ' .. d.lnum .. '\\n') end; "
    "vim.cmd('qa!') end, {wait})"
)


def test_the_neovim_snippet_for_the_installed_neovim_shows_the_findings(tmp_path: Path) -> None:
    # a real Neovim, headless, with the snippet as its init.lua, on examples/broken.xodr:
    # its diagnostics are check's findings (CI installs Debian 12's Neovim 0.7.2)
    import os
    import shutil
    import subprocess
    import sys

    from xodrlint.api import lint_file

    version = _neovim()
    if version is None:
        pytest.skip("nvim is not installed (Debian: apt-get install neovim)")
    runnable = [
        body
        for body in _blocks("lua")
        if "require(" not in body and _versions(body)[0] <= version <= _versions(body)[1]
    ]
    if not runnable:
        pytest.skip(f"no snippet of docs/editors.md is for Neovim {version[0]}.{version[1]}")
    example = tmp_path / "broken.xodr"
    shutil.copyfile(DOC.parents[1] / "examples" / "broken.xodr", example)
    expected = sorted(
        f"{finding.code} {finding.line - 1}" for finding in lint_file(example).findings
    )
    assert expected
    # the server of this environment, whatever the PATH holds
    path = os.pathsep.join([str(Path(sys.executable).parent), os.environ.get("PATH", "")])
    for body in runnable:
        init = tmp_path / "init.lua"
        init.write_text(body, encoding="utf-8")
        shown: list[str] = []
        for wait in (4000, 12000):  # a slow machine gets a second, longer look
            done = subprocess.run(
                [
                    "nvim",
                    "--headless",
                    "-u",
                    str(init),
                    str(example),
                    "+" + _REPORT.format(wait=wait),
                ],
                capture_output=True,
                text=True,
                timeout=120,
                cwd=tmp_path,
                env={**os.environ, "PATH": path, "XDG_STATE_HOME": str(tmp_path / "state")},
                check=False,
            )
            shown = sorted(line for line in done.stdout.splitlines() if line.strip())
            if shown:
                break
        assert shown == expected, (body[:40], done.stdout, done.stderr)


def test_a_lua_snippet_that_does_not_parse_fails() -> None:
    exceptions = pytest.importorskip("luaparser.ast", reason="luaparser is missing")
    with pytest.raises(exceptions.SyntaxException):
        _lua_fields('vim.lsp.config("xodrlint", { cmd = { "xodrlint", ', "cmd")
