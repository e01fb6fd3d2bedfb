"""A robot cycle whose legs each have their own swing family and parameters.

:meth:`~scalf_opt.energy.pipeline.EnergyPipeline.robot_cycle` gives every leg the same family;
a result file (``optimize --leg RF``: RF and LF optimized, LH and RH on the reference) or a
simulation plan may mix them.
"""

from __future__ import annotations

from collections.abc import Mapping

import numpy as np

from scalf_opt.energy.cycle import LegCycle, RobotCycle
from scalf_opt.energy.pipeline import EnergyPipeline
from scalf_opt.locomotion.swing.registry import make_family
from scalf_opt.types import LEG_NAMES

SwingChoice = tuple[str, np.ndarray]
"""A leg's swing: the family's name and its parameters (family units; empty for the reference)."""

REFERENCE_SWINGS: dict[str, SwingChoice] = {leg: ("reference", np.zeros(0)) for leg in LEG_NAMES}
"""Every leg on the cubic-spline reference swing."""


def planned_cycle(pipeline: EnergyPipeline, swings: Mapping[str, SwingChoice]) -> RobotCycle:
    """Every leg's cycle, each with its own swing family and parameters.

    Raises:
        ConfigError: A family name is unknown.
        InfeasibleError, GaitError: A path leaves the leg's reach or joint limits.
    """
    chosen = {
        leg: (make_family(family), np.asarray(theta, dtype=float))
        for leg, (family, theta) in ((leg, swings[leg]) for leg in LEG_NAMES)
    }
    legs: dict[str, LegCycle] = {
        leg: pipeline.leg_cycle(leg, *chosen[leg], swings=chosen) for leg in LEG_NAMES
    }
    return RobotCycle(
        pipeline.gait,
        pipeline.accounting,
        legs,
        pipeline.robot.total_mass_kg,
        loads=pipeline.loads,
    )
