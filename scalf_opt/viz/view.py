"""The 3-D view as one offline HTML file: the Python side of ``scalf-opt view``.

>>> from scalf_opt.viz.view import view
>>> view("scene.html")                                  # SCalf: reference and default optimum
>>> view("cmp.html", robot="hyq", from_dirs=["a", "b"])  # two saved optima on HyQ
"""

from __future__ import annotations

from collections.abc import Sequence
from pathlib import Path

from scalf_opt.errors import ConfigError
from scalf_opt.files import write_atomic
from scalf_opt.locomotion.gait import Gait
from scalf_opt.locomotion.scaling import default_gait_for
from scalf_opt.model.robot import Robot
from scalf_opt.types import Accounting
from scalf_opt.viz.html import scene_page
from scalf_opt.viz.scene import SceneOptions, build_scene
from scalf_opt.viz.trajectories import Trajectory, shown_trajectories


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
) -> Path:
    """Write the offline HTML view of ``trajectories`` on ``robot`` to ``out`` (atomically).

    Raises:
        ConfigError: Bad output path or options; meshcat is not installed.
        ModelError: The robot's visual geometry cannot be loaded.
    """
    path = check_output_file(out, ".html")
    return write_atomic(path, scene_page(build_scene(robot, trajectories, options)))


def view(
    out: str | Path = "scene.html",
    robot: str | Robot = "scalf",
    from_dirs: Sequence[str | Path] = (),
    gait: Gait | None = None,
    accounting: Accounting = "paper",
    options: SceneOptions | None = None,
) -> tuple[Path, list[Trajectory]]:
    """Build and write the view; return the file and the trajectories shown.

    Args:
        out: The HTML file to write.
        robot: A catalog name (``scalf``, ``hyq``, ``solo12``) or a loaded robot.
        from_dirs: Result directories of ``scalf-opt optimize --out``; none: the reference and
            the default optimum (``joint-6``, Ipopt) are computed.
        gait: The gait without ``from_dirs`` (default: the robot's).
        accounting: Power accounting without ``from_dirs``.
        options: Scene options (cycles, frame rate, colouring, playback speed).

    Raises:
        ConfigError: Bad arguments, or a gait together with result directories.
        NotSolvedError: The default optimum did not converge (nothing is written).
    """
    from scalf_opt.robots.loading import load_robot

    check_output_file(out, ".html")
    if gait is not None and from_dirs:
        raise ConfigError("give a gait or result directories (which bring their own), not both")
    loaded = load_robot(robot) if isinstance(robot, str) else robot
    base = gait or default_gait_for(loaded)
    _, shown = shown_trajectories(loaded, base, from_dirs, accounting)
    return write_scene_html(out, loaded, shown, options), shown
