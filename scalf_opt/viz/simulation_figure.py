"""The figure of a simulated trot.

Trunk height and pitch and the vertical foot forces over time, and each leg's joint energy per
cycle beside the model's. A fall (red) and a divergence of MuJoCo's integration (purple, the check
that failed named) are lines across the panels over time; a run that diverged is NaN from there
on (no line drawn), and its energies, not measured, are said so.
"""

from __future__ import annotations

from collections.abc import Mapping

import matplotlib

matplotlib.use("Agg")  # files only: no display needed

import matplotlib.pyplot as plt
import numpy as np
from matplotlib.figure import Figure

from scalf_opt.viz.plotting import fitted_title, mark_stops, run_stops


def simulation_figure(
    t_s: np.ndarray,
    trunk_height_m: np.ndarray,
    planned_height_m: float,
    trunk_pitch_rad: np.ndarray,
    vertical_force_n: Mapping[str, np.ndarray],
    model_force_n: float,
    title: str,
    height_band_m: float = 0.004,
    startup_s: float | None = None,
    phase_energy_j: Mapping[str, Mapping[str, Mapping[str, float]]] | None = None,
    energy_goal: float | None = None,
    fell_at_s: float | None = None,
    diverged_at_s: float | None = None,
    divergence: str | None = None,
) -> Figure:
    """Panels over time (trunk height, trunk pitch, vertical ground force per foot) and energy.

    With ``phase_energy_j`` a fourth panel: each leg's joint energy per cycle, simulated beside
    the model's, stance and swing stacked, its difference and the goal written above.

    Args:
        t_s: Time [s], shape (n,).
        trunk_height_m: Trunk height, shape (n,) [m].
        planned_height_m: The height the model assumes [m] (drawn dashed).
        trunk_pitch_rad: Trunk pitch, shape (n,) [rad].
        vertical_force_n: Per leg, the vertical ground force on the foot, shape (n,) [N].
        model_force_n: The model's stance force (half the carried weight) [N], drawn dashed.
        title: Figure title.
        height_band_m: Half-height of the band drawn around the planned height [m] (the
            paper's 4 mm).
        startup_s: End of the start-up (the first gait cycle) [s], shaded: every number of
            the simulation's report is taken after it.
        phase_energy_j: Per leg and phase (``stance``, ``swing``) the ``simulated`` and
            ``model`` joint energy per cycle [J] (``simulation.json``'s
            ``joint_energy_per_phase_j``).
        energy_goal: The per-leg goal on the relative difference (0.05: 5 %).
        fell_at_s: When the robot fell [s], or ``None``.
        diverged_at_s: When the step in which MuJoCo's integration diverged started [s], or
            ``None``.
        divergence: Which of MuJoCo's checks failed then, in words (``bad accelerations,
            MuJoCo's BADQACC``).
    """
    rows = 3 if phase_energy_j is None else 4
    fig = plt.figure(figsize=(10, 8 if rows == 3 else 10.5), layout="constrained")
    grid = fig.add_gridspec(rows, 1, height_ratios=(1, 1, 1, 1.1)[:rows])
    ax_z = fig.add_subplot(grid[0])
    ax_p = fig.add_subplot(grid[1], sharex=ax_z)
    ax_f = fig.add_subplot(grid[2], sharex=ax_z)
    for ax in (ax_z, ax_p):
        ax.tick_params(labelbottom=False)
    ax_z.plot(t_s, 1e3 * (trunk_height_m - planned_height_m), lw=1)
    ax_z.axhline(0.0, color="grey", ls="--", lw=1)
    for edge in (-height_band_m, height_band_m):
        ax_z.axhline(1e3 * edge, color="tab:red", ls=":", lw=1)
    ax_z.set_ylabel("trunk height - planned [mm]")
    # wrapped: a robot's gait numbers to six digits ran past the figure's edge (Solo12)
    ax_z.set_title(fitted_title(title, 10.0, 10.0), fontsize=10)
    ax_p.plot(t_s, 1e3 * trunk_pitch_rad, lw=1)
    ax_p.set_ylabel("trunk pitch [mrad]")
    for leg, force in vertical_force_n.items():
        ax_f.plot(t_s, force, lw=1, label=leg)
    ax_f.axhline(model_force_n, color="grey", ls="--", lw=1, label="model")
    if startup_s is not None:
        for ax in (ax_z, ax_p, ax_f):
            ax.axvspan(
                float(t_s[0]),
                startup_s,
                color="0.85",
                zorder=0,
                label="start-up cycle (left out of the report)" if ax is ax_f else None,
            )
    ax_f.set_ylabel("vertical ground force [N]")
    ax_f.set_xlabel("time [s]")
    ax_f.legend(fontsize=8, ncol=7, loc="upper center", bbox_to_anchor=(0.5, -0.22))
    for ax in (ax_z, ax_p, ax_f):
        ax.grid(True, alpha=0.3)
    mark_stops((ax_z, ax_p, ax_f), run_stops(fell_at_s, diverged_at_s, divergence))
    if phase_energy_j is not None:
        _energy_panel(fig.add_subplot(grid[3]), phase_energy_j, energy_goal)
    return fig


def _energy_panel(
    ax: plt.Axes,
    phase_energy_j: Mapping[str, Mapping[str, Mapping[str, float]]],
    goal: float | None,
) -> None:
    """Per leg two stacked bars (model, simulated: stance below, swing above).

    The difference of their totals is written above them, in red beyond the goal.
    """
    legs = list(phase_energy_j)
    x = np.arange(len(legs), dtype=float)
    width = 0.38
    tops = []
    for offset, source, hatch in ((-width / 2, "model", ""), (width / 2, "simulated", "//")):
        stance = np.array([phase_energy_j[leg]["stance"][source] for leg in legs])
        swing = np.array([phase_energy_j[leg]["swing"][source] for leg in legs])
        ax.bar(
            x + offset,
            stance,
            width,
            color="tab:blue",
            hatch=hatch,
            edgecolor="white",
            label=f"stance, {source}",
        )
        ax.bar(
            x + offset,
            swing,
            width,
            bottom=stance,
            color="tab:orange",
            hatch=hatch,
            edgecolor="white",
            label=f"swing, {source}",
        )
        tops.append(stance + swing)
    model, simulated = tops
    for k in range(len(legs)):
        change = 100.0 * (simulated[k] - model[k]) / model[k]
        missed = goal is not None and not abs(change) <= 100.0 * goal  # NaN: not measured
        ax.annotate(
            f"{change:+.1f} %" if np.isfinite(change) else "not\nmeasured",
            (x[k], float(np.nanmax([model[k], simulated[k]]))),
            xytext=(0, 3),
            textcoords="offset points",
            ha="center",
            fontsize=9,
            color="tab:red" if missed else "black",
        )
    goal_text = "" if goal is None else f" (goal: within {100 * goal:g} % on every leg)"
    ax.set_title(f"joint energy per cycle, simulated against the model{goal_text}", fontsize=10)
    ax.set_xticks(x, legs)
    ax.set_ylabel("joint energy per cycle [J]")
    top = np.nanmax(np.concatenate([model, simulated]), initial=0.0)
    ax.set_ylim(0.0, 1.15 * float(top) if top > 0 else 1.0)
    ax.grid(True, axis="y", alpha=0.3)
    ax.legend(fontsize=8, ncol=4, loc="upper center", bbox_to_anchor=(0.5, -0.12))
