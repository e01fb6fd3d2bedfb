"""What ``view`` and ``figures`` show: the reference and the default optimum, or saved swings.

The default optimum comes from :func:`~scalf_opt.api.optimization.optimize_swing`, the one
optimization entry, so the view's legend and the figures print the energies ``scalf-opt
optimize`` prints (the reference at the optimum's converged rate, like with like). Saved swings
(``scalf-opt optimize --out DIR``) are evaluated on their own gait, at the rate they were saved
at, with the reference on that gait first. :mod:`scalf_opt.viz` then only draws.

>>> import scalf_opt.api.presentation as show
>>> path, shown = show.view("scene.html")                  # SCalf: reference, default optimum
>>> files, shown = show.figures("figures", robot="hyq")
"""

from __future__ import annotations

from collections.abc import Callable, Sequence
from dataclasses import replace
from pathlib import Path
from typing import TYPE_CHECKING

import numpy as np

from scalf_opt.api.gaits import as_robot
from scalf_opt.api.optimization import optimize_swing
from scalf_opt.energy.cycle import RobotCycle
from scalf_opt.energy.loads import DEFAULT_LOADS
from scalf_opt.energy.pipeline import EnergyPipeline
from scalf_opt.errors import ConfigError, ScalfError
from scalf_opt.io.saved import SavedSwings, read_saved_swings
from scalf_opt.locomotion.gait import Gait
from scalf_opt.locomotion.scaling import default_gait_for
from scalf_opt.locomotion.swing.names import DEFAULT_FAMILY
from scalf_opt.locomotion.swing.registry import make_family
from scalf_opt.model.robot import Robot
from scalf_opt.types import LEG_NAMES, Accounting
from scalf_opt.viz.trajectories import REFERENCE_LABEL, Trajectory

if TYPE_CHECKING:  # the drawing libraries load when something is drawn (meshcat is an extra)
    from scalf_opt.viz.scene import SceneOptions
    from scalf_opt.viz.whole_body_walk import ShownPlan

Progress = Callable[[str], None]


class NotSolvedError(ScalfError):
    """The optimum behind a trajectory to show did not converge: nothing is presented.

    The command line exits with code 3 on it (an optimizer did not converge), not 2.
    """


def saved_trajectory(pipeline: EnergyPipeline, saved: SavedSwings) -> Trajectory:
    """The swings of a result directory, evaluated leg by leg with their own families.

    Raises:
        InfeasibleError: A saved swing cannot be realised by this robot (another robot's result).
    """
    chosen = {}
    for leg in LEG_NAMES:
        family = make_family(saved.families.get(leg, "reference"))
        theta = saved.parameters.get(leg)
        chosen[leg] = (family, np.zeros(family.n_params) if theta is None else np.asarray(theta))
    legs = {leg: pipeline.leg_cycle(leg, *chosen[leg], swings=chosen) for leg in LEG_NAMES}
    cycle = RobotCycle(
        pipeline.gait,
        pipeline.accounting,
        legs,
        pipeline.robot.total_mass_kg,
        loads=pipeline.loads,
    )
    return Trajectory(saved.label, cycle)


def parent_of(robot: Robot) -> Robot:
    """The robot a variant was derived from.

    Raises:
        ConfigError: ``robot`` is not a variant.
    """
    if robot.parent is None:
        raise ConfigError(
            f"--beside-parent: {robot.urdf_path} is not a variant (scalf-opt variant writes one, "
            "with its record beside it)"
        )
    return robot.parent


def beside_parent(
    robot: Robot, shown: Sequence[Trajectory], progress: Progress | None = None
) -> list[Trajectory]:
    """A variant's trajectories, then its parent's reference and default optimum beside them.

    The parent walks the gait the variant's trajectories walk, under their accounting and loads,
    so that the two differ by the variant's geometry alone; every label names its robot.

    Raises:
        ConfigError: ``robot`` is not a variant (``scalf-opt variant`` writes one, its record
            beside it).
        NotSolvedError: The parent's default optimum did not converge.
    """
    parent = parent_of(robot)
    cycle = shown[0].cycle
    result = optimize_swing(
        parent,
        cycle.gait,
        family=DEFAULT_FAMILY,
        accounting=cycle.accounting,
        progress=progress,
        loads=cycle.loads,
    )
    if result.cycle is None:
        raise NotSolvedError(f"{parent.name}'s default optimum was not solved: {result.failure()}")
    optimum = f"optimum ({DEFAULT_FAMILY}, {result.settings.method})"
    own = [replace(t, label=f"{robot.name}: {t.label}") for t in shown]
    return [
        *own,
        Trajectory(f"{parent.name}: {REFERENCE_LABEL}", result.reference, robot=parent),
        Trajectory(f"{parent.name}: {optimum}", result.cycle, robot=parent),
    ]


def shown_trajectories(
    robot: Robot,
    gait: Gait,
    from_dirs: Sequence[str | Path] = (),
    accounting: Accounting = "paper",
    progress: Progress | None = None,
    loads: str | None = None,
) -> tuple[EnergyPipeline, list[Trajectory]]:
    """The pipeline and the trajectories to show: reference first.

    Args:
        robot: The robot.
        gait: The gait when no directory is given (a directory brings its own).
        from_dirs: Result directories of ``scalf-opt optimize --out``; none: the default optimum.
        accounting: Power accounting when no directory is given.
        progress: Called with a label as each step of the optimization starts.
        loads: The stance load model; ``None``: the directories' own (they must agree), else
            ``whole-body``.

    Returns:
        The pipeline the trajectories were evaluated with (at the optimum's rate) and the
        trajectories.

    Raises:
        ConfigError: A directory cannot be read, or the directories' gaits or accountings differ.
        NotSolvedError: The default optimum did not converge.
    """
    saved = [read_saved_swings(d) for d in from_dirs]
    for swings in saved:
        swings.check_robot(robot)
    if not saved:
        result = optimize_swing(
            robot,
            gait,
            family=DEFAULT_FAMILY,
            accounting=accounting,
            progress=progress,
            loads=loads or DEFAULT_LOADS,
        )
        if result.cycle is None:
            raise NotSolvedError(f"the default optimum was not solved: {result.failure()}")
        label = f"optimum ({DEFAULT_FAMILY}, {result.settings.method})"
        return result.pipeline, [
            Trajectory(REFERENCE_LABEL, result.reference),
            Trajectory(label, result.cycle),
        ]
    first = saved[0]
    for other in saved[1:]:
        for what, a, b in (
            ("gait", first.gait, other.gait),
            ("accounting", first.accounting, other.accounting),
            ("loads", first.loads, other.loads),
        ):
            if a != b:
                raise ConfigError(
                    f"{other.source}: its {what} differs from {first.source}'s; "
                    "compare results of one gait, accounting and load model"
                )
    pipeline = EnergyPipeline(robot, first.gait, first.accounting, loads=loads or first.loads)
    reference = Trajectory(REFERENCE_LABEL, pipeline.robot_cycle(make_family("reference")))
    return pipeline, [reference, *(saved_trajectory(pipeline, s) for s in saved)]


def search_pipeline(
    shown: EnergyPipeline, gait: Gait, from_dirs: Sequence[str | Path]
) -> EnergyPipeline:
    """The pipeline the pattern-search figure optimizes the paper family on.

    The gait as given (its own rate, where ``scalf-opt optimize --family paper`` would start),
    not the default optimum's converged rate; with saved results, their gait.
    """
    return shown if from_dirs else shown.with_gait(gait)


def _one_or_many(given: str | Path | Sequence[str | Path]) -> tuple[str | Path, ...]:
    """A path, or paths: one directory or format is not read letter by letter."""
    return (given,) if isinstance(given, str | Path) else tuple(given)


def _robot_and_gait(
    robot: str | Robot, gait: Gait | None, from_dirs: Sequence[str | Path]
) -> tuple[Robot, Gait]:
    if gait is not None and from_dirs:
        raise ConfigError("give a gait or result directories (which bring their own), not both")
    loaded = as_robot(robot)
    return loaded, gait or default_gait_for(loaded)


def view_cycles(
    out: str | Path,
    from_dirs: str | Path | Sequence[str | Path],
    robot: str | Robot | None = None,
    options: SceneOptions | None = None,
) -> tuple[Path, list[ShownPlan]]:
    """Write the offline 3-D view of saved 3-D cycles (``optimize --model 3d --out DIR``).

    Args:
        out: The HTML file to write.
        from_dirs: One or several 3-D cycle folders, shown side by side.
        robot: The robot (default: the first folder's, from its ``summary.json``); a folder of
            another robot is refused.
        options: Scene options (cycles, frame rate, colouring, playback speed).

    Returns:
        The page, and the plans shown (each with its folder's headline).

    Raises:
        ConfigError: A folder that is not a readable 3-D cycle, or of another robot; a bad
            output path or options.
    """
    from scalf_opt.energy.whole_body import WholeBodyPhysics
    from scalf_opt.io.whole_body_export import read_cycle
    from scalf_opt.viz.view import check_output_file, write_plan_scene_html
    from scalf_opt.viz.visuals import load_visuals
    from scalf_opt.viz.whole_body_walk import ShownPlan

    check_output_file(out, ".html")
    saved = [read_cycle(Path(d)) for d in _one_or_many(from_dirs)]
    if not saved:
        raise ConfigError("give at least one 3-D cycle folder", field="from_dirs")
    loaded = as_robot(robot if robot is not None else str(saved[0].summary.get("robot")))
    physics = WholeBodyPhysics.of(loaded)
    shown = [ShownPlan.of(cycle, physics) for cycle in saved]  # another robot's is refused
    page = write_plan_scene_html(out, shown, options, load_visuals(loaded))
    return page, shown


def _three_d_folders(from_dirs: Sequence[str | Path], gait: Gait | None, loads: str | None) -> bool:
    """Whether ``from_dirs`` are 3-D cycles (all of them; a mix is refused, as a gait or loads).

    Raises:
        ConfigError: 3-D and sagittal folders together; a gait or loads with 3-D cycles.
    """
    from scalf_opt.io.whole_body_export import is_3d_cycle

    kinds = {str(d): is_3d_cycle(Path(d)) for d in from_dirs}
    if not any(kinds.values()):
        return False
    if not all(kinds.values()):
        sagittal = next(d for d, three_d in kinds.items() if not three_d)
        raise ConfigError(
            f"{sagittal}: not a 3-D cycle, beside 3-D cycles; 3-D and sagittal results are "
            "shown apart",
            field="from_dirs",
        )
    if gait is not None or loads is not None:
        raise ConfigError(
            "a 3-D cycle brings its own gait and contact forces: give no gait or loads",
            field="gait" if gait is not None else "loads",
        )
    return True


def view(
    out: str | Path = "scene.html",
    robot: str | Robot | None = None,
    from_dirs: str | Path | Sequence[str | Path] = (),
    gait: Gait | None = None,
    accounting: Accounting = "paper",
    options: SceneOptions | None = None,
    progress: Progress | None = None,
    loads: str | None = None,
) -> tuple[Path, list[Trajectory]]:
    """Build and write the offline 3-D view; return the file and the trajectories shown.

    Args:
        out: The HTML file to write.
        robot: A catalog name (``scalf``, ``hyq``, ``solo12``, ...) or a loaded robot (default:
            a 3-D cycle's own robot, else ``scalf``).
        from_dirs: Result directories of ``scalf-opt optimize --out`` (one or several); none:
            the reference and the default optimum are computed. 3-D cycles
            (``optimize --model 3d --out``) are shown as :func:`view_cycles` shows them, the
            whole robot walking each plan; the trajectories returned are then none (the plans
            are :func:`view_cycles`'s).
        gait: The gait without ``from_dirs`` (default: the robot's).
        accounting: Power accounting without ``from_dirs``.
        options: Scene options (cycles, frame rate, colouring, playback speed).
        progress: Called with a label as each step of the optimization starts.
        loads: The stance load model (default: the directories', else ``whole-body``).

    Raises:
        ConfigError: Bad arguments, or a gait together with result directories.
        NotSolvedError: The default optimum did not converge (nothing is written).
    """
    from scalf_opt.viz.view import check_output_file, write_scene_html

    check_output_file(out, ".html")
    from_dirs = _one_or_many(from_dirs)
    if _three_d_folders(from_dirs, gait, loads):
        return view_cycles(out, from_dirs, robot, options)[0], []
    loaded, base = _robot_and_gait("scalf" if robot is None else robot, gait, from_dirs)
    _, shown = shown_trajectories(loaded, base, from_dirs, accounting, progress, loads)
    return write_scene_html(out, loaded, shown, options), shown


def figures(
    out: str | Path = "figures",
    robot: str | Robot = "scalf",
    from_dirs: str | Path | Sequence[str | Path] = (),
    gait: Gait | None = None,
    accounting: Accounting = "paper",
    formats: str | Sequence[str] | None = None,
    grid_points: int | None = None,
    progress: Progress | None = None,
    loads: str | None = None,
) -> tuple[list[Path], list[Trajectory]]:
    """Compute what to compare and write every figure; return the files and the trajectories.

    Args:
        out: Output directory.
        robot: A catalog name or a loaded robot.
        from_dirs: Result directories of ``scalf-opt optimize --out`` (one or several); none:
            the reference and the default optimum.
        gait: The gait without ``from_dirs`` (default: the robot's).
        accounting: Power accounting without ``from_dirs``.
        formats: File formats, one or several (default: PNG and SVG).
        grid_points: Landscape points per parameter of the pattern-search figure (>= 3;
            default :data:`scalf_opt.studies.search.GRID_POINTS`).
        progress: Called with a label as each step starts.
        loads: The stance load model (default: the directories', else ``whole-body``).

    Raises:
        ConfigError: Bad arguments, or a gait together with result directories.
        NotSolvedError: The default optimum did not converge (nothing is written).
    """
    from scalf_opt.studies.search import GRID_POINTS, search_study
    from scalf_opt.viz.figure_set import write_figures
    from scalf_opt.viz.plotting import FORMATS

    grid_points = GRID_POINTS if grid_points is None else grid_points
    if grid_points < 3:
        raise ConfigError(
            f"the landscape grid needs at least 3 points, got {grid_points}", field="grid"
        )
    from_dirs = _one_or_many(from_dirs)
    loaded, base = _robot_and_gait(robot, gait, from_dirs)
    pipeline, shown = shown_trajectories(loaded, base, from_dirs, accounting, progress, loads)
    if progress is not None:
        progress("the pattern search's landscape")
    search = search_study(search_pipeline(pipeline, base, from_dirs), grid_points=grid_points)
    chosen = tuple(str(f) for f in _one_or_many(formats)) if formats else FORMATS
    return write_figures(out, loaded, shown, search, chosen), shown
