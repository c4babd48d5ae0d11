"""The rule API is a promise to pack authors: every name in ``xodrlint.rules.__all__``, and
every field, property and method of the types it exports, stays while ``API_VERSION``'s
major number does.

The surface below is the record of rule API 1.3 (1.1 added ``rule(..., since=)``, the
model's junctions and lane links, and ``Road.profiles``; 1.2 the lane profiles,
``section_ranges``, ``CHILD_KINDS`` and :mod:`xodrlint.rules.geometry`, so that the
built-in packs use the rule API alone; 1.3 fixes: ``Hit.fix``, ``Fix``,
``Applicability`` and the edit helpers; unreleased, so still growing). Removing or renaming anything in it
breaks packs: raise the major number (and say so in the changelog). Adding something is
compatible: record it here and raise the minor number, so that a pack using it can
declare the version it needs.
"""

from __future__ import annotations

import dataclasses
import enum
import importlib
import inspect
import subprocess
import sys

import pytest

import xodrlint.rules
from xodrlint.rules import API_VERSION

RECORDED_VERSION = (1, 3)
#: Each name with what a pack may use of it: a type's attributes, a function's
#: parameters, ``None`` for a constant or an alias.
RECORDED: dict[str, list[str] | None] = {
    "API_VERSION": None,
    "Applicability": ["SAFE", "UNSAFE"],
    "CHILD_KINDS": None,
    "NON_TRAFFIC_LANE_TYPES": None,
    "RAIL_LANE_TYPES": None,
    "RESERVED_PREFIXES": None,
    "S_TOLERANCE": None,
    "Connection": [
        "connecting_road", "contact_point", "element", "id", "incoming_road", "lane_links",
    ],
    "Cubic": ["a", "at", "b", "c", "d", "element", "start"],
    "Extremes": ["high", "low", "s_high", "s_low"],
    "Fix": ["applicability", "edits", "message"],
    "Hit": ["column", "defers_to", "element", "fix", "kind", "line", "message", "related"],
    "Junction": ["connections", "element", "id"],
    "JunctionLaneLink": ["element", "from_id", "to_id"],
    "Lane": [
        "element", "id", "is_rail", "predecessors", "side", "successors", "type", "widths",
        "widths_complete",
    ],
    "LaneLink": ["element", "id"],
    "LaneSection": ["element", "lanes", "rail_lanes", "s"],
    "PartnerRef": ["element", "id", "name"],
    "Piecewise": ["defined_from", "piece_at", "pieces", "starts", "zero_before"],
    "Platform": ["element", "id", "name", "segments"],
    "RailNetwork": [
        "derived", "junction_by_id", "junctions", "platforms", "problems", "rail_roads",
        "road_by_id", "roads", "segments", "shared", "stations", "switch_by_id", "switches",
        "switches_by_main_track", "switches_by_side_track",
    ],
    "Road": [
        "element", "has_rail_lane", "id", "lane_offsets", "lane_offsets_complete",
        "lane_sections", "lane_template", "lane_types", "lanes", "length", "links",
        "profiles", "section_ranges",
    ],
    "RoadLanes": ["offsets", "offsets_complete", "sections"],
    "RoadLink": ["contact_point", "element", "element_id", "element_type", "kind"],
    "Rule": ["check", "code", "meta"],
    "RuleOption": [
        "as_dict", "checked", "default", "description", "is_number", "kind", "minimum", "name",
        "number", "parsed", "text", "unit",
    ],
    "Segment": ["element", "road_id", "s_end", "s_start", "side"],
    "Settings": None,
    "Severity": ["ERROR", "INFO", "WARNING", "rank"],
    "Station": ["element", "id", "name", "platforms", "type"],
    "Switch": ["element", "id", "main_track", "name", "partner", "position", "road", "side_track"],
    "TrackRef": ["dir", "element", "road_id", "s"],
    "centre_terms": ["road", "section", "section_start", "lane"],
    "collect": ["package"],
    "extremes": ["terms", "start", "end"],
    "insert_element": ["anchor", "tag", "attributes", "where", "children"],
    "integer": ["element", "attribute"],
    "lane_width": ["lane", "section_start"],
    "non_finite": ["element", "attribute"],
    "number": ["element", "attribute"],
    "numbers": ["element", "attributes"],
    "remove_comment": ["comment"],
    "replace_comment": ["comment", "text"],
    "rule": [
        "code", "name", "uid", "severity", "aliases", "options", "defers_to", "opt_in", "since",
    ],
    "section_ranges": ["sections", "length"],
    "set_attribute": ["element", "name", "value"],
}  # fmt: skip
#: The same record for :mod:`xodrlint.rules.geometry` (rule API 1.2).
RECORDED_GEOMETRY: dict[str, list[str] | None] = {
    "Entry": ["cubic", "element", "readable", "s"],
    "GeometryProblem": ["element", "message", "road_id"],
    "LaneBend": ["bend", "lane", "record", "section_start"],
    "LaneCurvature": ["bends", "tracks_bending"],
    "PlanView": ["ends", "line", "problems"],
    "Pose": ["hdg", "offset", "x", "y"],
    "Record": ["end", "hdg", "length", "local", "max_curvature", "pose_at", "s", "x", "y"],
    "ReferenceLine": [
        "elements", "guessed", "pose", "problems", "record_at", "records", "s_range", "starts",
    ],
    "TrackGeometry": [
        "lane_end_point", "lane_point", "nearest", "plan_view", "plan_views", "point",
        "reference_line",
    ],
    "TrackPoint": ["direction", "distance_to", "heading", "x", "y"],
    "VerticalProfiles": ["elevation", "elevation_at", "superelevation", "tracks"],
    "record_elements": ["road", "line"],
    "turn_beyond": ["first", "second", "limit_degrees"],
    "unreadable_numbers": ["element", "names"],
}  # fmt: skip
#: Each module of the rule API with its record.
MODULES: dict[str, dict[str, list[str] | None]] = {
    "xodrlint.rules": RECORDED,
    "xodrlint.rules.geometry": RECORDED_GEOMETRY,
}


def _surface(value: object) -> list[str] | None:
    """What a pack may use of ``value``: the public attributes a type defines (not those
    of ``tuple``, ``str`` or ``object``), a function's parameters in order."""
    if isinstance(value, type):
        names = {
            name
            for klass in value.__mro__
            if klass.__module__.startswith("xodrlint.")
            for name in vars(klass)
        }
        if dataclasses.is_dataclass(value):
            names |= {field.name for field in dataclasses.fields(value)}
        if issubclass(value, enum.Enum):
            names |= {member.name for member in value}
        return sorted(name for name in names if not name.startswith("_"))
    if inspect.isfunction(value):
        return list(inspect.signature(value).parameters)
    return None


def test_the_recorded_version_is_the_current_one() -> None:
    assert API_VERSION == RECORDED_VERSION, (
        "API_VERSION changed: record the surface of the new version in this test"
    )


@pytest.mark.parametrize(
    ("module", "name"),
    [(module, name) for module, record in MODULES.items() for name in sorted(record)],
)
def test_no_recorded_name_is_removed_or_renamed(module: str, name: str) -> None:
    api = importlib.import_module(module)
    assert name in api.__all__, (
        f"{module}.{name} is part of rule API {RECORDED_VERSION}: removing or renaming "
        "it breaks packs (raise API_VERSION's major number if that is meant)"
    )
    current = _surface(getattr(api, name))
    recorded = MODULES[module][name]
    if recorded is not None:
        assert current is not None
        missing = [attribute for attribute in recorded if attribute not in current]
        assert not missing, (
            f"{name} lost {missing}, part of rule API {RECORDED_VERSION}: that breaks packs "
            "(raise API_VERSION's major number if that is meant)"
        )
        if inspect.isfunction(getattr(api, name)):
            assert current[: len(recorded)] == recorded, f"{name}'s parameters moved"


@pytest.mark.parametrize("module", sorted(MODULES))
def test_every_name_of_the_rule_api_is_recorded(module: str) -> None:
    api = importlib.import_module(module)
    record = MODULES[module]
    current = {name: _surface(getattr(api, name)) for name in api.__all__}
    added = {
        name: value
        for name, value in current.items()
        if name not in record or value != record[name]
    }
    assert not added, (
        f"{module} grew: {added}; record it here and raise API_VERSION's minor number, "
        "so that packs using it can say they need it"
    )


def test_the_geometry_is_loaded_only_when_a_rule_asks() -> None:
    # the rule API's geometry is most of a rail run's import time: importing the rule
    # API (as every pack does) must not load it
    code = "import sys, xodrlint.rules; print('xodrlint.geometry' in sys.modules)"
    out = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, check=True)
    assert out.stdout == "False\n"


def test_every_name_is_importable_from_one_place() -> None:
    namespace: dict[str, object] = {}
    exec("from xodrlint.rules import *", namespace)
    assert set(xodrlint.rules.__all__) <= set(namespace)


def test_the_model_types_are_the_model_s_own() -> None:
    import xodrlint.model

    for name in xodrlint.rules.__all__:
        if name in xodrlint.model.__all__:
            assert getattr(xodrlint.rules, name) is getattr(xodrlint.model, name)
