"""Reproduce the paper's Tables 5 and 6: reference, pattern search and Ipopt, side by side.

For the RF and LH legs (LF and RH repeat them half a cycle later, the paper's symmetry):

* the cubic-spline reference;
* the pattern search on the paper family with the paper's settings (start (0, 0), step
  (0.5, 0.5), precision 0.1), and again at precision 1e-4 (validation);
* Ipopt on the paper family (the NLP optimum the pattern search is validated against);
* Ipopt on the richest default family, warm-started from the paper family's optimum (nested).
"""

from __future__ import annotations

import time
from collections.abc import Callable, Sequence
from dataclasses import dataclass, field
from typing import Any

import numpy as np

from scalf_opt.energy.cycle import RobotCycle, change_percent
from scalf_opt.energy.pipeline import EnergyPipeline
from scalf_opt.io.provenance import provenance
from scalf_opt.locomotion.gait import Gait
from scalf_opt.locomotion.swing.names import DEFAULT_FAMILY
from scalf_opt.locomotion.swing.registry import make_family
from scalf_opt.model.robot import Robot
from scalf_opt.optimize.pattern_search import PatternSearchOptions
from scalf_opt.optimize.problem import SwingProblem
from scalf_opt.optimize.solve import SwingOptimum, run_ipopt, run_pattern_search
from scalf_opt.types import FIRST_PAIR

FINE_PRECISION = 1e-4
"""Pattern-search precision of the validation run."""

PAIR = FIRST_PAIR

RUNS: dict[str, tuple[str, str]] = {
    "pattern": ("paper", "pattern search, paper family (precision 0.1)"),
    "pattern_fine": ("paper", f"pattern search, paper family (precision {FINE_PRECISION:g})"),
    "ipopt": ("paper", "Ipopt, paper family"),
    "ipopt_rich": (DEFAULT_FAMILY, f"Ipopt, {DEFAULT_FAMILY} family"),
}
"""Run key -> (family, label)."""


@dataclass
class Reproduction:
    """Everything the paper report shows.

    Attributes:
        gait: The gait.
        reference: Robot cycle with the reference swing on every leg.
        optima: Run key -> leg -> optimizer answer.
        cycles: Run key -> robot cycle with that run's swing (LF, RH by symmetry).
        wall_time_s: Time of the whole reproduction [s].
    """

    gait: Gait
    reference: RobotCycle
    optima: dict[str, dict[str, SwingOptimum]] = field(default_factory=dict)
    cycles: dict[str, RobotCycle] = field(default_factory=dict)
    wall_time_s: float = 0.0

    @property
    def all_solved(self) -> bool:
        """Every optimizer converged to a feasible point."""
        return all(o.success for runs in self.optima.values() for o in runs.values())


def reproduce(
    pipeline: EnergyPipeline,
    ipopt_options: dict[str, Any] | None = None,
    progress: Callable[[str], None] | None = None,
) -> Reproduction:
    """Run every optimizer of the paper's comparison on the RF and LH legs.

    Args:
        pipeline: Robot, gait (accounting: the paper's).
        ipopt_options: Extra Ipopt options (e.g. ``{"print_level": 5}`` for its log).
        progress: Called with a label before each optimizer run.
    """
    start = time.perf_counter()

    def step(label: str) -> None:
        if progress is not None:
            progress(label)

    out = Reproduction(pipeline.gait, pipeline.robot_cycle(make_family("reference")))
    paper, rich = make_family("paper"), make_family(DEFAULT_FAMILY)
    for key in RUNS:
        out.optima[key] = {}
    for leg in PAIR:
        problem = SwingProblem(pipeline, leg, paper)
        step(f"{leg}: {RUNS['pattern'][1]}")
        out.optima["pattern"][leg] = run_pattern_search(problem)
        step(f"{leg}: {RUNS['pattern_fine'][1]}")
        out.optima["pattern_fine"][leg] = run_pattern_search(
            problem, options=PatternSearchOptions(precision=FINE_PRECISION)
        )
        step(f"{leg}: {RUNS['ipopt'][1]}")
        nlp = run_ipopt(problem, ipopt_options=ipopt_options)
        out.optima["ipopt"][leg] = nlp
        rich_problem = SwingProblem(pipeline, leg, rich)
        warm = rich.embed(nlp.theta, paper) if nlp.success else None
        step(f"{leg}: {RUNS['ipopt_rich'][1]}")
        out.optima["ipopt_rich"][leg] = run_ipopt(rich_problem, warm, ipopt_options)
    for key, (family_name, _) in RUNS.items():
        runs = out.optima[key]
        if all(o.success for o in runs.values()):
            thetas = {leg: runs[leg].theta for leg in PAIR}
            out.cycles[key] = pipeline.robot_cycle(make_family(family_name), thetas)
    out.wall_time_s = time.perf_counter() - start
    return out


def gap_percent(optimum: SwingOptimum, best: SwingOptimum) -> float:
    """How much higher ``optimum``'s exact swing energy is than ``best``'s [%]."""
    return 100.0 * (optimum.swing_energy_j - best.swing_energy_j) / best.swing_energy_j


def table6_rows(rep: Reproduction) -> list[dict[str, float | str]]:
    """Rows of Table 6: per trajectory, energies per leg and their changes against the reference."""
    ref = rep.reference
    rows: list[dict[str, float | str]] = []
    for key, cycle in [("reference", ref), *rep.cycles.items()]:
        label = "reference (cubic spline)" if key == "reference" else RUNS[key][1]
        row: dict[str, float | str] = {"trajectory": label}
        for leg in PAIR:
            row[f"{leg}_swing_j"] = cycle.legs[leg].swing_energy_j
            row[f"{leg}_cycle_j"] = cycle.legs[leg].energy_j
            row[f"{leg}_swing_change_pct"] = change_percent(
                cycle.legs[leg].swing_energy_j, ref.legs[leg].swing_energy_j
            )
            row[f"{leg}_cycle_change_pct"] = change_percent(
                cycle.legs[leg].energy_j, ref.legs[leg].energy_j
            )
        row["total_energy_j"] = cycle.energy_j
        row["total_change_pct"] = change_percent(cycle.energy_j, ref.energy_j)
        row["average_power_w"] = cycle.average_power_w
        row["cost_of_transport"] = cycle.cost_of_transport
        rows.append(row)
    return rows


def table5_rows(rep: Reproduction) -> list[dict[str, float | str]]:
    """Rows of Table 5: the optimum's parameters, iterations and swing energy per run and leg."""
    rows: list[dict[str, float | str]] = []
    for key, (family, label) in RUNS.items():
        for leg in PAIR:
            o = rep.optima[key][leg]
            row: dict[str, float | str] = {"run": label, "family": family, "leg": leg}
            if family == "paper":
                row["C1"], row["C2"] = float(o.theta[0]), float(o.theta[1])
            row.update(
                {
                    "iterations": o.iterations,
                    "evaluations": o.evaluations,
                    "swing_energy_j": o.swing_energy_j,
                    "status": o.status,
                    "wall_time_s": o.wall_time_s,
                }
            )
            rows.append(row)
    return rows


def summary(
    rep: Reproduction, robot: Robot, command: Sequence[str] | None = None
) -> dict[str, object]:
    """Plain data of the whole reproduction (``paper.json``), with its provenance."""
    return {
        "provenance": provenance(robot, command),
        "gait": rep.gait.to_dict(),
        "reference_average_power_w": rep.reference.average_power_w,
        "table5": table5_rows(rep),
        "table6": table6_rows(rep),
        "optima": {k: {leg: o.as_dict() for leg, o in v.items()} for k, v in rep.optima.items()},
        "validation": {
            leg: {
                "gap_at_paper_precision_pct": gap_percent(
                    rep.optima["pattern"][leg], rep.optima["ipopt"][leg]
                ),
                "gap_at_fine_precision_pct": gap_percent(
                    rep.optima["pattern_fine"][leg], rep.optima["ipopt"][leg]
                ),
                "parameter_distance": float(
                    np.linalg.norm(
                        rep.optima["pattern"][leg].theta - rep.optima["ipopt"][leg].theta
                    )
                ),
            }
            for leg in PAIR
        },
        "wall_time_s": rep.wall_time_s,
        "all_solved": rep.all_solved,
    }
