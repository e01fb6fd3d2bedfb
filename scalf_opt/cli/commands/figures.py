"""``scalf-opt figures``: the paper's figures (8-13, 17, 18, Table 6), and a landscape it lacked."""

from __future__ import annotations

import argparse
import sys
from pathlib import Path

from scalf_opt.cli.options import add_gait, add_robot, load_gait, load_robot

NAME = "figures"
HELP = "draw the paper's figures (PNG and SVG): joints, forces, foot paths, search, energy"


def add_arguments(parser: argparse.ArgumentParser) -> None:  # noqa: D103
    add_robot(parser)
    add_gait(parser)
    parser.add_argument(
        "--from",
        dest="from_dirs",
        metavar="DIR",
        type=Path,
        action="append",
        default=[],
        help="a directory written by 'optimize --out' (repeat to compare; default: the "
        "reference and the default optimum, joint-6 by Ipopt)",
    )
    parser.add_argument(
        "--out", type=Path, default=Path("figures"), help="output directory (default figures)"
    )
    parser.add_argument(
        "--format",
        dest="formats",
        choices=("png", "svg"),
        action="append",
        help="file format (repeatable; default: both png and svg)",
    )
    parser.add_argument(
        "--grid",
        type=int,
        default=61,
        help="points per parameter of the pattern search's energy landscape (default 61)",
    )


def run(args: argparse.Namespace) -> int:
    """Exit 0 when every figure is written, 3 when the default optimum is not solved."""
    from scalf_opt.errors import ConfigError
    from scalf_opt.viz.figure_set import write_figures
    from scalf_opt.viz.trajectories import NotSolvedError, shown_trajectories

    if args.out.exists() and not args.out.is_dir():
        raise ConfigError(f"{args.out}: exists and is not a directory")
    if args.grid < 3:
        raise ConfigError(f"--grid must be at least 3, got {args.grid}")
    if args.from_dirs and args.gait is not None:
        raise ConfigError("--gait and --from: a result directory brings its own gait")
    robot = load_robot(args)
    try:
        pipeline, shown = shown_trajectories(
            robot, load_gait(args, robot), args.from_dirs, args.accounting
        )
    except NotSolvedError as exc:
        print(f"scalf-opt: error: {exc}; nothing written", file=sys.stderr)
        return 3
    for trajectory in shown:
        cycle = trajectory.cycle
        print(
            f"{trajectory.label}: {cycle.energy_j:.3f} J per cycle, {cycle.average_power_w:.2f} W"
        )
    formats = tuple(dict.fromkeys(args.formats or ("png", "svg")))
    written = write_figures(args.out, robot, pipeline, shown, formats, args.grid)
    names = sorted({p.stem for p in written}, key=[p.stem for p in written].index)
    print(f"wrote {args.out}/: {', '.join(names)} ({', '.join(formats)})")
    return 0
