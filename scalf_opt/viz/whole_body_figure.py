"""A 3-D cycle over time: the trunk's height, roll and pitch, and the feet's vertical forces.

Drawn from the files ``optimize --model 3d --out DIR`` writes (:func:`~scalf_opt.io.
whole_body_export.read_cycle`), so that what is shown is what a controller would read. The values
are the plan's nodes (markers) joined by straight lines; where no foot carries force (a flying
trot's flight) the background is shaded. Angles in degrees (converted here, at the edge).
"""

from __future__ import annotations

from collections.abc import Sequence

import matplotlib.pyplot as plt
import numpy as np
from matplotlib.figure import Figure

from scalf_opt.energy.whole_body import quaternion_rpy
from scalf_opt.io.whole_body_export import SavedCycle
from scalf_opt.types import LEG_NAMES
from scalf_opt.viz.colors import LEG_COLORS, trajectory_color
from scalf_opt.viz.plotting import DASHES, SWING_SHADE, style


def roll_pitch_rad(quat_xyzw: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Roll and pitch [rad] of unit quaternions (4, n) as ``(x, y, z, w)``.

    The angles of ``R = R_z(yaw) R_y(pitch) R_x(roll)``, the 3-D model's own convention
    (:func:`~scalf_opt.energy.whole_body.quaternion_rpy`).
    """
    rpy = quaternion_rpy(quat_xyzw)
    return rpy[0], rpy[1]


def _label(cycle: SavedCycle) -> str:
    s = cycle.summary
    return (
        f"{cycle.directory.name}: {s.get('robot', '?')}, T={s.get('period_s', float('nan')):g} s, "
        f"duty {s.get('duty_cycle', float('nan')):g}, {s.get('speed_m_s', float('nan')):.3g} m/s"
    )


def _flight_spans(
    t_s: np.ndarray, total_n: np.ndarray, period_s: float
) -> list[tuple[float, float]]:
    """Time spans [s] where no foot carries force (between nodes where the total is zero)."""
    spans = []
    ends = np.append(t_s, period_s)
    for k in range(len(t_s)):
        following = total_n[(k + 1) % len(t_s)]
        if total_n[k] <= 0.0 and following <= 0.0:
            spans.append((float(ends[k]), float(ends[k + 1])))
    return spans


def trunk_figure(cycles: Sequence[SavedCycle]) -> Figure:
    """Height, roll, pitch of the trunk and each foot's vertical force over one cycle."""
    with style():
        fig, axes = plt.subplots(4, 1, figsize=(8.0, 8.0), sharex=True)
        for c, cycle in enumerate(cycles):
            cols = cycle.columns
            period = float(cycle.summary.get("period_s", cols["t_s"][-1]))
            t = cols["t_s"] / period
            quat = np.vstack([cols[f"base_quat_{a}"] for a in ("x", "y", "z", "w")])
            roll, pitch = roll_pitch_rad(quat)
            color, dash = trajectory_color(c + 1), DASHES[c % len(DASHES)]
            style_kw = {"color": color, "linestyle": dash, "marker": ".", "markersize": 3}
            # the cycle closes on itself: its first node again at t = T
            closed = np.append(t, 1.0)

            def wrap(values: np.ndarray) -> np.ndarray:
                return np.append(values, values[0])

            axes[0].plot(closed, wrap(cols["base_pos_z_m"]), label=_label(cycle), **style_kw)
            axes[1].plot(closed, wrap(np.degrees(roll)), **style_kw)
            axes[2].plot(closed, wrap(np.degrees(pitch)), **style_kw)
            forces = [cols[f"{foot}_force_z_n"] for foot in cycle.feet]
            for i, (foot, fz) in enumerate(zip(cycle.feet, forces, strict=True)):
                leg = LEG_NAMES[i] if i < len(LEG_NAMES) else foot
                axes[3].plot(
                    closed,
                    wrap(fz),
                    color=LEG_COLORS.get(leg, color),
                    linestyle=dash,
                    marker=".",
                    markersize=3,
                    label=f"{leg} ({foot})" if c == 0 else None,
                )
            if forces:
                for start, end in _flight_spans(cols["t_s"], np.sum(forces, axis=0), period):
                    for ax in axes:
                        ax.axvspan(start / period, end / period, color=SWING_SHADE, lw=0)
        axes[0].set_ylabel("trunk height [m]")
        axes[1].set_ylabel("roll [deg]")
        axes[2].set_ylabel("pitch [deg]")
        axes[3].set_ylabel("vertical force [N]")
        axes[3].set_xlabel("time over the period, t / T (shaded: flight, no foot on the ground)")
        axes[0].legend(loc="best")
        axes[3].legend(loc="upper right", ncol=2)
        axes[0].set_title("The 3-D cycle: trunk height, roll, pitch and the feet's vertical forces")
        axes[3].set_xlim(0.0, 1.0)
        fig.tight_layout()
    return fig
