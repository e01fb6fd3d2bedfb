"""``scalf-opt model``: a leg's parameters as Pinocchio sees them."""

from __future__ import annotations

import argparse

from scalf_opt.cli.options import GAIT_OPTIONS, add_leg, add_robot, bounded, load_robot
from scalf_opt.locomotion.gait import MAX_GAIT_LENGTH_M

NAME = "model"
HELP = "print a leg's parameters as Pinocchio sees them"
EXAMPLES = (
    ("scalf-opt model", "SCalf's RF leg: masses, lengths, inertias, limits, drives, posture"),
    ("scalf-opt model --robot hyq --leg LH", "another robot, another leg"),
    ("scalf-opt model --urdf my_robot.urdf --json", "any quadruped's URDF, as JSON"),
)
JSON = True


def add_arguments(parser: argparse.ArgumentParser) -> None:  # noqa: D103
    add_robot(parser)
    add_leg(parser)
    parser.add_argument(
        "--stance-height",
        type=bounded(float, MAX_GAIT_LENGTH_M),
        metavar="X",
        help=GAIT_OPTIONS["stance_height_m"][2],
    )


def run(args: argparse.Namespace) -> int:  # noqa: D103
    from scalf_opt.actuators.sidecar import drives_for, leg_drives
    from scalf_opt.api import read_gait
    from scalf_opt.io.model_summary import model_summary
    from scalf_opt.viz.report import model_report

    robot = load_robot(args)
    leg = robot.leg(args.leg)
    height = args.stance_height or read_gait(robot=robot).stance_height_m
    drives = leg_drives(drives_for(robot), leg.joint_names)
    from scalf_opt.io.provenance import provenance

    data = {
        "provenance": provenance(robot, args.argv),
        **model_summary(robot, args.leg, drives, height),
    }
    args.console.text(model_report(data))
    args.console.json(data)
    return 0
