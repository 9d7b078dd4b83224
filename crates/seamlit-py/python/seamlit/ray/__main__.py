"""``python -m seamlit.ray fix SRC DST [--address ADDR] [options]`` and ``python -m
seamlit.ray inspect SRC REPORT``: see docs/fleet.md.

Exit status: 0 when every file was fixed, unchanged or skipped; 2 when a file was refused
(bad input) and 1 when one failed, as ``seamlit fix`` does for a folder.
"""

from __future__ import annotations

import argparse
import sys
from typing import Any, Dict, List, Optional

_MODES = ("flat", "object", "model")
_WEIGHTINGS = ("angle", "area", "angle-area", "uniform")
_TANGENTS = ("seamlit", "mikktspace", "none")
_NORMALS = ("auto", "smooth-shared", "keep", "recompute")


def _fix_flags(parser: argparse.ArgumentParser) -> None:
    """The flags ``seamlit fix`` and ``seamlit inspect`` share, spelled the same."""
    parser.add_argument("--mode", choices=_MODES, default="model")
    parser.add_argument("--crease", type=float, metavar="DEG")
    parser.add_argument("--weld-tolerance", metavar="X")
    parser.add_argument("--weighting", choices=_WEIGHTINGS)
    parser.add_argument("--tangents", choices=_TANGENTS)
    parser.add_argument("--normals", choices=_NORMALS)
    parser.add_argument("--tessellation", type=int, default=16, metavar="N")
    parser.add_argument(
        "--asset-root",
        action="append",
        default=[],
        metavar="DIR",
        help="a folder besides the model's own that a USD stage's files may come from (for an object-store SRC: a folder relative to SRC)",
    )
    parser.add_argument("--address", help="the Ray cluster (as ray.init takes it; default RAY_ADDRESS or a local one)")
    parser.add_argument("--no-recurse", action="store_true", help="only the models directly in SRC")
    parser.add_argument("--quiet", action="store_true", help="no progress lines, only the summary")


def parser() -> argparse.ArgumentParser:
    top = argparse.ArgumentParser(prog="python -m seamlit.ray", description=__doc__.split("\n\n")[0])
    commands = top.add_subparsers(dest="command", required=True)
    fix = commands.add_parser("fix", help="fix every model under SRC into DST, with a report")
    fix.add_argument("src", metavar="SRC")
    fix.add_argument("dst", metavar="DST")
    fix.add_argument("--format", choices=("glb", "gltf", "obj"), default="glb")
    fix.add_argument("--overwrite-input", action="store_true")
    fix.add_argument("--keep-compression", action="store_true")
    fix.add_argument("--skin-seams", choices=("match", "keep"), default="match")
    fix.add_argument("--samples", type=int, default=30, metavar="N")
    fix.add_argument("--pictures", type=int, default=24, metavar="N", help="before/after pictures in the summary")
    fix.add_argument("--engine", choices=("auto", "cli", "package"), default="auto")
    _fix_flags(fix)
    inspect = commands.add_parser("inspect", help="measure every model under SRC into a report, fixing nothing")
    inspect.add_argument("src", metavar="SRC")
    inspect.add_argument("report", metavar="REPORT", help="the parquet file to write")
    _fix_flags(inspect)
    return top


def _options(args: argparse.Namespace, fix: bool) -> Dict[str, Any]:
    options: Dict[str, Any] = {"mode": args.mode, "tessellation": args.tessellation}
    for name in ("crease", "weld_tolerance", "weighting", "tangents", "normals"):
        value = getattr(args, name)
        if value is not None:
            options[name] = value
    if args.asset_root:
        options["asset_roots"] = list(args.asset_root)
    if fix:
        options["skin_seams"] = args.skin_seams
        options["samples"] = args.samples
        if args.keep_compression:
            options["keep_compression"] = True
        if args.overwrite_input:
            options["overwrite_input"] = True
    return options


def main(argv: Optional[List[str]] = None) -> int:
    args = parser().parse_args(argv)
    from . import fix, inspect

    try:
        if args.command == "fix":
            summary = fix(
                args.src,
                args.dst,
                address=args.address,
                output_format=args.format,
                recurse=not args.no_recurse,
                pictures=args.pictures,
                engine=args.engine,
                progress=not args.quiet,
                **_options(args, True),
            )
        else:
            summary = inspect(
                args.src,
                args.report,
                address=args.address,
                recurse=not args.no_recurse,
                progress=not args.quiet,
                **_options(args, False),
            )
    except (ValueError, FileNotFoundError) as e:
        print(f"error: {e}", file=sys.stderr)
        return 2
    print(summary.line())
    if summary.failed:
        return 1
    return 2 if summary.refused else 0


if __name__ == "__main__":
    sys.exit(main())
