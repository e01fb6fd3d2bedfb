"""Over one gait cycle: joint angles, torques, powers (Figures 9-11) and foot forces (13).

Joint figures: one row per joint (hip pitch, knee), one column per leg of the diagonal pair (RF,
LH; LF and RH repeat them half a cycle later), one line per trajectory in its colour; the swing
phase is shaded. Angles in degrees (converted here, at the edge), torques in N m, powers in W.
"""

from __future__ import annotations

from collections.abc import Sequence
from typing import Literal

import matplotlib.pyplot as plt
import numpy as np
from matplotlib.axes import Axes
from matplotlib.figure import Figure

from scalf_opt.locomotion.forces import GRAVITY_M_S2
from scalf_opt.types import FIRST_PAIR, JOINT_ROLES, LEG_NAMES
from scalf_opt.viz.colors import LEG_COLORS, trajectory_color
from scalf_opt.viz.plotting import DASHES, cycle_samples, shade_swing, style
from scalf_opt.viz.trajectories import Trajectory, energy_models

JointQuantity = Literal["angle", "torque", "power"]

_QUANTITIES: dict[str, tuple[str, str, float, str]] = {
    "angle": ("q", "joint angle [deg]", 180.0 / np.pi, "Joint angles over a cycle"),
    "torque": ("tau", "joint torque [N m]", 1.0, "Joint torques over a cycle"),
    "power": (
        "power",
        "charged power [W]",
        1.0,
        "Joint power over a cycle (the accounting's joint power + drive losses)",
    ),
}
"""Quantity -> (output name, axis label with unit, factor from SI, title)."""


def joint_figure(
    trajectories: Sequence[Trajectory],
    quantity: JointQuantity,
    legs: Sequence[str] = FIRST_PAIR,
) -> Figure:
    """Hip and knee ``quantity`` of ``legs`` over one cycle, one line per trajectory."""
    name, ylabel, factor, title = _QUANTITIES[quantity]
    with style():
        fig, axes = plt.subplots(
            len(JOINT_ROLES),
            len(legs),
            figsize=(8.0, 5.2),
            sharex=True,
            sharey="row",
            squeeze=False,
            layout="constrained",
        )
        for col, leg in enumerate(legs):
            for index, trajectory in enumerate(trajectories):
                leg_cycle = trajectory.cycle.legs[leg]
                t, values = cycle_samples(leg_cycle, name)
                for row in range(len(JOINT_ROLES)):
                    axes[row, col].plot(
                        t,
                        factor * values[row],
                        color=trajectory_color(index),
                        ls=DASHES[index % len(DASHES)] if index == 0 else "-",
                        lw=1.4,
                        label=trajectory.label,
                    )
            for row, joint in enumerate(JOINT_ROLES):
                ax = axes[row, col]
                shade_swing(ax, trajectories[0].cycle.legs[leg], label=row == 0)
                ax.set_title(f"{leg} {joint}", loc="left", fontsize=9)
                if col == 0:
                    ax.set_ylabel(ylabel)
                if quantity == "power":
                    _energy_notes(ax, trajectories, leg, row)
            axes[-1, col].set_xlabel("time in the cycle [s]")
            axes[-1, col].set_xlim(0.0, trajectories[0].cycle.gait.period_s)
        handles, labels = axes[0, 0].get_legend_handles_labels()
        fig.suptitle(f"{title}\n{energy_models(trajectories)}")
        fig.legend(handles, labels, loc="outside lower center", ncols=min(len(labels), 3))
    return fig


def _energy_notes(ax: Axes, trajectories: Sequence[Trajectory], leg: str, row: int) -> None:
    """Each trajectory's energy of this joint over the cycle, in its colour, top left."""
    for index, trajectory in enumerate(trajectories):
        leg_cycle = trajectory.cycle.legs[leg]
        energy = leg_cycle.stance.energy_j[row] + leg_cycle.swing.energy_j[row]
        ax.text(
            0.02,
            0.96 - 0.09 * index,
            f"{energy:.3f} J per cycle",
            transform=ax.transAxes,
            ha="left",
            va="top",
            fontsize=7,
            color=trajectory_color(index),
        )


def foot_force_figure(
    trajectory: Trajectory, carried_mass_kg: float, legs: Sequence[str] = LEG_NAMES
) -> Figure:
    """Ground reaction force on each foot over one trajectory's cycle (the paper's Figure 13).

    Under the paper's trunk-only loads the forces do not depend on the swing; under whole-body
    loads they do, so the title names the trajectory and the load model. Half the carried weight
    ``M g / 2`` is marked (the trunk's, or the whole robot's under whole-body loads): with two
    feet on the ground in a trot, each carries about that much. Under trunk-only loads the
    horizontal forces are zero (the paper's constant speed); their panel says how close.

    Args:
        trajectory: The trajectory whose forces are drawn.
        carried_mass_kg: The mass the stance feet carry [kg] (the load model's).
        legs: The legs drawn.
    """
    cycle = trajectory.cycle
    with style():
        fig, (ax_z, ax_x) = plt.subplots(
            2,
            1,
            figsize=(8.0, 4.6),
            sharex=True,
            height_ratios=(3, 1),
            layout="constrained",
        )
        largest_x = 0.0
        for leg in legs:
            t, grf = cycle_samples(cycle.legs[leg], "grf")
            dash = "-" if leg in FIRST_PAIR else "--"
            color = LEG_COLORS.get(leg, "#555555")
            ax_z.plot(t, grf[1], lw=1.5, ls=dash, color=color, label=leg)
            ax_x.plot(t, grf[0], lw=1.2, ls=dash, color=color)
            largest_x = max(largest_x, float(np.nanmax(np.abs(grf[0]))))
        half = 0.5 * carried_mass_kg * GRAVITY_M_S2
        ax_z.axhline(half, color="#555555", ls=":", lw=1)
        ax_z.annotate(
            f"half the weight the stance feet carry ({carried_mass_kg:.4g} kg), {half:.4g} N",
            (0.01, half),
            xycoords=("axes fraction", "data"),
            xytext=(0, 3),
            textcoords="offset points",
            fontsize=7,
            color="#555555",
            # the feet's curves cross the line: a backing keeps the label legible over them
            bbox={"facecolor": "white", "edgecolor": "none", "alpha": 0.85, "pad": 1.0},
        )
        ax_z.set_ylabel("vertical force $F_z$ [N]")
        ax_z.set_title(
            f"Ground reaction force on each foot: {trajectory.label}, {cycle.loads} loads; "
            f"shaded: {legs[0]}'s swing",
            fontsize=9,
        )
        ax_z.legend(loc="center right", ncols=2)
        if largest_x < 1e-6 * max(half, 1.0):
            ax_x.set_ylim(-0.05 * half, 0.05 * half)
            ax_x.text(
                0.01,
                0.9,
                f"zero: the trunk does not accelerate (largest |F_x| {largest_x:.1e} N, round-off)",
                transform=ax_x.transAxes,
                va="top",
                fontsize=7,
                color="#555555",
            )
        ax_x.set_ylabel("$F_x$ [N]")
        ax_x.set_xlabel("time in the cycle [s]")
        ax_x.set_xlim(0.0, cycle.gait.period_s)
        for ax in (ax_z, ax_x):
            shade_swing(ax, cycle.legs[legs[0]], label=ax is ax_z)
    return fig
