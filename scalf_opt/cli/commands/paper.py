"""``scalf-opt paper``: the paper's Tables 5 and 6 beside the paper's numbers."""

from __future__ import annotations

import argparse
from pathlib import Path

from scalf_opt.cli.options import (
    add_accept_unconverged,
    add_gait,
    add_robot,
    check_output_dir,
    load_gait,
    load_robot,
)

NAME = "paper"
HELP = "reproduce the paper's Tables 5 and 6 (the main job)"


def add_arguments(parser: argparse.ArgumentParser) -> None:  # noqa: D103
    add_robot(parser)
    add_gait(parser, accounting=False)
    parser.add_argument(
        "--out",
        type=Path,
        default=Path("results/paper"),
        help="output directory (default results/paper)",
    )
    parser.add_argument(
        "--quick",
        action="store_true",
        help="the paper's comparison only: leave out the free-trajectory bound (and the gaps to "
        "it) and the free stance, which take most of the time",
    )
    add_accept_unconverged(parser)


def run(args: argparse.Namespace) -> int:
    """Exit 0 when everything converged, 3 otherwise (unless accepted)."""
    from scalf_opt.api import paper
    from scalf_opt.cli.progress import ProgressBar
    from scalf_opt.studies.paper_report import paper_markdown, write_paper_outputs

    check_output_dir(args.out)
    robot = load_robot(args)
    gait = load_gait(args, robot)
    with ProgressBar(None, "paper", enabled=not args.quiet) as bar:
        result = paper(
            robot,
            gait,
            quick=args.quick,
            verbose=args.verbose,
            progress=bar.step,
            command=args.argv,
        )
    rep = result.reproduction
    written = write_paper_outputs(rep, robot, args.out, args.argv)
    args.console.text(paper_markdown(rep, robot))
    args.console.text(f"wrote {args.out}/" + ", ".join(p.name for p in written))
    if not rep.all_solved:
        args.console.error("not converged: " + "; ".join(rep.failures()) + " (see the report)")
        return 0 if args.accept_unconverged else 3
    return 0
