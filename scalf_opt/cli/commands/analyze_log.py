"""``scalf-opt analyze-log``: the energy in a robot's log (cylinder CSV, export CSV, ROS 2 bag).

The layout of the paper's Table 7; with ``--plan DIR`` the plan beside it, and with ``--figure``
the measured against the planned power over one cycle.
"""

from __future__ import annotations

import argparse
from pathlib import Path
from typing import Any

from scalf_opt.cli.options import (
    add_robot,
    check_output_file,
    load_gait,
    load_robot,
)
from scalf_opt.errors import ConfigError

NAME = "analyze-log"
HELP = (
    "mechanical energy per leg and phase from a robot's log: a cylinder CSV, the CSV of "
    "`export`, or a ROS 2 bag (MCAP, sqlite3)"
)
EXAMPLES = (
    ("scalf-opt analyze-log results/log.csv", "the energy in a cylinder log (paper Table 7)"),
    (
        "scalf-opt analyze-log run.mcap --topic /joint_states --plan results/optimum",
        "a ROS 2 bag against the plan the robot ran",
    ),
    ("scalf-opt analyze-log log.csv --period 0.5 --json", "a log without contacts, as JSON"),
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
        metavar="NAME",
        help="the topic of sensor_msgs/JointState messages: the joints (position, velocity, "
        "effort = angle, rate, torque) or the cylinders (length, speed, force); default: the "
        "bag's only one",
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
        metavar="NAME",
        help="NAME=URDF_JOINT: a name in the messages and the URDF joint (or the joint of the "
        "cylinder) it is; repeat for every leg joint (default: the URDF's own names); other "
        "joints are ignored",
    )
    robot_log = parser.add_argument_group(
        "a robot's own log, every joint (a bag of any message type, a wide CSV)"
    )
    robot_log.add_argument(
        "--mapping",
        metavar="FILE",
        help="where the log keeps each joint: a mapping file (.toml; examples/mappings/) or the "
        "name of a built-in one (joint_state, unitree_go, unitree_legged_msgs); a bag whose "
        "topic is a Unitree LowState is read without it",
    )
    robot_log.add_argument(
        "--odometry",
        metavar="NAME",
        help="a nav_msgs/Odometry topic of the bag: the trunk's speed (the cost of transport)",
    )
    robot_log.add_argument(
        "--speed",
        dest="speed_m_s",
        type=float,
        metavar="X",
        help="the forward speed [m/s] (over the odometry's): the cost of transport",
    )
    robot_log.add_argument(
        "--compare",
        action="store_true",
        help="evaluate the model at the log's measured gait (period, duty, speed, stance height) "
        "and compare every joint's energy; with --figure, their power over a cycle",
    )
    parser.add_argument(
        "--plan",
        type=Path,
        metavar="DIR",
        help="the optimum the robot ran (DIR/summary.json): its gait, and its robot when the "
        "catalog has it, are used, and its energy and power are compared with the log's",
    )
    parser.add_argument(
        "--figure",
        type=Path,
        metavar="FILE",
        help="with --plan: write the measured against the planned power over one cycle",
    )
    add_robot(parser)
    parser.add_argument(
        "--period",
        dest="period_s",
        type=float,
        metavar="X",
        help="the log's gait period [s] (default: the median time between its touch-downs, "
        "else the motion's period, else the gait file's, else the robot's default trot's)",
    )
    parser.add_argument(
        "--gait",
        type=Path,
        metavar="FILE",
        help="gait file whose timing is used when the log has no contact column",
    )


def run(args: argparse.Namespace) -> int:  # noqa: D103
    from scalf_opt.api import analyze_log
    from scalf_opt.api.robot_logs import robot_log_mapping
    from scalf_opt.logs.report import log_report

    mapping = robot_log_mapping(
        args.log, args.topic, args.mapping, args.odometry, args.speed_m_s, args.compare
    )
    if mapping is not None:
        return run_robot_log(args, mapping)
    if args.figure is not None and args.plan is None:
        raise ConfigError("--figure: draws the log against the plan: give --plan DIR too")
    if args.figure is not None and args.figure.suffix != ".png":
        raise ConfigError(f"--figure {args.figure}: give a .png file")
    check_output_file(args.figure, "--figure")
    robot = load_robot(args, args.plan)
    # --period is the log's period; without it, the contacts', the motion's, the gait's
    period = args.period_s
    if args.plan is not None:
        if args.gait is not None:
            raise ConfigError("--gait and --plan: the plan brings its own gait")
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
    args.console.text(log_report(result.analysis, source, result.report_kind).rstrip("\n"))
    data = result.to_dict()
    if "plan_comparison" in data:
        args.console.text(plan_report(data["plan_comparison"]))
    args.console.json(data)
    for path in written:
        args.console.text(f"wrote {path}")
    return 0


def run_robot_log(args: argparse.Namespace, mapping: Any) -> int:
    """A robot's own log, every joint, read through ``mapping`` (its topic chosen)."""
    from scalf_opt.api import analyze_robot_log
    from scalf_opt.logs.robot_report import robot_log_report

    for given, option in (
        (args.plan, "--plan"),
        (args.signals, "--signals"),
        (args.joints, "--joint"),
        (args.period_s, "--period"),
        (args.gait, "--gait"),
    ):
        if given:
            raise ConfigError(
                f"{option} is for a log of the sagittal joints; a robot's own log (every joint, "
                "--mapping) measures its gait and compares with the model by --compare"
            )
    if args.figure is not None:
        if not args.compare:
            raise ConfigError("--figure: draws the log against the model: give --compare too")
        if args.figure.suffix != ".png":
            raise ConfigError(f"--figure {args.figure}: give a .png file")
    check_output_file(args.figure, "--figure")
    robot = load_robot(args, None)
    result = analyze_robot_log(
        args.log,
        robot,
        mapping=mapping,
        odometry_topic=args.odometry,
        speed_m_s=args.speed_m_s,
        compare=args.compare,
        command=args.argv,
    )
    written = [result.write_figure(args.figure)] if args.figure is not None else []
    data = result.to_dict()
    args.console.text(robot_log_report(data))
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
