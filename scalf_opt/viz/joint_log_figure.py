"""The figure of a robot's log against the model at its gait: every joint's power over a cycle."""

from __future__ import annotations

from typing import Any

import matplotlib

matplotlib.use("Agg")  # files only: no display needed

import matplotlib.pyplot as plt
import numpy as np
from matplotlib.figure import Figure

from scalf_opt.viz.plotting import fitted_title


def joint_comparison_figure(comparison: Any, title: str) -> Figure:
    """A panel per joint (a row per leg, trunk first): measured and planned power over a cycle.

    Dashed lines mark lift-off: the log's (orange) and the model's (blue, dotted).

    Args:
        comparison: A ``scalf_opt.logs.log_plan.LogPlanComparison`` (its ``joints``, each with
            ``leg``, ``joint``, ``measured_j``, ``planned_j``, ``ratio``, ``measured_w`` and
            ``planned_w`` on its ``phase`` grid, and its ``gait``): the floor above draws it.
        title: Figure title.
    """
    legs = list(dict.fromkeys(c.leg for c in comparison.joints))
    columns = max(sum(1 for c in comparison.joints if c.leg == leg) for leg in legs)
    fig, axes = plt.subplots(
        len(legs),
        columns,
        figsize=(3.6 * columns, 2.2 * len(legs) + 0.8),
        squeeze=False,
        sharex=True,
    )
    phase = comparison.phase
    for row, leg in enumerate(legs):
        mine = [c for c in comparison.joints if c.leg == leg]
        for col in range(columns):
            ax = axes[row][col]
            if col >= len(mine):
                ax.set_visible(False)
                continue
            c = mine[col]
            ax.plot(
                phase,
                c.measured_w,
                color="tab:orange",
                lw=1.4,
                label=f"measured {c.measured_j:.2f} J",
            )
            planned = "not modelled" if c.planned_j == 0 else f"planned {c.planned_j:.2f} J"
            ax.plot(phase, c.planned_w, color="tab:blue", lw=1.4, label=planned)
            ratio = "" if c.ratio is None else f"  (x{c.ratio:.2f})"
            ax.set_title(f"{leg} {c.joint}{ratio}", fontsize=8)
            ax.grid(True, alpha=0.3)
            ax.legend(fontsize=7, loc="upper right")
            if col == 0:
                ax.set_ylabel("|tau qd| [W]", fontsize=8)
            if row == len(legs) - 1:
                ax.set_xlabel("phase of the leg's cycle (0: touch-down)", fontsize=8)
            ax.tick_params(labelsize=7)
    # lift-off: the log's measured one and the model's (they differ for a flying trot)
    for ax in np.ravel(axes):
        if ax.get_visible():
            ax.axvline(comparison.log_duty_cycle, color="tab:orange", lw=0.8, ls="--")
            ax.axvline(comparison.gait.duty_cycle, color="tab:blue", lw=0.8, ls=":")
    fig.suptitle(fitted_title(title, 3.6 * columns, 9.0), fontsize=9)
    fig.tight_layout()
    return fig
