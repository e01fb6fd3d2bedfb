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

from scalf_opt.energy.cycle import RobotCycle
from scalf_opt.files import write_with
from scalf_opt.optimize.solve import SwingOptimum


def save_atomic(fig: Figure, path: Path) -> Path:
    """Save ``fig`` as PNG to ``path`` atomically and close it."""
    try:
        # no software/date metadata: the same inputs give the same bytes
        return write_with(
            path,
            lambda handle: fig.savefig(handle, format="png", dpi=110, metadata={"Software": None}),
        )
    finally:
        plt.close(fig)


def pattern_search_figure(optima: Mapping[str, SwingOptimum]) -> Figure:
    """C1, C2 and swing energy of the accepted points against the iteration (Figure 8)."""
    fig, axes = plt.subplots(3, 1, figsize=(7, 7), sharex=True)
    for (leg, optimum), style in zip(optima.items(), ("-o", "--s", "-.^", ":v"), strict=False):
        history = np.array(optimum.history)
        for ax, column, label in zip(
            axes, (1, 2, 3), ("C1 [deg]", "C2 [deg]", "swing energy [J]"), strict=True
        ):
            ax.plot(history[:, 0], history[:, column], style, ms=3, label=leg)
            ax.set_ylabel(label)
            ax.grid(True, alpha=0.3)
    axes[0].set_title("Pattern search on the paper family (accepted points)")
    axes[-1].set_xlabel("iteration")
    axes[0].legend()
    fig.tight_layout()
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
