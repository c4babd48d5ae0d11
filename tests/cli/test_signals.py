"""SIGTERM (a cancelled CI job, a stopped container) ends a run as Ctrl-C does: workers
stopped, no half-written report left, exit 143."""

from __future__ import annotations

import shutil
import signal
import subprocess
import sys
import time
from pathlib import Path

import pytest

from tests.conftest import REPO

BROKEN = REPO / "examples" / "broken.xodr"


def _group_members(group: int) -> list[int]:
    members = []
    for entry in Path("/proc").iterdir():
        if not entry.name.isdigit():
            continue
        try:
            fields = (entry / "stat").read_text().rsplit(")", 1)[1].split()
        except OSError:
            continue
        if int(fields[2]) == group and fields[0] != "Z":
            members.append(int(entry.name))
    return members


@pytest.mark.skipif(not Path("/proc").is_dir(), reason="needs /proc to see the workers")
@pytest.mark.parametrize(("sent", "code"), [(signal.SIGTERM, 143), (signal.SIGINT, 130)])
def test_a_signalled_batch_stops_its_workers_and_leaves_no_report(
    tmp_path: Path, sent: signal.Signals, code: int
) -> None:
    maps = tmp_path / "maps"
    maps.mkdir()
    for number in range(3000):
        shutil.copyfile(BROKEN, maps / f"m{number:04}.xodr")
    report = tmp_path / "report.json"
    run = subprocess.Popen(
        [sys.executable, "-m", "xodrlint", "check", "-j", "2", "-f", "json", "-o", report, maps],
        stdout=subprocess.DEVNULL,
        stderr=subprocess.PIPE,
        text=True,
        start_new_session=True,  # its own process group: its workers are found by it
    )
    deadline = time.monotonic() + 60
    while len(_group_members(run.pid)) < 3 and run.poll() is None:  # the two workers run
        assert time.monotonic() < deadline, "the workers never started"
        time.sleep(0.02)
    run.send_signal(sent)
    _, err = run.communicate(timeout=60)
    assert run.returncode == code, err
    assert "Traceback" not in err
    time.sleep(0.2)  # a killed worker is reaped by init, not at once
    assert _group_members(run.pid) == []
    assert not report.exists()
    assert [p.name for p in tmp_path.iterdir() if p.name.startswith(".report")] == []
