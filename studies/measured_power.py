"""The model's power of SCalf's reference trot beside the power the paper measured on the robot.

The paper's Table 7 measured 559.96 W on SCalf walking the reference trajectory (its 80 Hz
cylinder logs) and simulated 671.52 W (Table 6). This prints, for each stance load model, the
model's average power of the reference swing on the paper's trot (SCalf, the paper's accounting)
beside both, so that a reader sees which model the robot's own measurement supports:

    python studies/measured_power.py

A Markdown table on stdout; nothing is written.
"""

from __future__ import annotations

from scalf_opt.energy.cycle import change_percent
from scalf_opt.energy.loads import LOAD_MODELS
from scalf_opt.energy.pipeline import EnergyPipeline
from scalf_opt.locomotion.gait import Gait
from scalf_opt.locomotion.swing.registry import make_family
from scalf_opt.robots.loading import load_robot
from scalf_opt.studies.paper_data import MEASURED_AVERAGE_POWER_W, REFERENCE_AVERAGE_POWER_W


def rows() -> list[tuple[str, float]]:
    """Per load model, the reference swing's average power on the paper's trot [W]."""
    robot = load_robot("scalf")
    return [
        (
            loads,
            EnergyPipeline(robot, Gait(), loads=loads)
            .robot_cycle(make_family("reference"))
            .average_power_w,
        )
        for loads in LOAD_MODELS
    ]


def main() -> None:
    """Print the table (module docstring)."""
    print(
        "| stance loads | model [W] | vs measured 559.96 W | vs the paper's simulation 671.52 W |"
    )
    print("|---|---|---|---|")
    for loads, power in rows():
        print(
            f"| `{loads}` | {power:.2f} | {change_percent(power, MEASURED_AVERAGE_POWER_W):+.1f} % "
            f"| {change_percent(power, REFERENCE_AVERAGE_POWER_W):+.1f} % |"
        )


if __name__ == "__main__":
    main()
