"""OpenDRIVE's ``<include file=.../>`` (issue 31, item 4): the included file's content
joins the network, findings in it carry its path, line and XPath, and what cannot or may
not be read is an XS007 finding on the ``include``."""

from __future__ import annotations

import json
import os
from pathlib import Path
from typing import Any

import pytest

from tests.cli.test_cli import cli
from tests.conftest import REPO, SHARED_SCHEMAS, needs_shared
from xodrlint.findings import FileReport, Finding, Severity
from xodrlint.rules.registry import load_registry

CASES = REPO / "rules" / "XS007"
#: road 1 with switch 101, whose side track is road 2 (in parts/branch.xml)
MAIN = (CASES / "valid_included_road.xodr").read_text("utf-8")
BRANCH = (CASES / "parts" / "branch.xml").read_text("utf-8")
INCLUDE = '  <include file="parts/branch.xml"/>\n'
#: the geometry of these cases puts the side track 0.17 m off and each track 0.75 m off
#: its reference line: beside the point of these tests
NOT_HERE = ("--ignore", "SW011")


def _network(folder: Path, main: str = MAIN, branch: str = BRANCH) -> Path:
    (folder / "parts").mkdir(parents=True, exist_ok=True)
    (folder / "parts" / "branch.xml").write_text(branch, "utf-8")
    path = folder / "main.xodr"
    path.write_text(main, "utf-8")
    return path


def _findings(*args: str | Path, code: int = 1, stdin: bytes | None = None) -> list[dict[str, Any]]:
    result = cli("check", "-f", "json", *NOT_HERE, *args, code=code, stdin=stdin)
    findings: list[dict[str, Any]] = json.loads(result.stdout)["findings"]
    return findings


def _places(findings: list[dict[str, Any]]) -> list[tuple[str, str, int, int | None, str]]:
    return [(f["code"], f["path"], f["line"], f["column"], f["xpath"]) for f in findings]


def test_an_included_crossover_resolves_the_switch_that_names_it(tmp_path: Path) -> None:
    # the reproduction: the crossover road lives in another file
    main = _network(
        tmp_path, MAIN.replace('id="2"', 'id="13"'), BRANCH.replace('id="2"', 'id="13"')
    )
    assert _findings(main, "--select", "SW,PT,XS", code=0) == []
    (tmp_path / "parts" / "branch.xml").unlink()
    found = _findings(main, "--select", "SW,PT,XS")
    assert [(f["code"], f["line"]) for f in found] == [("SW004", 20), ("XS007", 24)]
    assert "names road '13', which does not exist" in found[0]["message"]
    assert found[1]["message"] == (
        "include 'parts/branch.xml' cannot be read: no such file or directory"
    )


def test_findings_in_an_included_file_carry_its_path_line_column_and_xpath(
    tmp_path: Path,
) -> None:
    main = _network(tmp_path)
    part = str(tmp_path / "parts" / "branch.xml")
    lane = "/lanes/laneSection/right/lane[@id='-1']"
    assert _places(_findings(main, "--select", "RL002")) == [
        ("RL002", str(main), 13, 11, f"/OpenDRIVE/road[@id='1']{lane}"),
        ("RL002", part, 12, 11, f"/OpenDRIVE/road[@id='2']{lane}"),
    ]
    # the text report's lines, and SARIF's artifact, name the included file too
    text = cli("check", "-q", *NOT_HERE, "--select", "RL002", main, code=1).stdout
    assert f"{part}:12:11: RL002" in text
    sarif = json.loads(cli("check", "-f", "sarif", "--select", "RL002", main, code=1).stdout)
    uris = [
        result["locations"][0]["physicalLocation"]["artifactLocation"]["uri"]
        for result in sarif["runs"][0]["results"]
    ]
    assert uris[0].endswith("/main.xodr") and uris[1].endswith("/parts/branch.xml")


def test_a_file_of_one_road_joins_as_that_road(tmp_path: Path) -> None:
    road = "\n".join(line for line in BRANCH.splitlines() if "OpenDRIVE" not in line)
    main = _network(tmp_path, branch=road)
    found = _findings(main, "--select", "SW004,XS007,RL002")
    assert [(f["code"], f["xpath"]) for f in found] == [
        ("RL002", "/OpenDRIVE/road[@id='1']/lanes/laneSection/right/lane[@id='-1']"),
        ("RL002", "/road/lanes/laneSection/right/lane[@id='-1']"),
    ]


def test_a_file_included_twice_joins_once(tmp_path: Path) -> None:
    main = _network(tmp_path, MAIN.replace(INCLUDE, INCLUDE * 2))
    found = _findings(main, "--select", "RL002,XS007,SW004")
    assert [f["path"].endswith("branch.xml") for f in found] == [False, True]


def _chain(folder: Path, length: int) -> Path:
    """main.xodr includes parts/p1.xml, which includes p2.xml, ... up to p<length>.xml,
    which holds road 2."""
    _network(folder)
    for number in range(1, length):
        text = f'<OpenDRIVE>\n  <include file="p{number + 1}.xml"/>\n</OpenDRIVE>\n'
        (folder / "parts" / f"p{number}.xml").write_text(text, "utf-8")
    (folder / "parts" / f"p{length}.xml").write_text(BRANCH, "utf-8")
    main = folder / "main.xodr"
    main.write_text(MAIN.replace("parts/branch.xml", "parts/p1.xml"), "utf-8")
    return main


def test_a_chain_of_eight_includes_is_followed_and_a_ninth_is_not(tmp_path: Path) -> None:
    assert _findings(_chain(tmp_path / "eight", 8), "--select", "SW004,XS007", code=0) == []
    found = _findings(_chain(tmp_path / "nine", 9), "--select", "SW004,XS007")
    assert [(f["code"], Path(f["path"]).name, f["line"]) for f in found] == [
        ("SW004", "main.xodr", 20),
        ("XS007", "p8.xml", 2),
    ]
    assert found[1]["message"] == "include 'p9.xml' is more than 8 includes deep"


def test_a_file_that_includes_itself_is_a_finding_on_the_include_that_closes_the_loop(
    tmp_path: Path,
) -> None:
    main = _network(tmp_path, MAIN.replace(INCLUDE, '  <include file="parts/a.xml"/>\n'))
    (tmp_path / "parts" / "a.xml").write_text(
        '<OpenDRIVE>\n  <include file="b.xml"/>\n</OpenDRIVE>\n', "utf-8"
    )
    (tmp_path / "parts" / "b.xml").write_text(
        '<OpenDRIVE>\n  <include file="a.xml"/>\n  <include file="../main.xodr"/>\n'
        '  <include file="branch.xml"/>\n</OpenDRIVE>\n',
        "utf-8",
    )
    found = _findings(main, "--select", "SW004,XS007")
    assert [(f["code"], Path(f["path"]).name, f["line"], f["message"]) for f in found] == [
        ("XS007", "b.xml", 2, "include 'a.xml' includes itself (a.xml -> b.xml -> a.xml)"),
        (
            "XS007",
            "b.xml",
            3,
            "include '../main.xodr' includes itself (main.xodr -> a.xml -> b.xml -> main.xodr)",
        ),
    ]


def test_only_files_in_the_checked_file_s_folder_are_read(tmp_path: Path) -> None:
    secret = tmp_path / "secret.xml"
    secret.write_text(BRANCH, "utf-8")
    folder = tmp_path / "maps"
    main = _network(folder)
    for name, target in (("up.xml", "../../secret.xml"), ("abs.xml", str(secret))):
        text = MAIN.replace(INCLUDE, f'  <include file="{target}"/>\n')
        (folder / name.replace(".xml", ".xodr")).write_text(text, "utf-8")
    (folder / "parts" / "link.xml").symlink_to(secret)
    (folder / "linked.xodr").write_text(MAIN.replace("branch.xml", "link.xml"), "utf-8")
    (folder / "inside.xodr").write_text(
        MAIN.replace("parts/branch.xml", str(folder / "parts" / "branch.xml")), "utf-8"
    )
    outside = f"lies outside {folder}, the folder of the file being checked"
    for name in ("up.xodr", "abs.xodr", "linked.xodr"):
        found = _findings(folder / name, "--select", "XS007,SW004")
        assert [f["code"] for f in found] == ["SW004", "XS007"], name
        assert found[1]["message"].endswith(outside), name
    # an absolute path inside the folder is followed
    assert _findings(folder / "inside.xodr", "--select", "XS007,SW004", code=0) == []
    assert main.exists()


@pytest.mark.parametrize(
    ("target", "reason"),
    [
        ("https://example.com/branch.xodr", "is a URL: xodrlint reads no include from the network"),
        ("file:///etc/passwd", "is a URL: xodrlint reads no include from the network"),
        ("parts/fifo.xml", "is a FIFO, not a regular file"),
        ("parts", "cannot be read: is a directory"),
        ("parts/broken.xml", "is not well-formed XML at line 2: "),
        ("", "names no file"),
    ],
)
def test_what_cannot_be_read_is_said_on_the_include(
    tmp_path: Path, target: str, reason: str
) -> None:
    main = _network(tmp_path, MAIN.replace(INCLUDE, f'  <include file="{target}"/>\n'))
    os.mkfifo(tmp_path / "parts" / "fifo.xml")
    (tmp_path / "parts" / "broken.xml").write_text("<OpenDRIVE>\n<road", "utf-8")
    [finding] = _findings(main, "--select", "XS007")
    assert finding["message"].startswith(f"include '{target}' {reason}")


def test_standard_input_follows_includes_only_when_named(tmp_path: Path) -> None:
    main = _network(tmp_path)
    data = main.read_bytes()
    [unnamed] = _findings("-", "--select", "XS007,SW004", stdin=data)[1:]
    assert unnamed["message"] == (
        "include 'parts/branch.xml' is not read: the file being checked was not read from a folder"
    )
    named = ("-", "--stdin-filename", str(main), "--select", "XS007,SW004")
    assert _findings(*named, stdin=data, code=0) == []


def test_an_ignore_file_comment_in_an_included_file_withholds_only_there(tmp_path: Path) -> None:
    branch = BRANCH.replace("<OpenDRIVE>", "<OpenDRIVE>\n<!-- xodrlint: ignore-file[RL002] -->")
    main = _network(tmp_path, branch=branch)
    found = _findings(main, "--select", "RL002")
    assert [Path(f["path"]).name for f in found] == ["main.xodr"]


@needs_shared
def test_the_schema_judges_each_file_as_written(tmp_path: Path) -> None:
    """With ASAM's 1.7 schema, the side track's reference to the included road is no
    keyref error, nor the include itself; a road nobody holds still is (as SW004)."""
    schema = ("--schema", SHARED_SCHEMAS / "1.7.0")
    main = _network(tmp_path)
    assert _findings(main, *schema, "--select", "XS,SW004", code=0) == []
    (tmp_path / "parts" / "branch.xml").write_text(BRANCH.replace('id="2"', 'id="3"'), "utf-8")
    found = _findings(main, *schema, "--select", "XS,SW004")
    assert [f["code"] for f in found] == ["SW004"]


def test_the_editor_shows_the_document_s_own_findings() -> None:
    from xodrlint.server.convert import diagnostics

    def finding(path: str, line: int) -> Finding:
        return Finding(path, line, 1, "RL002", "uid", Severity.WARNING, "m", "/OpenDRIVE")

    report = FileReport("main.xodr", findings=(finding("main.xodr", 2), finding("part.xml", 3)))
    text = "<OpenDRIVE>\n<a/>\n<b/>\n</OpenDRIVE>\n"
    shown = diagnostics(report, "file:///main.xodr", text, "utf-16", load_registry())
    assert [d.range.start.line for d in shown] == [1]


def test_a_map_without_includes_is_not_walked_for_them(tmp_path: Path) -> None:
    from xodrlint.document.includes import has_includes
    from xodrlint.document.load import load_bytes

    assert not has_includes(load_bytes(BRANCH.encode(), "x.xml"))
    assert has_includes(load_bytes(MAIN.encode(), "main.xodr"))
    in_user_data = BRANCH.replace(
        "<planView>", '<userData code="x"><include file="y"/></userData><planView>'
    )
    assert not has_includes(load_bytes(in_user_data.encode(), "x.xml"))


def test_the_map_draws_included_roads_and_places_their_findings(tmp_path: Path) -> None:
    # a file of one road: its findings' XPaths (/road/...) name nothing in the map's tree
    road = "\n".join(line for line in BRANCH.splitlines() if "OpenDRIVE" not in line)
    main = _network(tmp_path, branch=road)
    out = tmp_path / "map.html"
    result = cli("map", main, "-o", out, "--select", "RL002", code=1)
    assert "2 roads" in result.stderr and "2 of 2 findings placed" in result.stderr
    page = out.read_text("utf-8")
    data = json.loads(page.split('id="map-data">', 1)[1].split("</script>", 1)[0])
    assert [(f["line"], f["at"] is not None) for f in data["findings"]] == [(13, True), (11, True)]


def test_a_missing_reference_reads_back_from_its_message() -> None:
    from xodrlint.validation.messages import missing_reference, missing_reference_message

    message = missing_reference_message("sideTrack", "@id", "'13'", "road", "@id")
    assert missing_reference(message) == ("13", "road", "id")
    several = missing_reference_message("x", "@a and @b", "'1', '2'", "y", "@a and @b")
    assert missing_reference(several) is None


@needs_shared
def test_only_what_an_included_element_defines_resolves_a_reference(tmp_path: Path) -> None:
    """A junction connection from road 2 is resolved by the included road 2; one from
    road 9 stays an XS006, as without includes."""
    junction = (
        '  <junction id="5" name="j">\n'
        '    <connection id="0" incomingRoad="2" connectingRoad="1" contactPoint="start"/>\n'
        '    <connection id="1" incomingRoad="9" connectingRoad="1" contactPoint="start"/>\n'
        "  </junction>\n"
    )
    main = _network(tmp_path, MAIN.replace(INCLUDE, junction + INCLUDE))
    found = _findings(main, "--schema", SHARED_SCHEMAS / "1.7.0", "--select", "XS006")
    assert [(f["line"], f["message"]) for f in found] == [
        (26, "'connection/@incomingRoad' names '9', but no 'road' has that @id")
    ]


def test_a_utf16_map_follows_its_includes(tmp_path: Path) -> None:
    main = _network(tmp_path)
    text = MAIN.replace('encoding="UTF-8"', 'encoding="UTF-16"')
    main.write_bytes(text.encode("utf-16"))
    assert _findings(main, "--select", "SW004,XS007", code=0) == []
    main.write_bytes(text.replace("branch.xml", "missing.xml").encode("utf-16"))
    assert [f["code"] for f in _findings(main, "--select", "SW004,XS007")] == ["SW004", "XS007"]


def test_an_included_file_whose_root_is_an_include_is_a_finding(tmp_path: Path) -> None:
    main = _network(tmp_path, MAIN.replace("branch.xml", "indirect.xml"))
    (tmp_path / "parts" / "indirect.xml").write_text('<include file="branch.xml"/>', "utf-8")
    [finding] = _findings(main, "--select", "XS007")
    assert finding["message"] == (
        "include 'parts/indirect.xml' holds an include as its root element: "
        "include the file it names instead"
    )


def test_max_file_size_holds_for_included_files(tmp_path: Path) -> None:
    main = _network(tmp_path, branch=BRANCH + f"<!-- {'x' * 2000} -->\n")
    [finding] = _findings(main, "--select", "XS007", "--max-file-size", "1500")
    assert finding["message"] == "include 'parts/branch.xml' is larger than 1,500 bytes"


def test_suppressions_keep_to_their_own_file(tmp_path: Path) -> None:
    """An ignore-file comment before an included file's root applies there; an ignore
    comment that ends an included file does not reach the including file's next element;
    an unused file-wide one in an included file is reported at its own place."""
    before_root = BRANCH.replace(
        "<OpenDRIVE>", "<!-- xodrlint: ignore-file[RL002] -->\n<OpenDRIVE>"
    )
    main = _network(tmp_path, branch=before_root)
    assert [Path(f["path"]).name for f in _findings(main, "--select", "RL002")] == ["main.xodr"]

    trailing = BRANCH.replace("</OpenDRIVE>", "  <!-- xodrlint: ignore[RL002] -->\n</OpenDRIVE>")
    main = _network(tmp_path, MAIN.replace(INCLUDE, INCLUDE + _road_3()), trailing)
    found = _findings(main, "--select", "RL002")
    assert [(Path(f["path"]).name, f["xpath"].split("/")[2]) for f in found] == [
        ("main.xodr", "road[@id='1']"),
        ("main.xodr", "road[@id='3']"),
        ("branch.xml", "road[@id='2']"),
    ]

    unused = BRANCH.replace("</OpenDRIVE>", "  <!-- xodrlint: ignore-file[ST001] -->\n</OpenDRIVE>")
    main = _network(tmp_path, branch=unused)
    [finding] = _findings(main, "--select", "XL001,ST001")
    line = unused.splitlines().index("  <!-- xodrlint: ignore-file[ST001] -->") + 1
    assert (finding["path"], finding["line"]) == (str(tmp_path / "parts" / "branch.xml"), line)


def _road_3() -> str:
    """Road 2 of the cases as road 3, beside it: a main-file element after the include."""
    road = BRANCH.split("<OpenDRIVE>\n", 1)[1].split("</OpenDRIVE>", 1)[0]
    return road.replace('id="2"', 'id="3"')


def test_reports_keep_each_finding_s_own_file(tmp_path: Path) -> None:
    main = _network(tmp_path)
    text = cli("check", "--show-source", "--select", "RL002", main, code=1).stdout
    assert text.count(" | ") == 1  # the main file's line; none for the included one
    junit = cli("check", "-f", "junit", "--select", "RL002", main, code=1).stdout
    assert f'classname="{tmp_path / "parts" / "branch.xml"}"' in junit


def test_a_related_element_in_another_file_is_named_with_its_file(tmp_path: Path) -> None:
    # the included road holds a switch with the id of the main file's switch
    switch = '<railroad><switch name="W2" id="101" position="dynamic"><mainTrack id="2" s="1" dir="+"/><sideTrack id="1" s="0" dir="+"/></switch></railroad>\n  </road>'
    branch = BRANCH.replace("  </road>", "    " + switch, 1)
    main = _network(tmp_path, branch=branch)
    [found] = _findings(main, "--select", "SW007")
    assert found["message"].endswith(f"at {main} line 18")
    assert found["related"] == [
        {
            "line": 18,
            "xpath": "/OpenDRIVE/road[@id='1']/railroad/switch[@id='101']",
            "path": str(main),
        }
    ]


def test_a_linked_map_reads_its_includes_from_the_link_s_folder(tmp_path: Path) -> None:
    real = _network(tmp_path / "real")
    (tmp_path / "elsewhere").mkdir()
    link = tmp_path / "elsewhere" / "main.xodr"
    link.symlink_to(real)
    [finding] = _findings(link, "--select", "XS007")
    assert finding["message"] == (
        "include 'parts/branch.xml' cannot be read: no such file or directory"
    )
    # a link out of the link's folder is not followed; a copy in it is
    (tmp_path / "elsewhere" / "parts").symlink_to(tmp_path / "real" / "parts")
    [finding] = _findings(link, "--select", "XS007")
    assert "lies outside" in finding["message"]
    (tmp_path / "elsewhere" / "parts").unlink()
    (tmp_path / "elsewhere" / "parts").mkdir()
    (tmp_path / "elsewhere" / "parts" / "branch.xml").write_text(BRANCH, "utf-8")
    found = _findings(link, "--select", "XS007,RL002")
    assert [f["path"] for f in found] == [
        str(link),
        str(tmp_path / "elsewhere" / "parts" / "branch.xml"),
    ]


@pytest.mark.parametrize(
    "broken",
    [b"<OpenDRIVE>\n<road", b"<OpenDRIVE>\r\r<road id='1'></OpenDRIVE>", b"\n\n<a></b>"],
)
def test_an_included_file_is_parsed_as_a_checked_file_is(tmp_path: Path, broken: bytes) -> None:
    # one parse for every file read: the include's reason gives the line and the words
    # XS001 gives when the same bytes are checked on their own (a CR-only file too)
    main = _network(tmp_path)
    (tmp_path / "parts" / "branch.xml").write_bytes(broken)
    [alone] = _findings(tmp_path / "parts" / "branch.xml", "--select", "XS001")
    [finding] = _findings(main, "--select", "XS007")
    expected = f"is not well-formed XML at line {alone['line']}: {alone['message']}"
    assert finding["message"] == f"include 'parts/branch.xml' {expected}"


def test_a_map_is_searched_for_include_once() -> None:
    # the byte search runs over the whole file: the linter and has_includes both ask
    from xodrlint.document.includes import has_includes
    from xodrlint.document.load import load_bytes

    searched: list[object] = []

    class Searched(bytes):
        def __contains__(self, part: object) -> bool:
            searched.append(part)
            return super().__contains__(part)  # type: ignore[operator]

    doc = load_bytes(b'<OpenDRIVE><header revMajor="1" revMinor="7"/></OpenDRIVE>', "a.xodr")
    doc.data = Searched(doc.data)
    assert not doc.may_include and not has_includes(doc) and not doc.may_include
    assert searched == [b"include"]
