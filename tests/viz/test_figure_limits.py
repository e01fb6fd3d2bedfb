"""Every figure's axes show everything drawn on them, for every robot: no foot path, bar, marker
or band runs off an edge (a shared axis set by its last panel once cut HyQ's RF optimum off).

Each artist drawn in data coordinates is compared with the limits of its axes; artists placed
in axes coordinates (reference lines across the panel, legends, labels) cannot leave them.
"""

import numpy as np
import pytest
from matplotlib.axes import Axes
from matplotlib.collections import Collection
from matplotlib.lines import Line2D
from matplotlib.patches import Patch

from scalf_opt.robots.catalog import robot_names
from scalf_opt.robots.loading import load_robot
from scalf_opt.studies.search import search_study
from scalf_opt.viz.figure_set import FIGURE_NAMES, figure_drawers
from scalf_opt.viz.plotting import close
from tests.viz.conftest import coarse_pipeline, optimized_trajectory, reference_trajectory

GRID = 5


def data_points(artist, ax: Axes) -> np.ndarray:
    """The (x, y) data points an artist covers, or none if it is not drawn in data coordinates."""
    if not artist.get_visible() or artist.get_transform() != ax.transData:
        if isinstance(artist, Collection) and artist.get_offset_transform() == ax.transData:
            return np.asarray(artist.get_offsets(), dtype=float).reshape(-1, 2)
        return np.empty((0, 2))
    if isinstance(artist, Line2D):
        xy = np.asarray(artist.get_xydata(), dtype=float).reshape(-1, 2)
    elif isinstance(artist, Collection):
        paths = [p.vertices for p in artist.get_paths() if len(p.vertices)]
        xy = np.vstack(paths) if paths else np.empty((0, 2))
    elif isinstance(artist, Patch):
        xy = artist.get_path().vertices @ artist.get_patch_transform().get_matrix()[:2, :2].T
        xy = xy + artist.get_patch_transform().get_matrix()[:2, 2]
    else:
        return np.empty((0, 2))
    return xy[np.all(np.isfinite(xy), axis=1)]


def outside(ax: Axes) -> list[str]:
    """The artists of ``ax`` that reach beyond its limits (beyond 0.1 % of the span)."""
    (x0, x1), (y0, y1) = sorted(ax.get_xlim()), sorted(ax.get_ylim())
    tx, ty = 1e-3 * (x1 - x0), 1e-3 * (y1 - y0)
    found = []
    for artist in [*ax.lines, *ax.collections, *ax.patches]:
        xy = data_points(artist, ax)
        if not len(xy):
            continue
        bad = (
            (xy[:, 0] < x0 - tx)
            | (xy[:, 0] > x1 + tx)
            | (xy[:, 1] < y0 - ty)
            | (xy[:, 1] > y1 + ty)
        )
        if bad.any():
            found.append(
                f"{ax.get_title() or ax.get_ylabel()!r}: {type(artist).__name__} "
                f"{artist.get_label()!r} reaches ({xy[bad][0][0]:.4g}, {xy[bad][0][1]:.4g}) "
                f"outside x [{x0:.4g}, {x1:.4g}], y [{y0:.4g}, {y1:.4g}]"
            )
    return found


def titles_outside(fig) -> list[str]:
    """The axes titles that run past the figure's edges (a long title is cut off in the file)."""
    renderer = fig.canvas.get_renderer()
    box = fig.bbox
    found = []
    for ax in fig.axes:
        for title in (ax.title, ax._left_title, ax._right_title):
            if not title.get_text():
                continue
            extent = title.get_window_extent(renderer)
            if extent.x0 < box.x0 - 0.5 or extent.x1 > box.x1 + 0.5:
                found.append(f"title {title.get_text()!r} runs past the figure's edge")
    return found


@pytest.mark.parametrize("name", robot_names())
def test_every_figure_shows_everything_it_draws(name):
    robot = load_robot(name)
    pipeline = coarse_pipeline(robot)
    shown = [reference_trajectory(pipeline), optimized_trajectory(pipeline, "joint-4")]
    search = search_study(pipeline, grid_points=GRID)
    problems = []
    for figure_name, draw in figure_drawers(robot, shown, search).items():
        fig = draw()
        try:
            fig.canvas.draw()  # the limits a saved file has
            problems += [f"{figure_name}: {p}" for ax in fig.axes for p in outside(ax)]
            problems += [f"{figure_name}: {p}" for p in titles_outside(fig)]
        finally:
            close(fig)
    assert set(figure_drawers(robot, shown, search)) == set(FIGURE_NAMES)
    assert not problems, "\n".join(problems)


@pytest.mark.parametrize("name", robot_names())
def test_the_simulation_figure_shows_everything_it_draws(name):
    pytest.importorskip("mujoco")
    import scalf_opt as so
    from scalf_opt.errors import ModelError

    try:
        fig = so.simulate(load_robot(name), cycles=2).figure()
    except ModelError as exc:  # ANYmal C: MuJoCo refuses one of its inertias (a known limit)
        if "MuJoCo cannot compile" not in str(exc):
            raise
        pytest.skip(str(exc))
    try:
        fig.canvas.draw()
        # Solo12's title (its gait's numbers to six digits) ran past the right edge
        problems = [p for ax in fig.axes for p in outside(ax)] + titles_outside(fig)
        labels = [label for ax in fig.axes for label in ax.get_legend_handles_labels()[1]]
        assert any("start-up" in label for label in labels)  # the cycle left out is marked
        # the headline's per-leg energy comparison is drawn: each leg's difference above its bars
        energy = fig.axes[-1]
        assert energy.get_ylabel() == "joint energy per cycle [J]"
        assert [t.get_text().endswith(" %") for t in energy.texts] == [True] * 4
    finally:
        close(fig)
    assert not problems, "\n".join(problems)


def test_the_check_finds_an_artist_off_the_edge():
    import matplotlib.pyplot as plt

    fig, ax = plt.subplots()
    ax.plot([0, 1], [0, 1])
    ax.set_xlim(0, 0.5)
    assert outside(ax)
    plt.close(fig)


def test_long_titles_wrap_inside_the_figure():
    # a study's name and a log's file paths are the user's: the title wraps instead of running
    # past the edge, where the saved file cuts it off
    import numpy as np

    from scalf_opt.viz.log_figure import log_plan_figure
    from scalf_opt.viz.study_figures import study_figure

    name = "a study of a user's robot whose name says everything it sweeps " * 3
    rows = [
        {
            "case": i,
            "speed_m_s": 0.5 + 0.25 * i,
            "reference_energy_j": 10.0 + i,
            "optimized_energy_j": 9.0 + i,
            "saving_pct": 10.0 - i,
            "cost_of_transport_reference": 0.3,
            "cost_of_transport_optimized": 0.25,
            "status": "ok",
        }
        for i in range(3)
    ]
    t = np.linspace(0.0, 0.5, 50, endpoint=False)
    paths = "/home/someone/experiments/2026-12-04/a-long-folder-name/"
    figures = [
        study_figure(rows, "speed_m_s", name),
        log_plan_figure(
            t,
            100.0 + 10.0 * np.sin(t),
            t,
            100.0 + 9.0 * np.sin(t),
            {"RF": 1.0},
            {"RF": 1.1},
            f"{paths}run.mcap against the plan {paths}opt: 603.3 W measured, 556.5 W planned",
        ),
    ]
    for fig in figures:
        try:
            fig.canvas.draw()
            assert not titles_outside(fig)
        finally:
            close(fig)
