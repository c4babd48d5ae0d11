"""Linting time grows linearly with the network: a quadratic rule shows up as a ratio.

Absolute times say nothing on a shared machine; the ratio of two sizes measured side by
side does. Four times the network must take clearly less than sixteen times as long
(quadratic); linear work gives about four. Benchmarks, not this test, measure speed.
"""

from __future__ import annotations

import time

from tests.networks import network
from xodrlint.api import default_registry
from xodrlint.engine.linter import Linter, LintOptions

SMALL_UNITS = 100
FACTOR = 4
LINTER = Linter(default_registry(), LintOptions())


def _best_time(data: bytes, repeats: int = 3) -> float:
    best = float("inf")
    for _ in range(repeats):
        started = time.perf_counter()
        report = LINTER.lint_bytes(data, "synthetic.xodr")
        best = min(best, time.perf_counter() - started)
        assert report.findings == (), [f.message for f in report.findings][:3]
    return best


def test_synthetic_networks_are_clean_and_lint_in_linear_time() -> None:
    small = network(SMALL_UNITS)
    large = network(SMALL_UNITS * FACTOR)
    _best_time(small, repeats=1)  # warm up: schema compilation, imports
    ratio = _best_time(large) / _best_time(small)
    # linear: ~4; quadratic: ~16. 8 leaves room for noise and cache effects.
    assert ratio < 2 * FACTOR, f"4x the network took {ratio:.1f}x as long"
