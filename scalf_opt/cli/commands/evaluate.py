"""``scalf-opt evaluate``: the energy of the reference trajectory, or of a saved optimum."""

from __future__ import annotations

import argparse
from pathlib import Path

from scalf_opt.cli.options import add_gait, add_robot, load_gait, load_robot

NAME = "evaluate"
HELP = "energy of the cubic-spline reference trajectory, or of a saved optimum (--swing)"


def add_arguments(parser: argparse.ArgumentParser) -> None:  # noqa: D103
    add_robot(parser)
    add_gait(parser)
    parser.add_argument(
        "--swing",
        type=Path,
        metavar="FILE",
        help="evaluate the optimum saved in FILE (the summary.json of optimize --out) instead of "
        "the reference; the gait must have its timing (any rate and accounting)",
    )
    parser.add_argument("--out", type=Path, help="write summary.json and samples.csv here")


def run(args: argparse.Namespace) -> int:  # noqa: D103
    from scalf_opt.energy.peaks import cycle_peaks, cycle_violations, peaks_summary
    from scalf_opt.energy.pipeline import EnergyPipeline
    from scalf_opt.files import write_atomic
    from scalf_opt.io.optimum_file import check_timing, read_optimum
    from scalf_opt.io.results import cycle_summary, samples_csv_text, to_json
    from scalf_opt.locomotion.swing.registry import make_family
    from scalf_opt.studies import paper_data
    from scalf_opt.viz.optimization_report import peaks_table, violation_lines
    from scalf_opt.viz.report import evaluate_report

    saved = read_optimum(args.swing) if args.swing is not None else None
    robot = load_robot(args)
    gait = load_gait(args, robot)
    pipeline = EnergyPipeline(robot, gait, args.accounting)
    comparison = None
    if saved is None:
        cycle = pipeline.robot_cycle(make_family("reference"))
        title = "reference"
        if paper_data.is_paper_setup(robot, gait) and args.accounting == "paper":
            comparison = ("paper (Table 6)", paper_data.REFERENCE_AVERAGE_POWER_W)
    else:
        check_timing(saved, gait)
        cycle = pipeline.robot_cycle(make_family(saved.family), saved.thetas)
        title = f"saved optimum ({saved.family}, {args.swing})"
    print(evaluate_report(cycle, robot.name, title=title, comparison=comparison))
    if saved is not None and saved.sample_rate_hz > gait.sample_rate_hz:
        print(
            f"note: the optimum was found at {saved.sample_rate_hz:g} Hz; at "
            f"{gait.sample_rate_hz:g} Hz its energy is resolved less finely"
        )
    physics = {leg: pipeline.physics(leg) for leg in cycle.legs}
    peaks = cycle_peaks(cycle, physics)
    violations = cycle_violations(cycle, physics)
    print()
    print(peaks_table(peaks))
    for line in violation_lines(violations):
        print(line)
    if args.out is not None:
        summary = cycle_summary(cycle)
        summary["peaks"] = peaks_summary(peaks)
        summary["limit_violations"] = [v.message() for v in violations]
        if saved is not None:
            summary["swing_file"] = str(saved.path)
        write_atomic(args.out / "summary.json", to_json(summary))
        write_atomic(args.out / "samples.csv", samples_csv_text(cycle))
        print(f"wrote {args.out / 'summary.json'} and {args.out / 'samples.csv'}")
    return 0
