"""Names become one goal, once: the bound, the free stance and a family's swings are objects
from there down, and the options that do not go together are refused before a robot loads."""

import pytest

from scalf_opt.api.optimization import goal_from, optimize_goal
from scalf_opt.energy.margins import LimitMargins
from scalf_opt.energy.pipeline import EnergyPipeline
from scalf_opt.errors import ConfigError
from scalf_opt.locomotion.gait import Gait
from scalf_opt.optimize.goals import BoundGoal, FamilyGoal, StanceGoal


def test_each_kind_of_request_is_its_goal():
    family = goal_from(family="joint-4", legs="rf", starts=2, bound=True)
    assert isinstance(family, FamilyGoal) and family.family.name == "joint-4"
    assert family.legs == ("RF",) and family.settings.starts == 2 and family.with_bound
    assert family.swing.family is family.family and family.swing.margins == LimitMargins()
    bound = goal_from(family="free", margins=LimitMargins(0.01, 0.001))
    assert bound == BoundGoal(("RF", "LH"), LimitMargins(0.01, 0.001))
    stance = goal_from(family="paper", free_stance=True, method="pattern", precision=0.2)
    assert isinstance(stance, StanceGoal) and stance.settings.pattern.precision == 0.2


@pytest.mark.parametrize(
    ("options", "field"),
    [
        ({"family": "free", "bound": True}, "family"),
        ({"family": "free", "method": "pattern"}, "family"),
        ({"free_stance": True, "legs": "RF"}, "free_stance"),
        ({"precision": 0.1}, "precision"),
        ({"family": "bspline-16"}, "family"),
        ({"family": "reference"}, "family"),
    ],
)
def test_options_that_do_not_go_together_name_their_field(options, field):
    with pytest.raises(ConfigError) as info:
        goal_from(**options)
    assert info.value.field == field


def test_a_goal_is_reached_on_any_pipeline(scalf):
    goal = goal_from(family="paper", legs="RF")
    pipeline = EnergyPipeline(scalf, Gait(), loads="trunk")
    result = optimize_goal(scalf, pipeline, goal)
    assert result.converged and tuple(result.run.legs) == ("RF",)
    assert result.cycle.energy_j < result.reference.energy_j
