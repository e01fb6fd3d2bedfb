"""The colours every figure and the 3-D view give the trajectories, in the order shown.

The reference (always first) is dark grey; the others take matplotlib's tab10 hues without its
blue (the usual colour of robot legs), grey and olive, so that a trajectory keeps its colour from
the view to the figures.
"""

from __future__ import annotations

import numpy as np

TRAJECTORY_COLORS: tuple[str, ...] = (
    "#404040",  # dark grey: the reference
    "#d62728",  # red
    "#2ca02c",  # green
    "#ff7f0e",  # orange
    "#9467bd",  # purple
    "#17becf",  # cyan
    "#8c564b",  # brown
    "#e377c2",  # pink
)

JOINT_COLORS: dict[str, str] = {"hip": "#1f77b4", "knee": "#d62728"}
"""Colours of the two joints where a figure tells joints apart by colour."""

LEG_COLORS: dict[str, str] = {"RF": "#1f77b4", "LH": "#d62728", "LF": "#2ca02c", "RH": "#ff7f0e"}
"""Colours of the legs where a figure tells legs apart by colour."""


def trajectory_color(index: int) -> str:
    """The colour of the ``index``-th trajectory shown (cycling after eight)."""
    return TRAJECTORY_COLORS[index % len(TRAJECTORY_COLORS)]


def hex_rgb(color: str) -> np.ndarray:
    """``#rrggbb`` as RGB in [0, 1], shape (3,)."""
    return np.array([int(color[i : i + 2], 16) / 255.0 for i in (1, 3, 5)])
