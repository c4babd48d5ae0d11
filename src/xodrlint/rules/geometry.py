"""The rule API's geometry: where a road's tracks run, for rules that judge them.

Import it inside a rule, where it is needed, not at the top of a rule module: a map
without tracks, and a run that selects no geometry rule, then never load it (it is most
of a rail run's import time).

- :class:`TrackGeometry`, shared per file (``network.shared(TrackGeometry)``): each road's
  plan view judged once (:class:`PlanView`: its :class:`ReferenceLine` when every record
  can be evaluated, else each :class:`GeometryProblem`), and :class:`TrackPoint` values on
  it: a track's point at ``s``, a lane's centre at ``s`` or at a road end;
- :class:`LaneCurvature`, shared per file: each rail or tram lane's tightest bend
  (:class:`LaneBend`) on each plan-view :class:`Record`;
- :class:`VerticalProfiles`, shared per file: a track's elevation and superelevation as
  the cubics they are (each :class:`Entry`);
- :class:`Pose`: a point and a heading; :func:`turn_beyond`: the angle between two
  directions when it exceeds a limit; :func:`unreadable_numbers` and
  :func:`record_elements`: what a finding about a record names.

Every name in ``__all__`` is part of the rule API (:data:`xodrlint.rules.API_VERSION`
1.2 and later), recorded as the names of ``xodrlint.rules`` are.
"""

from xodrlint.geometry.curvature import LaneBend, LaneCurvature, record_elements
from xodrlint.geometry.curves import Pose, Record
from xodrlint.geometry.evaluable import PlanView
from xodrlint.geometry.planview import GeometryProblem, ReferenceLine, unreadable_numbers
from xodrlint.geometry.profiles import Entry, VerticalProfiles
from xodrlint.geometry.tracks import TrackGeometry, TrackPoint, turn_beyond

__all__ = [
    "Entry",
    "GeometryProblem",
    "LaneBend",
    "LaneCurvature",
    "PlanView",
    "Pose",
    "Record",
    "ReferenceLine",
    "TrackGeometry",
    "TrackPoint",
    "VerticalProfiles",
    "record_elements",
    "turn_beyond",
    "unreadable_numbers",
]
