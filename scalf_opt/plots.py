"""Matplotlib figures of the paper reproduction, written atomically as PNG files.

* ``pattern_search.png``: the pattern search's accepted points, C1, C2 and the swing energy per
  iteration (the paper's Figure 8), for RF and LH.
* ``swing_paths.png``: the RF swing foot path in the leg frame and the swing power of both joints
  for the reference, the paper family's optimum and the richest family's optimum.
"""

from __future__ import annotations

import os
from pathlib import Path

import matplotlib

matplotlib.use("Agg")  # files only: no display needed

import matplotlib.pyplot as plt
import numpy as np
from matplotlib.figure import Figure

from scalf_opt.reproduction import PAIR, RUNS, Reproduction
from scalf_opt.results import temporary_sibling


def save_atomic(fig: Figure, path: Path) -> Path:
    """Save ``fig`` as PNG to ``path`` atomically and close it."""
    fd, tmp = temporary_sibling(path)
    try:
        with os.fdopen(fd, "wb") as handle:
            # no software/date metadata: the same inputs give the same bytes
            fig.savefig(handle, format="png", dpi=110, metadata={"Software": None})
        os.replace(tmp, path)
    finally:
        Path(tmp).unlink(missing_ok=True)
        plt.close(fig)
    return path


def pattern_search_figure(rep: Reproduction) -> Figure:
    """C1, C2 and swing energy of the accepted points against the iteration (Figure 8)."""
    fig, axes = plt.subplots(3, 1, figsize=(7, 7), sharex=True)
    for leg, style in zip(PAIR, ("-o", "--s"), strict=True):
        history = np.array(rep.optima["pattern"][leg].history)
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


def swing_figure(rep: Reproduction, leg: str = "RF") -> Figure:
    """Foot path and joint power over the swing of ``leg`` for each trajectory."""
    fig, (ax_path, ax_power) = plt.subplots(1, 2, figsize=(11, 4.2))
    cycles = [("reference (cubic spline)", rep.reference)]
    cycles += [
        (RUNS[key][1], rep.cycles[key]) for key in ("ipopt", "ipopt_rich") if key in rep.cycles
    ]
    ground = -rep.gait.stance_height_m
    for label, cycle in cycles:
        swing = cycle.legs[leg].swing
        foot = swing.values["foot"]
        ax_path.plot(foot[0], foot[1] - ground, label=label)
        total = swing.values["power"].sum(axis=0)
        ax_power.plot(swing.tau_s, total, label=f"{label}: {swing.energy_j.sum():.2f} J")
    ax_path.axhline(rep.gait.clearance_m, color="grey", ls=":", lw=1)
    ax_path.annotate("H", (0.0, rep.gait.clearance_m), color="grey")
    ax_path.set_xlabel("foot x in the leg frame [m]")
    ax_path.set_ylabel("foot height above the ground [m]")
    ax_path.set_title(f"{leg} swing foot path")
    ax_path.set_aspect("equal", adjustable="datalim")
    ax_power.set_xlabel("time since lift-off [s]")
    ax_power.set_ylabel("hip + knee power [W]")
    ax_power.set_title(f"{leg} swing power (|tau qd| + friction heat)")
    for ax in (ax_path, ax_power):
        ax.grid(True, alpha=0.3)
        ax.legend(fontsize=8)
    fig.tight_layout()
    return fig


def write_paper_figures(rep: Reproduction, out: Path) -> list[Path]:
    """Write both figures into ``out``; returns their paths."""
    return [
        save_atomic(pattern_search_figure(rep), out / "pattern_search.png"),
        save_atomic(swing_figure(rep), out / "swing_paths.png"),
    ]
