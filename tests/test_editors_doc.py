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


def test_the_neovim_lua_parses_and_starts_the_server() -> None:
    bodies = _blocks("lua")
    assert len(bodies) == 2  # vim.lsp.config, and lspconfig for an older Neovim
    for body in bodies:
        assert _lua_fields(body, "cmd") == [COMMAND]
        assert _lua_fields(body, "filetypes") == [["xodr"]]


def test_a_lua_snippet_that_does_not_parse_fails() -> None:
    exceptions = pytest.importorskip("luaparser.ast", reason="luaparser is missing")
    with pytest.raises(exceptions.SyntaxException):
        _lua_fields('vim.lsp.config("xodrlint", { cmd = { "xodrlint", ', "cmd")
