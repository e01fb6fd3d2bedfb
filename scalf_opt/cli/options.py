"""Options several commands share (robot, gait, accounting) and what they load."""

from __future__ import annotations

import argparse
from pathlib import Path
from typing import TYPE_CHECKING

from scalf_opt.robots.catalog import robot_names
from scalf_opt.types import Accounting, choices

if TYPE_CHECKING:
    from scalf_opt.locomotion.gait import Gait
    from scalf_opt.model.robot import Robot


def add_robot(parser: argparse.ArgumentParser) -> None:
    """``--urdf PATH`` or ``--robot NAME``."""
    group = parser.add_mutually_exclusive_group()
    group.add_argument("--urdf", type=Path, help="URDF file (default: SCalf's)")
    group.add_argument("--robot", choices=robot_names(), help="a known robot instead of --urdf")


def add_gait(parser: argparse.ArgumentParser, accounting: bool = True) -> None:
    """``--gait FILE`` and, unless told otherwise, ``--accounting``."""
    parser.add_argument(
        "--gait",
        type=Path,
        help="gait file (TOML); fields left out take the robot's default (the paper's trot "
        "scaled to its leg length)",
    )
    if accounting:
        parser.add_argument(
            "--accounting",
            choices=choices(Accounting),
            default="paper",
            help="joint power accounting (default: the paper's |tau*qd| + drive losses)",
        )


def load_robot(args: argparse.Namespace) -> Robot:
    """The robot named by ``--urdf`` or ``--robot`` (default: SCalf)."""
    from scalf_opt.robots.loading import load_robot as load

    return load(name=args.robot, urdf=args.urdf)


def load_gait(args: argparse.Namespace, robot: Robot) -> Gait:
    """The gait of ``--gait`` over the robot's default gait."""
    from scalf_opt.locomotion.gait_file import read_gait
    from scalf_opt.locomotion.scaling import default_gait_for

    base = default_gait_for(robot)
    return read_gait(args.gait, base) if args.gait is not None else base
