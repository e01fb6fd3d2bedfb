"""``scalf-opt analyze-log``: the energy in a cylinder log, in the layout of the paper's Table 7."""

from __future__ import annotations

import argparse
from pathlib import Path

from scalf_opt.cli.options import add_gait, add_robot, gait_overrides, load_gait, load_robot

NAME = "analyze-log"
HELP = "mechanical energy per leg and phase from a cylinder log (lengths and forces)"
JSON = True


def add_arguments(parser: argparse.ArgumentParser) -> None:  # noqa: D103
    parser.add_argument("log", type=Path, metavar="FILE.csv", help="the cylinder log")
    add_robot(parser)
    add_gait(parser, accounting=False)


def run(args: argparse.Namespace) -> int:  # noqa: D103
    from scalf_opt.api import analyze_log
    from scalf_opt.logs.report import log_report

    robot = load_robot(args)
    gait = load_gait(args, robot)
    # --period is the log's period; without it, the contacts' and then the gait's
    period = gait.period_s if "period_s" in gait_overrides(args) else None
    result = analyze_log(args.log, robot, gait, period_s=period, command=args.argv)
    args.console.text(log_report(result.analysis).rstrip("\n"))
    args.console.json(result.to_dict())
    return 0
