"""Which limits a 3-D plan rides: the constraints its optimum is pinned at.

An optimum of the 3-D cycle NLP (:mod:`~scalf_opt.optimize.whole_body_nlp`) sits where a cheaper
motion would break something: a joint's range, velocity or effort limit, a drive's bound (each
less its margin), or an end of the period's range when the period is free. :func:`pinned_limits`
reads the plan at the NLP's read points (its schedule's: by default the nodes, quarter points
and midpoints) and names each
limit some point reaches to within :data:`PINNED_SHARE` of the limit's span.
"""

from __future__ import annotations

import math

import numpy as np

from scalf_opt.energy.whole_body_plan import WholeBodyPlan
from scalf_opt.optimize.whole_body_nlp import CycleProblem

PINNED_SHARE = 1e-3
"""A limit counts as pinned when a read point comes within this share of its span (of the
bound's size when one end is infinite): Ipopt's solution meets its bounds to about 1e-8."""


def _read_point_values(
    problem: CycleProblem, plan: WholeBodyPlan
) -> tuple[np.ndarray, np.ndarray, dict[str, np.ndarray]]:
    """The coordinates, rates [SI] and node-function outputs at every read point."""
    schedule = plan.schedule
    fractions = [f for f, _ in schedule.read_points]
    nodes = np.arange(schedule.intervals)
    x, xd, _ = plan.states_at(np.concatenate([(nodes + f) * schedule.step_s for f in fractions]))
    outputs = [plan.node_outputs(problem.accounting)] + [
        plan.inner_outputs(problem.accounting, f) for f in fractions[1:]
    ]
    merged = {name: np.hstack([o[name] for o in outputs]) for name in outputs[0]}
    return x, xd, merged


def pinned_limits(problem: CycleProblem, plan: WholeBodyPlan) -> tuple[str, ...]:
    """Every limit ``plan`` reaches (module docstring), as ``"<joint> <quantity> <end>: <source>"``.

    ``problem`` gives the margins and the period's range; ``plan`` its optimum.
    """
    physics = problem.physics
    x, xd, outputs = _read_point_values(problem, plan)
    pinned = []
    for bound in problem.margins.apply(physics.joint_bounds()):
        j = bound.joint
        if bound.output == "q":
            values = x[6 + j]
        elif bound.output == "qd":
            values = xd[6 + j]
        elif bound.output == "tau":
            values = outputs["tau"][j]
        else:
            values = np.ravel(outputs[f"{bound.output}_{j}"])
        ends = [e for e in (bound.lower, bound.upper) if math.isfinite(e)]
        if not ends:
            continue
        span = bound.upper - bound.lower if len(ends) == 2 else max(abs(ends[0]), 1e-12)
        name = f"{physics.joint_names[j]} {bound.output}"
        if math.isfinite(bound.upper) and values.max() >= bound.upper - PINNED_SHARE * span:
            pinned.append(f"{name} upper: {bound.source}")
        if math.isfinite(bound.lower) and values.min() <= bound.lower + PINNED_SHARE * span:
            pinned.append(f"{name} lower: {bound.source}")
    if problem.period_range_s is not None:
        shortest, longest = problem.period_range_s
        span = longest - shortest
        period = plan.schedule.period_s
        if period <= shortest + PINNED_SHARE * span:
            pinned.append(f"period lower: the period's range ({shortest:g} s)")
        if period >= longest - PINNED_SHARE * span:
            pinned.append(f"period upper: the period's range ({longest:g} s)")
    return tuple(pinned)
