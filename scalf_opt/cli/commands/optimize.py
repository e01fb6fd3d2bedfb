"""``scalf-opt optimize``: optimize the swing of one or more legs."""

from __future__ import annotations

import argparse
import sys
from pathlib import Path
from typing import TYPE_CHECKING, Any

from scalf_opt.cli.options import add_gait, add_robot, load_gait, load_robot
from scalf_opt.errors import ConfigError
from scalf_opt.locomotion.swing.names import DEFAULT_FAMILY
from scalf_opt.types import FIRST_PAIR, LEG_NAMES, Method, choices

if TYPE_CHECKING:
    from scalf_opt.energy.cycle import RobotCycle
    from scalf_opt.energy.pipeline import EnergyPipeline
    from scalf_opt.locomotion.swing.family import SwingFamily
    from scalf_opt.optimize.driver import Settings

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
    parser.add_argument(
        "--method",
        choices=choices(Method),
        default="ipopt",
        help="ipopt (default), pattern (the paper's pattern search), or free: the "
        "free-trajectory bound (dense B-splines refined until the energy converges; no family)",
    )
    parser.add_argument(
        "--precision", type=float, default=0.1, help="pattern-search precision (default 0.1)"
    )
    parser.add_argument(
        "--starts",
        type=int,
        default=1,
        help="deterministic starts per leg (default 1; the first is the default start): the "
        "best is kept, the spread reported",
    )
    parser.add_argument(
        "--bound",
        action="store_true",
        help="also compute the free-trajectory bound and report each optimum's gap to it",
    )
    parser.add_argument(
        "--free-stance",
        action="store_true",
        help="beyond the paper: also optimize the stance height z0 and the stance x-offsets "
        "(front and hind) within the joint limits, reach, stroke and clearance; reports how "
        "much of the saving comes from the stance and how much from the swing",
    )
    parser.add_argument("--out", type=Path, help="write summary.json and samples.csv here")


def _settings(args: argparse.Namespace) -> Settings:
    from scalf_opt.optimize.driver import Settings
    from scalf_opt.optimize.pattern_search import PatternSearchOptions

    if not args.precision > 0:
        raise ConfigError(f"--precision must be > 0, got {args.precision}")
    return Settings(
        method=args.method,
        starts=args.starts,
        pattern=PatternSearchOptions(precision=args.precision),
    )


def run(args: argparse.Namespace) -> int:
    """Exit 0 when every leg is solved, 3 when an optimizer fails."""
    from scalf_opt.energy.pipeline import EnergyPipeline
    from scalf_opt.locomotion.swing.names import parse_bspline_name
    from scalf_opt.locomotion.swing.registry import make_family

    legs = LEG_CHOICES[args.leg]
    settings = _settings(args)
    if parse_bspline_name(args.family) is not None:
        raise ConfigError(f"--family {args.family}: B-splines are the free method's: --method free")
    family = make_family(args.family)
    if family.n_params == 0:
        raise ConfigError(f"--family {args.family}: has no free parameter to optimize")
    if args.free_stance and (args.method == "free" or args.leg != "pair"):
        raise ConfigError(
            "--free-stance optimizes the diagonal pair's swings with a family: use it with "
            "--leg pair and --method ipopt or pattern"
        )
    robot = load_robot(args)
    pipeline = EnergyPipeline(robot, load_gait(args, robot), args.accounting)
    if args.free_stance:
        outcome = _free_stance(pipeline, family, settings)
    elif args.method == "free":
        outcome = _free_method(pipeline, legs)
    else:
        outcome = _family_method(args, pipeline, legs, family, settings)
    if outcome is None:
        return 3
    _finish(args, *outcome)
    return 0


Outcome = tuple["EnergyPipeline", "RobotCycle", "RobotCycle", dict[str, Any]]
"""What :func:`_finish` reports and writes: the pipeline at the result's rate, the optimized
cycle, the reference cycle, and the records for ``summary.json``."""


def _family_method(
    args: argparse.Namespace,
    pipeline: EnergyPipeline,
    legs: tuple[str, ...],
    family: SwingFamily,
    settings: Settings,
) -> Outcome | None:
    """Pattern search or Ipopt on a family (and the bound with ``--bound``)."""
    from scalf_opt.io.optimum_file import optimization_record
    from scalf_opt.optimize.bound import bound_for
    from scalf_opt.optimize.driver import optimize_swings
    from scalf_opt.viz.optimization_report import optimization_report, optimization_warnings
    from scalf_opt.viz.report import evaluate_report

    run = optimize_swings(pipeline, legs, family, settings)
    data: dict[str, Any] = {}
    if args.bound and run.success:
        data["free_bound"] = {}
        for leg, result in run.legs.items():
            bound = bound_for(pipeline, leg, [(family, result.best.theta)])
            result.bound_check_energy_j = bound.check_energy_j
            data["free_bound"][leg] = bound.as_dict()
    print(optimization_report(run))
    for line in optimization_warnings(run):
        print(line)
    if not run.success:
        failed = [f"{r.leg} ({r.best.status})" for r in run.legs.values() if not r.success]
        if not run.converged_sampling:
            failed.append(f"the sampling did not converge by {run.rate_hz:g} Hz")
        print(
            f"scalf-opt: error: not solved: {', '.join(failed)}; no optimum is reported",
            file=sys.stderr,
        )
        return None
    data["optimization"] = {leg: r.as_dict() for leg, r in run.legs.items()}
    data["optimization_run"] = optimization_record(run)
    cycle = run.cycle()
    print()
    title = f"optimized ({family.name}, {settings.method})"
    print(evaluate_report(cycle, pipeline.robot.name, title=title))
    return run.pipeline, cycle, run.reference_cycle(), data


def _free_method(pipeline: EnergyPipeline, legs: tuple[str, ...]) -> Outcome | None:
    """The free-trajectory bound of each leg, reported as an optimum."""
    from scalf_opt.locomotion.swing.registry import make_family
    from scalf_opt.optimize.bound import bound_cycle_inputs, bound_for
    from scalf_opt.optimize.driver import check_bounded
    from scalf_opt.viz.optimization_report import bound_report
    from scalf_opt.viz.report import evaluate_report

    check_bounded(pipeline, legs)
    bounds = {leg: bound_for(pipeline, leg) for leg in legs}
    print(bound_report(bounds))
    if not all(b.success for b in bounds.values()):
        print("scalf-opt: error: the free-trajectory bound did not converge", file=sys.stderr)
        return None
    at_rate, family, thetas = bound_cycle_inputs(pipeline, bounds)
    data: dict[str, Any] = {
        "optimization": {
            leg: {
                **b.result.as_dict(),
                "family": family.name,
                "method": "free",
                "parameters": dict(
                    zip(family.parameter_names, map(float, thetas[leg]), strict=True)
                ),
            }
            for leg, b in bounds.items()
        },
        "free_bound": {leg: b.as_dict() for leg, b in bounds.items()},
    }
    cycle = at_rate.robot_cycle(family, thetas)
    print()
    title = f"free-trajectory bound ({family.name})"
    print(evaluate_report(cycle, pipeline.robot.name, title=title))
    return at_rate, cycle, at_rate.robot_cycle(make_family("reference")), data


def _free_stance(
    pipeline: EnergyPipeline, family: SwingFamily, settings: Settings
) -> Outcome | None:
    """The stance height and x-offsets optimized together with the swings."""
    from scalf_opt.io.optimum_file import optimization_record
    from scalf_opt.optimize.free_stance import optimize_stance
    from scalf_opt.viz.optimization_report import (
        free_stance_report,
        optimization_report,
        optimization_warnings,
    )
    from scalf_opt.viz.report import evaluate_report

    result = optimize_stance(pipeline, family, settings)
    run = result.best.run
    if run is None or not result.success:
        print(
            f"scalf-opt: error: the stance search did not converge ({result.best.reason})",
            file=sys.stderr,
        )
        return None
    print(optimization_report(run))
    for line in optimization_warnings(run):
        print(line)
    print()
    print(free_stance_report(result))
    cycle = result.cycle()
    print()
    title = f"free stance ({family.name}, {settings.method})"
    print(evaluate_report(cycle, pipeline.robot.name, title=title))
    data: dict[str, Any] = {
        "optimization": {leg: r.as_dict() for leg, r in run.legs.items()},
        "optimization_run": optimization_record(run),
        "free_stance": result.as_dict(),
    }
    return run.pipeline, cycle, result.reference, data


def _finish(
    args: argparse.Namespace,
    pipeline: EnergyPipeline,
    cycle: RobotCycle,
    reference: RobotCycle,
    data: dict[str, Any],
) -> None:
    """Peaks and limits, then the files."""
    from scalf_opt.energy.peaks import cycle_peaks, cycle_violations, peaks_summary
    from scalf_opt.files import write_atomic
    from scalf_opt.io.results import cycle_summary, samples_csv_text, to_json
    from scalf_opt.viz.optimization_report import peaks_table, violation_lines

    physics = {leg: pipeline.physics(leg) for leg in cycle.legs}
    peaks = cycle_peaks(cycle, physics)
    violations = cycle_violations(cycle, physics)
    print()
    print(peaks_table(peaks, cycle_peaks(reference, physics)))
    for line in violation_lines(violations):
        print(line)
    if args.out is None:
        return
    summary = cycle_summary(cycle)
    summary.update(data)
    summary["reference_total_energy_per_cycle_j"] = reference.energy_j
    summary["peaks"] = peaks_summary(peaks)
    summary["limit_violations"] = [v.message() for v in violations]
    write_atomic(args.out / "summary.json", to_json(summary))
    write_atomic(args.out / "samples.csv", samples_csv_text(cycle))
    print(f"wrote {args.out / 'summary.json'} and {args.out / 'samples.csv'}")
