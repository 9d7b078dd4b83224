#!/usr/bin/env python3
"""Issue 44's ratios from one run, and README.md's performance table made from them.

The 1M-triangle teapot (`seamlit-bench teapot 128`: 32 objects, UVs, the brick normal map, no
normals or tangents) through the default `seamlit fix`, against the floor of reading and
writing the same file while computing nothing (seamlit-io's `load_save` example); the same
model with its normals and no tangents (`fix --tangents none` of it) against its own floor;
the same model as `.usdc` (bench/glb_to_usd.py, Pixar's USD) and as Blender's `.fbx` beside
Blender's `.glb` of one scene (crates/seamlit-io/benches/fbx_inputs.py, the bpy module),
each fixed against its `.glb`. Every case is a whole process, all of them run in turn, round
after round (this machine's speed moves within minutes: alternating weighs on all alike);
the medians of wall time and of peak resident memory (the kernel's `ru_maxrss`, what GNU
time prints).

    cargo build --release -p seamlit -p seamlit-bench
    cargo build --release -p seamlit-io --example load_save
    bench/performance.py [--runs 11] [--threads 2] [--tangent-rounds 3] [--work DIR]
                         [--baseline BINARY] [--readme]

And MikkTSpace on one thread against meshoptimizer's `generate_tangents` (criterion, `cargo
bench -p seamlit-mesh --bench tangents`, `--tangent-rounds` runs of it): what MikkTSpace adds
to a fix that has its normals (`fix/mikktspace/1t` less `fix/normals-only/1t`) against the
generator alone on the fixed model's normals (`generator/meshopt/1t`), the medians of the
rounds' ratios.

`--baseline BINARY` runs every `seamlit` case with another build too (say, a copy of
`target/release/seamlit` made before a change, kept on the same file system), in the same
rounds, the two in turn (which goes first alternates), and prints each case's medians before
and after and their ratios: a change's own figures, from one run.

`--readme` writes the table into README.md between its two `bench/performance.py` markers.
The `.usdc` and `.fbx` rows are left out, with a line saying so, where `pxr` (usd-core) or
`bpy` cannot be imported. Keep the binaries where they are built: a binary's own pages count
in its peak memory, differently from tmpfs than from disk.
"""

from __future__ import annotations

import argparse
import datetime
import os
import statistics
import subprocess
import sys
import tempfile
import time
from pathlib import Path
from typing import Dict, List, Optional, Sequence, Tuple

REPO = Path(__file__).resolve().parents[1]
RELEASE = REPO / "target" / "release"
README = REPO / "README.md"
BEGIN = "<!-- bench/performance.py: begin -->"
END = "<!-- bench/performance.py: end -->"


class Case:
    """One command, run as a whole process once per round."""

    def __init__(self, name: str, argv: Sequence[str]) -> None:
        self.name, self.argv = name, list(argv)
        self.walls: List[float] = []
        self.peaks: List[int] = []  # KiB

    def run(self, threads: int) -> None:
        env = dict(os.environ, RAYON_NUM_THREADS=str(threads))
        cores = f"0-{threads - 1}" if threads > 1 else "0"
        with tempfile.TemporaryFile() as err:
            started = time.perf_counter()
            # taskset execs the command in its own process: wait4's usage is the command's.
            child = subprocess.Popen(["taskset", "-c", cores, *self.argv], stdout=subprocess.DEVNULL, stderr=err, env=env)
            _, status, usage = os.wait4(child.pid, 0)
            wall = time.perf_counter() - started
            child.returncode = os.waitstatus_to_exitcode(status)
            if child.returncode != 0:
                err.seek(0)
                tail = err.read().decode("utf-8", "replace").strip().splitlines()[-3:]
                sys.exit(f"bench/performance.py: {self.name} failed ({' '.join(self.argv)}): {' / '.join(tail)}")
        self.walls.append(wall)
        self.peaks.append(usage.ru_maxrss)

    @property
    def wall(self) -> float:
        return statistics.median(self.walls)

    @property
    def mib(self) -> float:
        return statistics.median(self.peaks) / 1024


def binary(path: Path, build: str) -> str:
    if not path.is_file():
        sys.exit(f"bench/performance.py: {path.relative_to(REPO)} is missing: {build}")
    return str(path)


def importable(module: str) -> bool:
    return subprocess.run([sys.executable, "-c", f"import {module}"], capture_output=True).returncode == 0


def make(argv: Sequence[str], what: str) -> None:
    done = subprocess.run(list(argv), capture_output=True, text=True)
    if done.returncode != 0:
        sys.exit(f"bench/performance.py: making {what} failed: {done.stderr.strip()[-500:]}")


def inputs(work: Path, seamlit: str, bench: str) -> Tuple[Dict[str, Path], List[str]]:
    """The models, made in ``work``; and a line for each row left out."""
    files = {"glb": work / "t.glb", "nt": work / "nt.glb"}
    make([bench, "teapot", "128", str(files["glb"])], "the teapot")
    make([seamlit, "fix", str(files["glb"]), "-o", str(files["nt"]), "--tangents", "none"], "the teapot with normals")
    missing = []
    if importable("pxr"):
        files["usdc"] = work / "t.usdc"
        make([sys.executable, str(REPO / "bench/glb_to_usd.py"), str(files["glb"]), str(files["usdc"])], "the .usdc")
    else:
        missing.append("the `.usdc` row: Pixar's USD is not installed (pip install usd-core)")
    if importable("bpy"):
        pair = work / "pair"
        pair.mkdir(exist_ok=True)
        script = REPO / "crates/seamlit-io/benches/fbx_inputs.py"
        make([sys.executable, str(script), str(files["nt"]), str(pair)], "Blender's .fbx and .glb")
        files["fbx"], files["fbx_glb"] = pair / "model.fbx", pair / "model.glb"
    else:
        missing.append("the `.fbx` row: Blender's bpy module is not installed (pip install bpy)")
    return files, missing


def cases(files: Dict[str, Path], seamlit: str, floor: str, work: Path) -> Dict[str, Case]:
    out = lambda name: str(work / name)
    found = {
        "fix": Case("fix", [seamlit, "fix", str(files["glb"]), "-o", out("o.glb")]),
        "floor": Case("floor", [floor, str(files["glb"]), out("f.glb")]),
        "nt": Case("nt", [seamlit, "fix", str(files["nt"]), "-o", out("o-nt.glb")]),
        "nt_floor": Case("nt_floor", [floor, str(files["nt"]), out("f-nt.glb")]),
    }
    if "usdc" in files:
        found["usdc"] = Case("usdc", [seamlit, "fix", str(files["usdc"]), "-o", out("o.usdc")])
    if "fbx" in files:
        found["fbx"] = Case("fbx", [seamlit, "fix", str(files["fbx"]), "-o", out("o-fbx.glb")])
        found["fbx_glb"] = Case("fbx_glb", [seamlit, "fix", str(files["fbx_glb"]), "-o", out("o-fbx-glb.glb")])
    return found


#: The criterion cases of MikkTSpace against meshoptimizer's generator, the 1M teapot.
TANGENT_CASES = ("fix/mikktspace/1t", "fix/normals-only/1t", "generator/meshopt/1t")


def tangent_round() -> Dict[str, float]:
    """One run of the three criterion cases: each one's median estimate, in ms."""
    pattern = "(" + "|".join(TANGENT_CASES) + ")/1048k"
    argv = ["cargo", "bench", "-q", "-p", "seamlit-mesh", "--bench", "tangents", "--", "--noplot", pattern]
    done = subprocess.run(argv, cwd=REPO, capture_output=True, text=True)
    if done.returncode != 0:
        sys.exit(f"bench/performance.py: {' '.join(argv)} failed: {done.stderr.strip()[-500:]}")
    found: Dict[str, float] = {}
    name = None
    for line in done.stdout.splitlines():
        words = line.split()
        if words and words[0].startswith("tangents/"):
            name = words[0][len("tangents/") :].rsplit("/", 1)[0]
        if name and "time:" in words:
            # time:   [low unit median unit high unit]
            at = words.index("time:")
            value, unit = float(words[at + 3]), words[at + 4]
            found[name] = value * {"s": 1000.0, "ms": 1.0, "µs": 0.001, "us": 0.001}[unit]
            name = None
    missing = [c for c in TANGENT_CASES if c not in found]
    if missing:
        sys.exit(f"bench/performance.py: criterion printed no time for {', '.join(missing)}")
    return found


def tangent_ratio(rounds: List[Dict[str, float]]) -> Tuple[float, float, float]:
    """The median over the rounds of (meshopt / what MikkTSpace adds), with the medians of
    what MikkTSpace adds and of meshopt, in ms."""
    adds = [r["fix/mikktspace/1t"] - r["fix/normals-only/1t"] for r in rounds]
    ratios = [r["generator/meshopt/1t"] / a for r, a in zip(rounds, adds)]
    meshopt = [r["generator/meshopt/1t"] for r in rounds]
    return statistics.median(ratios), statistics.median(adds), statistics.median(meshopt)


def table(c: Dict[str, Case], threads: int, tangents: Optional[Tuple[float, float, float]]) -> List[str]:
    """The README's table, from the medians."""
    fix, floor, nt, nt_floor = c["fix"], c["floor"], c["nt"], c["nt_floor"]
    over = lambda a, b: f"{a.wall / b.wall:.1f}x, {a.mib / b.mib:.2f}x"
    lines = [
        f"| | wall time, {plural(threads, 'thread')} | peak memory | against the floor |",
        "|---|---:|---:|---:|",
        f"| `seamlit fix` (default) | **{fix.wall:.2f} s** | **{fix.mib:.0f} MiB** | {over(fix, floor)} |",
        f"| load and save, no fix | {floor.wall:.2f} s | {floor.mib:.0f} MiB | 1x |",
        "| the same model with its normals, no tangents (`fix` keeps the normals, MikkTSpace "
        f"against them) | {nt.wall:.2f} s | {nt.mib:.0f} MiB | {over(nt, nt_floor)} its floor "
        f"({nt_floor.wall:.2f} s, {nt_floor.mib:.0f} MiB) |",
    ]
    if "usdc" in c:
        usdc = c["usdc"]
        lines.append(
            f"| the same model as `.usdc`, `fix -o .usdc` (the default options) | "
            f"{usdc.wall / fix.wall:.2f}x the `.glb`'s fix ({usdc.wall:.2f} s) | {usdc.mib:.0f} MiB | |"
        )
    if "fbx" in c:
        fbx, glb = c["fbx"], c["fbx_glb"]
        lines.append(
            f"| the same model as Blender's `.fbx` beside Blender's `.glb` of it (the default options) | "
            f"{fbx.wall / glb.wall:.2f}x the `.glb`'s fix ({fbx.wall:.2f} s against {glb.wall:.2f} s) | "
            f"{fbx.mib:.0f} MiB | |"
        )
    if tangents is not None:
        ratio, adds, meshopt = tangents
        lines.append(
            "| MikkTSpace on one thread against meshoptimizer's `generate_tangents` (what it adds to a "
            "fix that has its normals, against the generator alone on those normals; criterion) | "
            f"{ratio:.2f}x faster ({adds:.0f} against {meshopt:.0f} ms) | | |"
        )
    return lines


def comparison(found: Dict[str, Case], before: Dict[str, Case]) -> List[str]:
    """Each case run with the baseline too: its medians before and after, and their ratios."""
    lines = [
        "| case | baseline | this build | this / baseline |",
        "|---|---:|---:|---:|",
    ]
    for name, old in before.items():
        new = found[name]
        lines.append(
            f"| {name} (`{' '.join(Path(a).name for a in new.argv[1:3])} ...`) | {old.wall * 1000:.0f} ms, {old.mib:.1f} MiB | "
            f"{new.wall * 1000:.0f} ms, {new.mib:.1f} MiB | {new.wall / old.wall:.3f}x, {new.mib / old.mib:.3f}x |"
        )
    return lines


def plural(n: int, word: str) -> str:
    return f"{n} {word}" + ("" if n == 1 else "s")


def machine() -> str:
    model = "unknown CPU"
    try:
        for line in Path("/proc/cpuinfo").read_text().splitlines():
            if line.startswith("model name"):
                model = line.split(":", 1)[1].strip()
                break
    except OSError:
        pass
    return f"{model}, {os.cpu_count()} cores"


def commit() -> str:
    done = subprocess.run(["git", "-C", str(REPO), "rev-parse", "--short", "HEAD"], capture_output=True, text=True)
    # What the binaries are built from (the README and BENCHMARKS.md may be mid-edit).
    sources = ["crates", "bench", "examples", "Cargo.toml", "Cargo.lock"]
    dirty = subprocess.run(["git", "-C", str(REPO), "status", "--porcelain", "--untracked-files=no", "--", *sources],
                           capture_output=True, text=True)
    return done.stdout.strip() + (" with changes" if dirty.stdout.strip() else "") if done.returncode == 0 else "unknown"


def write_readme(lines: List[str]) -> None:
    """README.md with ``lines`` between the markers, written under a temporary name and
    renamed."""
    text = README.read_text()
    start, end = text.find(BEGIN), text.find(END)
    if start < 0 or end < start:
        sys.exit(f"bench/performance.py: README.md has no '{BEGIN}' ... '{END}' markers")
    new = text[: start + len(BEGIN)] + "\n" + "\n".join(lines) + "\n" + text[end:]
    temporary = README.with_name(".README.md.tmp")
    temporary.write_text(new)
    os.replace(temporary, README)


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--runs", type=int, default=11, help="rounds of every case (medians; default 11)")
    parser.add_argument("--threads", type=int, default=2, help="threads (and cores) of each process (default 2)")
    parser.add_argument("--tangent-rounds", type=int, default=3, help="runs of the criterion cases (0: left out; default 3)")
    parser.add_argument("--work", type=Path, help="where the models are made (default: a temporary folder)")
    parser.add_argument("--baseline", type=Path, metavar="BINARY",
                        help="another seamlit binary to run every seamlit case with too, alternated, for before and after")
    parser.add_argument("--readme", action="store_true", help="write the table into README.md")
    args = parser.parse_args()
    if args.runs < 1 or args.tangent_rounds < 0 or not 1 <= args.threads <= (os.cpu_count() or 1):
        sys.exit(f"bench/performance.py: --runs at least 1, --threads 1 to {os.cpu_count()}")
    seamlit = binary(RELEASE / "seamlit", "cargo build --release -p seamlit")
    bench = binary(RELEASE / "seamlit-bench", "cargo build --release -p seamlit-bench")
    floor = binary(RELEASE / "examples" / "load_save", "cargo build --release -p seamlit-io --example load_save")
    if args.baseline is not None and not (args.baseline.is_file() and os.access(args.baseline, os.X_OK)):
        sys.exit(f"bench/performance.py: --baseline {args.baseline}: not an executable file")
    with tempfile.TemporaryDirectory(prefix="seamlit-performance-") as scratch:
        work = args.work or Path(scratch)
        work.mkdir(parents=True, exist_ok=True)
        files, missing = inputs(work, seamlit, bench)
        found = cases(files, seamlit, floor, work)
        before = {}
        if args.baseline is not None:
            before = {
                name: Case(f"{name} (baseline)", [str(args.baseline.resolve()), *case.argv[1:]])
                for name, case in found.items()
                if case.argv[0] == seamlit
            }
        started = datetime.datetime.now(datetime.timezone.utc)
        load = os.getloadavg()[0]
        for round in range(args.runs):
            for name, case in found.items():
                pair = [case, before[name]] if name in before else [case]
                for each in pair if round % 2 == 0 else reversed(pair):
                    each.run(args.threads)
            print(f"round {round + 1}/{args.runs}", file=sys.stderr)
        rounds = []
        for round in range(args.tangent_rounds):
            rounds.append(tangent_round())
            print(f"criterion round {round + 1}/{args.tangent_rounds}: {rounds[-1]}", file=sys.stderr)
        ended = datetime.datetime.now(datetime.timezone.utc)
    for case in found.values():
        print(f"{case.name}: {case.wall * 1000:.1f} ms, {case.mib:.1f} MiB ({' '.join(case.argv[:2])} ...)")
    lines = table(found, args.threads, tangent_ratio(rounds) if rounds else None)
    when = f"{started:%Y-%m-%d %H:%M}" + (f" to {ended:%H:%M}" if f"{ended:%H:%M}" != f"{started:%H:%M}" else "") + " UTC"
    note = (
        f"Measured {when} at {commit()} on {machine()} (load {load:.1f} at the start), medians of "
        f"{plural(args.runs, 'round')}, every case in each round"
        + (f"; the criterion cases in {plural(len(rounds), 'run')} after them" if rounds else "")
        + f": `bench/performance.py --runs {args.runs}"
        + (f" --threads {args.threads}" if args.threads != 2 else "")
        + f" --tangent-rounds {args.tangent_rounds} --readme`."
    )
    lines += ["", note] + [f"Left out: {m}." for m in missing]
    print()
    print("\n".join(lines))
    if before:
        print(f"\nAgainst the baseline {args.baseline} (the same rounds, alternated):\n")
        print("\n".join(comparison(found, before)))
    if args.readme:
        write_readme(lines)
        print("\nREADME.md: the performance table written", file=sys.stderr)


if __name__ == "__main__":
    main()
