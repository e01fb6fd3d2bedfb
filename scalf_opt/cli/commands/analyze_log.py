"""``scalf-opt analyze-log``: the energy in a robot's log (cylinder CSV, export CSV, ROS 2 bag).

The layout of the paper's Table 7; with ``--plan DIR`` the plan beside it, and with ``--figure``
the measured against the planned power over one cycle.
"""

from __future__ import annotations

import argparse
from pathlib import Path
from typing import Any

from scalf_opt.cli.options import (
    GAIT_OPTIONS,
    add_gait,
    add_robot,
    check_output_file,
    gait_overrides,
    load_gait,
    load_robot,
)
from scalf_opt.errors import ConfigError

NAME = "analyze-log"
HELP = (
    "mechanical energy per leg and phase from a robot's log: a cylinder CSV, the CSV of "
    "`export`, or a ROS 2 bag (MCAP, sqlite3)"
)
JSON = True


def joint_pair(text: str) -> tuple[str, str]:
    """``NAME=URDF_JOINT`` for argparse ``type=``."""
    name, sep, joint = text.partition("=")
    if not sep or not name.strip() or not joint.strip():
        raise argparse.ArgumentTypeError(f"{text!r} is not NAME=URDF_JOINT")
    return name.strip(), joint.strip()


def add_arguments(parser: argparse.ArgumentParser) -> None:  # noqa: D103
    parser.add_argument(
        "log", type=Path, metavar="FILE", help="the log: .csv, .mcap, .db3 or a ROS 2 bag folder"
    )
    bag = parser.add_argument_group("ROS 2 bags (extra 'ros')")
    bag.add_argument(
        "--topic",
        help="the topic of sensor_msgs/JointState messages: the joints (position, velocity, "
        "effort = angle, rate, torque) or the cylinders (length, speed, force)",
    )
    bag.add_argument(
        "--signals",
        choices=("joints", "cylinders"),
        help="what the topic holds (default: the joints if it names a URDF joint, else the "
        "cylinders, named <joint>_cylinder)",
    )
    bag.add_argument(
        "--joint",
        dest="joints",
        action="append",
        type=joint_pair,
        metavar="NAME=URDF_JOINT",
        help="a name in the messages and the URDF joint (or the joint of the cylinder) it is; "
        "repeat for every leg joint (default: the URDF's own names); other joints are ignored",
    )
    parser.add_argument(
        "--plan",
        type=Path,
        metavar="DIR",
        help="the optimum the robot ran (DIR/summary.json): its gait is used, and its energy "
        "and power are compared with the log's",
    )
    parser.add_argument(
        "--figure",
        type=Path,
        metavar="FILE.png",
        help="with --plan: write the measured against the planned power over one cycle",
    )
    add_robot(parser)
    add_gait(parser, accounting=False)


def run(args: argparse.Namespace) -> int:  # noqa: D103
    from scalf_opt.api import analyze_log
    from scalf_opt.logs.report import log_report

    if args.figure is not None and args.plan is None:
        raise ConfigError("--figure: draws the log against the plan: give --plan DIR too")
    if args.figure is not None and args.figure.suffix != ".png":
        raise ConfigError(f"--figure {args.figure}: give a .png file")
    check_output_file(args.figure, "--figure")
    robot = load_robot(args)
    overrides = gait_overrides(args)
    # --period is the log's period; without it, the contacts', the motion's, the gait's
    period = overrides.get("period_s")
    if args.plan is not None:
        others = [GAIT_OPTIONS[f][0] for f in overrides if f != "period_s"]
        if args.gait is not None or others:
            given = "--gait" if args.gait is not None else others[0]
            raise ConfigError(f"{given} and --plan: the plan brings its own gait")
        gait = None
    else:
        gait = load_gait(args, robot)
    names = dict(args.joints) if args.joints else None
    if names is not None and len(names) != len(args.joints):
        raise ConfigError("--joint: a name is mapped twice")
    result = analyze_log(
        args.log,
        robot,
        gait,
        period_s=period,
        command=args.argv,
        topic=args.topic,
        joint_names=names,
        signals=args.signals,
        plan=args.plan,
    )
    written = [result.write_figure(args.figure)] if args.figure is not None else []
    source = result.measured.velocity_source if result.measured is not None else "filter"
    kind = "joint" if result.joint_log else "cylinder"
    args.console.text(log_report(result.analysis, source, kind).rstrip("\n"))
    data = result.to_dict()
    if "plan_comparison" in data:
        args.console.text(plan_report(data["plan_comparison"]))
    args.console.json(data)
    for path in written:
        args.console.text(f"wrote {path}")
    return 0


def plan_report(comparison: dict[str, Any]) -> str:
    """The log against the plan: per leg and for the robot."""
    lines = [
        "",
        f"against the plan {comparison['plan']} (mechanical energy sum |tau qd| per cycle)",
        "leg   measured [J]   planned [J]   change",
    ]
    for leg, v in comparison["legs"].items():
        lines.append(
            f"{leg:4s}  {v['measured_j']:12.3f}  {v['planned_j']:12.3f}  "
            f"{_signed(v['change_percent']):+7.2f} %"
        )
    lines.append(
        f"average power: {comparison['measured_average_power_w']:.2f} W measured, "
        f"{comparison['planned_average_power_w']:.2f} W planned "
        f"({_signed(comparison['change_percent']):+.2f} %)"
    )
    return "\n".join(lines)


def _signed(percent: float) -> float:
    """``percent`` rounded to the printed 0.01, without a sign on zero (no "-0.00 %")."""
    return round(percent, 2) + 0.0
