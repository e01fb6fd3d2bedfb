"""``scalf-opt optimize``: optimize the swing of one or more legs."""

from __future__ import annotations

import argparse
from pathlib import Path

from scalf_opt.cli.options import (
    add_gait,
    add_robot,
    check_output_dir,
    leg_name,
    load_gait,
    load_robot,
)
from scalf_opt.locomotion.swing.names import DEFAULT_FAMILY
from scalf_opt.types import FIRST_PAIR, LEG_NAMES, Method, choices

NAME = "optimize"
HELP = "optimize the swing of one or more legs"
JSON = True


def add_arguments(parser: argparse.ArgumentParser) -> None:  # noqa: D103
    add_robot(parser)
    add_gait(parser)
    parser.add_argument(
        "--leg",
        type=leg_name,
        default="PAIR",
        choices=(*LEG_NAMES, "PAIR"),
        metavar="{RF,LH,LF,RH,pair}",
        help="the leg to optimize; 'pair' (default): RF and LH, whose optima LF and RH repeat "
        "half a cycle later (the paper's symmetry); a single leg's twin repeats it too",
    )
    parser.add_argument(
        "--family",
        default=DEFAULT_FAMILY,
        help=f"paper, fourier-N (foot space) or joint-N (joint space), N in 2..12 "
        f"(default {DEFAULT_FAMILY})",
    )
    parser.add_argument("--method", choices=choices(Method), default="ipopt")
    parser.add_argument(
        "--precision",
        type=float,
        help="pattern-search precision (default 0.1, the paper's); --method pattern only",
    )
    parser.add_argument("--out", type=Path, help="write summary.json and samples.csv here")


def run(args: argparse.Namespace) -> int:
    """Exit 0 when every leg is solved, 3 when an optimizer fails."""
    from scalf_opt.api import optimize_swing
    from scalf_opt.cli.progress import ProgressBar
    from scalf_opt.viz.report import evaluate_report, optimum_report

    check_output_dir(args.out)
    robot = load_robot(args)
    gait = load_gait(args, robot)
    legs = FIRST_PAIR if args.leg == "PAIR" else (args.leg,)
    with ProgressBar(len(legs), "optimize", enabled=not args.quiet) as bar:
        result = optimize_swing(
            robot,
            gait,
            family=args.family,
            method=args.method,
            legs=legs,
            accounting=args.accounting,
            precision=args.precision,
            verbose=args.verbose,
            progress=bar.step,
            command=args.argv,
        )
    console = args.console
    console.text(optimum_report(result.optima, result.reference))
    console.json(result.to_dict())
    if result.cycle is None:
        failed = [o for o in result.optima.values() if not o.success]
        names = ", ".join(f"{o.leg} ({o.status})" for o in failed)
        console.error(f"not solved: {names}; no optimum is reported")
        return 3
    written = result.write(args.out) if args.out is not None else []
    title = f"optimized ({args.family}, {args.method})"
    console.text("\n" + evaluate_report(result.cycle, robot.name, title=title))
    if written:
        console.text("wrote " + " and ".join(str(p) for p in written))
    return 0
