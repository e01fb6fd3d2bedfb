"""The paper's pattern search drawn over the energy landscape it searches (Figure 8, and more).

The paper's Figure 8 shows C1, C2 and the swing energy per iteration; the landscape it walked on
was never shown. Here, per leg of the diagonal pair: the exact swing energy of the paper family
over (C1, C2) as filled contours, the infeasible region hatched, the reference's swing energy as
a contour line (inside it the paper family beats the reference), the pattern search's accepted
points (its feasibility phase from the infeasible start (0, 0), then its energy phase) and
Ipopt's optimum; below, the energy of the accepted points per iteration, with the feasibility
phase's constraint violation, and the reference and Ipopt levels.

The searches and the landscape are computed above this floor
(:func:`scalf_opt.studies.search.search_study`); this module only draws them.
"""

from __future__ import annotations

from dataclasses import dataclass

import matplotlib.pyplot as plt
import numpy as np
from matplotlib import patheffects
from matplotlib.axes import Axes
from matplotlib.colors import LogNorm
from matplotlib.contour import QuadContourSet
from matplotlib.figure import Figure
from matplotlib.ticker import FormatStrFormatter, LogLocator, MaxNLocator, NullFormatter

from scalf_opt.optimize.landscape import EnergyLandscape
from scalf_opt.optimize.solve import SwingOptimum
from scalf_opt.viz.plotting import style

FEASIBILITY_COLOR = "#ff7f0e"
SEARCH_COLOR = "#d62728"
IPOPT_COLOR = "#17becf"


@dataclass(frozen=True)
class LegSearch:
    """What the figure shows for one leg.

    Attributes:
        pattern: The pattern search (the paper's settings) on the paper family.
        ipopt: Ipopt on the same family (the NLP optimum).
        landscape: The exact swing energy over (C1, C2), at the optima's rate.
        reference_swing_j: The reference spline's swing energy at the same rate [J].
        pattern_rates_hz: Every rate the pattern search ran at, the last its answer's (the
            sampling refinement restarts it at a finer rate from the coarser optimum, and its
            history is that last run's).
    """

    pattern: SwingOptimum
    ipopt: SwingOptimum
    landscape: EnergyLandscape
    reference_swing_j: float
    pattern_rates_hz: tuple[float, ...] = ()


def search_figure(study: dict[str, LegSearch]) -> Figure:
    """The landscape with the searches (top) and the energy per iteration (bottom), per leg."""
    legs = list(study)
    with style():
        fig, axes = plt.subplots(
            2,
            len(legs),
            figsize=(8.0, 7.4),
            height_ratios=(1.5, 1),
            squeeze=False,
            layout="constrained",
        )
        levels = _levels(study)
        filled = [
            _landscape_panel(axes[0, col], study[leg], leg, levels) for col, leg in enumerate(legs)
        ]
        for col, leg in enumerate(legs):
            _iteration_panel(axes[1, col], study[leg], leg)
        bar = fig.colorbar(filled[-1], ax=axes[0, :], shrink=0.9, ticks=_nice_ticks(levels))
        bar.ax.yaxis.set_major_formatter(FormatStrFormatter("%g"))
        bar.ax.yaxis.set_minor_formatter(NullFormatter())
        bar.set_label("exact swing energy [J] (log scale)")
        handles, labels = axes[0, 0].get_legend_handles_labels()
        more, more_labels = axes[1, 0].get_legend_handles_labels()
        fig.legend(
            handles + more, labels + more_labels, loc="outside lower center", ncols=3, fontsize=7
        )
        fig.suptitle("Pattern search on the paper family over its exact swing-energy landscape")
    return fig


def _levels(study: dict[str, LegSearch]) -> np.ndarray:
    """Contour levels shared by every leg: log-spaced, lowest energy to the 99th percentile.

    The corners of a grid can be far higher than anything of interest.
    """
    energies = np.concatenate([s.landscape.energy_j.ravel() for s in study.values()])
    low = float(np.nanmin(energies))
    high = float(np.nanpercentile(energies, 99))
    return np.geomspace(low, max(high, 1.01 * low), 16)


def _nice_ticks(levels: np.ndarray) -> list[float]:
    """1-2-5 values inside the levels' range, for a legible log colour bar."""
    lo, hi = float(levels[0]), float(levels[-1])
    decades = range(int(np.floor(np.log10(lo))), int(np.ceil(np.log10(hi))) + 1)
    ticks = [m * 10.0**d for d in decades for m in (1, 2, 5)]
    return [t for t in ticks if lo <= t <= hi]


def _landscape_panel(ax: Axes, search: LegSearch, leg: str, levels: np.ndarray) -> QuadContourSet:
    land = search.landscape
    energy = np.ma.masked_invalid(land.energy_j)
    filled = ax.contourf(
        land.x,
        land.y,
        energy,
        levels=levels,
        norm=LogNorm(levels[0], levels[-1]),
        cmap="viridis",
        extend="max",
    )
    filled.set_edgecolor("face")  # no hairline seams between the bands in vector output
    infeasible = (~land.feasible).astype(float)
    if infeasible.any():
        ax.contourf(land.x, land.y, infeasible, levels=[0.5, 1.5], colors="white", alpha=0.45)
        ax.contourf(land.x, land.y, infeasible, levels=[0.5, 1.5], colors="none", hatches=["////"])
        ax.contour(land.x, land.y, infeasible, levels=[0.5], colors="black", linewidths=0.8)
        ax.plot([], [], color="black", lw=0.8, label="border of the infeasible region (hatched)")
    if np.nanmin(land.energy_j) < search.reference_swing_j < np.nanmax(land.energy_j):
        outline = [patheffects.withStroke(linewidth=2.6, foreground="black")]
        level = ax.contour(
            land.x,
            land.y,
            energy,
            levels=[search.reference_swing_j],
            colors="white",
            linestyles="--",
            linewidths=1.2,
        )
        level.set(path_effects=outline)
        ax.plot(
            [],
            [],
            color="white",
            ls="--",
            lw=1.2,
            path_effects=outline,
            label="the reference's swing energy (inside: lower)",
        )
    details = search.pattern.pattern_details
    feasibility = np.array(details.feasibility_history, dtype=float).reshape(-1, 4)
    accepted = np.array(details.history, dtype=float).reshape(-1, 4)
    if feasibility.size:
        ax.plot(
            feasibility[:, 1],
            feasibility[:, 2],
            "--o",
            color=FEASIBILITY_COLOR,
            ms=3.5,
            mfc="white",
            lw=1.2,
            label="pattern search: feasibility phase",
        )
    ax.plot(
        accepted[:, 1],
        accepted[:, 2],
        "-o",
        color=SEARCH_COLOR,
        ms=3,
        lw=1.2,
        label="pattern search: energy phase",
    )
    ax.plot(0.0, 0.0, "s", color="black", ms=5, label="start (0, 0)")
    ax.plot(
        *search.ipopt.theta[:2], "*", color=IPOPT_COLOR, mec="black", ms=12, label="Ipopt's optimum"
    )
    names = land.parameter_names
    ax.set_xlabel(f"C1 = {names[0]} amplitude [{land.unit}]")
    ax.set_ylabel(f"C2 = {names[1]} amplitude [{land.unit}]")
    ax.set_title(f"{leg}: exact swing energy over (C1, C2)", fontsize=9, loc="left")
    ax.grid(False)
    return filled


def _iteration_panel(ax: Axes, search: LegSearch, leg: str) -> None:
    pattern = search.pattern
    accepted = np.array(pattern.pattern_details.history, dtype=float).reshape(-1, 4)
    feasibility = np.array(pattern.pattern_details.feasibility_history, dtype=float).reshape(-1, 4)
    if feasibility.size:
        end = float(feasibility[-1, 0])
        ax.axvspan(0.0, end, color=FEASIBILITY_COLOR, alpha=0.12, lw=0)
        twin = ax.twinx()
        twin.plot(
            feasibility[:, 0],
            feasibility[:, 3],
            "--o",
            color=FEASIBILITY_COLOR,
            ms=3,
            mfc="white",
            lw=1.2,
        )
        twin.set_ylabel("violation [m, rad, share of limit]", color=FEASIBILITY_COLOR)
        twin.tick_params(axis="y", colors=FEASIBILITY_COLOR)
        twin.set_ylim(bottom=0.0)
        twin.grid(False)
        twin.spines["right"].set_visible(True)
    ax.plot(accepted[:, 0], accepted[:, 3], "-o", color=SEARCH_COLOR, ms=3, lw=1.2)
    ax.axhline(
        search.reference_swing_j, color="#404040", ls="--", lw=1, label="reference swing energy"
    )
    ax.axhline(
        search.ipopt.swing_energy_j, color=IPOPT_COLOR, ls=":", lw=1.6, label="Ipopt's optimum"
    )
    ax.set_yscale("log")
    ax.yaxis.set_major_locator(LogLocator(base=10.0, subs=(1.0, 2.0, 3.0, 5.0)))
    ax.yaxis.set_major_formatter(FormatStrFormatter("%g"))
    ax.yaxis.set_minor_formatter(NullFormatter())
    ax.set_xlabel("iteration [count]")
    ax.set_ylabel("swing energy [J]")
    gap = 100.0 * (pattern.swing_energy_j - search.ipopt.swing_energy_j)
    gap /= search.ipopt.swing_energy_j
    title = (
        f"{leg}: {pattern.swing_energy_j:.4g} J in {pattern.iterations} iterations, "
        f"{gap:+.2f} % vs Ipopt"
    )
    if len(search.pattern_rates_hz) > 1:
        *_, coarse, fine = search.pattern_rates_hz
        title += f"\nrestarted at {fine:g} Hz from the {coarse:g} Hz optimum"
    ax.set_title(title, fontsize=8, loc="left")
    # iterations are counts: integer ticks, and an axis as long as the search even when it
    # accepted a single point (Go1's search ends in 3 iterations without moving)
    ax.xaxis.set_major_locator(MaxNLocator(integer=True))
    ax.set_xlim(left=0.0, right=max(float(accepted[-1, 0]), float(pattern.iterations), 1.0))
