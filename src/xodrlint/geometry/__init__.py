"""Plan-view geometry: where a road's reference line runs, for the track-geometry rules
(:mod:`~xodrlint.geometry.tracks`: track points and directions of travel at switches and
joints) and for drawing (:mod:`~xodrlint.geometry.sampling`, loaded only by the map).
Pure computation over the parsed tree; a road's plan view is read only when asked for."""

from __future__ import annotations

from typing import TYPE_CHECKING, Any

from xodrlint.geometry.curves import Arc, Line, ParamPoly3, Poly3, Pose, Record, Spiral
from xodrlint.geometry.planview import GeometryProblem, ReferenceLine, read_record, reference_line

if TYPE_CHECKING:
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


def __getattr__(name: str) -> Any:
    if name in ("adaptive", "polylines"):  # sampling is the map's: a lint run never loads it
        from xodrlint.geometry import sampling

        return getattr(sampling, name)
    raise AttributeError(f"module {__name__!r} has no attribute {name!r}")
