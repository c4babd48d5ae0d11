"""Stage 2 for OpenDRIVE 1.8 and later: schema sets written in XSD 1.1.

libxml2 reads only XSD 1.0, and full XSD 1.1 validation in Python (xmlschema) takes
about 25 s on a 20 MB map. So a 1.1 set is validated the fast way, and its findings
equal those of full validation in element, line, XPath and kind (a test proves it on the
corpus and on mutated files):

- :mod:`~xodrlint.validation.xsd11.form`: the set's XSD 1.0 form (``xs:assert`` and
  ``xs:alternative`` removed, ``vc:`` attributes resolved), derived once and cached;
- :mod:`~xodrlint.validation.xsd11.fast`: chooses the validator for a set and runs the
  fast path: libxml2 on the form, then the 1.1-only checks;
- :mod:`~xodrlint.validation.xsd11.governing`: the type XSD 1.1 validates each element
  by, and which elements the 1.1-only checks visit;
- :mod:`~xodrlint.validation.xsd11.alternatives`: type alternatives handed to libxml2
  as ``xsi:type`` marks;
- :mod:`~xodrlint.validation.xsd11.translation` and
  :mod:`~xodrlint.validation.xsd11.selectors`: ``xs:assert`` and the type alternatives'
  tests translated into XPath 1.0 once per set, run by libxml2;
- :mod:`~xodrlint.validation.xsd11.assertions`: ``xs:assert`` evaluated by xmlschema on
  just the elements whose type carries one, for what does not translate;
- :mod:`~xodrlint.validation.xsd11.wording`: a failed assertion in words;
- :mod:`~xodrlint.validation.xsd11.recovery`: the subtrees libxml2 stops looking at,
  validated again as XSD 1.1 does;
- :mod:`~xodrlint.validation.xsd11.full`: full validation with xmlschema, the reference
  and the fallback.
"""


class NeedsFull(Exception):
    """This document (or schema set) meets something the fast path cannot reproduce:
    validate it in full."""
