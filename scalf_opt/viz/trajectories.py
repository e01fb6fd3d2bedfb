"""The trajectories a view or a figure shows: a label and a whole robot cycle each.

These are records to draw; what to show, and the optimizations behind it, are decided above
this floor (:mod:`scalf_opt.api.presentation`): the cubic-spline reference and the default
optimum from the one optimization entry, or the swings saved by ``scalf-opt optimize --out``.
"""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass

from scalf_opt.energy.cycle import RobotCycle
from scalf_opt.model.robot import Robot

REFERENCE_LABEL = "reference (cubic spline)"


@dataclass(frozen=True)
class Trajectory:
    """One trajectory to show.

    Attributes:
        label: What the legend calls it.
        cycle: Every leg's stance and swing over one gait cycle.
        solved: The optimization behind it converged (always for the reference or a saved
            optimum, whose own status is in its result file).
        robot: Who walks it, when not the view's robot (a variant's parent beside it).
    """

    label: str
    cycle: RobotCycle
    solved: bool = True
    robot: Robot | None = None

    @property
    def energy_model(self) -> str:
        """What its energies are: ``loads 'whole-body', accounting 'paper', 300 Hz``."""
        return self.cycle.basis


def energy_models(trajectories: Sequence[Trajectory]) -> str:
    """The energy models of ``trajectories``, each once, for a figure's title."""
    return "; ".join(dict.fromkeys(t.energy_model for t in trajectories))


def energy_lines(trajectories: Sequence[Trajectory]) -> list[str]:
    """A line per trajectory, its energy per cycle and average power, and what they are.

    When the trajectories share their loads, accounting and rate, a first line says them once.
    """
    models = dict.fromkeys(t.energy_model for t in trajectories)
    lines = [f"the model's energy per cycle ({next(iter(models))}):"] if len(models) == 1 else []
    for t in trajectories:
        own = "" if len(models) == 1 else f" ({t.energy_model})"
        lines.append(f"  {t.label}: {t.cycle.energy_j:.3f} J, {t.cycle.average_power_w:.2f} W{own}")
    return lines
