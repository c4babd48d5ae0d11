"""The unsafe geometry fixes checked against the track-geometry code itself: after
SW011's fix the switch's two track points meet within ``switch-tolerance``; after
SW012's the directions of travel on its two tracks agree within ``switch-angle``;
after TR005's the named end is the one whose track point meets this road's end."""

from __future__ import annotations

import math
from pathlib import Path

from tests.conftest import REPO
from xodrlint.api import default_registry
from xodrlint.document.load import load_bytes
from xodrlint.engine.fixing import DIFF, FixPolicy
from xodrlint.engine.linter import Linter, LintOptions
from xodrlint.geometry.tracks import TrackGeometry, TrackPoint, angle_between
from xodrlint.model import RailNetwork, Switch, build_network

CASES = REPO / "rules"


def _fixed(code: str, case: str) -> tuple[bytes, RailNetwork]:
    options = LintOptions(select=(code,), fixes=FixPolicy(mode=DIFF, unsafe=True), place_fixes=True)
    source = CASES / code / case
    fixed, report = Linter(default_registry(), options).fixed_source(source.read_bytes(), case)
    assert report.fixed >= 1 and report.internal_errors == ()
    doc = load_bytes(fixed, case)
    return fixed, build_network(doc.root)


def _points(network: RailNetwork, switch: Switch) -> tuple[TrackPoint | None, TrackPoint | None]:
    tracks = TrackGeometry(network)
    main, side = switch.main_track, switch.side_track
    assert main is not None and side is not None and main.s is not None and side.s is not None
    main_road = network.road_by_id[main.road_id or ""]
    side_road = network.road_by_id[side.road_id or ""]
    return tracks.point(main_road, main.s), tracks.point(side_road, side.s)


def test_after_sw011s_fix_the_track_points_meet() -> None:
    _, network = _fixed("SW011", "invalid_side_track_ends_short.xodr")
    for switch in network.switches:
        main, side = _points(network, switch)
        assert main is not None and side is not None
        assert main.distance_to(side) <= 0.1


def test_after_sw012s_fix_the_directions_agree() -> None:
    _, network = _fixed("SW012", "invalid_main_track_dir_reversed.xodr")
    for switch in network.switches:
        main, side = _points(network, switch)
        assert main is not None and side is not None
        assert switch.main_track is not None and switch.side_track is not None
        entering = main.direction(switch.main_track.dir or "+")
        leaving = side.direction(switch.side_track.dir or "+")
        assert angle_between(entering, leaving) <= math.radians(15)


def test_after_tr005s_fix_the_named_end_meets_this_one() -> None:
    _, network = _fixed("TR005", "invalid_no_contact_point.xodr")
    tracks = TrackGeometry(network)
    for road in network.roads:
        for link in road.links:
            if link.element_type != "road" or road.length is None:
                continue
            target = network.road_by_id[link.element_id or ""]
            assert target.length is not None and link.contact_point in ("start", "end")
            here = tracks.point(road, 0.0 if link.kind == "predecessor" else road.length)
            there = tracks.point(target, 0.0 if link.contact_point == "start" else target.length)
            assert here is not None and there is not None
            assert here.distance_to(there) <= 0.1


def test_sw011s_fix_looks_along_the_plan_view_not_the_written_length(tmp_path: Path) -> None:
    # a road that says it is 1e9 m long over a 100 m plan view: the search samples the
    # plan view (a few hundred points), where a search along the written length took
    # gigabytes; run under a 1 GB address-space limit, in a process of its own
    import subprocess
    import sys

    source = (CASES / "SW011" / "invalid_side_track_ends_short.xodr").read_text("utf-8")
    assert '<road name="main" length="100"' in source
    target = tmp_path / "long.xodr"
    target.write_text(
        source.replace('<road name="main" length="100"', '<road name="main" length="1e9"')
    )
    script = (
        "import resource, sys\n"
        "resource.setrlimit(resource.RLIMIT_AS, (1 << 30, 1 << 30))\n"
        "from xodrlint.api import lint_file\n"
        "report = lint_file(sys.argv[1], select=['SW011'])\n"
        "print(len(report.findings), report.internal_errors)\n"
    )
    done = subprocess.run(
        [sys.executable, "-c", script, str(target)], capture_output=True, text=True, check=False
    )
    assert done.returncode == 0, done.stderr
    assert done.stdout.strip() == "1 ()"
