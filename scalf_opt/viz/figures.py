"""Matplotlib figures, written atomically and byte-for-byte deterministically as PNG files.

* :func:`pattern_search_figure`: the pattern search's accepted points, C1, C2 and the swing
  energy per iteration (the paper's Figure 8), one line per leg;
* :func:`swing_figure`: a leg's swing foot path in the leg frame and its swing power for several
  trajectories.
"""

from __future__ import annotations

from collections.abc import Mapping, Sequence
from pathlib import Path

import matplotlib

matplotlib.use("Agg")  # files only: no display needed

import matplotlib.pyplot as plt
import numpy as np
from matplotlib.figure import Figure
from matplotlib.patches import Patch
from matplotlib.ticker import MaxNLocator

from scalf_opt.energy.cycle import RobotCycle
from scalf_opt.optimize.solve import SwingOptimum
from scalf_opt.viz.colors import LEG_COLORS
from scalf_opt.viz.plotting import save_figure


def save_atomic(fig: Figure, path: Path) -> Path:
    """Save ``fig`` to ``path`` (:func:`~scalf_opt.viz.plotting.save_figure`) and close it."""
    try:
        return save_figure(fig, path)
    finally:
        plt.close(fig)


def pattern_search_figure(optima: Mapping[str, SwingOptimum]) -> Figure:
    """C1, C2 and swing energy of the accepted points against the iteration (Figure 8).

    A search started where a constraint is violated first minimizes the violation (its
    feasibility phase): its points are drawn hollow in the parameters' panels over a shaded
    span, where no energy is defined yet.
    """
    fig, axes = plt.subplots(3, 1, figsize=(7, 7), sharex=True)
    ends = []  # each leg's last iteration of its feasibility phase
    styles = ("-o", "--s", "-.^", ":v")
    for (leg, optimum), style in zip(optima.items(), styles, strict=False):
        color = LEG_COLORS[leg]
        details = optimum.pattern_details
        history = np.array(details.history)
        phase1 = np.array(details.feasibility_history, dtype=float).reshape(-1, 4)
        for ax, column, label in zip(
            axes, (1, 2, 3), ("C1 [deg]", "C2 [deg]", "swing energy [J]"), strict=True
        ):
            if phase1.size and column < 3:
                ax.plot(
                    phase1[:, 0], phase1[:, column], ":" + style[-1], ms=3, mfc="white", color=color
                )
            ax.plot(history[:, 0], history[:, column], style, ms=3, color=color, label=leg)
            ax.set_ylabel(label)
            ax.grid(True, alpha=0.3)
        if phase1.size:
            ends.append(float(phase1[-1, 0]))
    feasibility_end = min(ends, default=0.0)  # where no leg has an energy yet
    if feasibility_end > 0.0:
        for ax in axes:
            ax.axvspan(0.0, feasibility_end, color="#808080", alpha=0.12, lw=0)
        axes[-1].text(
            0.5 * feasibility_end,
            0.5,
            "feasibility phase:\nno energy yet",
            transform=axes[-1].get_xaxis_transform(),
            ha="center",
            va="center",
            fontsize=8,
            color="#404040",
        )
    axes[0].set_title("Pattern search on the paper family (accepted points)")
    axes[-1].set_xlabel("iteration [count]")
    axes[-1].xaxis.set_major_locator(MaxNLocator(integer=True))
    handles, labels = axes[0].get_legend_handles_labels()
    if feasibility_end > 0.0:
        handles.append(Patch(color="#808080", alpha=0.25))
        labels.append("feasibility phase (hollow: minimizing the constraint violation)")
    fig.legend(handles, labels, fontsize=8, loc="lower center", ncol=len(handles))
    fig.tight_layout(rect=(0.0, 0.04, 1.0, 1.0))  # room for the legend below the panels
    return fig


def swing_figure(trajectories: Sequence[tuple[str, RobotCycle]], leg: str = "RF") -> Figure:
    """Foot path and joint power over the swing of ``leg`` for each labelled cycle."""
    fig, (ax_path, ax_power) = plt.subplots(1, 2, figsize=(11, 4.2))
    gait = trajectories[0][1].gait
    ground = -gait.stance_height_m
    for label, cycle in trajectories:
        swing = cycle.legs[leg].swing
        foot = swing.values["foot"]
        ax_path.plot(foot[0], foot[1] - ground, label=label)
        total = swing.values["power"].sum(axis=0)
        ax_power.plot(swing.t_phase_s, total, label=f"{label}: {swing.energy_j.sum():.2f} J")
    ax_path.axhline(gait.clearance_m, color="grey", ls=":", lw=1)
    ax_path.annotate("H", (0.0, gait.clearance_m), color="grey")
    ax_path.set_xlabel("foot x in the leg frame [m]")
    ax_path.set_ylabel("foot height above the ground [m]")
    ax_path.set_title(f"{leg} swing foot path")
    ax_path.set_aspect("equal", adjustable="datalim")
    ax_power.set_xlabel("time since lift-off [s]")
    ax_power.set_ylabel("hip + knee power [W]")
    ax_power.set_title(f"{leg} swing power (charged joint power + drive losses)")
    for ax in (ax_path, ax_power):
        ax.grid(True, alpha=0.3)
        ax.legend(fontsize=8)
    fig.tight_layout()
    return fig
