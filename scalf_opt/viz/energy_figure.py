"""Energy per cycle by leg, phase and joint as stacked bars (the paper's Table 6, drawn).

One group of bars per trajectory, one bar per leg (RF, LH, LF, RH), each stacked from the stance
hip, stance knee, swing hip and swing knee energies; the drives' losses (SCalf: the cylinders'
friction heat) are hatched inside each segment. Each group is labelled with the whole robot's
energy per cycle and its change against the first trajectory (the reference).
"""

from __future__ import annotations

import math
from collections.abc import Sequence

import matplotlib.pyplot as plt
import numpy as np
from matplotlib.figure import Figure
from matplotlib.patches import Patch

from scalf_opt.energy.cycle import change_percent
from scalf_opt.types import JOINT_ROLES, LEG_NAMES
from scalf_opt.viz.colors import trajectory_color
from scalf_opt.viz.plotting import style
from scalf_opt.viz.trajectories import Trajectory, energy_models

SEGMENT_COLORS: dict[tuple[str, str], str] = {
    ("stance", "hip"): "#1f77b4",
    ("stance", "knee"): "#9ecae1",
    ("swing", "hip"): "#d62728",
    ("swing", "knee"): "#fc9272",
}
"""Colour of each stacked segment: (phase, joint)."""


def energy_bars_figure(trajectories: Sequence[Trajectory]) -> Figure:
    """Stacked energy per leg, phase and joint for each trajectory."""
    legs = [leg for leg in LEG_NAMES if leg in trajectories[0].cycle.legs]
    width, gap = 0.8, 1.0
    with style():
        fig, ax = plt.subplots(figsize=(8.0, 4.4), layout="constrained")
        centers = []
        reference = trajectories[0].cycle.energy_j
        top = max(max(t.cycle.legs[leg].energy_j for leg in legs) for t in trajectories)
        # every label with the same decimals, four significant digits on the tallest bar
        decimals = max(0, 3 - math.floor(math.log10(top))) if top > 0.0 else 3
        for group, trajectory in enumerate(trajectories):
            start = group * (len(legs) + gap)
            xs = start + np.arange(len(legs))
            centers.append(float(xs.mean()))
            for x, leg in zip(xs, legs, strict=True):
                leg_cycle = trajectory.cycle.legs[leg]
                bottom = 0.0
                for phase_result in (leg_cycle.stance, leg_cycle.swing):
                    for j, joint in enumerate(JOINT_ROLES):
                        energy = float(phase_result.energy_j[j])
                        loss = float(phase_result.loss_j[j])
                        color = SEGMENT_COLORS[(phase_result.phase, joint)]
                        ax.bar(
                            x, energy, width, bottom=bottom, color=color, edgecolor="white", lw=0.5
                        )
                        if loss > 0.0:
                            ax.bar(
                                x,
                                loss,
                                width,
                                bottom=bottom + energy - loss,
                                color="none",
                                edgecolor="#333333",
                                hatch="...",
                                lw=0,
                            )
                        bottom += energy
                ax.text(
                    x,
                    bottom + 0.01 * top,
                    f"{bottom:.{decimals}f}",
                    ha="center",
                    va="bottom",
                    fontsize=7,
                )
            total = trajectory.cycle.energy_j
            note = f"{total:.{decimals}f} J per cycle"
            if group > 0:
                note += f"\n{change_percent(total, reference):+.1f} %"
            ax.text(
                centers[-1],
                1.1 * top,
                note,
                ha="center",
                va="bottom",
                fontsize=8,
                color=trajectory_color(group),
                fontweight="bold",
            )
        ticks = [
            g * (len(legs) + gap) + k for g in range(len(trajectories)) for k in range(len(legs))
        ]
        ax.set_xticks(ticks, [leg for _ in trajectories for leg in legs])
        for group, trajectory in enumerate(trajectories):
            ax.annotate(
                _wrap(trajectory.label),
                (centers[group], 0.0),
                xycoords=("data", "axes fraction"),
                xytext=(0, -22),
                textcoords="offset points",
                ha="center",
                va="top",
                fontsize=8,
                color=trajectory_color(group),
            )
        ax.set_ylim(0.0, 1.32 * top)
        ax.set_ylabel("energy per cycle [J]")
        ax.grid(axis="x", visible=False)
        handles = [Patch(color=c, label=f"{p} {j}") for (p, j), c in SEGMENT_COLORS.items()]
        handles.append(
            Patch(facecolor="none", edgecolor="#333333", hatch="...", label="of which drive losses")
        )
        ax.legend(
            handles=handles, loc="upper right", ncols=5, fontsize=7, bbox_to_anchor=(1.0, 1.0)
        )
        ax.set_title(
            "Energy per cycle by leg, phase and joint (the paper's Table 6)\n"
            + energy_models(trajectories)
        )
    return fig


def _wrap(label: str, width: int = 28) -> str:
    """Break a long label at spaces so that it fits under its group of bars."""
    words, lines, line = label.split(), [], ""
    for word in words:
        if line and len(line) + 1 + len(word) > width:
            lines.append(line)
            line = word
        else:
            line = f"{line} {word}".strip()
    return "\n".join([*lines, line])
