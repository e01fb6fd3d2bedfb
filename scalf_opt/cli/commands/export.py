"""``scalf-opt export``: the planned trot for a controller, at any rate, over N cycles."""

from __future__ import annotations

import argparse
import math
from pathlib import Path

from scalf_opt.cli.options import (
    MAX_RATE_HZ,
    Outputs,
    add_robot,
    add_source_model,
    bounded,
    check_not_the_source,
    check_output_file,
    load_robot,
)
from scalf_opt.errors import ConfigError

NAME = "export"
HELP = (
    "the optimized trot for a controller: per leg and joint angle, velocity, acceleration, "
    "feed-forward torque, contact, foot position, cylinders (CSV, JSON or a ROS 2 bag)"
)
EXAMPLES = (
    (
        "scalf-opt export --from results/optimum --rate 1000 --out plan.csv",
        "the saved optimum at 1 kHz, one row per instant and leg",
    ),
    (
        "scalf-opt export --from results/optimum --rate 500 --cycles 10 --out plan.mcap",
        "ten cycles as a ROS 2 bag",
    ),
    (
        "scalf-opt export --robot hyq --from results/hyq --rate 1000 --out hyq.json",
        "another robot's optimum as JSON",
    ),
    (
        "scalf-opt export --from results/go1-3d --rate 500 --cycles 4 --out go1.csv",
        "a 3-D cycle (optimize --model 3d --out): the whole robot per instant, wide",
    ),
)
FORMATS = (".csv", ".json", ".mcap")
"""``scalf_opt.io.plan_export.EXPORT_FORMATS``, the writers' suffixes (a test checks they agree:
the command line does not import the writers before it runs)."""

MAX_CYCLES = 1000
"""Most cycles exported: ``scalf_opt.io.plan_export.MAX_CYCLES``, which the command line does not
import (it pulls in CasADi; a test checks they agree)."""


def add_arguments(parser: argparse.ArgumentParser) -> None:  # noqa: D103
    parser.add_argument(
        "--from",
        dest="source",
        type=Path,
        required=True,
        metavar="DIR",
        help="the optimum: DIR/summary.json as `optimize --out DIR` writes it (its robot by "
        "default when the catalog has it, else give the same --urdf); a 3-D cycle's folder "
        "(optimize or gait --model 3d) exports the whole robot",
    )
    add_source_model(
        parser,
        "exported one row per instant with the trunk's pose, velocities and accelerations, every "
        "joint's angle, velocity, acceleration and torque, every foot's force (CSV or JSON)",
    )
    parser.add_argument(
        "--rate",
        type=bounded(float, MAX_RATE_HZ),
        required=True,
        metavar="X",
        help="sample rate [Hz], at most 100000; a sample falls on every touch-down and lift-off: "
        "a rate that "
        "puts none there becomes the nearest that does (the paper's trot: any multiple of 4 Hz)",
    )
    parser.add_argument(
        "--out",
        type=Path,
        required=True,
        metavar="FILE",
        help="FILE.csv (a row per instant and leg), FILE.json, or FILE.mcap (a ROS 2 bag of "
        "sensor_msgs/JointState and trajectory_msgs/JointTrajectory; extra 'ros')",
    )
    parser.add_argument(
        "--cycles",
        type=bounded(int, MAX_CYCLES),
        metavar="N",
        default=1,
        help=f"gait cycles, repeated seamlessly, 1..{MAX_CYCLES} (default 1)",
    )
    add_robot(parser)


def run(args: argparse.Namespace) -> int:  # noqa: D103
    from scalf_opt.api import export_plan

    if args.out.suffix not in FORMATS:
        raise ConfigError(
            f"--out {args.out}: unknown format {args.out.suffix or '(no suffix)'!r} "
            f"(give {', '.join(FORMATS)})"
        )
    check_output_file(args.out, "--out")
    check_not_the_source(args.out, args.source, "--out")
    from scalf_opt.io.whole_body_export import is_3d_cycle

    three_d = is_3d_cycle(args.source)
    if args.model == "3d" and not three_d:
        raise ConfigError(
            f"--from {args.source}: not a 3-D cycle (no plan.csv beside a summary.json of "
            "model 3d; optimize --model 3d --out DIR writes one)",
            field="source",
        )
    if three_d and args.model != "sagittal":
        return _run_3d(args)
    robot = load_robot(args, args.source)
    result = export_plan(
        args.source, robot, rate_hz=args.rate, cycles=args.cycles, command=args.argv
    )
    path = result.write(args.out)
    export = result.export
    joints = [name for pair in export.joints.values() for name in pair]
    cylinders = ", cylinder length, speed and force" if export.has_cylinders else ""
    args.console.text(
        f"{export.saved.label}: {result.samples} instants per leg at {export.rate_hz:.6g} Hz "
        f"({export.cycles} cycle{'s' if export.cycles > 1 else ''} of "
        f"{export.saved.gait.period_s:g} s), joints {', '.join(joints)}"
    )
    args.console.text(
        "per joint: angle, velocity, acceleration, feed-forward torque; per leg: contact, foot "
        f"(x, z) in the hip frame{cylinders}"
    )
    if export.rate_hz != export.requested_rate_hz:
        period = export.saved.gait.period_s
        args.console.text(
            f"note: {export.rate_hz:.6g} Hz, not {export.requested_rate_hz:g} Hz: the nearest rate "
            f"that puts a sample on every touch-down and lift-off of the {period:g} s cycle "
            f"({round(export.rate_hz * period)} samples); the time stamps are exact"
        )
    if path.suffix == ".mcap":
        args.console.text("topics: " + "\n        ".join(export.bag_topic_lines()))
    args.console.text(f"wrote {path}")
    return 0


def _run_3d(args: argparse.Namespace) -> int:
    """Export a 3-D cycle at ``--rate`` over ``--cycles`` (``.csv`` or ``.json``)."""
    from scalf_opt.energy.whole_body import WholeBodyPhysics
    from scalf_opt.files import write_atomic
    from scalf_opt.io.whole_body_dense import DENSE_FORMATS, dense_export
    from scalf_opt.io.whole_body_export import read_cycle, saved_plan

    if args.out.suffix not in DENSE_FORMATS:
        raise ConfigError(
            f"--out {args.out}: a 3-D cycle is exported to {' or '.join(DENSE_FORMATS)} (a ROS 2 "
            "bag holds the sagittal export's messages)",
            field="out",
        )
    saved = read_cycle(args.source)
    if args.robot is None and args.urdf is None:
        args.robot = saved.summary.get("robot")
    robot = load_robot(args)
    plan = saved_plan(saved, WholeBodyPhysics.of(robot))
    accounting = saved.summary.get("accounting", "paper")
    export = dense_export(plan, accounting, args.rate, args.cycles)
    text = export.csv_text() if args.out.suffix == ".csv" else export.json_text(robot.name)
    path = write_atomic(args.out, text)
    n = export.samples_per_cycle * export.cycles
    args.console.text(
        f"3-D cycle of {robot.name} from {args.source}: {n} instants at {export.rate_hz:.6g} Hz "
        f"({export.cycles} cycle{'s' if export.cycles > 1 else ''} of {export.period_s:g} s), "
        f"{len(export.columns)} columns: the trunk's pose, velocities and accelerations (world "
        "frame), every joint's angle, velocity, acceleration and torque, every foot's force"
    )
    if not math.isclose(export.rate_hz, export.requested_rate_hz, rel_tol=1e-9):
        args.console.text(
            f"note: {export.rate_hz:.6g} Hz, not {export.requested_rate_hz:g} Hz: a whole number "
            f"of samples between the plan's nodes ({plan.schedule.intervals} per cycle), so a "
            "sample falls on every node, touch-down and lift-off"
        )
    args.console.text(f"wrote {path}")
    return 0


def outputs(args: argparse.Namespace) -> Outputs:
    """The exported file, moved into place when it is complete."""
    return Outputs(files={"--out": args.out})
