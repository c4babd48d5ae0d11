"""Regenerate the map screenshots in docs/images/ with headless Chromium.

    python docs/screenshots.py [--corpus ../shared/corpus/rail]

Each map is drawn by the installed ``xodrlint map`` and photographed by Debian's Chromium
(``apt-get install chromium``) with ``--screenshot``; the page's ``#finding=N`` address
selects and centres a finding first. ASAM's examples come from the shared corpus, which
is not part of this repository: only our rendering of them is committed.
"""

from __future__ import annotations

import argparse
import shutil
import subprocess
import sys
import tempfile
from pathlib import Path
from typing import Final

REPO: Final = Path(__file__).resolve().parents[1]
IMAGES: Final = REPO / "docs" / "images"
CHROMIUM: Final = "/usr/bin/chromium"
#: Headless, and nothing that reaches for the network (it may be closed): the browser test
#: (tests/mapview/test_map_browser.py) starts Chromium with these too.
HEADLESS_FLAGS: Final = (
    "--headless",
    "--no-sandbox",
    "--disable-gpu",
    "--disable-quic",
    "--no-first-run",
    "--disable-background-networking",
    "--disable-component-update",
    "--disable-sync",
)
SCREENSHOT_FLAGS: Final = (
    "--hide-scrollbars",
    "--window-size=1400,800",
    # lets the page's animation frame (the selection's repaint) run before the shot
    "--virtual-time-budget=3000",
)


def shots(corpus: Path) -> list[tuple[Path, str, str]]:
    """(source, image name, page address suffix) for each screenshot."""
    return [
        (corpus / "ASAM-1.7.0_Ex_Railway-Switch.xodr", "map-asam-switch.png", ""),
        (corpus / "ASAM-1.7.0_Ex_Railway-Station.xodr", "map-asam-station.png", ""),
        (REPO / "examples" / "broken.xodr", "map-broken.png", "#finding=2"),
    ]


def xodrlint() -> str:
    beside = Path(sys.executable).parent / "xodrlint"
    return str(beside) if beside.exists() else shutil.which("xodrlint") or "xodrlint"


def take(source: Path, image: Path, suffix: str, work: Path) -> None:
    page = work / (source.stem + ".html")
    # from the map's own folder, so that the page is titled with the file's name only
    drawn = subprocess.run(
        [xodrlint(), "map", source.name, "-o", str(page)],
        check=False,  # exit 1 means findings: the map is written all the same
        capture_output=True,
        text=True,
        cwd=source.parent,
    )
    if drawn.returncode not in (0, 1) or not page.exists():
        raise SystemExit(f"{source}: xodrlint map failed: {drawn.stderr.strip()}")
    profile = work / "chromium-profile"
    command = [
        CHROMIUM,
        *HEADLESS_FLAGS,
        *SCREENSHOT_FLAGS,
        f"--user-data-dir={profile}",
        f"--screenshot={image}",
    ]
    subprocess.run([*command, page.as_uri() + suffix], capture_output=True, check=True)
    print(f"{image.relative_to(REPO)} from {source.name}")


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--corpus", type=Path, default=REPO.parent / "shared" / "corpus" / "rail")
    args = parser.parse_args()
    IMAGES.mkdir(parents=True, exist_ok=True)
    with tempfile.TemporaryDirectory() as folder:
        for source, name, suffix in shots(args.corpus):
            if not source.exists():
                print(f"skipped {name}: {source} is absent", file=sys.stderr)
                continue
            take(source, IMAGES / name, suffix, Path(folder))


if __name__ == "__main__":
    main()
