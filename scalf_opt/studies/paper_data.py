"""The numbers the SCalf paper reports, for side-by-side comparison in reports.

Only results live here (Tables 5 and 6, Section 1); the model's inputs come from the URDF and the
actuator file. Percentages are signed changes of the optimized trajectory against the reference.
"""

from __future__ import annotations

from scalf_opt.energy.accounting import PAPER_ACCOUNTING
from scalf_opt.energy.loads import PAPER_LOADS
from scalf_opt.locomotion.gait import Gait
from scalf_opt.model.robot import Robot

REFERENCE_AVERAGE_POWER_W = 671.52
"""Table 6: average total leg power of the reference trajectory (simulation) [W]."""

OPTIMIZED_AVERAGE_POWER_W = 617.68
"""Table 6: average total leg power of the energy-efficient trajectory (simulation) [W]."""

MEASURED_AVERAGE_POWER_W = 559.96
"""Table 7: average power of the robot's legs measured on SCalf walking the reference trajectory
(80 Hz cylinder logs, mean of 5 cycles) [W]."""

MEASURED_OPTIMIZED_AVERAGE_POWER_W = 517.68
"""Table 7: the same, walking the energy-efficient trajectory [W]."""

TABLE6_CHANGE_PERCENT: dict[str, dict[str, float]] = {
    "RF": {"swing": -26.26, "cycle": -8.56},
    "LH": {"swing": -22.98, "cycle": -7.46},
    "total": {"total": -8.02},
}
"""Table 6: change of swing and whole-cycle energy per leg, and of the total energy [%]."""

TABLE5_RF = {"C1": -33.76, "C2": 15.30, "iterations": 108}
"""Table 5: the RF leg's pattern-search optimum (the LH values were lost in extraction)."""

MIT_CHEETAH_COT = 0.51
"""Section 1: cost of transport of the MIT Cheetah, for comparison."""


def is_paper_setup(
    robot: Robot, gait: Gait, power: str = PAPER_ACCOUNTING, loads: str = PAPER_LOADS
) -> bool:
    """SCalf on the paper's gait, accounting and (trunk-only) loads: what its numbers fit."""
    return (
        robot.name == "scalf"
        and gait == Gait()
        and power == PAPER_ACCOUNTING
        and loads == PAPER_LOADS
    )
