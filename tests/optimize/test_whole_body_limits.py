"""Which limits a 3-D optimum rides, against the plan read through Pinocchio's own dynamics."""

import math

import numpy as np
import pytest

from scalf_opt.locomotion.periodic_spline import READ_POINTS
from scalf_opt.optimize.whole_body_limits import PINNED_SHARE, pinned_limits

pytestmark = [pytest.mark.slow, pytest.mark.xdist_group(name="whole_body_cycle")]


def test_a_limit_is_named_exactly_when_the_plan_reaches_it(go1_cycle):
    """Every joint range, velocity and effort limit (less margins): named by ``pinned_limits``
    if and only if the plan, read at the NLP's read points through ``pin.rnea``, comes within
    the pinned share of it; Go1's optimum rides at least one (an optimum sits on its limits)."""
    from dataclasses import replace

    problem, solution = go1_cycle
    plan = solution.plan
    pinned = set(pinned_limits(problem, plan))
    assert pinned
    schedule = plan.schedule
    nodes = np.arange(schedule.intervals)
    times = np.concatenate([(nodes + f) * schedule.step_s for f, _ in READ_POINTS])
    samples = plan.samples(times)
    checked = 0
    for bound in problem.margins.apply(problem.physics.joint_bounds()):
        j = bound.joint
        values = {"q": samples.x[6 + j], "qd": samples.xd[6 + j], "tau": samples.tau_nm[j]}.get(
            bound.output
        )
        if values is None:
            continue
        span = bound.upper - bound.lower
        name = f"{problem.physics.joint_names[j]} {bound.output}"
        for end, reached in (
            (
                "upper",
                math.isfinite(bound.upper) and values.max() >= bound.upper - PINNED_SHARE * span,
            ),
            (
                "lower",
                math.isfinite(bound.lower) and values.min() <= bound.lower + PINNED_SHARE * span,
            ),
        ):
            assert (f"{name} {end}: {bound.source}" in pinned) == reached, (name, end)
            checked += 1
    assert checked >= 6 * problem.physics.n_joints
    # the period at an end of its range is named too
    free = replace(problem, period_range_s=(schedule.period_s, 2 * schedule.period_s))
    assert "period lower: the period's range" in "; ".join(pinned_limits(free, plan))
