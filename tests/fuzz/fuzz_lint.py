"""Coverage-guided fuzzing of the whole lint of one document, with atheris (libFuzzer).

Not a pytest module (its name does not start with ``test_``): a run lasts minutes to
hours. Every input goes through :func:`xodrlint.lint_bytes` with all rules; an exception
escaping it or a malformed finding is a crash that libFuzzer saves for a regression test.
How to run it is in the README, "Fuzzing".
"""

from __future__ import annotations

import sys

import atheris  # type: ignore[import-not-found, import-untyped, unused-ignore]

# Rules, schema checks and formatters load lazily: the warm-up lint imports them inside
# the block, so that they are instrumented too.
with atheris.instrument_imports(include=["xodrlint"]):
    from xodrlint.api import lint_bytes

    for minor, typed in ((b"7", b""), (b"9", b' xsi:type="t_road"')):
        # 1.9 too, with an xsi:type: the XSD 1.1 routes (the fast one and xmlschema's)
        # load lazily as well (with a schema path set, their modules are imported here)
        lint_bytes(
            b'<OpenDRIVE xmlns:xsi="http://www.w3.org/2001/XMLSchema-instance">'
            b'<header revMajor="1" revMinor="' + minor + b'"/><road id="1"' + typed + b">"
            b'<railroad><switch id="1"/></railroad></road></OpenDRIVE>'
        )

from tests.wellformed import assert_well_formed


def lint_one(data: bytes) -> None:
    assert_well_formed(lint_bytes(data, "fuzz.xodr"))


def main() -> None:
    atheris.Setup(sys.argv, lint_one)
    atheris.Fuzz()


if __name__ == "__main__":
    main()
