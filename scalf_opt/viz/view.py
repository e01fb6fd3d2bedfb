"""The 3-D view as one offline HTML file, drawn from the trajectories (or 3-D plans) it is given.

What to show is decided above this floor (:func:`scalf_opt.api.presentation.view`).
"""

from __future__ import annotations

from collections.abc import Sequence
from pathlib import Path
from typing import TYPE_CHECKING

from scalf_opt.errors import ConfigError
from scalf_opt.files import write_atomic
from scalf_opt.model.robot import Robot
from scalf_opt.viz.html import scene_page
from scalf_opt.viz.scene import SceneOptions, build_scene
from scalf_opt.viz.trajectories import Trajectory
from scalf_opt.viz.visuals import Visual

if TYPE_CHECKING:
    from scalf_opt.viz.whole_body_walk import ShownPlan


def check_output_file(path: str | Path, suffix: str) -> Path:
    """``path`` as an output file: not a directory, with the expected suffix.

    Raises:
        ConfigError: ``path`` is a directory or has another suffix.
    """
    out = Path(path)
    if out.is_dir():
        raise ConfigError(f"{out}: is a directory; give a file name ending in {suffix}")
    if out.suffix.lower() != suffix:
        raise ConfigError(f"{out}: the output file must end in {suffix}")
    return out


def write_scene_html(
    out: str | Path,
    robot: Robot,
    trajectories: Sequence[Trajectory],
    options: SceneOptions | None = None,
    visuals: tuple[list[Visual], list[str]] | None = None,
) -> Path:
    """Write the offline HTML view of ``trajectories`` on ``robot`` to ``out`` (atomically).

    ``visuals``: the robot's visuals, when loaded already (see
    :func:`~scalf_opt.viz.scene.build_scene`).

    Raises:
        ConfigError: Bad output path or options; meshcat is not installed.
        ModelError: The robot's visual geometry cannot be loaded.
    """
    path = check_output_file(out, ".html")
    return write_atomic(path, scene_page(build_scene(robot, trajectories, options, visuals)))


def write_plan_scene_html(
    out: str | Path,
    shown: Sequence[ShownPlan],
    options: SceneOptions | None = None,
    visuals: tuple[list[Visual], list[str]] | None = None,
) -> Path:
    """Write the offline HTML view of 3-D whole-body plans to ``out`` (atomically).

    ``visuals``: the first plan's robot's visuals, when loaded already (see
    :func:`~scalf_opt.viz.whole_body_walk.build_plan_scene`).

    Raises:
        ConfigError: Bad output path or options; meshcat is not installed.
        ModelError: The robot's visual geometry cannot be loaded.
    """
    from scalf_opt.viz.whole_body_walk import build_plan_scene

    path = check_output_file(out, ".html")
    return write_atomic(path, scene_page(build_plan_scene(shown, options, visuals)))
