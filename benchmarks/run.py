"""xodrlint against ``xmllint --noout --schema``, side by side, alternating and repeated.

    python benchmarks/run.py --schemas ../shared/schemas [--repeat 5] [--workdir DIR]

Generates the networks (benchmarks/generate.py), then runs every command of a round in
turn, ``--repeat`` rounds, so that a noisy machine slows both sides alike, and prints
the median wall time and peak RSS of each command and the ratios of issue 5, each the
median of its per-round ratios (a round runs both commands back to back):

- R1: xodrlint (all rules, JSON output) on a 20 MB OpenDRIVE 1.7 network / xmllint on it
- R2: xodrlint on the same network declared 1.8 (XSD 1.1) / xmllint on the 1.7 file
- R3: xodrlint on a 0.2 MB file / ``python -c "import typer, rich.console, lxml.etree"``
- M:  xodrlint's peak RSS on the 20 MB 1.7 file / xmllint's
- S:  xodrlint on 40 MB / on 20 MB
- B:  200 small files with ``-j 1`` / with ``-j 2`` (a speed-up)
- G:  xodrlint on the 20 MB 1.7 network / the same without the track-geometry rules
      (SW011, SW012, TR001, TR002; issue 15: they may add less than 5% to the run)

pip compiles bytecode when it installs a package; an editable install in an environment
with PYTHONDONTWRITEBYTECODE does not, so the script compiles xodrlint's first.
"""

from __future__ import annotations

import argparse
import compileall
import os
import shutil
import statistics
import subprocess
import sys
import time
from collections.abc import Sequence
from dataclasses import dataclass, field
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parent))
from generate import GENERATOR_VERSION, write_network

MB = 1024 * 1024
TARGETS = {"R1": 1.5, "R2": 2.0, "R3": 1.5, "M": 1.5, "S": 2.2, "B": 1.6, "G": 1.05}
#: The rules that evaluate plan-view geometry, left out for the G figure's baseline.
GEOMETRY_RULES = "SW011,SW012,TR001,TR002"


@dataclass
class Command:
    name: str
    argv: list[str]
    env: dict[str, str] = field(default_factory=dict)
    seconds: list[float] = field(default_factory=list)
    peak_kb: list[int] = field(default_factory=list)

    def run(self) -> None:
        env = {**os.environ, **self.env}
        started = time.perf_counter()
        process = subprocess.Popen(
            self.argv, env=env, stdout=subprocess.DEVNULL, stderr=subprocess.PIPE
        )
        _, status, usage = os.wait4(process.pid, 0)
        elapsed = time.perf_counter() - started
        process.returncode = os.waitstatus_to_exitcode(status)
        error = process.stderr.read().decode() if process.stderr else ""
        if process.returncode not in (0,):
            raise SystemExit(f"{self.name} failed ({process.returncode}): {error[-400:]}")
        self.seconds.append(elapsed)
        self.peak_kb.append(usage.ru_maxrss)

    @property
    def median(self) -> float:
        return statistics.median(self.seconds)

    @property
    def median_kb(self) -> float:
        return statistics.median(self.peak_kb)


def _entry(schemas: Path, version: str) -> Path:
    from xodrlint.validation.sets import SchemaFinder

    major, minor = (int(part) for part in version.split("."))
    found = SchemaFinder(option=schemas).find(major, minor)
    if found is None or found.is_builtin:
        raise SystemExit(f"no official OpenDRIVE {version} schema under {schemas}")
    return found.entry


def prepare(workdir: Path, size_mb: float) -> dict[str, Path]:
    workdir = workdir / f"generator-{GENERATOR_VERSION}"  # never an older generator's files
    workdir.mkdir(parents=True, exist_ok=True)
    files = {
        "n17": workdir / f"network-{size_mb:g}mb-1.7.xodr",
        "n18": workdir / f"network-{size_mb:g}mb-1.8.xodr",
        "n17x2": workdir / f"network-{2 * size_mb:g}mb-1.7.xodr",
        "small": workdir / "network-0.2mb-1.7.xodr",
    }
    sizes = {"n17": size_mb, "n18": size_mb, "n17x2": 2 * size_mb, "small": 0.2}
    for key, path in files.items():
        if not path.exists():
            write_network(path, int(sizes[key] * MB), minor=8 if key == "n18" else 7)
    batch = workdir / "batch-200"
    if not batch.exists():
        batch.mkdir()
        for number in range(200):
            write_network(batch / f"map-{number:03}.xodr", 20 * 1024 + (number % 7) * 1024)
    files["batch"] = batch
    return files


def commands(files: dict[str, Path], schemas: Path) -> list[Command]:
    xodrlint = shutil.which("xodrlint", path=str(Path(sys.executable).parent)) or "xodrlint"
    xmllint = shutil.which("xmllint")
    if xmllint is None:
        raise SystemExit("xmllint is not installed (Debian: apt-get install libxml2-utils)")
    env = {"XODRLINT_SCHEMA_PATH": str(schemas)}
    check = [xodrlint, "check", "--exit-zero", "-f", "json", "-o", os.devnull]
    return [
        Command(
            "xmllint 1.7",
            [xmllint, "--noout", "--schema", str(_entry(schemas, "1.7")), str(files["n17"])],
        ),
        Command("xodrlint 1.7", [*check, str(files["n17"])], env),
        Command("1.7 no geometry", [*check, "--ignore", GEOMETRY_RULES, str(files["n17"])], env),
        Command("xodrlint 1.8", [*check, str(files["n18"])], env),
        Command("xodrlint 1.7 x2", [*check, str(files["n17x2"])], env),
        Command("python imports", [sys.executable, "-c", "import typer, rich.console, lxml.etree"]),
        Command("xodrlint 0.2 MB", [*check, str(files["small"])], env),
        Command("batch -j 1", [*check, "-j", "1", str(files["batch"])], env),
        Command("batch -j 2", [*check, "-j", "2", str(files["batch"])], env),
    ]


def report(runs: Sequence[Command]) -> dict[str, float]:
    by = {c.name: c for c in runs}

    def ratio(top: str, bottom: str, kind: str = "seconds") -> float:
        # per round, then the median: the two commands of a round ran back to back, so a
        # machine that speeds up or slows down between rounds moves both alike
        pairs = zip(getattr(by[top], kind), getattr(by[bottom], kind), strict=True)
        return statistics.median(a / b for a, b in pairs)

    figures = {
        "R1": ratio("xodrlint 1.7", "xmllint 1.7"),
        "R2": ratio("xodrlint 1.8", "xmllint 1.7"),
        "R3": ratio("xodrlint 0.2 MB", "python imports"),
        "M": ratio("xodrlint 1.7", "xmllint 1.7", "peak_kb"),
        "S": ratio("xodrlint 1.7 x2", "xodrlint 1.7"),
        "B": ratio("batch -j 1", "batch -j 2"),
        "G": ratio("xodrlint 1.7", "1.7 no geometry"),
    }
    print(f"{'command':<18} {'median s':>9} {'peak MB':>8}   runs (s)")
    for c in runs:
        shown = " ".join(f"{s:.2f}" for s in c.seconds)
        print(f"{c.name:<18} {c.median:>9.2f} {c.median_kb / 1024:>8.0f}   {shown}")
    print()
    for key, value in figures.items():
        target = TARGETS[key]
        ok = value >= target if key == "B" else value <= target
        relation = ">=" if key == "B" else "<="
        print(f"{key:<3} {value:6.2f}   target {relation} {target}   {'met' if ok else 'MISSED'}")
    return figures


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    default_schemas = os.environ.get("XODRLINT_SCHEMA_PATH", "../shared/schemas")
    parser.add_argument("--schemas", type=Path, default=Path(default_schemas))
    parser.add_argument("--repeat", type=int, default=5)
    parser.add_argument("--size-mb", type=float, default=20.0)
    parser.add_argument("--workdir", type=Path, default=Path("/tmp/xodrlint-bench"))
    args = parser.parse_args(argv)
    import xodrlint

    compileall.compile_dir(Path(xodrlint.__file__).parent, quiet=1)
    files = prepare(args.workdir, args.size_mb)
    runs = commands(files, args.schemas.resolve())
    for command in runs:  # warm-up: page cache, schema caches, bytecode
        command.run()
        command.seconds.clear()
        command.peak_kb.clear()
    for round_number in range(args.repeat):
        for command in runs:
            command.run()
        print(f"round {round_number + 1}/{args.repeat} done", file=sys.stderr)
    python = sys.version.split()[0]
    print(f"machine: {os.cpu_count()} cores, {_memory_gb():.0f} GiB; python {python}")
    report(runs)
    return 0


def _memory_gb() -> float:
    with Path("/proc/meminfo").open(encoding="ascii") as meminfo:
        total_kb = int(meminfo.readline().split()[1])
    return total_kb / MB


if __name__ == "__main__":
    sys.exit(main())
