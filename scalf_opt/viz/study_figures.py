"""The figure of a study: energy before and after optimization, and the saving, over its cases.

Numeric x (a swept gait field, a scale, the speed): lines, one per combination of the other swept
values. Text x (robots, families): grouped bars. Top: energy per gait cycle, reference (dashed)
and optimized (solid); middle: the saving in percent; bottom: the cost of transport. A case that
did not succeed is left out of the lines and marked ``x`` on the x axis.
"""

from __future__ import annotations

from collections.abc import Sequence
from typing import Any

import matplotlib

matplotlib.use("Agg")  # files only: no display needed

import matplotlib.pyplot as plt
import numpy as np
from matplotlib.axes import Axes
from matplotlib.figure import Figure

from scalf_opt.io.study_columns import RESULT_COLUMNS
from scalf_opt.tables import is_number
from scalf_opt.viz.plotting import fitted_title

_RESULT_KEYS = frozenset({"case", *RESULT_COLUMNS})
"""The columns that are results, not swept values."""


_UNITS = (
    ("_m_s", "m/s"),
    ("_hz", "Hz"),
    ("_kg", "kg"),
    ("_pct", "%"),
    ("_m", "m"),
    ("_s", "s"),
    ("_j", "J"),
    ("_w", "W"),
)
"""Column-name suffixes and the units they stand for (the longest first)."""

_NAMES = {
    "period_s": "gait period T",
    "duty_cycle": "duty cycle",
    "step_length_m": "step length S",
    "clearance_m": "clearance H",
    "stance_height_m": "stance height z0",
    "sample_rate_hz": "sample rate",
    "stance_x_offset_front_m": "front feet ahead of their hips",
    "stance_x_offset_hind_m": "hind feet ahead of their hips",
    "speed_m_s": "speed",
    "total_mass_kg": "total mass",
    "thigh_to_shank": "thigh / shank length",
}
"""Plain names of the columns a study sweeps or plots against."""


def axis_label(column: str) -> str:
    """A study column as an axis label: a plain name and its unit (``speed_m_s``: speed [m/s]).

    ``gait.`` and ``variant.`` prefixes go; a scale reads ``thigh length scale [x]``; a column of
    text (a robot, a family) is named as it is.
    """
    field = column.split(".")[-1]
    if field in _NAMES:
        name = _NAMES[field]
    elif field.endswith("_scale"):
        return field.replace("_", " ") + " [x]"
    else:
        name = field
        for suffix, _ in _UNITS:
            if field.endswith(suffix):
                name = field.removesuffix(suffix)
                break
        name = name.replace("_", " ")
    for suffix, unit in _UNITS:
        if field.endswith(suffix):
            return f"{name} [{unit}]"
    return f"{name} [-]" if field in ("duty_cycle", "thigh_to_shank") else name


def _value_label(column: str, value: Any) -> str:
    """``clearance H 0.04 m``: a swept value in a legend."""
    label = axis_label(column)
    if label.endswith("]"):
        name, _, unit = label[:-1].rpartition(" [")
        if unit == "x":
            return f"{name} x{value}"
        return f"{name} {value}" if unit == "-" else f"{name} {value} {unit}"
    return f"{label} {value}"


def _groups(rows: Sequence[dict[str, Any]], x: str) -> dict[str, list[dict[str, Any]]]:
    """Rows grouped by the swept values other than ``x`` (label -> rows, in order)."""
    swept = [
        k
        for k in rows[0]
        if k not in _RESULT_KEYS
        and k != x
        and not k.endswith(("_j", "_w", "_pct"))
        and not k.startswith("cost_of_transport")
    ]

    def follows_x(key: str) -> bool:  # set together with x (a combined axis): not a group
        seen: dict[str, str] = {}
        return all(seen.setdefault(str(r.get(x)), str(r.get(key))) == str(r.get(key)) for r in rows)

    varying = [k for k in swept if len({str(r.get(k)) for r in rows}) > 1 and not follows_x(k)]
    out: dict[str, list[dict[str, Any]]] = {}
    for row in rows:
        label = ", ".join(_value_label(k, row.get(k)) for k in varying) or "all cases"
        out.setdefault(label, []).append(row)
    return out


def study_figure(rows: Sequence[dict[str, Any]], x: str, title: str) -> Figure:
    """Energies, saving and cost of transport of a study's rows against column ``x``."""
    fig, axes = plt.subplots(3, 1, figsize=(8, 9), sharex=True)
    ax_e, ax_s, ax_c = axes
    if not rows:
        ax_e.text(0.5, 0.5, "no cases", ha="center", transform=ax_e.transAxes)
        return fig
    ok = [r for r in rows if r.get("status") == "ok"]
    numeric = all(is_number(r.get(x)) for r in rows)
    if numeric:
        _study_lines(axes, rows, x)
    else:
        _study_bars(axes, rows, x)
    dashed = "\n(dashed: reference)" if numeric else ""
    ax_e.set_ylabel(f"energy per cycle [J]{dashed}")
    ax_s.set_ylabel("saving [%]")
    ax_c.set_ylabel(f"cost of transport [-]{dashed}")
    ax_c.set_xlabel(axis_label(x))
    ax_e.set_title(fitted_title(f"{title}: {len(ok)} of {len(rows)} cases solved", 8.0, 12.0))
    for ax in axes:
        ax.grid(True, alpha=0.3)
    handles, _ = ax_e.get_legend_handles_labels()
    if handles:
        ax_e.legend(fontsize=8)
    fig.tight_layout()
    return fig


def _study_lines(axes: Sequence[Axes], rows: Sequence[dict[str, Any]], x: str) -> None:
    """A numeric ``x``: a line per group of rows (reference dashed), failed cases as red x."""
    ax_e, ax_s, ax_c = axes
    colors = plt.rcParams["axes.prop_cycle"].by_key()["color"] * 10
    for (label, group), color in zip(_groups(rows, x).items(), colors, strict=False):
        good = sorted((r for r in group if r.get("status") == "ok"), key=lambda r: r[x])
        xs = [r[x] for r in good]
        for ax, key, style, name in (
            (ax_e, "reference_energy_j", "--o", None),
            (ax_e, "optimized_energy_j", "-o", label),
            (ax_s, "saving_pct", "-o", label),
            (ax_c, "cost_of_transport_reference", "--o", None),
            (ax_c, "cost_of_transport_optimized", "-o", None),
        ):
            ax.plot(xs, [r[key] for r in good], style, ms=3, color=color, label=name)
    bad = [r[x] for r in rows if r.get("status") != "ok"]
    for ax in axes:
        if bad:
            ax.plot(bad, [0.0] * len(bad), "x", color="red", transform=ax.get_xaxis_transform())


def _study_bars(axes: Sequence[Axes], rows: Sequence[dict[str, Any]], x: str) -> None:
    """A categorical ``x``: bars per case (reference grey), a failed case at zero."""
    ax_e, ax_s, ax_c = axes

    def values(key: str) -> list[float]:
        return [r[key] if r.get("status") == "ok" else 0.0 for r in rows]

    pos = np.arange(len(rows))
    ax_e.bar(pos - 0.2, values("reference_energy_j"), 0.4, label="reference", color="0.7")
    ax_e.bar(pos + 0.2, values("optimized_energy_j"), 0.4, label="optimized", color="C0")
    ax_e.set_yscale("log")
    ax_s.bar(pos, values("saving_pct"), 0.5)
    ax_c.bar(pos - 0.2, values("cost_of_transport_reference"), 0.4, color="0.7", label="reference")
    ax_c.bar(pos + 0.2, values("cost_of_transport_optimized"), 0.4, color="C0", label="optimized")
    ax_c.set_xticks(pos, [str(r.get(x)) for r in rows], rotation=20)


def scan_figure(
    x: Sequence[float],
    y: Sequence[float],
    labels: tuple[str, str, str],
    target: tuple[float, str] | None = None,
    marks: Sequence[tuple[float, float, str]] = (),
) -> Figure:
    """One curve ``y(x)`` with an optional horizontal target line and labelled points.

    Args:
        x: Abscissae.
        y: Values.
        labels: (x label, y label, title).
        target: (value, label) of a horizontal line.
        marks: (x, y, label) of points to mark.
    """
    fig, ax = plt.subplots(figsize=(7, 4.2))
    ax.plot(x, y, "-o", ms=3, color="C0")
    if target is not None:
        ax.axhline(target[0], color="C3", ls="--", lw=1, label=target[1])
    for (mx, my, label), color in zip(marks, ("C1", "C2", "C4", "C5"), strict=False):
        ax.plot([mx], [my], "s", ms=7, color=color, label=label)
    ax.set_xlabel(labels[0])
    ax.set_ylabel(labels[1])
    ax.set_title(labels[2])
    ax.grid(True, alpha=0.3)
    if target is not None or marks:
        ax.legend(fontsize=8)
    fig.tight_layout()
    return fig
