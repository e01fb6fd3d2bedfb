"""The figure of ``scalf-opt gait``: the cost of transport against speed, and the cheapest gaits.

Top: the cost of transport of the cheapest trot (solid), of the robot's default trot retimed to
each speed with optimized swings (dashed) and with the reference swing (dotted); a speed whose
search did not succeed is marked ``x`` on the axis. Below, one panel each: the cheapest gait's
period, duty cycle, step length, stance height, stance x-offsets (front and hind) and average
power against speed, with units. Every cheapest gait sits on some limit (``pinned_by`` names
them); one held by an edge of the search box rather than by the robot is a hollow marker, on its
cheapest cost of transport and in every panel: a wider box might find a cheaper gait there (the
duty's floor of 0.5 is the model's own limit, not the box's).
"""

from __future__ import annotations

import math
from collections.abc import Sequence
from typing import Any

import matplotlib

matplotlib.use("Agg")  # files only: no display needed

import matplotlib.pyplot as plt
from matplotlib.figure import Figure

PANELS: tuple[tuple[tuple[tuple[str, str], ...], str, float], ...] = (
    ((("period_s", "period T"),), "period T [s]", 1.0),
    ((("duty_cycle", "duty cycle"),), "duty cycle [-]", 1.0),
    ((("step_length_m", "step length S"),), "step length S [mm]", 1000.0),
    ((("stance_height_m", "stance height z0"),), "stance height z0 [mm]", 1000.0),
    (
        (("stance_x_offset_front_m", "front"), ("stance_x_offset_hind_m", "hind")),
        "feet ahead of hips [mm]",
        1000.0,
    ),
    ((("average_power_w", "average power"),), "average power [W]", 1.0),
)
"""The lower panels: (columns and labels, axis label with unit, factor from SI to the unit)."""

COT_LINES = (
    ("cost_of_transport", "cheapest trot (timing, stance and swings optimized)", "-", "o"),
    ("default_cost_of_transport", "default trot, optimized swings", "--", "s"),
    ("reference_cost_of_transport", "default trot, reference swing", ":", "^"),
)
"""The top panel's lines: (column, label, line style, marker)."""


def _value(row: dict[str, Any], key: str) -> float:
    value = row.get(key)
    if value is None or value == "":
        return math.nan
    return float(value)


def _line(rows: Sequence[dict[str, Any]], key: str, factor: float = 1.0) -> tuple[list, list]:
    points = [(_value(r, "speed_m_s"), _value(r, key) * factor) for r in rows]
    points = [(x, y) for x, y in points if math.isfinite(y)]
    return [x for x, _ in points], [y for _, y in points]


def held_by_the_box(pinned_by: str) -> bool:
    """Whether a step further leaves the search box (``pinned_by``, ``gaits.csv``'s column).

    The duty's floor of 0.5, a trot's, is the model's limit (it walks no flight phase), not the
    search's: a gait held by it alone is not.
    """
    return any(
        "search box" in part and "a trot's floor" not in part for part in pinned_by.split("; ")
    )


def gait_figure(rows: Sequence[dict[str, Any]], title: str) -> Figure:
    """The figure of ``gaits.csv``'s rows (see the module docstring)."""
    rows = sorted(rows, key=lambda r: _value(r, "speed_m_s"))
    ok = [r for r in rows if r.get("status") == "ok"]
    failed = [_value(r, "speed_m_s") for r in rows if r.get("status") != "ok"]
    fig = plt.figure(figsize=(9.5, 11.5), layout="constrained")
    grid = fig.add_gridspec(4, 2, height_ratios=(1.6, 1, 1, 1))
    top = fig.add_subplot(grid[0, :])
    pinned = [r for r in ok if held_by_the_box(str(r.get("pinned_by") or ""))]
    for key, label, style, marker in COT_LINES:
        source = ok if key == "cost_of_transport" else rows
        xs, ys = _line(source, key)
        if xs:
            (line,) = top.plot(xs, ys, style, marker=marker, label=label)
            if key == "cost_of_transport":  # the cheapest gait's own pins, as in the panels
                top.plot(*_line(pinned, key), marker, mfc="white", color=line.get_color())
    if pinned:
        top.plot(
            [],
            [],
            "o",
            mfc="white",
            color="gray",
            label="hollow marker: held by an edge of the search box (column pinned_by)",
        )
    if failed:
        top.plot(failed, [0.0] * len(failed), "x", color="tab:red", label="search not solved")
    top.set_xlabel("speed v [m/s]")
    top.set_ylabel("cost of transport E / (m g d) [-]")
    top.set_ylim(bottom=0.0)
    top.grid(True, alpha=0.3)
    top.legend(loc="best", fontsize=9)
    top.set_title(title)
    for index, (columns, ylabel, factor) in enumerate(PANELS):
        ax = fig.add_subplot(grid[1 + index // 2, index % 2], sharex=top)
        for column, label in columns:
            xs, ys = _line(ok, column, factor)
            (line,) = ax.plot(xs, ys, "-o", label=label if len(columns) > 1 else None)
            px, py = _line(pinned, column, factor)
            ax.plot(px, py, "o", mfc="white", color=line.get_color())
        if len(columns) > 1:
            ax.legend(fontsize=8, loc="best")
        ax.set_ylabel(ylabel)
        ax.set_xlabel("speed v [m/s]")
        ax.grid(True, alpha=0.3)
    return fig
