"""The 3-D cycle's driver: solve on a coarse grid, refine it, and keep the ten-times rule.

Ipopt solves the 3-D cycle NLP (:mod:`~scalf_opt.optimize.whole_body_nlp`) readily on a coarse
grid but creeps on a fine one from the kinematic start (measured on Go1: 18 nodes converge in 417
iterations; 36 nodes from the kinematic start had not converged after 1,500). So the driver solves
on a grid a quarter of the asked rate, then doubles the grid, each time starting from the last
optimum read on the new nodes (its spline and forces), until it reaches the asked rate. There it
re-reads the optimum at ten times the rate through Pinocchio
(:meth:`~scalf_opt.energy.whole_body_plan.WholeBodyPlan.check`). While the energy there differs
from the plan's own by more than :data:`RATE_TOLERANCE` it refines, at most
:data:`MAX_EXTRA_REFINEMENTS` times: it doubles the grid, and the last time it reads the same
grid more densely instead (:data:`FINE_READS_PER_INTERVAL` points per interval instead of
:data:`~scalf_opt.locomotion.periodic_spline.READS_PER_INTERVAL`, starting from the optimum
itself). The answer is converged only if every solve converged and the last check agrees.

Why doubling first: a finer grid is a richer plan and a truer one between the nodes (the trunk's
wrench left there shrinks), which the referee feels; a denser reading only reads the same plan's
energy more exactly. Measured on Go1 at 25 Hz: read denser on 10 nodes the plan passed the rule
but cost 12.77 J per cycle and the referee found +9.5 to +10.2 % per leg; on 18 nodes, 11.09 J
and +6.3 to +6.8 %. Why the denser reading last: a plan that still misses the rule by a little
mostly does so in the charged power ``|tau qd|``, whose kinks (where a joint's power changes
sign) the optimizer places between the read points (SCalf at 1.0 m/s on 32 nodes: the drives'
Stribeck heat agreed with ten times the rate to 1e-4, the charged power was 0.5 % short); a
second doubling costs more per iteration and, from there, can take thousands of iterations
(SCalf on about 70 nodes: 3,000), where the denser reading takes a few hundred at 1.4 to 2 times
the cost per iteration.
"""

from __future__ import annotations

import math
from collections.abc import Callable
from dataclasses import dataclass, replace

import numpy as np

from scalf_opt.energy.whole_body_plan import PlanCheck, WholeBodyPlan
from scalf_opt.locomotion.contact_schedule import trot_schedule
from scalf_opt.locomotion.periodic_spline import READS_PER_INTERVAL
from scalf_opt.optimize.whole_body_nlp import CycleProblem, CycleSolution, solve_cycle

RATE_TOLERANCE = 0.005
"""Largest relative difference between the energy at the nodes and at ten times their rate."""

CHECK_FACTOR = 10
"""The check's rate over the plan's."""

COARSEST_SHARE = 0.25
"""The first grid's rate as a share of the asked rate."""

MAX_EXTRA_REFINEMENTS = 2
"""Refinements beyond the asked rate while the check disagrees: doublings of the grid, the last
one a denser reading of the same grid instead."""

FINE_READS_PER_INTERVAL = 8
"""The read points per interval of the denser reading (composite Simpson's rule on eighths)."""

WARM_GRID_SHARE = 2.0
"""A warm start's first grid is at most this multiple of the asked rate (one doubling beyond it:
where Go1's cold trots pass the ten-times rule). Measured on Go1's chain 1.0 -> 1.2 -> 1.4 m/s:
the 1.2 m/s answer failed the rule on 20 nodes and was refined to 40; 1.4 m/s then started, and
stayed, on 40 nodes (6.5 minutes for that one solve on a loaded machine)."""

MIN_NODES_PER_PHASE = 3
"""The coarsest grid keeps at least this many nodes in each stance and each swing."""


@dataclass(frozen=True)
class GridStep:
    """One solve of the refinement.

    Attributes:
        nodes: The grid's node count.
        reads_per_interval: The read points per interval the NLP saw.
        solution: What Ipopt returned.
        energy_j: The plan's energy per cycle at its nodes [J].
        check: Its re-reading at ten times the rate.
    """

    nodes: int
    reads_per_interval: int
    solution: CycleSolution
    energy_j: float
    check: PlanCheck

    @property
    def rate_difference(self) -> float:
        """The check's energy relative to the nodes' (``E_10x / E - 1``)."""
        return self.check.energy.total_j / self.energy_j - 1.0


@dataclass(frozen=True)
class CycleResult:
    """The optimum of a 3-D cycle and how it was reached.

    Attributes:
        steps: Every solve, coarsest first; the last is the answer.
    """

    steps: tuple[GridStep, ...]

    @property
    def last(self) -> GridStep:
        """The answer's solve."""
        return self.steps[-1]

    @property
    def plan(self) -> WholeBodyPlan:
        """The optimum (the last solve's plan)."""
        return self.last.solution.plan

    @property
    def grid_change(self) -> tuple[float, int] | None:
        """How much the last grid moved the answer, and from which grid.

        The answer's energy at ten times its rate against the optimum of the last solve on
        fewer nodes, also at ten times its rate (the energies both plans really spend):
        ``(E / E_coarser - 1, coarser node count)``; ``None`` when every solve had the answer's
        node count. The ten-times rule checks that the optimizer saw the plan's energy; this
        says whether a finer grid still finds cheaper plans.
        """
        coarser = [step for step in self.steps if step.nodes < self.last.nodes]
        if not coarser:
            return None
        before = coarser[-1]
        return self.last.check.energy.total_j / before.check.energy.total_j - 1.0, before.nodes

    @property
    def converged(self) -> bool:
        """Every solve converged and the last plan's energy holds at ten times its rate."""
        solved = all(step.solution.success for step in self.steps)
        return solved and abs(self.last.rate_difference) <= RATE_TOLERANCE

    def failure(self) -> str:
        """Why it did not converge, in words (empty when it did)."""
        for step in self.steps:
            if not step.solution.success:
                return f"Ipopt on {step.nodes} nodes: {step.solution.status}"
        if not self.converged:
            return (
                f"the energy at {CHECK_FACTOR}x the rate differs by "
                f"{100 * self.last.rate_difference:+.2f} % (the rule: within "
                f"{100 * RATE_TOLERANCE:g} %)"
            )
        return ""


def resampled(plan: WholeBodyPlan, problem: CycleProblem) -> WholeBodyPlan:
    """``plan`` read on ``problem``'s grid.

    Its spline at the new nodes, its forces there (zero where the new schedule has a foot in the
    air or at a contact's edge).
    """
    schedule = problem.schedule
    x, xd, xdd = plan.states_at(schedule.times_s)
    forces = plan.forces_at(schedule.times_s) * np.repeat(schedule.loaded, 3, axis=0)
    return replace(plan, schedule=schedule, x=x, xd=xd, xdd=xdd, forces_n=forces)


def optimize_cycle(
    problem: CycleProblem,
    sample_rate_hz: float,
    progress: Callable[[str], None] | None = None,
    start: WholeBodyPlan | None = None,
) -> CycleResult:
    """Optimise ``problem``'s cycle at ``sample_rate_hz`` by grid refinement (module docstring).

    ``problem.schedule`` gives the period (the start's, when ``problem.period_range_s`` leaves
    it free: each finer grid starts from the last solve's) and the duty factor; its own grid and
    reading are replaced. ``start``: a plan to start from instead of the kinematic start (another
    speed's answer, of the same duty factor): the first grid is then its own, not the coarse one,
    but no finer than :data:`WARM_GRID_SHARE` times the asked rate (a start refined further for
    its own speed's ten-times rule does not hand its finest grid down a chain of speeds), read as
    densely as the start was; the refinements beyond the asked rate count from there.
    """
    period, duty = problem.schedule.period_s, problem.schedule.duty_cycle
    phase_nodes = MIN_NODES_PER_PHASE / (period * min(duty, 1 - duty))
    rate = max(COARSEST_SHARE * sample_rate_hz, phase_nodes)
    reads = READS_PER_INTERVAL
    steps: list[GridStep] = []
    plan: WholeBodyPlan | None = None
    extra = 0
    denser = False  # the next solve reads the last one's grid more densely
    if start is not None:
        plan = replace(start, speed_m_s=problem.speed_m_s)
        own = start.schedule.intervals / start.schedule.period_s
        rate = min(own, WARM_GRID_SHARE * sample_rate_hz)
        reads = start.schedule.reads_per_interval
        extra = max(0, round(math.log2(rate / sample_rate_hz))) + (reads > READS_PER_INTERVAL)
    while True:
        if plan is not None:
            period = plan.schedule.period_s  # the last solve's (its own when free)
        if denser and plan is not None:
            schedule = replace(plan.schedule, reads_per_interval=reads)
        else:
            schedule = replace(trot_schedule(period, duty, rate), reads_per_interval=reads)
        last = steps[-1] if steps else None
        if last and not denser and schedule.intervals <= last.nodes:
            rate *= 2  # the duty factor's grid rounds this rate to the last step's nodes
            continue
        step_problem = replace(problem, schedule=schedule)
        first = None if plan is None else resampled(plan, step_problem)
        if progress is not None:
            denser_note = f", read at {reads} points each" if reads != READS_PER_INTERVAL else ""
            progress(f"3-D cycle on {schedule.intervals} nodes{denser_note}")
        solution = solve_cycle(step_problem, first)
        plan = solution.plan
        energy = plan.evaluate(problem.accounting).total_j
        check = plan.check(problem.accounting, CHECK_FACTOR)
        steps.append(GridStep(schedule.intervals, reads, solution, energy, check))
        denser = False
        if not solution.success:
            break
        if rate >= sample_rate_hz * (1 - 1e-9):
            if abs(steps[-1].rate_difference) <= RATE_TOLERANCE or extra >= MAX_EXTRA_REFINEMENTS:
                break
            extra += 1
            # the last refinement reads the grid denser (unless it already is); the others
            # double it
            denser = extra == MAX_EXTRA_REFINEMENTS and reads < FINE_READS_PER_INTERVAL
            if denser:
                reads = FINE_READS_PER_INTERVAL
                continue
        rate = min(2 * rate, sample_rate_hz) if rate < sample_rate_hz else 2 * rate
    return CycleResult(tuple(steps))
