"""What an optimization asks for, as objects: the goals the API hands to the optimizers.

A command's options are names (``--family free``, ``--free-stance``); they become one goal here,
once, in :func:`scalf_opt.api.optimization.goal_from`, and everything below works with the
goal's objects (the family, the settings, the margins), never with the names again:

* :class:`FamilyGoal`: the swings of some legs in a swing family, solved by the one driver
  (:func:`~scalf_opt.optimize.driver.optimize_swings`), with or without the free-trajectory
  bound beside them;
* :class:`BoundGoal`: the free-trajectory bound itself, reported as an optimum;
* :class:`StanceGoal`: the stance height and x-offsets optimized with the diagonal pair's swings.

The gait search's goal, the cheapest trot at a speed, is
:class:`~scalf_opt.optimize.gait_search.GaitGoal` (beside the search box it holds).
"""

from __future__ import annotations

from dataclasses import dataclass

from scalf_opt.energy.margins import LimitMargins
from scalf_opt.locomotion.swing.family import SwingFamily
from scalf_opt.optimize.driver import Settings
from scalf_opt.optimize.problem import SwingGoal
from scalf_opt.types import FIRST_PAIR


@dataclass(frozen=True)
class FamilyGoal:
    """The swings of ``legs`` in ``family``.

    Attributes:
        legs: The legs to optimize (a leg not given takes its twin's optimum).
        family: The swing family, with parameters to optimize.
        settings: The solver, starts and margins.
        with_bound: Also compute each leg's free-trajectory bound and the gap to it.
    """

    legs: tuple[str, ...]
    family: SwingFamily
    settings: Settings
    with_bound: bool = False

    @property
    def swing(self) -> SwingGoal:
        """One leg's swing goal: the family within the margins."""
        return SwingGoal(self.family, self.settings.margins)


@dataclass(frozen=True)
class BoundGoal:
    """The free-trajectory bound of ``legs``: dense B-splines refined until the energy converges.

    Attributes:
        legs: The legs.
        margins: How far inside the joint range and the stroke the bound's swings stay.
    """

    legs: tuple[str, ...]
    margins: LimitMargins


@dataclass(frozen=True)
class StanceGoal:
    """The stance (height, feet's x-offsets) optimized with the diagonal pair's swings.

    Attributes:
        family: The pair's swing family.
        settings: The solver, starts and margins of the swings' solves.
    """

    family: SwingFamily
    settings: Settings
    legs: tuple[str, ...] = FIRST_PAIR


Goal = FamilyGoal | BoundGoal | StanceGoal
"""Any goal :func:`scalf_opt.api.optimization.optimize_goal` takes."""
