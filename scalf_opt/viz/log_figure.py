"""The figure of a log against its plan: the robot's power over one cycle, each leg's energy."""

from __future__ import annotations

from collections.abc import Mapping

import matplotlib

matplotlib.use("Agg")  # files only: no display needed

import matplotlib.pyplot as plt
import numpy as np
from matplotlib.figure import Figure

from scalf_opt.viz.plotting import fitted_title


def log_plan_figure(
    measured_t_s: np.ndarray,
    measured_w: np.ndarray,
    planned_t_s: np.ndarray,
    planned_w: np.ndarray,
    measured_j: Mapping[str, float],
    planned_j: Mapping[str, float],
    title: str,
) -> Figure:
    """Two panels: mechanical power over one cycle, measured and planned; energy per leg.

    Args:
        measured_t_s: Cycle times of the measured power (0: RF touches down) [s].
        measured_w: The robot's measured mechanical power, mean over the log's cycles [W].
        planned_t_s: Cycle times of the planned power [s].
        planned_w: The robot's planned mechanical power [W].
        measured_j: Per leg, the measured mechanical energy per cycle [J].
        planned_j: Per leg, the planned one [J].
        title: Figure title.
    """
    fig, (ax_p, ax_e) = plt.subplots(
        1, 2, figsize=(12, 4.4), gridspec_kw={"width_ratios": [2.2, 1]}
    )
    for t, power, color, label in (
        (planned_t_s, planned_w, "tab:blue", "planned"),
        (measured_t_s, measured_w, "tab:orange", "measured (mean over the cycles)"),
    ):
        # periodic: close the curve at the period with the first sample
        closed_t = np.append(t, t[-1] + (t[1] - t[0]))
        closed_w = np.append(power, power[0])
        energy = np.trapezoid(closed_w, closed_t)
        ax_p.plot(closed_t, closed_w, color=color, lw=1.5, label=f"{label}: {energy:.1f} J")
    ax_p.set_xlabel("cycle time [s] (0: RF and LH touch down)")
    ax_p.set_ylabel("mechanical power sum |F v| of all legs [W]")
    ax_p.set_title(fitted_title(title, 8.0, 9.0), fontsize=9)  # it names the files
    ax_p.legend(fontsize=8)
    legs = list(measured_j)
    x = np.arange(len(legs))
    ax_e.bar(x - 0.2, [planned_j[leg] for leg in legs], 0.4, label="planned")
    ax_e.bar(x + 0.2, [measured_j[leg] for leg in legs], 0.4, label="measured")
    for k, leg in enumerate(legs):
        change = 100.0 * (measured_j[leg] - planned_j[leg]) / planned_j[leg]
        ax_e.annotate(
            f"{change:+.1f} %",
            (k, max(measured_j[leg], planned_j[leg])),
            ha="center",
            va="bottom",
            fontsize=8,
        )
    ax_e.set_xticks(x, legs)
    ax_e.set_ylabel("mechanical energy per cycle [J]")
    ax_e.set_title("per leg", fontsize=9)
    ax_e.legend(fontsize=8, loc="lower right")
    for ax in (ax_p, ax_e):
        ax.grid(True, alpha=0.3)
    fig.tight_layout()
    return fig
