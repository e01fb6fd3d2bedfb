"""Every figure of ``scalf-opt figures``, drawn and written in one go.

=================  =========================================================  =====================
file (.png, .svg)  what                                                       the paper
=================  =========================================================  =====================
joint_angles       hip and knee angle over a cycle, RF and LH                 Figure 9
joint_torques      hip and knee torque over a cycle                           Figure 10
joint_powers       hip and knee charged power, with each joint's energy       Figure 11
foot_forces        ground reaction forces of every foot over a cycle          Figure 13
foot_paths         swing and stance foot paths in the leg frame               Figure 12
leg_snapshots      stick figures of the leg through the swing                 Figures 17, 18
search_landscape   pattern search and Ipopt over the (C1, C2) landscape       Figure 8 (+ landscape)
energy_bars        energy per leg, phase and joint                            Table 6
=================  =========================================================  =====================

(``scalf-opt paper`` draws the paper's Figure 8 itself, the search's accepted points alone, as
``pattern_search.png``; the landscape here has its own name.)
"""

from __future__ import annotations

from collections.abc import Callable, Sequence
from pathlib import Path

from matplotlib.figure import Figure

from scalf_opt.energy.loads import stance_loads
from scalf_opt.errors import ConfigError
from scalf_opt.model.robot import Robot
from scalf_opt.types import FIRST_PAIR
from scalf_opt.viz.cycle_figures import foot_force_figure, joint_figure
from scalf_opt.viz.energy_figure import energy_bars_figure
from scalf_opt.viz.plotting import FORMATS, save_in_formats
from scalf_opt.viz.search_figure import LegSearch, search_figure
from scalf_opt.viz.stick_figure import foot_path_figure, leg_snapshot_figure
from scalf_opt.viz.trajectories import Trajectory

FIGURE_NAMES = (
    "joint_angles",
    "joint_torques",
    "joint_powers",
    "foot_forces",
    "foot_paths",
    "leg_snapshots",
    "search_landscape",
    "energy_bars",
)
"""The figures, in the order they are written."""


def figure_drawers(
    robot: Robot,
    trajectories: Sequence[Trajectory],
    search: dict[str, LegSearch],
    legs: Sequence[str] = FIRST_PAIR,
) -> dict[str, Callable[[], Figure]]:
    """Each figure's name (:data:`FIGURE_NAMES`) and the function that draws it (nothing drawn yet).

    Args:
        robot: The robot.
        trajectories: What to compare, the reference first.
        search: The pattern search and Ipopt over their landscape, per leg.
        legs: The legs drawn where a figure shows some legs.
    """
    return {
        "joint_angles": lambda: joint_figure(trajectories, "angle", legs),
        "joint_torques": lambda: joint_figure(trajectories, "torque", legs),
        "joint_powers": lambda: joint_figure(trajectories, "power", legs),
        "foot_forces": lambda: foot_force_figure(
            trajectories[0], stance_loads(trajectories[0].cycle.loads).carried_mass_kg(robot)
        ),
        "foot_paths": lambda: foot_path_figure(trajectories, legs),
        "leg_snapshots": lambda: leg_snapshot_figure(robot, trajectories, legs),
        "search_landscape": lambda: search_figure(search),
        "energy_bars": lambda: energy_bars_figure(trajectories),
    }


def write_figures(
    out: str | Path,
    robot: Robot,
    trajectories: Sequence[Trajectory],
    search: dict[str, LegSearch],
    formats: Sequence[str] = FORMATS,
    legs: Sequence[str] = FIRST_PAIR,
    on_written: Callable[[Path], None] | None = None,
) -> list[Path]:
    """Draw every figure and write it in every format to ``out`` (atomically, deterministically).

    Args:
        out: Output directory (created if missing).
        robot: The robot.
        trajectories: What to compare, the reference first.
        search: The pattern search and Ipopt over their landscape, per leg
            (:func:`scalf_opt.studies.search.search_study`).
        formats: File formats (``png``, ``svg``).
        legs: The legs drawn where a figure shows some legs (default: the diagonal pair).
        on_written: Called with each file as it is written (progress).

    Returns:
        The files written, in :data:`FIGURE_NAMES` order, each in ``formats`` order.

    Raises:
        ConfigError: An unknown format, or nothing to draw.
    """
    unknown = [f for f in formats if f not in FORMATS]
    if unknown or not formats:
        raise ConfigError(f"figure formats must be among {', '.join(FORMATS)}, got {formats}")
    if not trajectories:
        raise ConfigError("nothing to draw: give at least one trajectory")
    directory = Path(out)
    if directory.exists() and not directory.is_dir():
        raise ConfigError(f"{directory}: exists and is not a directory")
    drawers = figure_drawers(robot, trajectories, search, legs)
    written = []
    for name in FIGURE_NAMES:
        written += save_in_formats(drawers[name](), directory, name, formats, on_written)
    return written
