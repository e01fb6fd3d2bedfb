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
JSON = True
VERBOSE = True
EXAMPLES = (
    ("scalf-opt paper", "Tables 5 and 6 with the bound and the free stance (results/paper)"),
    ("scalf-opt paper --quick --out results/quick", "the paper's comparison only"),
    ("scalf-opt paper --json | head", "the same data as paper.json"),
    ("scalf-opt paper --quick --markdown", "the whole report (report.md) on stdout"),
)


def add_arguments(parser: argparse.ArgumentParser) -> None:  # noqa: D103
    add_robot(parser)
    add_gait(parser, accounting=False)
    parser.add_argument(
        "--out",
        type=Path,
        default=Path("results/paper"),
        metavar="DIR",
        help="output directory (default results/paper)",
    )
    parser.add_argument(
        "--quick",
        action="store_true",
        help="the paper's comparison only: leave out the free-trajectory bound (and the gaps to "
        "it) and the free stance, which take most of the time",
    )
    parser.add_argument(
        "--markdown",
        action="store_true",
        help="print the whole Markdown report (report.md: Tables 5 and 6 per leg, the "
        "validation, the bound, the stance) instead of its summary",
    )
    add_accept_unconverged(parser)


def run(args: argparse.Namespace) -> int:
    """Exit 0 when everything converged, 3 otherwise (unless accepted)."""
    from scalf_opt.api import paper
    from scalf_opt.cli.progress import ProgressBar
    from scalf_opt.studies.paper_report import (
        paper_markdown,
        paper_summary,
        write_paper_outputs,
    )

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
    if args.markdown:
        args.console.text(paper_markdown(rep, robot))
    else:
        args.console.text(paper_summary(rep, robot, args.out / "report.md"))
    args.console.text(f"wrote {args.out}/" + ", ".join(p.name for p in written))
    args.console.json(result.to_dict())
    if not rep.all_solved:
        args.console.error("not converged: " + "; ".join(rep.failures()) + " (see the report)")
        return 0 if args.accept_unconverged else 3
    return 0
