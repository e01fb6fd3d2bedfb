"""The figure of ``gait --model 3d``: the cost of transport against speed, and the answers' timing.

Top: the cost of transport of each speed's cheapest 3-D cycle (solid, filled markers), every other
converged start (small hollow markers, so that a reader sees how far the starts' local optima
spread), a speed where no start converged (``x`` on the axis) and, when given, a sagittal
``gait`` run's cheapest trots (dashed) for comparison. Below: the answers' period, duty factor,
stride and mean drawn power against speed, with units (the sagittal run's dashed beside them).
"""

from __future__ import annotations

import math
from collections.abc import Sequence
from typing import Any

import matplotlib

matplotlib.use("Agg")  # files only: no display needed

import matplotlib.pyplot as plt
from matplotlib.axes import Axes
from matplotlib.figure import Figure

PANELS_3D: tuple[tuple[str, str, float], ...] = (
    ("period_s", "period T [s]", 1.0),
    ("duty_cycle", "duty factor [-]", 1.0),
    ("stride_m", "stride v T [mm]", 1000.0),
    ("average_power_w", "mean drawn power [W]", 1.0),
)
"""The lower panels: (column, axis label with unit, factor from SI to the unit)."""


def _number(value: Any) -> float:
    if value is None or value == "":
        return math.nan
    return float(value)


def _sagittal(row: dict[str, Any], column: str) -> float:
    """A sagittal ``gaits.csv`` row's value of a 3-D panel's column (its stride: ``v T``)."""
    if column == "stride_m":
        return _number(row.get("speed_m_s")) * _number(row.get("period_s"))
    return _number(row.get(column))


def _other_starts(
    rows: Sequence[dict[str, Any]], answers: Sequence[Sequence[Any]]
) -> tuple[list[float], list[float]]:
    """Every converged start but each speed's cheapest: (speeds, costs of transport)."""
    xs, ys = [], []
    for row, speed_answers in zip(rows, answers, strict=True):
        best = _number(row.get("cost_of_transport"))
        for answer in speed_answers:
            cot = answer.cost_of_transport
            if answer.converged and math.isfinite(cot) and cot != best:
                xs.append(_number(row["speed_m_s"]))
                ys.append(cot)
    return xs, ys


def _cost_panel(
    top: Axes,
    rows: Sequence[dict[str, Any]],
    answers: Sequence[Sequence[Any]],
    solved_sagittal: Sequence[dict[str, Any]],
) -> None:
    """The top panel: the costs of transport against speed (module docstring)."""
    ok = [r for r in rows if r["status"] == "ok"]
    top.plot(
        [_number(r["speed_m_s"]) for r in ok],
        [_number(r["cost_of_transport"]) for r in ok],
        "-o",
        color="tab:blue",
        label="3-D whole body, cheapest start (period free)",
    )
    others_x, others_y = _other_starts(rows, answers)
    if others_x:
        top.plot(others_x, others_y, "o", mfc="white", color="tab:blue", ms=5, label="other starts")
    if solved_sagittal:
        top.plot(
            [_number(r["speed_m_s"]) for r in solved_sagittal],
            [_number(r["cost_of_transport"]) for r in solved_sagittal],
            "--s",
            color="tab:orange",
            label="sagittal model, cheapest trot (the --sagittal gait run)",
        )
    failed = [_number(r["speed_m_s"]) for r in rows if r["status"] != "ok"]
    if failed:
        top.plot(failed, [0.0] * len(failed), "x", color="tab:red", label="no start converged")
    top.set_xlabel("speed v [m/s]")
    top.set_ylabel("cost of transport E / (m g d) [-]")
    top.set_ylim(bottom=0.0)
    top.grid(True, alpha=0.3)
    top.legend(loc="best", fontsize=9)


def gait_3d_figure(
    rows: Sequence[dict[str, Any]],
    answers: Sequence[Sequence[Any]],
    title: str,
    compare: Sequence[dict[str, Any]] | None = None,
) -> Figure:
    """The figure of ``gaits.csv``'s ``rows`` and every start's ``answers`` (module docstring).

    ``answers[i]`` are the :class:`~scalf_opt.api.gait_3d.StartAnswer` of ``rows[i]``'s speed;
    ``compare``: a sagittal ``gaits.csv``'s rows (``speed_m_s``, ``status``,
    ``cost_of_transport``).
    """
    fig = plt.figure(figsize=(9.5, 9.0), layout="constrained")
    grid = fig.add_gridspec(3, 2, height_ratios=(1.6, 1, 1))
    top = fig.add_subplot(grid[0, :])
    solved = [r for r in compare or () if r.get("status") == "ok"]
    _cost_panel(top, rows, answers, solved)
    top.set_title(title, fontsize=10)
    ok = [r for r in rows if r["status"] == "ok"]
    speeds = [_number(r["speed_m_s"]) for r in ok]
    for index, (column, ylabel, factor) in enumerate(PANELS_3D):
        ax = fig.add_subplot(grid[1 + index // 2, index % 2], sharex=top)
        ax.plot(speeds, [_number(r[column]) * factor for r in ok], "-o", color="tab:blue")
        if solved:
            values = [_sagittal(r, column) * factor for r in solved]
            ax.plot([_number(r["speed_m_s"]) for r in solved], values, "--s", color="tab:orange")
        ax.set_ylabel(ylabel)
        ax.set_xlabel("speed v [m/s]")
        ax.grid(True, alpha=0.3)
    return fig
