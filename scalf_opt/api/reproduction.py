"""``paper``: the paper's Tables 5 and 6 reproduced on a robot, and what lies beyond them."""

from __future__ import annotations

from collections.abc import Callable, Sequence
from dataclasses import dataclass
from typing import Any

from scalf_opt.api.gaits import VERBOSE_IPOPT, as_robot, command_tuple, read_gait
from scalf_opt.energy.loads import PAPER_LOADS
from scalf_opt.energy.pipeline import EnergyPipeline
from scalf_opt.locomotion.gait import Gait
from scalf_opt.model.robot import Robot
from scalf_opt.studies.paper import Reproduction, reproduce, summary


@dataclass(frozen=True)
class PaperResult:
    """The paper's Tables 5 and 6 reproduced on a robot (see :mod:`scalf_opt.studies.paper`)."""

    robot: Robot
    reproduction: Reproduction
    command: tuple[str, ...] | None = None

    def to_dict(self) -> dict[str, Any]:
        """Plain data: ``paper.json``."""
        return summary(self.reproduction, self.robot, self.command)


def paper(
    robot: str | Robot | None = None,
    gait: Gait | None = None,
    *,
    quick: bool = False,
    verbose: bool = False,
    progress: Callable[[str], None] | None = None,
    command: Sequence[str] | None = None,
) -> PaperResult:
    """Reproduce the paper's Tables 5 and 6 (reference, pattern search, Ipopt) on ``robot``.

    Args:
        robot: The robot (default: SCalf).
        gait: The gait (default: the robot's default trot).
        quick: Leave out what goes beyond the paper (the free-trajectory bound and the free
            stance), which takes most of the time.
        verbose: Print Ipopt's own log.
        progress: Called with a label as each step starts.
        command: The command line, recorded in the result's provenance.
    """
    robot = as_robot(robot)
    pipeline = EnergyPipeline(robot, gait or read_gait(robot=robot), loads=PAPER_LOADS)
    rep = reproduce(
        pipeline,
        beyond=not quick,
        ipopt_options=VERBOSE_IPOPT if verbose else None,
        progress=progress,
    )
    return PaperResult(robot, rep, command_tuple(command))
