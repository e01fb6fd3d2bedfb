"""``scalf-opt export``: the planned trot for a controller, at any rate, over N cycles."""

from __future__ import annotations

import argparse
from pathlib import Path

from scalf_opt.cli.options import (
    MAX_RATE_HZ,
    Outputs,
    add_robot,
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
        "default when the catalog has it, else give the same --urdf)",
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


def outputs(args: argparse.Namespace) -> Outputs:
    """The exported file, moved into place when it is complete."""
    return Outputs(files={"--out": args.out})
