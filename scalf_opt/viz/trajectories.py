"""The trajectories a view or a figure shows: a label and a whole robot cycle each.

These are records to draw; what to show, and the optimizations behind it, are decided above
this floor (:mod:`scalf_opt.api.presentation`): the cubic-spline reference and the default
optimum from the one optimization entry, or the swings saved by ``scalf-opt optimize --out``.
"""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass

from scalf_opt.energy.cycle import RobotCycle

REFERENCE_LABEL = "reference (cubic spline)"


@dataclass(frozen=True)
class Trajectory:
    """One trajectory to show.

    Attributes:
        label: What the legend calls it.
        cycle: Every leg's stance and swing over one gait cycle.
        solved: The optimization behind it converged (always for the reference or a saved
            optimum, whose own status is in its result file).
    """

    label: str
    cycle: RobotCycle
    solved: bool = True

    @property
    def energy_model(self) -> str:
        """What its energies were evaluated with: ``whole-body loads, paper accounting``."""
        return f"{self.cycle.loads} loads, {self.cycle.accounting} accounting"


def energy_models(trajectories: Sequence[Trajectory]) -> str:
    """The energy models of ``trajectories``, each once, for a figure's title."""
    return "; ".join(dict.fromkeys(t.energy_model for t in trajectories))
