"""Foot paths (the paper's Figure 12) and stick figures of the leg through the swing (17, 18).

Leg frame: origin at the pitching hip, x forward; heights are above the ground. Lengths are true
(equal aspect ratio). The stick figure (hip, knee, foot) comes from Pinocchio's forward
kinematics of the sampled joint angles, not from the foot path, so the two figures cross-check.
"""

from __future__ import annotations

from collections.abc import Sequence

import matplotlib.pyplot as plt
import numpy as np
import pinocchio as pin
from matplotlib.figure import Figure

from scalf_opt.model.robot import Robot
from scalf_opt.types import FIRST_PAIR
from scalf_opt.viz.colors import trajectory_color
from scalf_opt.viz.plotting import style
from scalf_opt.viz.trajectories import Trajectory

SNAPSHOTS = 9
"""Stick figures per swing (lift-off and touch-down included)."""


def leg_points_m(robot: Robot, leg: str, q: np.ndarray) -> np.ndarray:
    """Hip, knee and foot in the leg frame (x, height above the hip) for joint angles ``q``.

    Args:
        robot: The robot.
        leg: Leg name.
        q: Joint angles (hip pitch, knee), shape (2, n) [rad].

    Returns:
        Points, shape (n, 3, 2): hip (0, 0), knee, foot as (x, z) [m].
    """
    model_leg = robot.leg(leg)
    model, data = model_leg.model, model_leg.model.createData()
    hip = model_leg.hip_origin_m
    out = np.zeros((q.shape[1], 3, 2))
    for k in range(q.shape[1]):
        pin.framesForwardKinematics(model, data, np.asarray(q[:, k], dtype=float))
        knee = data.oMi[2].translation - hip
        foot = data.oMf[model_leg.foot_frame_id].translation - hip
        out[k, 1] = knee[0], knee[2]
        out[k, 2] = foot[0], foot[2]
    return out


def foot_path_figure(
    trajectories: Sequence[Trajectory], legs: Sequence[str] = FIRST_PAIR
) -> Figure:
    """The foot's path over a cycle in the leg frame, every trajectory overlaid (Figure 12).

    One panel per leg, true lengths (equal aspect ratio): the swing arcs, the stance line on the
    ground, lift-off and touch-down, and the clearance H required at mid-swing.
    """
    gait = trajectories[0].cycle.gait
    ground = gait.stance_height_m
    with style():
        fig, axes = plt.subplots(
            len(legs),
            1,
            figsize=(8.0, 1.1 + 2.5 * len(legs)),
            sharex=True,
            squeeze=False,
            layout="constrained",
        )
        for row, leg in enumerate(legs):
            ax = axes[row, 0]
            for index, trajectory in enumerate(trajectories):
                leg_cycle = trajectory.cycle.legs[leg]
                swing = leg_cycle.swing.values["foot"]
                ax.plot(
                    swing[0],
                    swing[1] + ground,
                    color=trajectory_color(index),
                    lw=1.8,
                    label=f"{trajectory.label}: swing {leg_cycle.swing_energy_j:.4g} J",
                )
                peak = int(np.argmax(swing[1]))
                ax.plot(
                    swing[0, peak],
                    swing[1, peak] + ground,
                    "o",
                    ms=3,
                    color=trajectory_color(index),
                )
            stance = trajectories[0].cycle.legs[leg].stance.values["foot"]
            ax.plot(
                stance[0],
                stance[1] + ground,
                color="#8c6d46",
                lw=3,
                solid_capstyle="butt",
                label="stance (foot on the ground)",
            )
            swing = trajectories[0].cycle.legs[leg].swing.values["foot"]
            ax.plot(*_pt(swing[:, 0], ground), "v", color="black", ms=7, zorder=5, label="lift-off")
            ax.plot(
                *_pt(swing[:, -1], ground), "^", color="black", ms=7, zorder=5, label="touch-down"
            )
            ax.plot(
                [],
                [],
                "|",
                color="#555555",
                ms=9,
                label=f"H = {1000 * gait.clearance_m:.4g} mm, required at mid-swing",
            )
            for trajectory in trajectories:
                foot = trajectory.cycle.legs[leg].swing.values["foot"]
                mid = foot.shape[1] // 2
                ax.plot([foot[0, mid]] * 2, [0.0, gait.clearance_m], color="#555555", lw=0.8)
            ax.axhline(0.0, color="#8c6d46", lw=0.8, zorder=0)
            ax.set_ylabel("height above\nthe ground [m]")
            ax.set_title(f"{leg} foot, leg frame (x from the pitching hip)", fontsize=9, loc="left")
        # the panels share their x axis: one set of limits that holds every leg's paths
        feet = [
            np.hstack([c.swing.values["foot"], c.stance.values["foot"]])
            for c in (t.cycle.legs[leg] for t in trajectories for leg in legs)
        ]
        x_lo = min(float(f[0].min()) for f in feet)
        x_hi = max(float(f[0].max()) for f in feet)
        top = max(float(f[1].max()) + ground for f in feet)
        margin = 0.08 * (x_hi - x_lo)
        for ax in axes[:, 0]:
            ax.set_xlim(x_lo - margin, x_hi + margin)
            ax.set_ylim(-0.12 * top, 1.15 * top)
            ax.set_aspect("equal", adjustable="box")
        axes[-1, 0].set_xlabel("x from the hip (forward) [m]")
        handles, labels = axes[0, 0].get_legend_handles_labels()
        fig.legend(handles, labels, loc="outside lower center", ncols=2)
        fig.suptitle("Foot paths over a cycle (dots: each swing's highest point)")
    return fig


def leg_snapshot_figure(
    robot: Robot,
    trajectories: Sequence[Trajectory],
    legs: Sequence[str] = FIRST_PAIR,
    snapshots: int = SNAPSHOTS,
) -> Figure:
    """Stick figures of ``legs`` through the swing for each trajectory (Figures 17, 18).

    One panel per leg and trajectory, four to a row, true lengths; the leg darkens as the swing
    goes on, from lift-off to touch-down.
    """
    gait = trajectories[0].cycle.gait
    ground = gait.stance_height_m
    panels = [(leg, index) for leg in legs for index in range(len(trajectories))]
    cols = min(4, len(panels))
    rows = -(-len(panels) // cols)
    with style():
        fig, axes = plt.subplots(
            rows,
            cols,
            figsize=(8.0, 0.6 + 2.8 * rows),
            sharex=True,
            sharey=True,
            squeeze=False,
            layout="constrained",
        )
        for ax in axes.flat[len(panels) :]:
            ax.set_visible(False)
        for ax, (leg, index) in zip(axes.flat, panels, strict=False):
            trajectory = trajectories[index]
            color = trajectory_color(index)
            leg_cycle = trajectory.cycle.legs[leg]
            swing = leg_cycle.swing.values["foot"]
            ax.plot(swing[0], swing[1] + ground, color=color, lw=1.6)
            q = leg_cycle.swing.values["q"]
            picks = np.linspace(0, q.shape[1] - 1, snapshots).round().astype(int)
            for k, pose in enumerate(leg_points_m(robot, leg, q[:, picks])):
                shade = 0.2 + 0.8 * k / max(1, snapshots - 1)
                ax.plot(
                    pose[:, 0],
                    pose[:, 1] + ground,
                    "-o",
                    color=color,
                    alpha=shade,
                    lw=1.0,
                    ms=2.5,
                    mfc="white",
                )
            ax.plot(*_pt(swing[:, 0], ground), "v", color="black", ms=5, zorder=5)
            ax.plot(*_pt(swing[:, -1], ground), "^", color="black", ms=5, zorder=5)
            ax.axhline(0.0, color="#8c6d46", lw=1.5, zorder=0)
            ax.plot(0.0, ground, "s", color="black", ms=4)
            ax.set_title(f"{leg}: {trajectory.label}", fontsize=8, loc="left")
            ax.set_aspect("equal", adjustable="box")
        for ax in axes[:, 0]:
            ax.set_ylabel("height above the ground [m]")
        for ax in axes[-1, :]:
            ax.set_xlabel("x from the hip [m]")
        fig.suptitle(
            f"The leg through the swing, {snapshots} equal time steps, light to dark "
            "(▼ lift-off, ▲ touch-down, ■ pitching hip)"
        )
    return fig


def _pt(foot: np.ndarray, ground: float) -> tuple[float, float]:
    return float(foot[0]), float(foot[1] + ground)
