"""xodrlint against ``xmllint --noout --schema``, side by side, alternating and repeated.

    python benchmarks/run.py --schemas path/to/asam-schemas [--repeat 5] [--workdir DIR]
                             [--only mixed|rail|findings|dask|all] [--size-mb 20]
                             [--roads 1000000] [--roads-timeout 900]

Generates the networks (benchmarks/generate.py, benchmarks/railway.py), then runs every
command of a round in turn, ``--repeat`` rounds, so that a noisy machine slows both sides
alike, and prints the median wall time and peak RSS of each command and the figures of
issues 5 and 17, each the median of its per-round ratios (a round runs the commands back
to back). xodrlint runs all rules with JSON output; "rail" is the rail-dense railway of
railway.py (every road a track), "mixed" the city-and-rail network of generate.py.

- R1r: xodrlint on a 20 MB rail 1.7 network / xmllint on it
- R2r: xodrlint on the same rail network declared 1.8 (XSD 1.1) / xmllint on the 1.7 file
- R1:  xodrlint on a 20 MB mixed 1.7 network / xmllint on it
- R2:  xodrlint on the mixed network declared 1.8 / xmllint on the mixed 1.7 file
- R3:  xodrlint on a 0.2 MB file / ``python -c "import typer, rich.console, lxml.etree"``
- M:   xodrlint's peak RSS on the rail 1.7 file / xmllint's
- Mmix: the same on the mixed 1.7 file
- M8r: xodrlint's peak RSS on the rail file declared 1.8 / xmllint's on the 1.7 file
- R2r-R1r: how much more the 1.8 file costs than its 1.7 twin (issue 34: at most 0.05)
- S:   xodrlint on 40 MB mixed / on 20 MB mixed
- B:   200 small files with ``-j 1`` / with ``-j 2`` (a speed-up)
- G:   xodrlint on the mixed 1.7 network / the same without the track-geometry rules
       (SW011, SW012, TR001, TR002; issue 15: they may add less than 5% to the run)
- T:   xodrlint on the rail 1.7 network / the same without the track-network rules (TR:
       joints, links, lane links, plan view, profiles; issue 28: at most 10% of a run on a
       railway where every road is a track)
- F:   xodrlint on the many-findings rail file (an XS006 and an SW012 per switch, as large
       as the clean one) / on the clean rail 1.7 file
- F2:  time per finding at ~40,000 findings / at ~5,000 (two many-findings rail files of
       6,667 and 834 blocks; their findings counted once, in the warm-up)
- D:   2,000 small maps with ``--scheduler local --jobs 2`` (a LocalCluster of two
       worker processes) / with ``-j 2`` (issue 20); then, on a scheduler and two workers
       of their own, the per-file overhead of each process and the throughput it projects
       on N machines (benchmarks/cluster.py, the model of docs/distributed.md)
- MR1: "1M roads": xodrlint on 1,000,000 tiny schema-invalid roads with the official 1.7
       schema, wall seconds and peak RSS; one run after the rounds (``--roads``, 0 skips it)

The commands run as users run them: with bytecode caches. pip compiles bytecode when it
installs a package; an editable install in an environment with PYTHONDONTWRITEBYTECODE
does not, so the script compiles xodrlint's first, runs every command without
PYTHONDONTWRITEBYTECODE (which would make each start compile every module it imports
from source) and warms each once; its output says so. Linux
carries the runner's own peak RSS (some 20 MB, printed under the table) over to every child
it starts, so a smaller peak is shown as the runner's.
"""

from __future__ import annotations

import argparse
import compileall
import os
import resource
import shutil
import statistics
import subprocess
import sys
import tempfile
import threading
import time
from collections.abc import Callable, Iterable, Sequence
from dataclasses import dataclass, field
from datetime import datetime
from functools import partial
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parent))
import cluster
from generate import GENERATOR_VERSION, network, write_pieces
from railway import invalid_roads, railway

MB = 1024 * 1024
GB = 1000**3
TARGETS = {
    "R1r": 1.3, "R2r": 1.35, "R1": 1.2, "R2": 1.2, "R3": 1.25, "M": 1.3, "M8r": 1.3,
    "Mmix": 1.5,
    "S": 2.2, "B": 1.6, "G": 1.05, "T": 1.10, "F": 2.0, "F2": 1.3, "D": 1.3, "MR1 s": 60.0,
    "MR1 GB": 3.0,
}  # fmt: skip
#: How much more a file declared 1.8 may cost than its 1.7 twin (R2r - R1r).
R2R_OVER_R1R = 0.05
#: Dropped from the commands' environment: users have bytecode caches, and with this set
#: (as on the machines the team works on) every start would compile from source.
NO_BYTECODE = "PYTHONDONTWRITEBYTECODE"
#: Figures that are speed-ups: the higher the better.
AT_LEAST = frozenset({"B"})
#: figure: (command, command it is divided by, measure), the measure an attribute of Command
FIGURES = {
    "R1r": ("xodrlint rail 1.7", "xmllint rail 1.7", "seconds"),
    "R2r": ("xodrlint rail 1.8", "xmllint rail 1.7", "seconds"),
    "R1": ("xodrlint 1.7", "xmllint 1.7", "seconds"),
    "R2": ("xodrlint 1.8", "xmllint 1.7", "seconds"),
    "R3": ("xodrlint 0.2 MB", "python imports", "seconds"),
    "M": ("xodrlint rail 1.7", "xmllint rail 1.7", "peak_kb"),
    "M8r": ("xodrlint rail 1.8", "xmllint rail 1.7", "peak_kb"),
    "Mmix": ("xodrlint 1.7", "xmllint 1.7", "peak_kb"),
    "S": ("xodrlint 1.7 x2", "xodrlint 1.7", "seconds"),
    "B": ("batch -j 1", "batch -j 2", "seconds"),
    "G": ("xodrlint 1.7", "1.7 no geometry", "seconds"),
    "T": ("xodrlint rail 1.7", "rail 1.7 no track rules", "seconds"),
    "F": ("rail defects", "xodrlint rail 1.7", "seconds"),
    "F2": ("findings ~40k", "findings ~5k", "per_finding"),
    "D": ("dask local 2000", "pool -j 2 2000", "seconds"),
}
#: The F2 commands and the blocks of their many-findings railways (3 switches a block, 2
#: findings a switch).
F2_BLOCKS = {"findings ~40k": 6667, "findings ~5k": 834}
#: The rules that evaluate plan-view geometry, left out for the G figure's baseline.
GEOMETRY_RULES = "SW011,SW012,TR001,TR002"


@dataclass
class Command:
    name: str
    argv: list[str]
    env: dict[str, str] = field(default_factory=dict)
    seconds: list[float] = field(default_factory=list)
    peak_kb: list[int] = field(default_factory=list)
    findings: int = 0  # counted once, for the F2 commands

    def run(self, timeout: float | None = None) -> bool:
        """Runs the command once and records its time and peak RSS; False, and nothing
        recorded, if it was stopped after ``timeout`` seconds."""
        env = command_env(self.env)
        started = time.perf_counter()
        process = subprocess.Popen(
            self.argv, env=env, stdout=subprocess.DEVNULL, stderr=subprocess.PIPE
        )
        stopped = threading.Event()

        def stop() -> None:
            stopped.set()
            process.kill()

        timer = threading.Timer(timeout or 0, stop)
        if timeout is not None:
            timer.start()
        _, status, usage = os.wait4(process.pid, 0)
        elapsed = time.perf_counter() - started
        timer.cancel()
        process.returncode = os.waitstatus_to_exitcode(status)
        error = process.stderr.read().decode() if process.stderr else ""
        if stopped.is_set():
            return False
        if process.returncode not in (0,):
            raise SystemExit(f"{self.name} failed ({process.returncode}): {error[-400:]}")
        self.seconds.append(elapsed)
        self.peak_kb.append(usage.ru_maxrss)
        return True

    @property
    def per_finding(self) -> list[float]:
        return [seconds / self.findings for seconds in self.seconds]

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


@dataclass
class Inputs:
    """The input files, written on first use into the generator's versioned folder."""

    workdir: Path
    size_mb: float

    @property
    def folder(self) -> Path:
        folder = self.workdir / f"generator-{GENERATOR_VERSION}"  # no older generator's files
        folder.mkdir(parents=True, exist_ok=True)
        return folder

    @property
    def size_bytes(self) -> int:
        return int(self.size_mb * MB)

    def file(self, name: str, pieces: Callable[[], Iterable[str]]) -> Path:
        path = self.folder / name
        if not path.exists():  # whole or not at all, should the writing be interrupted
            partial_path = path.with_name(f"{name}.part")
            write_pieces(partial_path, pieces())
            partial_path.replace(path)
        return path

    def batch(self) -> Path:
        path = self.folder / "batch-200"
        if not path.exists():
            partial_path = path.with_name("batch-200.part")
            shutil.rmtree(partial_path, ignore_errors=True)
            partial_path.mkdir()
            for number in range(200):
                size = 20 * 1024 + (number % 7) * 1024
                write_pieces(partial_path / f"map-{number:03}.xodr", network(size))
            partial_path.replace(path)
        return path

    def small_maps(self) -> Path:
        return cluster.small_maps(self.folder)

    def mixed(self, megabytes: float, minor: int = 7) -> Path:
        name = f"network-{megabytes:g}mb-1.{minor}.xodr"
        return self.file(name, partial(network, int(megabytes * MB), minor))

    def rail(self, minor: int, defects: bool = False) -> Path:
        name = f"railway-{self.size_mb:g}mb-1.{minor}{'-defects' if defects else ''}.xodr"
        return self.file(name, partial(railway, self.size_bytes, minor, defects=defects))


@dataclass(frozen=True)
class Tools:
    """xodrlint's ``check`` (all rules, JSON to /dev/null) and xmllint with the 1.7 XSD."""

    check: list[str]
    xmllint: list[str]
    env: dict[str, str]

    @classmethod
    def find(cls, schemas: Path) -> Tools:
        xodrlint = shutil.which("xodrlint", path=str(Path(sys.executable).parent)) or "xodrlint"
        xmllint = shutil.which("xmllint")
        if xmllint is None:
            raise SystemExit("xmllint is not installed (Debian: apt-get install libxml2-utils)")
        check = [xodrlint, "check", "--exit-zero", "-f", "json", "-o", os.devnull]
        validate = [xmllint, "--noout", "--schema", str(_entry(schemas, "1.7"))]
        return cls(check, validate, {"XODRLINT_SCHEMA_PATH": str(schemas)})

    def xodrlint(self, name: str, *arguments: str | Path) -> Command:
        return Command(name, [*self.check, *map(str, arguments)], self.env)

    def validate(self, name: str, path: Path) -> Command:
        return Command(name, [*self.xmllint, str(path)])


def mixed(inputs: Inputs, tools: Tools) -> list[Command]:
    n17, batch = inputs.mixed(inputs.size_mb), inputs.batch()
    return [
        tools.validate("xmllint 1.7", n17),
        tools.xodrlint("xodrlint 1.7", n17),
        tools.xodrlint("1.7 no geometry", "--ignore", GEOMETRY_RULES, n17),
        tools.xodrlint("xodrlint 1.8", inputs.mixed(inputs.size_mb, 8)),
        tools.xodrlint("xodrlint 1.7 x2", inputs.mixed(2 * inputs.size_mb)),
        Command("python imports", [sys.executable, "-c", "import typer, rich.console, lxml.etree"]),
        tools.xodrlint("xodrlint 0.2 MB", inputs.mixed(0.2)),
        tools.xodrlint("batch -j 1", "-j", "1", batch),
        tools.xodrlint("batch -j 2", "-j", "2", batch),
    ]


def rail(inputs: Inputs, tools: Tools) -> list[Command]:
    rail17 = inputs.rail(7)
    return [
        tools.validate("xmllint rail 1.7", rail17),
        tools.xodrlint("xodrlint rail 1.7", rail17),
        tools.xodrlint("rail 1.7 no track rules", "--ignore", "TR", rail17),
        tools.xodrlint("xodrlint rail 1.8", inputs.rail(8)),
    ]


def findings(inputs: Inputs, tools: Tools) -> list[Command]:
    runs = [
        tools.xodrlint("xodrlint rail 1.7", inputs.rail(7)),
        tools.xodrlint("rail defects", inputs.rail(7, defects=True)),
    ]
    for name, blocks in F2_BLOCKS.items():
        pieces = partial(railway, minor=7, blocks=blocks, defects=True)
        runs.append(
            tools.xodrlint(name, inputs.file(f"railway-{blocks}blocks-1.7-defects.xodr", pieces))
        )
    return runs


def dask(inputs: Inputs, tools: Tools) -> list[Command]:
    maps = inputs.small_maps()
    return [
        tools.xodrlint("pool -j 2 2000", "-j", "2", maps),
        tools.xodrlint("dask local 2000", "--scheduler", "local", "--jobs", "2", maps),
    ]


GROUPS = {"mixed": mixed, "rail": rail, "findings": findings, "dask": dask}


def commands(inputs: Inputs, tools: Tools, only: str = "all") -> list[Command]:
    """The commands of a round, each once: every group's in turn, or one group's."""
    chosen = GROUPS.values() if only == "all" else [GROUPS[only]]
    runs: dict[str, Command] = {}
    for group in chosen:
        for command in group(inputs, tools):
            runs.setdefault(command.name, command)
    return list(runs.values())


#: Reads a JSON report in a process of its own: 40,000 findings in the runner would raise
#: its peak RSS, and with it the floor of every child's (see above).
COUNT = "import json, sys; print(len(json.load(open(sys.argv[1], 'rb'))['findings']))"


def command_env(extra: dict[str, str]) -> dict[str, str]:
    """The environment a measured command runs in: this one's, without
    PYTHONDONTWRITEBYTECODE (see NO_BYTECODE), with ``extra``."""
    return {**{k: v for k, v in os.environ.items() if k != NO_BYTECODE}, **extra}


def count_findings(command: Command) -> int:
    """The findings of one run of the command, read from its JSON report kept this once."""
    with tempfile.TemporaryDirectory() as folder:
        kept = Path(folder) / "report.json"
        argv = [str(kept) if argument == os.devnull else argument for argument in command.argv]
        subprocess.run(argv, env=command_env(command.env), check=True, capture_output=True)
        counted = subprocess.run(
            [sys.executable, "-c", COUNT, kept], check=True, capture_output=True, text=True
        )
        count = int(counted.stdout)
    if count == 0:
        raise SystemExit(f"{command.name}: no findings to divide its time by")
    return count


def measure(runs: Sequence[Command], repeat: int) -> None:
    for command in runs:  # warm-up: page cache, schema caches, bytecode
        if command.name in F2_BLOCKS:
            command.findings = count_findings(command)
        else:
            command.run()
            command.seconds.clear()
            command.peak_kb.clear()
    for round_number in range(repeat):
        for command in runs:
            command.run()
        print(f"round {round_number + 1}/{repeat} done", file=sys.stderr)


def figures(runs: Sequence[Command]) -> dict[str, float]:
    """Every figure whose two commands ran, each the median of its per-round ratios: the two
    commands of a round ran close together, so a machine that speeds up or slows down
    between rounds moves both alike."""
    by = {c.name: c for c in runs}
    found = {}
    for key, (top, bottom, measure_name) in FIGURES.items():
        if top in by and bottom in by:
            pairs = zip(
                getattr(by[top], measure_name), getattr(by[bottom], measure_name), strict=True
            )
            found[key] = statistics.median(a / b for a, b in pairs)
    return found


def report(runs: Sequence[Command]) -> dict[str, float]:
    found = figures(runs)
    print(f"{'command':<18} {'median s':>9} {'peak MB':>8} {'findings':>8}   runs (s)")
    for c in runs:
        shown = " ".join(f"{s:.2f}" for s in c.seconds)
        counted = c.findings or ""
        print(f"{c.name:<18} {c.median:>9.2f} {c.median_kb / 1024:>8.0f} {counted:>8}   {shown}")
    # Linux carries the forking process's peak over to the child it runs
    floor_mb = resource.getrusage(resource.RUSAGE_SELF).ru_maxrss / 1024
    print(f"(a peak below this runner's own, {floor_mb:.0f} MB, is shown as {floor_mb:.0f} MB)\n")
    for key, value in found.items():
        target = TARGETS[key]
        ok = value >= target if key in AT_LEAST else value <= target
        relation = ">=" if key in AT_LEAST else "<="
        print(f"{key:<4} {value:6.2f}   target {relation} {target}   {'met' if ok else 'MISSED'}")
    if "R1r" in found and "R2r" in found:  # 1.8 at the speed of 1.7 (issue 34)
        gap = found["R2r"] - found["R1r"]
        met = "met" if gap <= R2R_OVER_R1R else "MISSED"
        print(f"R2r-R1r {gap:+.2f}   target <= {R2R_OVER_R1R}   {met}")
    return found


def roads(inputs: Inputs, tools: Tools, count: int, timeout: float) -> str:
    """MR1: one run on ``count`` schema-invalid roads, stopped after ``timeout`` seconds."""
    path = inputs.file(f"roads-{count}-1.7.xodr", partial(invalid_roads, count, 7))
    command = tools.xodrlint(_roads_name(count), path)
    command.run(timeout)
    return roads_line(command, timeout)


def roads_line(command: Command, timeout: float) -> str:
    if not command.seconds:
        return f"MR1  {command.name}: timed out after {timeout:g} s   MISSED"
    seconds, gigabytes = command.seconds[0], command.peak_kb[0] * 1024 / GB
    most_seconds, most_gigabytes = TARGETS["MR1 s"], TARGETS["MR1 GB"]
    ok = seconds <= most_seconds and gigabytes <= most_gigabytes
    return (
        f"MR1  {command.name}: {seconds:.1f} s, target <= {most_seconds:g} s; peak "
        f"{gigabytes:.2f} GB, target <= {most_gigabytes:g} GB   {'met' if ok else 'MISSED'}"
    )


def _roads_name(count: int) -> str:
    for unit, size in (("M", 1_000_000), ("k", 1_000)):
        if count % size == 0:
            return f"{count // size}{unit} roads"
    return f"{count} roads"


def main(argv: list[str] | None = None) -> int:
    args = _parser().parse_args(argv)
    import xodrlint

    compileall.compile_dir(Path(xodrlint.__file__).parent, quiet=1)
    inputs = Inputs(args.workdir, args.size_mb)
    tools = Tools.find(args.schemas.resolve())
    runs = commands(inputs, tools, args.only)
    measure(runs, args.repeat)
    print(machine(tools))
    report(runs)
    if args.only in ("all", "dask"):
        found = cluster.measure_overhead(tools.check, tools.env, inputs.small_maps(), args.repeat)
        print("\n".join(cluster.model(found, os.cpu_count() or 1)), flush=True)
    if args.roads:
        print(roads(inputs, tools, args.roads, args.roads_timeout), flush=True)
    return 0


def _parser() -> argparse.ArgumentParser:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    default_schemas = os.environ.get("XODRLINT_SCHEMA_PATH", "../shared/schemas")
    parser.add_argument("--schemas", type=Path, default=Path(default_schemas))
    parser.add_argument("--repeat", type=int, default=5)
    parser.add_argument("--size-mb", type=float, default=20.0, help="mixed and rail networks")
    parser.add_argument("--workdir", type=Path, default=Path("/tmp/xodrlint-bench"))
    parser.add_argument("--only", choices=("all", *GROUPS), default="all")
    parser.add_argument("--roads", type=int, default=1_000_000, help="MR1's roads; 0: no MR1")
    parser.add_argument("--roads-timeout", type=float, default=900.0, help="seconds")
    return parser


def machine(tools: Tools) -> str:
    """The date, the machine and the versions, as a README quotes them."""
    date = datetime.now().astimezone().strftime("%Y-%m-%d %H:%M %Z")
    version = subprocess.run(
        [tools.xmllint[0], "--version"], check=False, capture_output=True, text=True
    )
    libxml = version.stderr.partition("\n")[0].partition("using ")[2]  # "libxml version N"
    python = sys.version.split()[0]
    bytecode = (
        f"commands run without {NO_BYTECODE} (set here), so they keep bytecode caches as"
        " users' installs do; each ran once to warm up before the rounds"
        if os.environ.get(NO_BYTECODE)
        else "commands keep bytecode caches as users' installs do; each ran once to warm up"
    )
    return (
        f"date: {date}\nmachine: {_cpu()}, {os.cpu_count()} cores, {_memory_gb():.0f} GiB; "
        f"python {python}; xmllint with {libxml or 'libxml of unknown version'}\n{bytecode}"
    )


def _cpu() -> str:
    try:
        with Path("/proc/cpuinfo").open(encoding="utf-8") as cpuinfo:
            for line in cpuinfo:
                if line.startswith("model name"):
                    return line.partition(":")[2].strip()
    except OSError:
        pass
    return "unknown CPU"


def _memory_gb() -> float:
    with Path("/proc/meminfo").open(encoding="ascii") as meminfo:
        total_kb = int(meminfo.readline().split()[1])
    return total_kb / MB


if __name__ == "__main__":
    sys.exit(main())
