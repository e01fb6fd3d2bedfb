"""The 3-D referee's run over time: the trunk and the feet's forces, simulated beside the plan.

Four panels over the simulated time: the trunk's height, roll and pitch, and each foot's vertical
ground force, the simulation solid and the plan dashed. The first cycle (the start-up, not
measured) is shaded; a fall (red) and a divergence of MuJoCo's integration (purple, the check
that failed named) are lines across every panel, where the run stopped. Angles in degrees
(converted here, at the edge).
"""

from __future__ import annotations

import textwrap

import matplotlib.pyplot as plt
import numpy as np
from matplotlib.figure import Figure

from scalf_opt.energy.whole_body import quaternion_rpy
from scalf_opt.types import LEG_NAMES
from scalf_opt.viz.colors import LEG_COLORS
from scalf_opt.viz.plotting import SWING_SHADE, mark_stops, run_stops, style

_EVERY = 5
"""Plot every fifth step (the steps are far finer than the figure)."""


def _roll_pitch_deg(q: np.ndarray) -> np.ndarray:
    """Roll and pitch [deg] (2, n) of Pinocchio configurations ``q`` (nq, n)."""
    return np.degrees(quaternion_rpy(q[3:7])[:2])


def _time_span(t_s: np.ndarray, stops_s: list[float], period_s: float) -> tuple[float, float]:
    """The time axis [s]: the record's, to where the run stopped (a step after its last step).

    A run that stopped ends 2 % of the span after the stop, so that its line stands clear of the
    axis' edge; one that stopped at its first step (an empty record) spans one period.
    """
    start = float(t_s[0]) if t_s.size else 0.0
    end = max([start, *t_s[-1:].tolist(), *stops_s])
    if end <= start:
        return start, start + period_s
    return start, end + (0.02 * (end - start) if stops_s else 0.0)


def cycle_simulation_figure(
    t_s: np.ndarray,
    q: np.ndarray,
    q_plan: np.ndarray,
    force_n: np.ndarray,
    plan_force_n: np.ndarray,
    fell_at_s: float | None,
    period_s: float,
    title: str,
    diverged_at_s: float | None = None,
    divergence: str | None = None,
) -> Figure:
    """The run (module docstring).

    Args:
        t_s: The steps' times (n,) [s].
        q: The robot's configurations, Pinocchio's free-flyer ``q`` (nq, n).
        q_plan: The plan's (nq, n).
        force_n: The ground's force on each foot (3, 4, n) [N], world axes.
        plan_force_n: The plan's (3, 4, n) [N].
        fell_at_s: When the robot fell [s], or ``None``.
        period_s: The gait period [s] (the first cycle is shaded).
        title: The figure's title.
        diverged_at_s: When the step in which MuJoCo's integration diverged started [s], or
            ``None``.
        divergence: Which of MuJoCo's checks failed then, in words (``bad accelerations,
            MuJoCo's BADQACC``).
    """
    stops = run_stops(fell_at_s, diverged_at_s, divergence)
    start, end = _time_span(t_s, [at for at, _, _ in stops], period_s)
    t = t_s[::_EVERY]
    q, q_plan = q[:, ::_EVERY], q_plan[:, ::_EVERY]
    angles, angles_plan = _roll_pitch_deg(q), _roll_pitch_deg(q_plan)
    with style():
        fig, axes = plt.subplots(4, 1, figsize=(9.0, 8.5), sharex=True)
        sim_kw = {"color": "black", "lw": 1.2}
        plan_kw = {"color": "tab:orange", "lw": 1.2, "linestyle": "--"}
        axes[0].plot(t, q[2], label="simulated", **sim_kw)
        axes[0].plot(t, q_plan[2], label="plan", **plan_kw)
        for row, ax in enumerate(axes[1:3]):
            ax.plot(t, angles[row], **sim_kw)
            ax.plot(t, angles_plan[row], **plan_kw)
        for i, leg in enumerate(LEG_NAMES):
            color = LEG_COLORS.get(leg, "black")
            axes[3].plot(t, force_n[2, i, ::_EVERY], color=color, lw=1.0, label=leg)
            axes[3].plot(t, plan_force_n[2, i, ::_EVERY], color=color, lw=1.0, ls="--")
        for ax in axes:
            ax.axvspan(0.0, min(period_s, end), color=SWING_SHADE, lw=0)
        axes[0].set_ylabel("trunk height [m]")
        axes[1].set_ylabel("roll [deg]")
        axes[2].set_ylabel("pitch [deg]")
        axes[3].set_ylabel("vertical force [N]")
        axes[3].set_xlabel(
            "time [s] (shaded: the first cycle, not measured; dashed: the plan"
            + ("; red: the fall" if fell_at_s is not None else "")
            + ("; purple: MuJoCo diverged" if diverged_at_s is not None else "")
            + ")"
        )
        axes[0].legend(loc="upper right", ncol=2)
        axes[3].legend(loc="upper right", ncol=4)
        axes[0].set_title(textwrap.fill(title, 110), fontsize=9)
        axes[3].set_xlim(start, end)
        mark_stops(axes, stops)
        fig.tight_layout()
    return fig
