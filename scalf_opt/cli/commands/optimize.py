"""``scalf-opt optimize``: optimize the swing of one or more legs."""

from __future__ import annotations

import argparse
import sys
from pathlib import Path

from scalf_opt.cli.options import add_gait, add_robot, load_gait, load_robot
from scalf_opt.errors import ConfigError
from scalf_opt.locomotion.swing.names import DEFAULT_FAMILY
from scalf_opt.types import FIRST_PAIR, LEG_NAMES, Method, choices

NAME = "optimize"
HELP = "optimize the swing of one or more legs"

LEG_CHOICES: dict[str, tuple[str, ...]] = {
    "pair": FIRST_PAIR,
    "all": LEG_NAMES,
    **{leg: (leg,) for leg in LEG_NAMES},
}


def add_arguments(parser: argparse.ArgumentParser) -> None:  # noqa: D103
    add_robot(parser)
    add_gait(parser)
    parser.add_argument(
        "--leg",
        default="pair",
        choices=LEG_CHOICES,
        help="RF, LH, LF, RH; 'pair' (default: RF and LH, LF and RH by symmetry) or 'all'",
    )
    parser.add_argument(
        "--family",
        default=DEFAULT_FAMILY,
        help=f"paper, fourier-N (foot space) or joint-N (joint space), N in 2..12 "
        f"(default {DEFAULT_FAMILY})",
    )
    parser.add_argument("--method", choices=choices(Method), default="ipopt")
    parser.add_argument(
        "--precision", type=float, default=0.1, help="pattern-search precision (default 0.1)"
    )
    parser.add_argument("--out", type=Path, help="write summary.json and samples.csv here")


def run(args: argparse.Namespace) -> int:
    """Exit 0 when every leg is solved, 3 when an optimizer fails."""
    from scalf_opt.energy.pipeline import EnergyPipeline
    from scalf_opt.files import write_atomic
    from scalf_opt.io.results import cycle_summary, samples_csv_text, to_json
    from scalf_opt.locomotion.swing.registry import make_family
    from scalf_opt.optimize.pattern_search import PatternSearchOptions
    from scalf_opt.optimize.problem import SwingProblem
    from scalf_opt.optimize.solve import optimize
    from scalf_opt.viz.report import evaluate_report, optimum_report

    legs = LEG_CHOICES[args.leg]
    family = make_family(args.family)
    if family.n_params == 0:
        raise ConfigError(f"--family {args.family}: has no free parameter to optimize")
    if not args.precision > 0:
        raise ConfigError(f"--precision must be > 0, got {args.precision}")
    robot = load_robot(args)
    pipeline = EnergyPipeline(robot, load_gait(args, robot), args.accounting)
    reference = pipeline.robot_cycle(make_family("reference"))
    options = PatternSearchOptions(precision=args.precision)
    optima = {
        leg: optimize(SwingProblem(pipeline, leg, family), args.method, pattern_options=options)
        for leg in legs
    }
    print(optimum_report(optima, reference))
    failed = [o for o in optima.values() if not o.success]
    if failed:
        names = ", ".join(f"{o.leg} ({o.status})" for o in failed)
        print(f"scalf-opt: error: not solved: {names}; no optimum is reported", file=sys.stderr)
        return 3
    # legs neither optimized nor twin of an optimized leg keep the reference swing
    cycle = pipeline.robot_cycle(family, {leg: o.theta for leg, o in optima.items()})
    print()
    print(evaluate_report(cycle, robot.name, title=f"optimized ({family.name}, {args.method})"))
    if args.out is not None:
        data = cycle_summary(cycle)
        data["optimization"] = {leg: o.as_dict() for leg, o in optima.items()}
        data["reference_total_energy_per_cycle_j"] = reference.energy_j
        write_atomic(args.out / "summary.json", to_json(data))
        write_atomic(args.out / "samples.csv", samples_csv_text(cycle))
        print(f"wrote {args.out / 'summary.json'} and {args.out / 'samples.csv'}")
    return 0
