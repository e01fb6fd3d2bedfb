"""The Python API end to end, on a robot that is not SCalf: the made-up electric quadruped in
examples/trotter/ (its URDF, legs file, actuator file and gait file).

    python examples/walkthrough.py [OUT_DIR]        (default: results/walkthrough)

1. load the robot from its URDF (the legs and actuator files beside it are found by name);
2. read a gait file over the robot's default trot;
3. evaluate the reference swing, then optimize the swing of the diagonal pair;
4. write the optimum (summary.json, samples.csv), evaluate it again from the file;
5. draw the figures and the offline 3-D view of both swings;
6. simulate both in MuJoCo (extra ``sim``), when it is installed;
7. derive a variant with 20 % longer thighs and compare it on the same gait.

Every step prints one line; every file goes under OUT_DIR.
"""

from __future__ import annotations

import sys
from pathlib import Path

import scalf_opt as so
from scalf_opt.robots.variants import VariantScales, derive_variant

HERE = Path(__file__).resolve().parent
URDF = HERE / "trotter" / "trotter.urdf"
GAIT = HERE / "trotter" / "slow_trot.toml"


def main(out: Path) -> None:
    """Run every step, writing under ``out``."""
    robot = so.load_robot(urdf=URDF)
    print(
        f"robot {robot.name}: {robot.total_mass_kg:.2f} kg, leg length {robot.leg_length_m:.3f} m"
    )

    gait = so.read_gait(GAIT, robot)
    print(f"gait: T = {gait.period_s} s, duty {gait.duty_cycle}, S = {gait.step_length_m} m")

    reference = so.evaluate(robot, gait)
    print(
        f"reference swing: {reference.energy_j:.2f} J per cycle, {reference.average_power_w:.1f} W"
    )

    optimum = so.optimize_swing(robot, gait, family="joint-4")
    saving = 1 - optimum.cycle.energy_j / optimum.reference.energy_j
    print(f"optimum (joint-4): {optimum.cycle.energy_j:.2f} J per cycle, {saving:.1%} less")
    saved = out / "optimum"
    optimum.write(saved)
    again = so.evaluate(robot, swing=saved / "summary.json")
    print(f"read back from {saved / 'summary.json'}: {again.energy_j:.2f} J per cycle")

    written, _ = so.figures(out / "figures", robot=robot, from_dirs=[saved], formats=("png",))
    print(f"figures: {len(written)} files in {out / 'figures'}")
    page, shown = so.view(out / "scene.html", robot=robot, from_dirs=[saved])
    print(f"3-D view: {page} ({len(shown)} trajectories)")

    try:
        simulation = so.simulate(robot, swings_from=saved, cycles=3)
    except ImportError:
        print("simulation: MuJoCo is not installed (pip install 'scalf-opt[sim]')")
    else:
        change = simulation.data["saving_vs_reference"]
        print(
            f"simulated: energy {change['simulated_percent']:+.1f} % against the reference "
            f"(model {change['model_percent']:+.1f} %)"
        )
        simulation.write(out / "simulation")

    variant = derive_variant(robot, VariantScales(thigh_length_scale=1.2), out / "long.urdf")
    long_thigh = so.load_robot(urdf=variant.urdf_path)
    longer = so.evaluate(long_thigh, gait)
    print(
        f"variant {variant.urdf_path.name} (thigh x1.2) on the same gait: "
        f"{longer.energy_j:.2f} J per cycle against {reference.energy_j:.2f} J"
    )


if __name__ == "__main__":
    main(Path(sys.argv[1]) if len(sys.argv) > 1 else Path("results/walkthrough"))
