"""``scalf-opt simulate``: the planned trot in MuJoCo, beside the energy model's prediction."""

from __future__ import annotations

import argparse
from pathlib import Path

from scalf_opt.cli.options import add_gait, add_robot, load_gait, load_robot
from scalf_opt.errors import ConfigError

NAME = "simulate"
HELP = "simulate the trot in MuJoCo: trunk motion, foot forces, joint energy against the model"


def add_arguments(parser: argparse.ArgumentParser) -> None:  # noqa: D103
    add_robot(parser)
    add_gait(parser)
    parser.add_argument(
        "--from",
        dest="source",
        type=Path,
        metavar="DIR",
        help="simulate the swings and gait of DIR/summary.json (as `optimize --out DIR` "
        "writes it; give the same --robot or --urdf), and the reference beside them "
        "(default: the reference swing)",
    )
    parser.add_argument(
        "--cycles", type=int, default=10, help="gait cycles to simulate, >= 2 (default 10)"
    )
    parser.add_argument(
        "--out",
        type=Path,
        default=Path("results/simulation"),
        help="write simulation.json and simulation.png here (default results/simulation)",
    )
    parser.add_argument(
        "--log",
        type=Path,
        metavar="FILE.csv",
        help="also write the cylinder log the robot's sensors would record (80 Hz, 0.1 mm, "
        "70 N), for `scalf-opt analyze-log`",
    )
    parser.add_argument(
        "--seed", type=int, default=0, help="seed of the log's sensor noise (default 0)"
    )
    parser.add_argument(
        "--servo-bandwidth",
        type=float,
        metavar="HZ",
        help="natural frequency of the joints' PD loops (default 30 Hz)",
    )


def run(args: argparse.Namespace) -> int:  # noqa: D103
    from scalf_opt.energy.pipeline import EnergyPipeline
    from scalf_opt.files import write_atomic
    from scalf_opt.io.optimum_file import read_planned_swings
    from scalf_opt.io.results import to_json
    from scalf_opt.logs.log_file import log_csv_text
    from scalf_opt.logs.sensors import JointMotion, SensorModel, sensor_log
    from scalf_opt.sim.experiment import simulation_file
    from scalf_opt.sim.plan import REFERENCE_SWINGS
    from scalf_opt.sim.report import simulation_report
    from scalf_opt.sim.settings import SimSettings
    from scalf_opt.viz.figures import save_atomic
    from scalf_opt.viz.simulation_figure import simulation_figure

    if args.cycles < 2:
        raise ConfigError(
            f"--cycles must be at least 2 (the first is the start-up), got {args.cycles}"
        )
    if args.source is not None and args.gait is not None:
        raise ConfigError("--gait: with --from DIR the gait is the one in DIR/summary.json")
    settings = (
        SimSettings()
        if args.servo_bandwidth is None
        else SimSettings(servo_bandwidth_hz=args.servo_bandwidth)
    )
    robot = load_robot(args)
    if args.source is not None:
        planned = read_planned_swings(args.source, robot)
        gait, swings = planned.gait, planned.swings
    else:
        gait, swings = load_gait(args, robot), dict(REFERENCE_SWINGS)
    pipeline = EnergyPipeline(robot, gait, args.accounting)
    cylinders = None
    if args.log is not None:
        from scalf_opt.logs.analysis import leg_cylinders

        cylinders = {leg: leg_cylinders(pipeline, leg) for leg in swings}
    source = None if args.source is None else str(args.source)
    data, trot = simulation_file(robot, pipeline, swings, settings, args.cycles, source)
    families = sorted({family for family, _ in swings.values()})
    title = (
        f"MuJoCo {data['mujoco_version']} simulation of {robot.name}, {', '.join(families)} swing: "
        f"trot T={gait.period_s:g} s, S={gait.step_length_m:g} m, z0={gait.stance_height_m:g} "
        f"m, {args.cycles} cycles, dt={1e3 * settings.timestep_s:g} ms, servo "
        f"{settings.servo_bandwidth_hz:g} Hz"
    )
    record = trot.record
    figure = simulation_figure(
        record.t_s,
        record.trunk[1],
        record.start_trunk_height_m,
        record.trunk[2],
        {leg: force[1] for leg, force in record.grf_n.items()},
        float(data["model_stance_force_mean_n"]["RF"]),
        title,
    )
    out: Path = args.out
    # the files first: a reader that closes the pipe early (`| head`) loses no result
    write_atomic(out / "simulation.json", to_json(data))
    save_atomic(figure, out / "simulation.png")
    written = [out / "simulation.json", out / "simulation.png"]
    if cylinders is not None:
        motions = {
            leg: JointMotion(
                record.t_s, record.q_rad[leg], record.tau_nm[leg], record.in_contact(leg)
            )
            for leg in cylinders
        }
        log = sensor_log(motions, cylinders, SensorModel(), args.seed, str(args.log))
        write_atomic(args.log, log_csv_text(log))
        written.append(args.log)
    print(simulation_report(data, title))
    print(f"wrote {', '.join(map(str, written))}")
    return 0
