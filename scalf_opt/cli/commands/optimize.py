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


def _settings(args: argparse.Namespace) -> Any:
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
    from scalf_opt.optimize.bound import bound_cycle_inputs, bound_for
    from scalf_opt.optimize.driver import check_bounded, optimize_swings
    from scalf_opt.viz.optimization_report import (
        bound_report,
        optimization_report,
        optimization_warnings,
    )
    from scalf_opt.viz.report import evaluate_report

    legs = LEG_CHOICES[args.leg]
    settings = _settings(args)
    if parse_bspline_name(args.family) is not None:
        raise ConfigError(f"--family {args.family}: B-splines are the free method's: --method free")
    family = make_family(args.family)
    if family.n_params == 0:
        raise ConfigError(f"--family {args.family}: has no free parameter to optimize")
    robot = load_robot(args)
    pipeline = EnergyPipeline(robot, load_gait(args, robot), args.accounting)
    data: dict[str, Any] = {}
    if args.free_stance:
        if args.method == "free" or args.leg != "pair":
            raise ConfigError(
                "--free-stance optimizes the diagonal pair's swings with a family: use it with "
                "--leg pair and --method ipopt or pattern"
            )
        return _free_stance(args, pipeline, family, settings)
    if args.method == "free":
        check_bounded(pipeline, legs)
        bounds = {leg: bound_for(pipeline, leg) for leg in legs}
        print(bound_report(bounds))
        if not all(b.success for b in bounds.values()):
            print("scalf-opt: error: the free-trajectory bound did not converge", file=sys.stderr)
            return 3
        at_rate, family, thetas = bound_cycle_inputs(pipeline, bounds)
        data["optimization"] = {
            leg: {
                **b.result.as_dict(),
                "family": family.name,
                "parameters": dict(
                    zip(family.parameter_names, map(float, thetas[leg]), strict=True)
                ),
            }
            for leg, b in bounds.items()
        }
        data["free_bound"] = {leg: b.as_dict() for leg, b in bounds.items()}
        title = f"free-trajectory bound ({family.name})"
    else:
        run_ = optimize_swings(pipeline, legs, family, settings)
        if args.bound and run_.success:
            for leg, result in run_.legs.items():
                bound = bound_for(pipeline, leg, [(family, result.best.theta)])
                result.bound_check_energy_j = bound.check_energy_j
                data.setdefault("free_bound", {})[leg] = bound.as_dict()
        print(optimization_report(run_))
        for line in optimization_warnings(run_):
            print(line)
        if not run_.success:
            names = ", ".join(
                f"{r.leg} ({r.best.status})" for r in run_.legs.values() if not r.success
            )
            if run_.converged_sampling or not names:
                names = names or "the sampling did not converge"
            print(f"scalf-opt: error: not solved: {names}; no optimum is reported", file=sys.stderr)
            return 3
        at_rate, thetas = run_.pipeline, run_.thetas
        data["optimization"] = {leg: r.as_dict() for leg, r in run_.legs.items()}
        from scalf_opt.io.optimum_file import optimization_record

        data["optimization_run"] = optimization_record(run_)
        title = f"optimized ({family.name}, {args.method})"
    cycle = at_rate.robot_cycle(family, thetas)
    reference = at_rate.robot_cycle(make_family("reference"))
    print()
    print(evaluate_report(cycle, robot.name, title=title))
    _finish(args, at_rate, cycle, reference, data)
    return 0


def _free_stance(args: argparse.Namespace, pipeline: Any, family: Any, settings: Any) -> int:
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
        return 3
    print(optimization_report(run))
    for line in optimization_warnings(run):
        print(line)
    print()
    print(free_stance_report(result))
    cycle = result.cycle()
    print()
    print(evaluate_report(cycle, pipeline.robot.name, title=f"free stance ({family.name})"))
    from scalf_opt.io.optimum_file import optimization_record

    data = {
        "optimization": {leg: r.as_dict() for leg, r in run.legs.items()},
        "optimization_run": optimization_record(run),
        "free_stance": result.as_dict(),
    }
    _finish(args, run.pipeline, cycle, result.reference, data)
    return 0


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
