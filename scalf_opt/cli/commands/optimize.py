"""``scalf-opt optimize``: optimize the swing of one or more legs."""

from __future__ import annotations

import argparse
import math
from pathlib import Path
from typing import TYPE_CHECKING

from scalf_opt.cli.commands.gait_3d import PERIOD_RANGE_HELP
from scalf_opt.cli.options import (
    add_accept_unconverged,
    add_friction,
    add_gait,
    add_loads,
    add_method,
    add_robot,
    bounded,
    check_output_dir,
    friction_of,
    gait_origin,
    leg_name,
    load_gait,
    load_robot,
    warn_without_effect,
)
from scalf_opt.energy.margins import (
    DEFAULT_EFFORT_SHARE,
    DEFAULT_LIFT_FRACTION,
    DEFAULT_STOP_MARGIN_RAD,
    DEFAULT_STROKE_MARGIN_M,
)
from scalf_opt.locomotion.swing.names import DEFAULT_FAMILY, FREE_FAMILY
from scalf_opt.types import FIRST_PAIR, LEG_NAMES

if TYPE_CHECKING:
    from scalf_opt.energy.margins import LimitMargins

MAX_STARTS = 100
"""Most starts per leg (each is a full solve)."""

MAX_STOP_MARGIN_DEG = 30.0
"""Largest joint-stop margin an option accepts [deg] (more leaves most joints no range)."""

MAX_STROKE_MARGIN_MM = 50.0
"""Largest stroke margin an option accepts [mm]."""

MAX_EFFORT_MARGIN_PCT = 50.0
"""Largest effort margin an option accepts [%]."""

MAX_LIFT_HEIGHT_MM = 1000.0
"""Largest lift height an option accepts [mm] (the clearance H bounds it in practice)."""

MAX_TOUCHDOWN_SPEED_M_S = 100.0
"""Largest touch-down speed an option accepts [m/s] (no swing comes near it: no bound)."""


SWING_FAMILY_HELP = (
    f"paper, fourier-N (foot space) or joint-N (joint space), N in 2..12 (default {DEFAULT_FAMILY})"
)
"""``--family``'s help where only a swing family fits (``gait``, whose trials are families)."""

FAMILY_HELP = (
    f"{SWING_FAMILY_HELP}; or {FREE_FAMILY}: the free-trajectory bound (dense B-splines refined "
    "until the energy converges)"
)
"""``--family``'s help where the free-trajectory bound is a choice too."""

NAME = "optimize"
HELP = "optimize the swing of one or more legs"
EXAMPLES = (
    ("scalf-opt optimize --out results/optimum", "Ipopt on joint-6 for RF and LH, written"),
    ("scalf-opt optimize --family paper --method pattern", "the paper's pattern search"),
    ("scalf-opt optimize --robot hyq --leg RF --bound", "and the free-trajectory bound"),
    (
        "scalf-opt optimize --model 3d --robot go1 --period 0.3 --duty 0.35 --speed 0.4",
        "a flying trot of the whole robot in 3-D",
    ),
)
JSON = True
VERBOSE = True


def add_arguments(parser: argparse.ArgumentParser) -> None:  # noqa: D103
    add_robot(parser)
    parser.add_argument(
        "--model",
        choices=("sagittal", "3d"),
        default="sagittal",
        help="sagittal (default): the swing of two-joint legs under a trunk on a fixed line, "
        "the paper's model; 3d: one periodic trot cycle of the whole robot (free trunk, every "
        "joint, contact forces in friction cones, --duty down to 0.2: a flying trot), solved "
        "by Ipopt on a refined grid (takes minutes; the Python API only had it before)",
    )
    add_friction(parser)
    parser.add_argument("--period-range", metavar="X", help=PERIOD_RANGE_HELP)
    add_gait(parser, speed=True)
    add_loads(parser)
    parser.add_argument(
        "--leg",
        type=leg_name,
        default="PAIR",
        choices=(*LEG_NAMES, "PAIR"),
        metavar="LEG",
        help="the leg to optimize, RF, LH, LF, RH or pair (any case); pair (default): RF and "
        "LH, whose optima LF and RH repeat half a cycle later (the paper's symmetry); a single "
        "leg's twin repeats it too",
    )
    parser.add_argument(
        "--family",
        default=DEFAULT_FAMILY,
        metavar="NAME",
        help=FAMILY_HELP,
    )
    add_method(parser)
    parser.add_argument(
        "--precision",
        type=bounded(float, 1.0),
        metavar="X",
        help="pattern-search precision, at most 1 (default 0.1, the paper's); --method pattern "
        "only",
    )
    parser.add_argument(
        "--starts",
        type=bounded(int, MAX_STARTS),
        default=1,
        metavar="N",
        help=f"deterministic starts per leg, 1..{MAX_STARTS} (default 1; the first is the default "
        "start): the best is kept, the spread reported",
    )
    parser.add_argument(
        "--bound",
        action="store_true",
        help="also compute the free-trajectory bound and report each optimum's gap to it",
    )
    parser.add_argument(
        "--free-stance",
        action="store_true",
        help="beyond the paper: also optimize the stance height z0 and the stance x-offsets "
        "(front and hind) within the joint limits, reach, stroke and clearance; reports how "
        "much of the saving comes from the stance and how much from the swing",
    )
    parser.add_argument(
        "--stop-margin",
        type=bounded(float, MAX_STOP_MARGIN_DEG, 0.0),
        default=math.degrees(DEFAULT_STOP_MARGIN_RAD),
        metavar="X",
        help="every optimized joint angle stays X degrees inside its range, 0..30 "
        f"(default {math.degrees(DEFAULT_STOP_MARGIN_RAD):g}: the simulated servo tracks within "
        "it; 0: the limits themselves, as the paper)",
    )
    parser.add_argument(
        "--stroke-margin",
        type=bounded(float, MAX_STROKE_MARGIN_MM, 0.0),
        default=1e3 * DEFAULT_STROKE_MARGIN_M,
        metavar="X",
        help="every cylinder length stays X mm inside its stroke, 0..50 (default "
        f"{1e3 * DEFAULT_STROKE_MARGIN_M:g})",
    )
    add_ground_margin_options(parser)
    parser.add_argument(
        "--out", type=Path, metavar="DIR", help="write summary.json and samples.csv in DIR"
    )
    add_accept_unconverged(parser)


def add_ground_margin_options(parser: argparse.ArgumentParser) -> None:
    """``--effort-margin``, ``--lift-height``, ``--lift-fraction``, ``--touchdown-speed``."""
    parser.add_argument(
        "--effort-margin",
        type=bounded(float, MAX_EFFORT_MARGIN_PCT, 0.0),
        default=100 * DEFAULT_EFFORT_SHARE,
        metavar="X",
        help="every torque and drive force (the swing's and the loaded stance legs') stays X "
        f"%% under its limit, 0..50 (default {100 * DEFAULT_EFFORT_SHARE:g}: room for the "
        "servo's feedback)",
    )
    parser.add_argument(
        "--lift-height",
        type=bounded(float, MAX_LIFT_HEIGHT_MM, 0.0),
        default=None,
        metavar="X",
        help="the swing foot rises at least as fast as a constant acceleration that takes it "
        "X mm up by the lift fraction of the swing, stays that high until the landing, and "
        "lands mirrored, 0..1000 (default: a fifth of the clearance H; 0: only above the "
        "ground)",
    )
    parser.add_argument(
        "--lift-fraction",
        type=bounded(float, 0.5),
        default=DEFAULT_LIFT_FRACTION,
        metavar="X",
        help="the share of the swing the lift and the landing take, in (0, 0.5] (default "
        f"{DEFAULT_LIFT_FRACTION:g})",
    )
    parser.add_argument(
        "--touchdown-speed",
        type=bounded(float, MAX_TOUCHDOWN_SPEED_M_S),
        default=None,
        metavar="X",
        help="over the landing (the last lift fraction of the swing) the foot comes down no "
        "faster than X m/s, at most 100 (default: 2.6 H / swing duration; 100: no bound)",
    )


def margins_from(args: argparse.Namespace) -> LimitMargins:
    """The margins the options give."""
    from scalf_opt.energy.margins import LiftProfile, LimitMargins

    height = None if args.lift_height is None else 1e-3 * args.lift_height
    lift = LiftProfile(height, args.lift_fraction, args.touchdown_speed)
    return LimitMargins(
        math.radians(args.stop_margin), 1e-3 * args.stroke_margin, args.effort_margin / 100, lift
    )


def check_family(name: str) -> None:
    """``--family`` names a swing family or ``free`` (a near miss of either is named).

    Raises:
        ConfigError: Neither.
    """
    from scalf_opt.locomotion.swing.registry import make_family

    if name != FREE_FAMILY:
        make_family(name, also=(FREE_FAMILY,))


def run(args: argparse.Namespace) -> int:
    """Exit 0 when everything converged, 3 when something did not (unless accepted)."""
    if args.model == "3d":
        from scalf_opt.cli.commands.optimize_3d import run_3d

        return run_3d(args, margins_from(args))
    if args.period_range is not None:
        from scalf_opt.errors import ConfigError

        raise ConfigError("--period-range is an option of --model 3d", field="period_range")
    friction_of(args)  # refused here: an option of --model 3d
    from scalf_opt.api.optimization import goal_from, optimize_goal
    from scalf_opt.cli.progress import ProgressBar
    from scalf_opt.energy.pipeline import EnergyPipeline
    from scalf_opt.optimize.goals import BoundGoal, StanceGoal
    from scalf_opt.viz.optimization_report import (
        bound_report,
        free_stance_report,
        optimization_report,
        optimization_warnings,
        peaks_table,
        violation_lines,
    )
    from scalf_opt.viz.report import evaluate_report

    check_output_dir(args.out)
    check_family(args.family)
    legs = FIRST_PAIR if args.leg == "PAIR" else (args.leg,)
    goal = goal_from(
        family=args.family,
        method=args.method,
        legs=legs,
        precision=args.precision,
        starts=args.starts,
        bound=args.bound,
        free_stance=args.free_stance,
        verbose=args.verbose,
        margins=margins_from(args),
    )
    robot = load_robot(args)
    warn_without_effect(args, robot)
    gait = load_gait(args, robot)
    pipeline = EnergyPipeline(robot, gait, args.accounting, loads=args.loads)
    with ProgressBar(None, "optimize", enabled=not args.quiet) as bar:
        result = optimize_goal(robot, pipeline, goal, bar.step, args.argv)
    console = args.console
    console.text(gait_origin(args, robot))
    written = result.write(args.out) if result.success and args.out is not None else []
    if result.run is not None:
        console.text(optimization_report(result.run))
        for line in optimization_warnings(result.run):
            console.text(line)
    if result.bounds:
        console.text(bound_report(result.bounds))
    if result.stance is not None and result.success:
        console.text("\n" + free_stance_report(result.stance))
    console.json(result.to_dict())
    if not result.success:
        console.error(f"not solved: {result.failure()}; no optimum is reported")
        return 3
    assert result.cycle is not None
    if isinstance(goal, BoundGoal):
        title = f"free-trajectory bound ({result.cycle.legs[legs[0]].swing_family})"
    elif isinstance(goal, StanceGoal):
        title = f"free stance ({args.family}, {args.method})"
    else:
        title = f"optimized ({args.family}, {args.method})"
    whole_cycle = ("the reference at this rate", result.reference.average_power_w)
    console.text("\n" + evaluate_report(result.cycle, robot.name, title, whole_cycle))
    console.text("\n" + peaks_table(result.peaks, result.reference_peaks))
    for line in violation_lines(result.violations):
        console.text(line)
    if written:
        console.text("wrote " + " and ".join(str(p) for p in written))
    if not result.converged:
        console.error(f"not converged: {result.failure()} (marked so in the outputs)")
        return 0 if args.accept_unconverged else 3
    return 0
