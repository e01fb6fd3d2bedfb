"""``scalf-opt model``: a leg's parameters as Pinocchio sees them."""

from __future__ import annotations

import argparse

from scalf_opt.cli.options import add_robot, load_robot
from scalf_opt.types import LEG_NAMES

NAME = "model"
HELP = "print a leg's parameters as Pinocchio sees them"


def add_arguments(parser: argparse.ArgumentParser) -> None:  # noqa: D103
    add_robot(parser)
    parser.add_argument("--leg", default="RF", choices=LEG_NAMES, help="the leg (default RF)")
    parser.add_argument(
        "--stance-height",
        type=float,
        help="hip height of the posture shown [m] (default: the robot's nominal stance height)",
    )


def run(args: argparse.Namespace) -> int:  # noqa: D103
    from scalf_opt.actuators.sidecar import drives_for, leg_drives
    from scalf_opt.locomotion.scaling import default_gait_for
    from scalf_opt.viz.report import model_report

    robot = load_robot(args)
    leg = robot.leg(args.leg)
    height = args.stance_height or default_gait_for(robot).stance_height_m
    print(model_report(robot, args.leg, leg_drives(drives_for(robot), leg.joint_names), height))
    return 0
