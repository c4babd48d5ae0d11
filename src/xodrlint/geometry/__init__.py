"""Plan-view geometry: where a road's reference line runs, for drawing and for placing
things along it (switches, platforms, findings). Pure computation over the parsed tree;
nothing in the lint pipeline imports it, so ``check`` never pays for it."""

from __future__ import annotations

from xodrlint.geometry.curves import Arc, Line, ParamPoly3, Poly3, Pose, Record, Spiral
from xodrlint.geometry.planview import GeometryProblem, ReferenceLine, read_record, reference_line
from xodrlint.geometry.sampling import adaptive, polylines

__all__ = [
    "Arc",
    "GeometryProblem",
    "Line",
    "ParamPoly3",
    "Poly3",
    "Pose",
    "Record",
    "ReferenceLine",
    "Spiral",
    "adaptive",
    "polylines",
    "read_record",
    "reference_line",
]
