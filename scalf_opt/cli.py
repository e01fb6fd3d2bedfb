"""The ``scalf-opt`` command line.

Every user mistake (:class:`~scalf_opt.errors.ScalfError`) ends as one line on stderr and exit
code 2, with no traceback; output files are written atomically, so nothing half-written remains.
"""

from __future__ import annotations

import argparse
import sys
from collections.abc import Sequence
from pathlib import Path

from scalf_opt.errors import ScalfError
from scalf_opt.gait import GaitSpec
from scalf_opt.robot import Robot


def _add_urdf(parser: argparse.ArgumentParser) -> None:
    group = parser.add_mutually_exclusive_group()
    group.add_argument("--urdf", type=Path, help="URDF file (default: the repository's SCalf)")
    group.add_argument(
        "--robot", choices=("scalf", "hyq", "solo12"), help="a known robot instead of --urdf"
    )


def _add_gait(parser: argparse.ArgumentParser) -> None:
    parser.add_argument("--gait", type=Path, help="gait file (TOML); default: the paper's trot")
    parser.add_argument(
        "--accounting",
        choices=("paper", "positive", "regenerative"),
        default="paper",
        help="joint power accounting (default: the paper's |tau*qd| + friction heat)",
    )


def build_parser() -> argparse.ArgumentParser:
    """The argument parser of every sub-command."""
    parser = argparse.ArgumentParser(
        prog="scalf-opt",
        description="Energy-efficient swing-foot trajectories for legged robots (SCalf paper).",
    )
    sub = parser.add_subparsers(dest="command", required=True, metavar="COMMAND")

    p = sub.add_parser("model", help="print a leg's parameters as Pinocchio sees them")
    _add_urdf(p)
    p.add_argument("--leg", default="RF", help="RF, LF, RH or LH (default RF)")
    p.add_argument("--stance-height", type=float, help="hip height for the posture [m]")

    p = sub.add_parser("evaluate", help="energy of the cubic-spline reference trajectory")
    _add_urdf(p)
    _add_gait(p)
    p.add_argument("--out", type=Path, help="write summary.json and samples.csv here")
    return parser


def load_robot(args: argparse.Namespace) -> Robot:
    """The robot named by ``--urdf`` or ``--robot``."""
    if getattr(args, "robot", None):
        return Robot.from_preset(args.robot)
    return Robot.from_urdf(args.urdf)


def load_gait(args: argparse.Namespace, robot: Robot | None = None) -> GaitSpec:
    """The gait of ``--gait`` or the paper's default (at the robot's stance height)."""
    if args.gait is not None:
        return GaitSpec.from_toml(args.gait)
    if robot is not None and robot.preset.name != "scalf":
        return GaitSpec().with_(stance_height_m=robot.preset.stance_height_m)
    return GaitSpec()


def cmd_model(args: argparse.Namespace) -> int:
    """``scalf-opt model``."""
    from scalf_opt.report import model_report

    robot = load_robot(args)
    print(model_report(robot, args.leg, args.stance_height))
    return 0


def cmd_evaluate(args: argparse.Namespace) -> int:
    """``scalf-opt evaluate``."""
    from scalf_opt.cycle import RobotEnergyModel
    from scalf_opt.report import evaluate_report
    from scalf_opt.results import cycle_summary, samples_csv_text, to_json, write_atomic
    from scalf_opt.swing import make_family

    robot = load_robot(args)
    gait = load_gait(args, robot)
    model = RobotEnergyModel(robot, gait, args.accounting)
    cycle = model.robot_cycle(make_family("reference"))
    print(evaluate_report(cycle, robot))
    if args.out is not None:
        write_atomic(args.out / "summary.json", to_json(cycle_summary(cycle)))
        write_atomic(args.out / "samples.csv", samples_csv_text(cycle))
        print(f"wrote {args.out / 'summary.json'} and {args.out / 'samples.csv'}")
    return 0


def main(argv: Sequence[str] | None = None) -> int:
    """Entry point of the ``scalf-opt`` console script."""
    parser = build_parser()
    args = parser.parse_args(argv)
    handlers = {"model": cmd_model, "evaluate": cmd_evaluate}
    try:
        return handlers[args.command](args)
    except ScalfError as exc:
        print(f"scalf-opt: error: {exc}", file=sys.stderr)
        return 2
    except KeyboardInterrupt:
        print("scalf-opt: interrupted", file=sys.stderr)
        return 130


if __name__ == "__main__":
    sys.exit(main())
