"""Properties of ``--fix`` on generated documents with defects (hypothesis): the fixed
document is the source with the reported edits made and no other byte changed, it is
well-formed, the fixed findings are gone, no finding is added, and fixing it again
changes nothing. The defects: a partner named unlike its switch (PT003), enumerated
values in another case or with blanks (XS006), idle suppression entries (XL001); the
documents vary in line ends, quotes, encodings and what the values hold."""

from __future__ import annotations

from collections import Counter

from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st
from lxml import etree

from tests.conftest import REPO
from xodrlint.api import default_registry
from xodrlint.document.edits import Edit, EditableSource
from xodrlint.document.load import parse_root
from xodrlint.engine.fixing import DIFF, FixPolicy
from xodrlint.engine.linter import Linter, LintOptions
from xodrlint.findings import FileReport
from xodrlint.fixes import Applicability

TEMPLATE = (REPO / "rules" / "PT003" / "invalid_name_mismatch.xodr").read_text("utf-8")
SELECT = ("PT003", "XS006", "XL001")
LINTER = Linter(
    default_registry(),
    LintOptions(select=SELECT, fixes=FixPolicy(mode=DIFF), place_fixes=True),
)

#: Names as maps hold them: letters and digits, and what must be escaped or referenced.
names = st.text(
    st.sampled_from([*"AWZaz019 -_&<>\"'é€", "\U0001f682"]), min_size=1, max_size=8
).filter(lambda name: name.strip() == name and name != "W12")
positions = st.sampled_from(["dynamic", "Dynamic", " DYNAMIC", "dynamic ", "straight", "Turn"])
suppressions = st.sampled_from(
    ["", "<!-- xodrlint: ignore[XS006] -->", "<!-- xodrlint: ignore[PT003, XS006] why -->"]
)


def _attribute(name: str, value: str, quote: str) -> str:
    escaped = value.replace("&", "&amp;").replace("<", "&lt;").replace(">", "&gt;")
    escaped = escaped.replace(quote, "&quot;" if quote == '"' else "&apos;")
    return f"{name}={quote}{escaped}{quote}"


@st.composite
def documents(draw: st.DrawFn) -> bytes:
    quote = draw(st.sampled_from(['"', "'"]))
    partner = _attribute("name", draw(names), quote)
    text = TEMPLATE.replace('<partner name="W23" id="32"/>', f'<partner {partner} id="32"/>')
    position = _attribute("position", draw(positions), quote)
    text = text.replace(
        '<switch name="W32" id="32" position="dynamic">',
        f'<switch name="W32" id="32"\n               {position}>',
    )
    comment = draw(suppressions)
    if comment:
        text = text.replace(
            '      <switch name="W12"', f'      {comment}\n      <switch name="W12"'
        )
    if draw(st.booleans()):
        text = text.replace("\n", "\r\n")
    if draw(st.booleans()):
        return ("\ufeff" + text.replace('encoding="UTF-8"', 'encoding="UTF-16"')).encode(
            "utf-16-le"
        )
    return text.encode("utf-8")


def _lint(data: bytes) -> FileReport:
    return LINTER.lint_bytes(data, "g.xodr")


def _keys(report: FileReport) -> Counter[tuple[str, str]]:
    return Counter((finding.code, finding.xpath) for finding in report.findings)


@settings(max_examples=60, deadline=None, suppress_health_check=[HealthCheck.too_slow])
@given(documents())
def test_fix_changes_only_the_reported_edits_and_leaves_nothing_to_fix(data: bytes) -> None:
    before = LINTER._lint_once(data, "g.xodr", (), None)[0]  # one lint, fixes placed
    fixed, after = LINTER.fixed_source(data, "g.xodr")
    safe = [f for f in before.findings if f.fix and f.fix.applicability is Applicability.SAFE]
    # the fixed document is the source with the reported edits made, and nothing else
    # (the defects here do not overlap: one pass makes them all)
    root = parse_root(data)
    assert isinstance(root, etree._Element)
    source = EditableSource(data, root)
    edits = [Edit(e.start, e.end, e.content) for f in safe for e in f.fix.edits]  # type: ignore[union-attr]
    assert fixed == source.apply(edits)
    assert isinstance(parse_root(fixed), etree._Element)  # well-formed
    assert after.internal_errors == ()
    assert after.fixed == len(safe)
    # the fixed findings are gone, and no finding came
    left = _keys(after)
    assert not left - _keys(before)
    assert all(left[(f.code, f.xpath)] == 0 for f in safe)
    assert not any(f.fix for f in after.findings)
    # a second run changes nothing
    assert LINTER.fixed_source(fixed, "g.xodr")[0] == fixed
