"""``scalf-opt simulate``: the planned trot in MuJoCo, beside the energy model's prediction."""

from __future__ import annotations

import argparse
from pathlib import Path
from typing import Any

from scalf_opt.cli.options import (
    Outputs,
    add_gait,
    add_loads,
    add_robot,
    bounded,
    check_not_the_source,
    check_output_dir,
    check_output_file,
    gait_origin,
    gait_overrides,
    load_gait,
    load_robot,
    option_given,
    warn_without_effect,
)
from scalf_opt.errors import ConfigError
from scalf_opt.types import LEG_NAMES

MAX_SEED = 2**32 - 1
"""Largest seed of the sensor noise (NumPy's seeds are 32-bit words)."""

MAX_SERVO_BANDWIDTH_HZ = 1000.0
"""Highest PD-loop natural frequency [Hz] (MuJoCo's step resolves far less)."""

NAME = "simulate"
HELP = "simulate the trot in MuJoCo: trunk motion, foot forces, joint energy against the model"
EXAMPLES = (
    ("scalf-opt simulate", "the reference swing in MuJoCo (results/simulate)"),
    ("scalf-opt simulate --from results/optimum", "a saved optimum, beside the reference"),
    ("scalf-opt simulate --log results/log.csv", "and the log SCalf's sensors would record"),
)
JSON = True


def add_arguments(parser: argparse.ArgumentParser) -> None:  # noqa: D103
    add_robot(parser)
    add_gait(parser)
    add_loads(parser, saved=True)
    parser.add_argument(
        "--from",
        dest="source",
        type=Path,
        metavar="DIR",
        help="simulate the swings and gait of DIR/summary.json (as `optimize --out DIR` "
        "writes it, a free stance included; its robot by default when the catalog has it), "
        "and the reference beside them where it is possible at that stance; a 3-D cycle "
        "(`optimize --model 3d --out DIR`: DIR/plan.csv) is refereed by the 3-D referee, the "
        "whole robot free (default: the reference swing)",
    )
    parser.add_argument(
        "--model",
        choices=("sagittal", "3d"),
        default="sagittal",
        help="the referee: sagittal (default), the trunk in its sagittal plane, the plan beside "
        "the reference; 3d, the whole robot free (trunk in six degrees of freedom, every joint, "
        "stance forces from a QP in friction cones), the sagittal plan as a 3-D plan whose "
        "moment about the diagonal acts; a 3-D cycle (--from DIR of optimize --model 3d) is "
        "refereed in 3-D",
    )
    parser.add_argument(
        "--cycles",
        type=int,
        metavar="N",
        default=10,
        help="gait cycles to simulate, 2..200 (default 10)",
    )
    parser.add_argument(
        "--out",
        type=Path,
        default=Path("results/simulate"),
        metavar="DIR",
        help="write simulation.json, simulation.png and report.txt here (default results/simulate)",
    )
    parser.add_argument(
        "--log",
        type=Path,
        metavar="FILE",
        help="also write the cylinder log the robot's sensors would record (80 Hz, 0.1 mm, "
        "70 N), for `scalf-opt analyze-log`: FILE.csv, or FILE.mcap, a ROS 2 bag with it on "
        "/cylinder_states and the joints' angles, rates and torques on /joint_states (1 kHz)",
    )
    parser.add_argument(
        "--seed",
        type=bounded(int, MAX_SEED, 0),
        default=0,
        metavar="N",
        help=f"seed of the log's sensor noise, 0..{MAX_SEED} (default 0)",
    )
    parser.add_argument(
        "--servo-bandwidth",
        type=bounded(float, MAX_SERVO_BANDWIDTH_HZ),
        metavar="N",
        help="natural frequency of the servo's feedback loops, at most 1000 Hz (default: from the "
        "leg length L, 55.7 sqrt(g/L)/(2 pi): 30 Hz on SCalf; the time step follows)",
    )
    parser.add_argument(
        "--ensemble",
        choices=("on", "off"),
        default="on",
        help="on: the verdict is the median over the referee ensemble (servo gains x0.5 and x2, "
        "contact time constant x0.5 and x2, foot radius x0.5 and x3, friction 0.6, touch-down "
        "detected 5 ms early and late), with its spread, its members run side by side on the "
        "cores; off: the nominal referee alone, a tenth of the work (default on)",
    )
    parser.add_argument(
        "--details",
        action="store_true",
        help="print the whole report (report.txt): also the plan followed exactly, the servo's "
        "work, contacts and joint stops",
    )


def run(args: argparse.Namespace) -> int:  # noqa: D103
    from scalf_opt.api import simulate
    from scalf_opt.io.whole_body_export import is_3d_cycle
    from scalf_opt.sim.report import DETAILS, simulation_report

    check_output_dir(args.out)
    if args.source is not None and (args.gait is not None or gait_overrides(args)):
        raise ConfigError("--gait and the gait options: with --from DIR the gait is DIR's")
    if args.source is not None and is_3d_cycle(args.source):
        if args.model == "sagittal" and option_given(args, "--model"):
            raise ConfigError(
                f"--model sagittal: {args.source} holds a 3-D cycle (leave --model out)",
                field="model",
            )
        return run_cycle(args)
    if args.model == "3d":
        return run_sagittal_in_3d(args)
    check_output_file(args.log, "--log")
    check_not_the_source(args.log, args.source, "--log")
    if args.log is not None and args.log.suffix not in (".csv", ".mcap"):
        raise ConfigError(f"--log {args.log}: give a .csv or an .mcap file")
    robot = load_robot(args, args.source)
    warn_without_effect(args, robot)
    if args.log is not None and args.log.suffix == ".csv":
        from scalf_opt.energy.pipeline import EnergyPipeline
        from scalf_opt.logs.analysis import leg_cylinders

        pipeline = EnergyPipeline(robot, load_gait(args, robot))
        for leg in LEG_NAMES:
            leg_cylinders(pipeline, leg)  # refuse a robot without cylinders before the work
    gait = None if args.source is not None else load_gait(args, robot)
    result = simulate(
        robot,
        gait,
        swings_from=args.source,
        cycles=args.cycles,
        accounting=args.accounting,
        servo_bandwidth_hz=args.servo_bandwidth,
        loads=args.loads,
        ensemble=args.ensemble == "on",
        command=args.argv,
    )
    # the files first: a reader that closes the pipe early (`| head`) loses no result
    written = result.write(args.out)
    if args.log is not None:
        written.append(result.write_log(args.log, args.seed))
    saved = f"the gait saved with the swings of {args.source}" if args.source else None
    args.console.text(gait_origin(args, robot, saved))
    args.console.text(simulation_report(result.data, result.title, details=args.details))
    if not args.details:
        args.console.text(f"the whole report: {args.out / 'report.txt'} ({DETAILS}; --details)")
    args.console.json(result.to_dict())
    args.console.text(f"wrote {', '.join(map(str, written))}")
    return 0


def outputs(args: argparse.Namespace) -> Outputs:
    """The folder and the log, moved into place together."""
    return Outputs(folders={"--out": args.out}, files={"--log": args.log})


def run_cycle(args: argparse.Namespace) -> int:
    """``simulate --from DIR`` of a 3-D cycle: the 3-D referee (exit 0)."""
    from scalf_opt.api import simulate_cycle
    from scalf_opt.io.whole_body_export import read_cycle

    if args.log is not None:
        raise ConfigError("--log: a 3-D cycle's simulation writes no sensor log", field="log")
    if args.loads is not None:
        raise ConfigError(
            "--loads: a 3-D cycle carries its own contact forces (leave it out)", field="loads"
        )
    saved = read_cycle(args.source)
    robot = load_robot(args) if (args.robot or args.urdf) else None
    result = simulate_cycle(
        args.source,
        robot,
        cycles=args.cycles,
        accounting=args.accounting if option_given(args, "--accounting") else None,
        servo_bandwidth_hz=args.servo_bandwidth,
        ensemble=args.ensemble == "on",
        command=args.argv,
    )
    return _report_3d(
        args,
        result,
        f"the 3-D cycle of {args.source} ({saved.summary.get('robot')}, "
        f"{saved.summary.get('nodes')} nodes), whole robot free in MuJoCo",
    )


def run_sagittal_in_3d(args: argparse.Namespace) -> int:
    """``simulate --model 3d`` of a sagittal plan: the 3-D referee (exit 0)."""
    from scalf_opt.api import simulate_3d

    if args.log is not None:
        raise ConfigError("--log: the 3-D referee writes no sensor log", field="log")
    robot = load_robot(args, args.source)
    warn_without_effect(args, robot)
    result = simulate_3d(
        robot,
        None if args.source is not None else load_gait(args, robot),
        swings_from=args.source,
        cycles=args.cycles,
        accounting=args.accounting,
        servo_bandwidth_hz=args.servo_bandwidth,
        loads=args.loads,
        ensemble=args.ensemble == "on",
        command=args.argv,
    )
    saved = f"the gait saved with the swings of {args.source}" if args.source else None
    return _report_3d(args, result, gait_origin(args, robot, saved))


def _report_3d(args: argparse.Namespace, result: Any, first_line: str) -> int:
    """Write a 3-D referee's files, then print ``first_line``, its report and the files (0).

    The files first: a reader that closes the pipe early (``| head``) loses no result.
    """
    from scalf_opt.sim.whole_body_report import cycle_simulation_report

    written = result.write(args.out)
    args.console.text(first_line)
    args.console.text(cycle_simulation_report(result.data, result.title, details=args.details))
    if not args.details:
        args.console.text(
            f"the whole report: {args.out / 'report.txt'} (the controller and the ensemble's "
            "members; --details)"
        )
    args.console.text("wrote " + ", ".join(str(p) for p in written))
    args.console.json(result.to_dict())
    return 0
