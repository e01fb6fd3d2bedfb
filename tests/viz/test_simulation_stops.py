"""``simulation.png`` marks where a run stopped: a fall and a divergence of MuJoCo's integration.

Each is a line across every panel over time at the instant, its words (the warning MuJoCo raised,
for a divergence) beside it on the first panel. The records are synthetic (no MuJoCo): a sagittal
record NaN from the divergence on, as the sagittal referee leaves it, and 3-D records cut short,
down to one that stopped at its first step.
"""

import numpy as np
import pytest

from scalf_opt.types import LEG_NAMES
from scalf_opt.viz.plotting import DIVERGENCE_COLOR, FALL_COLOR, close, save_figure
from scalf_opt.viz.simulation_figure import simulation_figure
from scalf_opt.viz.whole_body_sim_figure import cycle_simulation_figure

DT = 5e-4
WORDS = "bad accelerations, MuJoCo's BADQACC"


def lines_at(ax, at_s: float, color: str) -> list:
    """The vertical lines of ``ax`` at ``at_s`` [s] in ``color``."""
    from matplotlib.colors import to_rgba

    return [
        line
        for line in ax.lines
        if np.allclose(np.asarray(line.get_xdata(), dtype=float), at_s)
        and to_rgba(line.get_color()) == to_rgba(color)
    ]


def assert_marked(fig, axes, at_s: float, color: str, words: str) -> None:
    """A line at ``at_s`` on each of ``axes``, and ``words`` written on the first."""
    for ax in axes:
        assert len(lines_at(ax, at_s, color)) == 1, ax.get_ylabel()
    texts = [t.get_text() for t in axes[0].texts]
    assert any(words in t for t in texts), texts
    fig.canvas.draw()  # draws, NaN samples and all
    x0, x1 = axes[0].get_xlim()
    assert x0 <= at_s < x1  # inside the axis, clear of its right edge (where a 3-D record ends)


def _sagittal(n: int, diverged: int | None, energy_nan: bool):
    t = np.arange(n) * DT
    z, pitch = 0.75 + 1e-3 * np.sin(t), 1e-3 * np.cos(t)
    force = {leg: 500 + 100 * np.sin(t + i) for i, leg in enumerate(LEG_NAMES)}
    if diverged is not None:  # the sagittal referee's record: NaN from the divergence on
        for values in (z, pitch, *force.values()):
            values[diverged:] = np.nan
    simulated = np.nan if energy_nan else 11.0
    phases = {
        leg: {p: {"model": 10.0, "simulated": simulated} for p in ("stance", "swing")}
        for leg in LEG_NAMES
    }
    return t, z, pitch, force, phases


def test_the_sagittal_figure_marks_a_divergence_and_draws_past_its_nans(tmp_path):
    n, at = 2400, 1500
    t, z, pitch, force, phases = _sagittal(n, at, energy_nan=True)
    fig = simulation_figure(
        t,
        z,
        0.75,
        pitch,
        force,
        550.0,
        "a run that diverged",
        startup_s=0.6,
        phase_energy_j=phases,
        energy_goal=0.05,
        diverged_at_s=float(t[at]),
        divergence=WORDS,
    )
    try:
        over_time = fig.axes[:3]
        assert_marked(fig, over_time, float(t[at]), DIVERGENCE_COLOR, "BADQACC")
        assert any("MuJoCo diverged at 0.750 s" in t.get_text() for t in over_time[0].texts)
        # the energies, NaN (nothing measured), are said to be so, not drawn as "+nan %"
        energy = fig.axes[-1]
        assert [t.get_text() for t in energy.texts] == ["not\nmeasured"] * 4
        assert np.isfinite(energy.get_ylim()).all() and energy.get_ylim()[1] > 10.0
        assert save_figure(fig, tmp_path / "simulation.png").read_bytes()[:4] == b"\x89PNG"
    finally:
        close(fig)


def test_the_sagittal_figure_marks_a_fall_and_a_divergence_apart():
    t, z, pitch, force, phases = _sagittal(2400, 1500, energy_nan=False)
    fig = simulation_figure(
        t,
        z,
        0.75,
        pitch,
        force,
        550.0,
        "a run",
        startup_s=0.6,
        phase_energy_j=phases,
        fell_at_s=0.5,
        diverged_at_s=0.75,
        divergence=WORDS,
    )
    try:
        assert_marked(fig, fig.axes[:3], 0.5, FALL_COLOR, "fell at 0.500 s")
        assert_marked(fig, fig.axes[:3], 0.75, DIVERGENCE_COLOR, "BADQACC")
        assert [t.get_text() for t in fig.axes[-1].texts] == ["+10.0 %"] * 4
    finally:
        close(fig)


def _whole_body(n: int):
    t = np.arange(n) * DT
    q = np.zeros((19, n))
    q[2], q[6] = 0.26, 1.0  # trunk height, the quaternion's w
    q_plan = q.copy()
    force = np.zeros((3, 4, n))
    force[2] = 60.0
    return t, q, q_plan, force, force.copy()


@pytest.mark.parametrize("steps", [1000, 1, 0])
def test_the_3d_figure_marks_a_divergence_where_the_record_ends(steps):
    """The 3-D record ends before the step MuJoCo flagged: the line is a step after its last
    sample, inside the axis; a run that diverged at its first step has no sample at all."""
    at = steps * DT
    fig = cycle_simulation_figure(
        *_whole_body(steps),
        fell_at_s=None,
        period_s=0.35,
        title="a 3-D run that diverged",
        diverged_at_s=at,
        divergence="torques NaN or huge, MuJoCo's BADCTRL",
    )
    try:
        assert_marked(fig, fig.axes, at, DIVERGENCE_COLOR, "BADCTRL")
        assert "purple: MuJoCo diverged" in fig.axes[-1].get_xlabel()
    finally:
        close(fig)


def test_the_3d_figure_marks_a_fall_as_before():
    fig = cycle_simulation_figure(
        *_whole_body(800), fell_at_s=800 * DT, period_s=0.35, title="a 3-D run that fell"
    )
    try:
        assert_marked(fig, fig.axes, 800 * DT, FALL_COLOR, "fell at 0.400 s")
        assert "red: the fall" in fig.axes[-1].get_xlabel()
        assert "purple" not in fig.axes[-1].get_xlabel()
        assert not lines_at(fig.axes[0], 800 * DT, DIVERGENCE_COLOR)
    finally:
        close(fig)


def test_a_run_that_did_not_stop_has_no_mark():
    fig = cycle_simulation_figure(
        *_whole_body(800), fell_at_s=None, period_s=0.35, title="a 3-D run"
    )
    try:
        assert not fig.axes[0].texts
        assert fig.axes[0].get_xlim() == (0.0, 799 * DT)
    finally:
        close(fig)
