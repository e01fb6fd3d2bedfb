"""The pattern search and Ipopt on the paper family, and the landscape they search.

What :func:`~scalf_opt.viz.search_figure.search_figure` draws: both optimizers run through the
one optimization entry (:func:`~scalf_opt.optimize.driver.optimize_swings`, so the figure shows
the optima ``scalf-opt optimize --family paper`` reports), and the exact swing energy of the
paper family over (C1, C2) around them, at the rate they converged at.
"""

from __future__ import annotations

from collections.abc import Sequence

import numpy as np

from scalf_opt.energy.loads import PAPER_LOADS
from scalf_opt.energy.pipeline import EnergyPipeline
from scalf_opt.locomotion.swing.registry import make_family
from scalf_opt.optimize.driver import Settings, optimize_swings
from scalf_opt.optimize.landscape import energy_landscape
from scalf_opt.optimize.pattern_search import PatternSearchOptions
from scalf_opt.optimize.problem import SwingGoal
from scalf_opt.optimize.solvers import IpoptSolver, PatternSearchSolver
from scalf_opt.types import FIRST_PAIR
from scalf_opt.viz.search_figure import LegSearch

GRID_POINTS = 61
"""Landscape points per parameter by default (61 x 61 exact evaluations per leg)."""

FAMILY = "paper"
"""The family whose (C1, C2) plane is drawn."""


def search_study(
    pipeline: EnergyPipeline,
    legs: Sequence[str] = FIRST_PAIR,
    grid_points: int = GRID_POINTS,
    options: PatternSearchOptions | None = None,
) -> dict[str, LegSearch]:
    """Run the pattern search and Ipopt on the paper family and map the landscape around them.

    The grid covers every accepted point of both phases, Ipopt's optimum and the start, with a
    quarter of their span (at least 2 degrees) as margin on each side. The landscape is the
    paper's (its Figure 8): the swing energy, under the trunk-only loads whatever the
    pipeline's (under whole-body loads each leg's objective would add its pair's stance).
    """
    pipeline = pipeline.with_loads(PAPER_LOADS)
    family = make_family(FAMILY)
    pattern_settings = Settings(PatternSearchSolver.name, pattern=options or PatternSearchOptions())
    pattern_run = optimize_swings(pipeline, tuple(legs), family, pattern_settings)
    ipopt_run = optimize_swings(pipeline, tuple(legs), family, Settings(IpoptSolver.name))
    # the landscape at the finer of the two runs' rates (the paper family converges at the
    # gait's rate, so both are the same there)
    at_rate = max((pattern_run.pipeline, ipopt_run.pipeline), key=lambda p: p.gait.sample_rate_hz)
    out = {}
    for leg in legs:
        pattern = pattern_run.legs[leg].best
        ipopt = ipopt_run.legs[leg].best
        details = pattern.pattern_details
        points = [row[1:3] for row in (*details.feasibility_history, *details.history)]
        points += [tuple(ipopt.theta), (0.0, 0.0)]
        cloud = np.array(points, dtype=float)
        lo, hi = cloud.min(axis=0), cloud.max(axis=0)
        pad = np.maximum(0.25 * (hi - lo), 2.0)
        x = np.linspace(lo[0] - pad[0], hi[0] + pad[0], grid_points)
        y = np.linspace(lo[1] - pad[1], hi[1] + pad[1], grid_points)
        out[leg] = LegSearch(
            pattern=pattern,
            ipopt=ipopt,
            landscape=energy_landscape(SwingGoal(family).on(at_rate, leg), x, y),
            reference_swing_j=ipopt_run.legs[leg].reference_swing_energy_j,
            pattern_rates_hz=tuple(pattern_run.rates_hz),
        )
    return out
