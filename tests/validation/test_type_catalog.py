"""What a schema's named simple types allow, read down their chain of restrictions."""

from __future__ import annotations

from lxml import etree

from xodrlint.validation.messages import TypeCatalog

SCHEMA = b"""<xs:schema xmlns:xs="http://www.w3.org/2001/XMLSchema">
  <xs:simpleType name="t_grEqZero">
    <xs:restriction base="xs:double"><xs:minInclusive value="0"/></xs:restriction>
  </xs:simpleType>
  <xs:simpleType name="t_zeroOne">
    <xs:restriction base="t_grEqZero"><xs:maxInclusive value="1"/></xs:restriction>
  </xs:simpleType>
  <xs:simpleType name="t_either">
    <xs:union memberTypes="t_zeroOne xs:string"/>
  </xs:simpleType>
  <xs:simpleType name="t_onEither">
    <xs:restriction base="t_either"/>
  </xs:simpleType>
  <xs:simpleType name="t_loop">
    <xs:restriction base="t_loop"><xs:maxExclusive value="3"/></xs:restriction>
  </xs:simpleType>
</xs:schema>"""

CATALOG = TypeCatalog.from_documents([etree.fromstring(SCHEMA)])


def test_bounds_gather_down_the_chain() -> None:
    assert CATALOG.bounds("t_grEqZero") == {"min"}
    assert CATALOG.bounds("t_zeroOne") == {"min", "max"}
    assert CATALOG.bounds("xs:double") == frozenset()
    assert CATALOG.bounds("t_loop") == {"max"}  # a loop ends


def test_the_builtin_a_type_restricts() -> None:
    assert CATALOG.builtin_of("t_zeroOne") == "double"
    assert CATALOG.builtin_of("xs:double") == "double"
    assert CATALOG.builtin_of("double") == "double"
    assert CATALOG.builtin_of("t_onEither") is None  # a union has none
    assert CATALOG.builtin_of("t_loop") is None
    assert CATALOG.builtin_of("t_unknown") is None
