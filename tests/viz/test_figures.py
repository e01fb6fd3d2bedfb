"""The figures: deterministic bytes, units on every axis, true lengths, what each must show.

Coarse gaits (40 Hz) and small landscape grids keep the drawing fast; what is checked does not
depend on the resolution.
"""

from dataclasses import replace

import numpy as np
import pytest
from matplotlib.figure import Figure

from scalf_opt.cli import main
from scalf_opt.errors import ConfigError
from scalf_opt.locomotion.swing.registry import make_family
from scalf_opt.optimize.landscape import energy_landscape
from scalf_opt.optimize.problem import SwingProblem
from scalf_opt.optimize.solve import run_ipopt
from scalf_opt.studies.search import search_study
from scalf_opt.viz.cycle_figures import foot_force_figure, joint_figure
from scalf_opt.viz.energy_figure import energy_bars_figure
from scalf_opt.viz.figure_set import FIGURE_NAMES, write_figures
from scalf_opt.viz.figures import pattern_search_figure
from scalf_opt.viz.plotting import close, save_figure
from scalf_opt.viz.search_figure import search_figure
from scalf_opt.viz.stick_figure import foot_path_figure, leg_snapshot_figure
from tests.viz.conftest import (
    COARSE_RATE_HZ,
    coarse_pipeline,
    optimized_trajectory,
    reference_trajectory,
)

SMALL_GRID = 7


@pytest.fixture(scope="module")
def scalf_study(scalf_shown):
    pipeline, _ = scalf_shown
    return search_study(pipeline, grid_points=SMALL_GRID)


def every_figure(robot, pipeline, shown, study):
    yield "joint_angles", joint_figure(shown, "angle")
    yield "joint_torques", joint_figure(shown, "torque")
    yield "joint_powers", joint_figure(shown, "power")
    yield "foot_forces", foot_force_figure(shown[0], robot.total_mass_kg)
    yield "foot_paths", foot_path_figure(shown)
    yield "leg_snapshots", leg_snapshot_figure(robot, shown)
    yield "search_landscape", search_figure(study)
    yield "energy_bars", energy_bars_figure(shown)


def numeric(text):
    try:
        float(text.replace("\u2212", "-"))
    except ValueError:
        return False
    return True


def labels_with_units(fig: Figure):
    """Problems with the figure's axis labels: a label without a unit ``[...]``, or a numeric
    axis (categories, like leg names, need none) without a label of its own or of an axis it
    shares."""
    problems = []
    for ax in fig.axes:
        if not ax.get_visible() or ax.get_label() == "<colorbar>":
            continue
        for which in ("x", "y"):
            label = ax.get_xlabel() if which == "x" else ax.get_ylabel()
            if label:
                if "[" not in label or "]" not in label:
                    problems.append(f"{which} label without a unit: {label!r}")
                continue
            ticks = ax.get_xticklabels() if which == "x" else ax.get_yticklabels()
            texts = [t.get_text() for t in ticks if t.get_text()]
            if not texts or not all(map(numeric, texts)):
                continue  # no tick labels shown, or categories
            shared = ax.get_shared_x_axes() if which == "x" else ax.get_shared_y_axes()
            getter = "get_xlabel" if which == "x" else "get_ylabel"
            if not any(getattr(s, getter)() for s in shared.get_siblings(ax) if s is not ax):
                problems.append(f"{which} axis without a label in {ax.get_title(loc='left')!r}")
    return problems


def test_every_axis_has_units(scalf, scalf_shown, scalf_study):
    pipeline, shown = scalf_shown
    for name, fig in every_figure(scalf, pipeline, shown, scalf_study):
        fig.canvas.draw()  # tick labels exist once drawn
        assert labels_with_units(fig) == [], name
        close(fig)


def test_foot_paths_true_lengths_both_legs_lift_off_touch_down(scalf_shown, scalf):
    _, shown = scalf_shown
    for fig in (foot_path_figure(shown), leg_snapshot_figure(scalf, shown)):
        panels = [ax for ax in fig.axes if ax.get_visible()]
        assert {ax.get_title(loc="left")[:2] for ax in panels} == {
            "RF",
            "LH",
        }  # both legs of the pair
        for ax in panels:
            assert ax.get_aspect() == 1.0  # equal aspect: true lengths
            markers = {line.get_marker() for line in ax.get_lines()}
            assert {"v", "^"} <= markers  # lift-off, touch-down
        close(fig)


def test_snapshot_feet_lie_on_the_sampled_path(scalf_shown, scalf):
    """The stick figures' feet (Pinocchio's FK of the joint angles) are on the foot path
    computed by the pipeline: two routes to the same point."""
    from scalf_opt.viz.stick_figure import leg_points_m

    _, shown = scalf_shown
    for leg in ("RF", "LH"):
        swing = shown[1].cycle.legs[leg].swing
        points = leg_points_m(scalf, leg, swing.values["q"])
        np.testing.assert_allclose(points[:, 2, :].T, swing.values["foot"], atol=1e-12)
        knee = np.linalg.norm(points[:, 1, :], axis=1)  # hip to knee: the thigh, in the plane
        np.testing.assert_allclose(knee, scalf.leg(leg).thigh_length_m, rtol=1e-12)


def test_pattern_search_figure_shows_both_phases_and_levels(scalf_study):
    fig = search_figure(scalf_study)
    labels = set(
        fig.legends[0].get_texts()[i].get_text() for i in range(len(fig.legends[0].get_texts()))
    )
    assert "pattern search: feasibility phase" in labels
    assert "pattern search: energy phase" in labels
    assert "Ipopt's optimum" in labels and "reference swing energy" in labels
    for leg, axes in zip(("RF", "LH"), fig.axes[2:4], strict=True):
        levels = {
            round(line.get_ydata()[0], 9) for line in axes.get_lines() if len(line.get_ydata()) == 2
        }
        search = scalf_study[leg]
        assert round(search.reference_swing_j, 9) in levels
        assert round(search.ipopt.swing_energy_j, 9) in levels
    close(fig)


def test_figure_8_shows_the_feasibility_phase_too(scalf_study):
    """The paper's Figure 8 (``paper``'s ``pattern_search.png``): from the infeasible start
    (0, 0) its parameters' panels start at iteration 0 with the feasibility phase's points, over
    a shaded span where no energy exists (it began at the energy phase's first iteration)."""
    optima = {leg: search.pattern for leg, search in scalf_study.items()}
    fig = pattern_search_figure(optima)
    c1, _, energy = fig.axes
    for optimum in optima.values():
        phase1 = np.array(optimum.pattern_details.feasibility_history)
        assert phase1.shape[0] > 1 and phase1[0, 0] == 0.0
    assert min(line.get_xdata()[0] for line in c1.get_lines()) == 0.0
    first = min(optimum.pattern_details.history[0][0] for optimum in optima.values())
    assert first > 0 and min(line.get_xdata()[0] for line in energy.get_lines()) == first
    labels = [t.get_text() for t in fig.legends[0].get_texts()]
    assert labels[:2] == ["RF", "LH"] and labels[2].startswith("feasibility phase")
    assert all(len(ax.patches) == 1 for ax in fig.axes)  # the shaded span, in every panel
    close(fig)


def test_search_panels_say_when_the_search_restarted_at_a_finer_rate(scalf_study):
    # the sampling refinement restarts the search at a finer rate from the coarser optimum
    # (Go1's paper family: 283.483 Hz, then 566.965 Hz, where it accepted one point): the panel
    # names both rates, and its iteration axis has integer ticks whatever the history's length
    single = search_figure(scalf_study)
    assert all("restarted" not in ax.get_title(loc="left") for ax in single.axes[2:4])
    close(single)
    refined = {leg: replace(s, pattern_rates_hz=(200.0, 400.0)) for leg, s in scalf_study.items()}
    fig = search_figure(refined)
    for ax in fig.axes[2:4]:
        assert ax.get_title(loc="left").endswith("restarted at 400 Hz from the 200 Hz optimum")
        ticks = ax.get_xticks()
        assert np.all(ticks == np.round(ticks)) and ax.get_xlim()[1] >= 1.0
    close(fig)


def test_landscape_agrees_with_the_optimizers(scalf_shown):
    """Every feasible grid point costs at least Ipopt's optimum (which is feasible), and the
    landscape's energies are the problem's exact energies; the start (0, 0) is infeasible: its
    foot leaves the ground moving down (README, "Two optimizers")."""
    pipeline, _ = scalf_shown
    problem = SwingProblem(pipeline, "RF", make_family("paper"))
    ipopt = run_ipopt(problem)
    assert ipopt.success
    c1, c2 = ipopt.theta
    land = energy_landscape(problem, np.linspace(c1 - 3, c1 + 3, 9), np.linspace(c2 - 3, c2 + 3, 9))
    assert land.feasible.any() and not land.feasible.all()
    assert land.best[2] >= ipopt.swing_energy_j - 1e-6
    for j, i in zip(*np.nonzero(land.feasible), strict=True):
        assert land.energy_j[j, i] == problem.evaluate(np.array([land.x[i], land.y[j]])).energy_j
    origin = energy_landscape(problem, np.array([-1.0, 0.0]), np.array([0.0, 1.0]))
    assert not origin.feasible[0, 1]
    assert origin.reasons[0, 1] == "foot leaves or meets the ground from below"
    with pytest.raises(ConfigError, match="two"):
        energy_landscape(
            SwingProblem(pipeline, "RF", make_family("paper")), [0.0], [0.0], axes=(0, 0)
        )


def test_figures_are_deterministic_and_complete(tmp_path, scalf, scalf_shown, scalf_study):
    _, shown = scalf_shown
    first = write_figures(tmp_path / "a", scalf, shown, scalf_study)
    second = write_figures(tmp_path / "b", scalf, shown, scalf_study)
    assert [p.name for p in first] == [f"{n}.{k}" for n in FIGURE_NAMES for k in ("png", "svg")]
    for a, b in zip(first, second, strict=True):
        assert a.read_bytes() == b.read_bytes(), a.name
    svg = (tmp_path / "a" / "joint_angles.svg").read_text()
    assert "<dc:date>" not in svg and "Matplotlib v" not in svg  # no date, no version


@pytest.mark.parametrize("name", ["hyq", "solo12"])
def test_figures_of_other_robots(name, request, tmp_path):
    robot = request.getfixturevalue(name)
    pipeline = coarse_pipeline(robot)
    shown = [reference_trajectory(pipeline), optimized_trajectory(pipeline, "paper")]
    study = search_study(pipeline, grid_points=5)
    written = write_figures(tmp_path, robot, shown, study, ("png",))
    assert len(written) == len(FIGURE_NAMES) and all(p.stat().st_size > 10_000 for p in written)


def test_save_figure_refuses_other_formats(tmp_path):
    fig = Figure()
    with pytest.raises(ConfigError, match="png or svg"):
        save_figure(fig, tmp_path / "x.pdf")


def test_cli_figures(tmp_path, capsys):
    gait = tmp_path / "coarse.toml"
    gait.write_text(f"[gait]\nsample_rate_hz = {COARSE_RATE_HZ}\n")
    saved = tmp_path / "opt"
    assert main(["optimize", "--family", "paper", "--gait", str(gait), "--out", str(saved)]) == 0
    capsys.readouterr()
    out = tmp_path / "figs"
    code = main(
        ["figures", "--from", str(saved), "--format", "png", "--grid", "5", "--out", str(out)]
    )
    printed = capsys.readouterr().out
    assert code == 0 and "opt (paper, ipopt)" in printed
    assert sorted(p.name for p in out.iterdir()) == sorted(f"{n}.png" for n in FIGURE_NAMES)
    (tmp_path / "file").write_text("")
    for argv, message in (
        (["--grid", "2"], "--grid must be at least 3"),
        (["--out", str(tmp_path / "file")], "is a file, not a directory"),
        (["--from", str(saved), "--gait", str(gait)], "brings its own gait"),
    ):
        assert main(["figures", *argv]) == 2
        err = capsys.readouterr().err
        assert message in err and len(err.strip().splitlines()) == 1


def test_figures_api_default_trajectories(tmp_path, scalf):
    from scalf_opt.api.presentation import figures

    gait = coarse_pipeline(scalf).gait
    files, shown = figures(tmp_path, robot=scalf, gait=gait, formats=("png",), grid_points=3)
    assert [t.label for t in shown] == ["reference (cubic spline)", "optimum (joint-6, ipopt)"]
    assert all(t.solved for t in shown) and len(files) == len(FIGURE_NAMES)
    with pytest.raises(ConfigError, match="not both"):
        figures(tmp_path, robot=scalf, gait=gait, from_dirs=[tmp_path])


def test_a_stance_over_the_cycles_end_is_drawn_without_a_line_back_across_the_cycle(scalf):
    """Duty 0.6: LF's stance runs from 0.25 s over the cycle's end to 0.05 s of the next."""
    from scalf_opt.energy.pipeline import EnergyPipeline
    from scalf_opt.locomotion.gait import Gait
    from scalf_opt.viz.plotting import cycle_samples

    gait = Gait(duty_cycle=0.6, sample_rate_hz=COARSE_RATE_HZ)
    cycle = EnergyPipeline(scalf, gait, loads="trunk").robot_cycle(make_family("reference"))
    t, grf = cycle_samples(cycle.legs["LF"], "grf")
    assert t.shape[0] == grf.shape[1]
    runs = np.split(t, np.flatnonzero(np.isnan(t)))
    assert all(np.all(np.diff(run[~np.isnan(run)]) >= 0.0) for run in runs)  # never backwards
    assert len(runs) == 3  # the stance's start, its end after the wrap, the swing
    assert 0.0 <= np.nanmin(t) < 1e-6 and np.nanmax(t) <= gait.period_s


def test_energy_bar_labels_are_the_cycle_energies_with_one_precision(scalf_shown):
    """Every bar's label is its leg's cycle energy and the totals are the cycles', all printed with
    the same decimals (``7.340`` beside ``7.408``, not ``7.34``)."""
    _, shown = scalf_shown
    fig = energy_bars_figure(shown)
    texts = [t.get_text() for t in fig.axes[0].texts]
    bars = [t for t in texts if numeric(t)]
    legs = [leg for t in shown for leg in t.cycle.legs.values()]
    assert [float(b) for b in bars] == pytest.approx([leg.energy_j for leg in legs], abs=0.01)
    totals = [t.split(" J")[0] for t in texts if "J per cycle" in t]
    assert [float(t) for t in totals] == pytest.approx([t.cycle.energy_j for t in shown], abs=0.01)
    assert len({len(number.partition(".")[2]) for number in bars + totals}) == 1
    # the energies depend on the load model and the accounting: the title names them
    assert fig.axes[0].get_title().endswith("\nloads 'whole-body', accounting 'paper', 40 Hz")
    close(fig)


@pytest.mark.parametrize("loads", ["whole-body", "trunk"])
def test_the_foot_force_figure_marks_half_the_weight_the_feet_carry(scalf, loads):
    """Two stance feet of a trot carry on average half the weight their load model puts on
    them: the whole robot's under whole-body loads, the trunk's under the paper's. The marked
    line is that, and the cycle's mean stance force (its own computation) agrees."""
    from scalf_opt.energy.loads import stance_loads
    from scalf_opt.locomotion.forces import GRAVITY_M_S2
    from scalf_opt.viz.trajectories import Trajectory

    pipeline = coarse_pipeline(scalf).with_loads(loads)
    cycle = pipeline.robot_cycle(make_family("reference"))
    mass = stance_loads(loads).carried_mass_kg(scalf)
    expected = scalf.total_mass_kg if loads == "whole-body" else scalf.trunk_mass_kg
    assert mass == expected
    fig = foot_force_figure(Trajectory("reference", cycle), mass)
    ax = fig.axes[0]
    (marked,) = [line.get_ydata()[0] for line in ax.lines if line.get_linestyle() == ":"]
    assert marked == pytest.approx(0.5 * mass * GRAVITY_M_S2, rel=1e-12)
    assert cycle.mean_stance_force_n == pytest.approx(marked, rel=0.01)
    assert f"{loads} loads" in ax.get_title()
    close(fig)


def test_the_joint_figures_name_the_energy_model(scalf_shown):
    _, shown = scalf_shown
    fig = joint_figure(shown, "torque")
    assert fig.get_suptitle() == (
        "Joint torques over a cycle\nloads 'whole-body', accounting 'paper', 40 Hz"
    )
    close(fig)
