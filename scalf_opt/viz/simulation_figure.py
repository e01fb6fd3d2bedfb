"""The figure of a simulated trot: trunk height and pitch, vertical foot forces, over time."""

from __future__ import annotations

from collections.abc import Mapping

import matplotlib

matplotlib.use("Agg")  # files only: no display needed

import matplotlib.pyplot as plt
import numpy as np
from matplotlib.figure import Figure

from scalf_opt.viz.plotting import fitted_title


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
) -> Figure:
    """Three panels over time: trunk height, trunk pitch, vertical ground force per foot.

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
    """
    fig, (ax_z, ax_p, ax_f) = plt.subplots(3, 1, figsize=(10, 8), sharex=True)
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
    fig.tight_layout()
    return fig
