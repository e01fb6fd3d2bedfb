"""The trajectories a view or a figure shows: a label and a whole robot cycle each.

Without saved results these are the cubic-spline reference and the default optimum (the
``joint-6`` family for the diagonal pair, solved by Ipopt; LF and RH repeat it by symmetry);
with ``--from`` directories, the swings ``scalf-opt optimize --out`` saved there, evaluated on
their own gait (which every directory must share, so that like is compared with like), with the
reference on that gait first.
"""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass, field
from pathlib import Path

from scalf_opt.energy.cycle import RobotCycle
from scalf_opt.energy.pipeline import EnergyPipeline
from scalf_opt.errors import ConfigError, ScalfError
from scalf_opt.io.saved import SavedSwings, read_saved_swings
from scalf_opt.locomotion.gait import Gait
from scalf_opt.locomotion.swing.names import DEFAULT_FAMILY
from scalf_opt.locomotion.swing.registry import make_family
from scalf_opt.model.robot import Robot
from scalf_opt.optimize.problem import SwingProblem
from scalf_opt.optimize.solve import SwingOptimum, optimize
from scalf_opt.types import FIRST_PAIR, LEG_NAMES, Accounting, Method

REFERENCE_LABEL = "reference (cubic spline)"


class NotSolvedError(ScalfError):
    """An optimizer behind a trajectory to show did not converge: nothing is presented.

    The command line exits with code 3 on it (an optimizer did not converge), not 2.
    """


@dataclass(frozen=True)
class Trajectory:
    """One trajectory to show.

    Attributes:
        label: What the legend calls it.
        cycle: Every leg's stance and swing over one gait cycle.
        optima: The optimizer's answer per optimized leg (empty for the reference or a
            trajectory read from a file).
    """

    label: str
    cycle: RobotCycle
    optima: dict[str, SwingOptimum] = field(default_factory=dict)

    @property
    def solved(self) -> bool:
        """Every optimizer behind it converged to a feasible point."""
        return all(o.success for o in self.optima.values())


def reference_trajectory(pipeline: EnergyPipeline) -> Trajectory:
    """The cubic-spline reference on every leg."""
    return Trajectory(REFERENCE_LABEL, pipeline.robot_cycle(make_family("reference")))


def optimized_trajectory(
    pipeline: EnergyPipeline,
    family_name: str = DEFAULT_FAMILY,
    method: Method = "ipopt",
    legs: Sequence[str] = FIRST_PAIR,
) -> Trajectory:
    """Optimize ``legs`` (default: the diagonal pair; their twins repeat them) and evaluate."""
    family = make_family(family_name)
    optima = {leg: optimize(SwingProblem(pipeline, leg, family), method) for leg in legs}
    cycle = pipeline.robot_cycle(family, {leg: o.theta for leg, o in optima.items()})
    return Trajectory(f"optimum ({family.name}, {method})", cycle, optima)


def saved_trajectory(pipeline: EnergyPipeline, saved: SavedSwings) -> Trajectory:
    """The swings of a result directory, evaluated leg by leg with their own families.

    Raises:
        InfeasibleError: A saved swing cannot be realised by this robot (another robot's result).
    """
    legs = {}
    for leg in LEG_NAMES:
        family = saved.families.get(leg, "reference")
        theta = saved.parameters.get(leg)
        legs[leg] = pipeline.leg_cycle(leg, make_family(family), theta)
    cycle = RobotCycle(pipeline.gait, pipeline.accounting, legs, pipeline.robot.total_mass_kg)
    return Trajectory(saved.label, cycle)


def shown_trajectories(
    robot: Robot,
    gait: Gait,
    from_dirs: Sequence[str | Path] = (),
    accounting: Accounting = "paper",
) -> tuple[EnergyPipeline, list[Trajectory]]:
    """The pipeline and the trajectories to show: reference first.

    Args:
        robot: The robot.
        gait: The gait when no directory is given (a directory brings its own).
        from_dirs: Result directories of ``scalf-opt optimize --out``; none: the default optimum.
        accounting: Power accounting when no directory is given.

    Raises:
        ConfigError: A directory cannot be read, or the directories' gaits or accountings differ.
        NotSolvedError: The default optimum did not converge.
    """
    saved = [read_saved_swings(d) for d in from_dirs]
    for swings in saved:
        swings.check_robot(robot)
    if saved:
        first = saved[0]
        for other in saved[1:]:
            for what, a, b in (
                ("gait", first.gait, other.gait),
                ("accounting", first.accounting, other.accounting),
            ):
                if a != b:
                    raise ConfigError(
                        f"{other.source}: its {what} differs from {first.source}'s; "
                        "compare results of one gait and accounting"
                    )
        gait, accounting = first.gait, first.accounting
    pipeline = EnergyPipeline(robot, gait, accounting)
    shown = [reference_trajectory(pipeline)]
    if saved:
        shown += [saved_trajectory(pipeline, s) for s in saved]
    else:
        optimum = optimized_trajectory(pipeline)
        if not optimum.solved:
            failed = ", ".join(
                f"{o.leg} ({o.status})" for o in optimum.optima.values() if not o.success
            )
            raise NotSolvedError(f"the default optimum was not solved: {failed}")
        shown.append(optimum)
    return pipeline, shown
