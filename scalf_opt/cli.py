"""The ``scalf-opt`` command line.

Every user mistake (:class:`~scalf_opt.errors.ScalfError`) ends as one line on stderr and exit
code 2, with no traceback; output files are written atomically, so nothing half-written remains.
"""

from __future__ import annotations

import argparse
import sys
from collections.abc import Sequence
from pathlib import Path

from scalf_opt.errors import ConfigError, ScalfError
from scalf_opt.gait import GaitSpec
from scalf_opt.reproduction import DEFAULT_RICH_FAMILY
from scalf_opt.robot import LEG_NAMES, Robot


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

    p = sub.add_parser("optimize", help="optimize the swing of one or more legs")
    _add_urdf(p)
    _add_gait(p)
    p.add_argument(
        "--leg",
        default="pair",
        help="RF, LF, RH, LH; 'pair' (default: RF and LH, LF and RH by symmetry) or 'all'",
    )
    p.add_argument(
        "--family",
        default=DEFAULT_RICH_FAMILY,
        help=f"paper, fourier-N (foot space) or joint-N (joint space), N in 2..12 "
        f"(default {DEFAULT_RICH_FAMILY})",
    )
    p.add_argument("--method", choices=("pattern", "ipopt"), default="ipopt")
    p.add_argument(
        "--precision", type=float, default=0.1, help="pattern-search precision (default 0.1)"
    )
    p.add_argument("--out", type=Path, help="write summary.json and samples.csv here")

    p = sub.add_parser("paper", help="reproduce the paper's Tables 5 and 6 (the main job)")
    _add_urdf(p)
    p.add_argument("--gait", type=Path, help="gait file (TOML); default: the paper's trot")
    p.add_argument(
        "--out",
        type=Path,
        default=Path("results/paper"),
        help="output directory (default results/paper)",
    )
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


def _legs_to_optimize(choice: str) -> tuple[str, ...]:
    if choice == "pair":
        return ("RF", "LH")
    if choice == "all":
        return LEG_NAMES
    if choice in LEG_NAMES:
        return (choice,)
    raise ConfigError(f"--leg {choice!r}: use RF, LF, RH, LH, pair or all")


def cmd_optimize(args: argparse.Namespace) -> int:
    """``scalf-opt optimize``: exit 0 when every leg is solved, 3 when an optimizer fails."""
    from scalf_opt.cycle import RobotEnergyModel
    from scalf_opt.optimize.pattern_search import PatternSearchOptions
    from scalf_opt.optimize.problem import SwingProblem
    from scalf_opt.optimize.solve import optimize
    from scalf_opt.report import evaluate_report, optimum_report
    from scalf_opt.results import cycle_summary, samples_csv_text, to_json, write_atomic
    from scalf_opt.swing import make_family

    legs = _legs_to_optimize(args.leg)
    family = make_family(args.family)
    if family.n_params == 0:
        raise ConfigError(f"--family {args.family}: has no free parameter to optimize")
    if not args.precision > 0:
        raise ConfigError(f"--precision must be > 0, got {args.precision}")
    robot = load_robot(args)
    model = RobotEnergyModel(robot, load_gait(args, robot), args.accounting)
    reference = model.robot_cycle(make_family("reference"))
    options = PatternSearchOptions(precision=args.precision)
    optima = {
        leg: optimize(SwingProblem(model, leg, family), args.method, pattern_options=options)
        for leg in legs
    }
    print(optimum_report(optima, reference))
    failed = [o for o in optima.values() if not o.success]
    if failed:
        names = ", ".join(f"{o.leg} ({o.status})" for o in failed)
        print(f"scalf-opt: error: not solved: {names}; no optimum is reported", file=sys.stderr)
        return 3
    # legs neither optimized nor twin of an optimized leg keep the reference swing
    cycle = model.robot_cycle(family, {leg: o.theta for leg, o in optima.items()})
    print()
    print(evaluate_report(cycle, robot, title=f"optimized ({family.name}, {args.method})"))
    if args.out is not None:
        data = cycle_summary(cycle)
        data["optimization"] = {leg: o.as_dict() for leg, o in optima.items()}
        data["reference_total_energy_per_cycle_j"] = reference.energy_j
        write_atomic(args.out / "summary.json", to_json(data))
        write_atomic(args.out / "samples.csv", samples_csv_text(cycle))
        print(f"wrote {args.out / 'summary.json'} and {args.out / 'samples.csv'}")
    return 0


def cmd_paper(args: argparse.Namespace) -> int:
    """``scalf-opt paper``: Tables 5 and 6 beside the paper's numbers."""
    from scalf_opt.plots import write_paper_figures
    from scalf_opt.report import paper_markdown
    from scalf_opt.reproduction import reproduce, summary, table5_rows, table6_rows
    from scalf_opt.results import rows_csv_text, to_json, write_atomic

    robot = load_robot(args)
    rep = reproduce(robot, load_gait(args, robot))
    report = paper_markdown(rep, robot)
    print(report)
    out = args.out
    write_atomic(out / "report.md", report)
    write_atomic(out / "paper.json", to_json(summary(rep)))
    write_atomic(out / "table5.csv", rows_csv_text(table5_rows(rep)))
    write_atomic(out / "table6.csv", rows_csv_text(table6_rows(rep)))
    figures = write_paper_figures(rep, out)
    print(
        f"wrote {out}/report.md, paper.json, table5.csv, table6.csv, "
        + " and ".join(f.name for f in figures)
    )
    if not rep.all_solved:
        print("scalf-opt: error: an optimizer did not converge (see the report)", file=sys.stderr)
        return 3
    return 0


def main(argv: Sequence[str] | None = None) -> int:
    """Entry point of the ``scalf-opt`` console script."""
    parser = build_parser()
    args = parser.parse_args(argv)
    handlers = {
        "model": cmd_model,
        "evaluate": cmd_evaluate,
        "optimize": cmd_optimize,
        "paper": cmd_paper,
    }
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
