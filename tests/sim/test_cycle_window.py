"""``--cycles N`` measures ``N - 1`` cycles (the first is the start-up), whatever the rounding.

A gait period need not be a whole number of simulation steps: Go1's default trot lasts
T = 0.352755 s, 705.5 steps of 0.5 ms, so two cycles are 1,411.02 steps. The 3-D referee ran
``round(2 T / dt) = 1,411`` steps and measured the whole cycles after the first that those held,
``floor(1,411 dt / T) - 1 = 0``: ``--cycles 2`` printed a NaN verdict. The run's length and the
measured window now count the steps the same way (the steps that start within the cycles); the
sagittal referee rounds both the same way (``round``) and is checked here too.
"""

from types import SimpleNamespace

import numpy as np
import pytest

from scalf_opt.sim.metrics import averaged_steps
from scalf_opt.sim.whole_body_metrics import measured_window
from scalf_opt.sim.whole_body_run import cycles_in_steps, steps_in_cycles

GO1_PERIOD_S = 0.35275521196984827
"""Go1's default trot period [s] (``default_gait_for``): 705.51 steps of 0.5 ms."""

PERIODS_AND_STEPS = [
    (GO1_PERIOD_S, 5e-4),  # two cycles a hair more than 1,411 steps
    (0.6, 5e-4),  # a whole number of steps (SCalf's)
    (0.3, 1e-4),  # a whole number of steps, which the division misses by a rounding error
    (0.70045, 5e-4),  # half a step over
    (0.70075, 5e-4),  # 1.5 steps over: round() goes up
    (0.4311702567967362, 7.49e-4),  # a free period and another step
    *((float(t), 5e-4) for t in np.random.default_rng(0).uniform(0.2, 1.2, 20)),
]


def _record(steps: int, timestep_s: float) -> SimpleNamespace:
    """A record's timing alone: ``steps`` steps of ``timestep_s`` from time 0."""
    return SimpleNamespace(t_s=np.arange(steps) * timestep_s, timestep_s=timestep_s)


@pytest.mark.parametrize(("period_s", "dt"), PERIODS_AND_STEPS)
def test_a_run_of_n_cycles_measures_n_minus_one(period_s, dt):
    for cycles in range(2, 13):
        steps = steps_in_cycles(cycles, period_s, dt)
        # the steps that start within the cycles, no more
        assert (steps - 1) * dt < cycles * period_s <= steps * dt + 1e-12
        assert cycles_in_steps(steps, period_s, dt) == cycles
        window, whole = measured_window(_record(steps, dt), period_s)
        assert whole == cycles - 1
        t = np.arange(steps) * dt
        # from the first step of the second cycle to the run's last
        assert t[window.start] >= period_s - 1e-12 > t[window.start - 1]
        assert window.stop == steps
        assert abs((window.stop - window.start) * dt - whole * period_s) < dt


def test_go1s_two_cycles_measure_one():
    """The case reported: ``simulate --from DIR --cycles 2`` of a Go1 cycle measured none."""
    assert round(2 * GO1_PERIOD_S / 5e-4) == 1411  # what the run took
    assert steps_in_cycles(2, GO1_PERIOD_S, 5e-4) == 1412
    window, whole = measured_window(_record(1412, 5e-4), GO1_PERIOD_S)
    assert whole == 1 and window == slice(706, 1412)


@pytest.mark.parametrize(("period_s", "dt"), PERIODS_AND_STEPS)
def test_a_run_cut_short_measures_the_whole_cycles_it_holds(period_s, dt):
    """A fall or a divergence ends the record early: the cycles it holds whole are measured."""
    full = steps_in_cycles(4, period_s, dt)
    for steps in range(full - 3, full):  # the fourth cycle a few steps short
        assert measured_window(_record(steps, dt), period_s)[1] == 2
    for steps in (0, 1, steps_in_cycles(1, period_s, dt), steps_in_cycles(2, period_s, dt) - 1):
        window, whole = measured_window(_record(steps, dt), period_s)
        assert whole == 0 and window.stop == window.start  # nothing measured


@pytest.mark.parametrize(("period_s", "dt"), PERIODS_AND_STEPS)
def test_the_sagittal_referee_counts_its_cycles_as_it_runs_them(period_s, dt):
    """The sagittal run takes ``round(N T / dt)`` steps; its metrics average ``N - 1`` cycles."""
    for cycles in range(2, 13):
        steps = round(cycles * period_s / dt)  # sim.run.simulate's length
        measured, averaged = averaged_steps(_record(steps, dt), period_s)
        assert averaged == cycles - 1
        # the steps after the start-up, within a step of the cycles they stand for (the
        # window's two ends rounded each to the nearest step)
        assert abs(measured.sum() * dt - averaged * period_s) <= dt + 1e-12


def test_go1s_two_cycles_in_the_3d_referee_measure_one():
    """The whole 3-D referee on Go1's default trot (its sagittal plan), two cycles: one measured.

    Before the fix the run stopped a step short of the second cycle's end and measured none: the
    energies NaN, the goal not met.
    """
    pytest.importorskip("mujoco")
    from scalf_opt.api import simulate_3d

    result = simulate_3d("go1", cycles=2, ensemble=False)
    data, record = result.data, result.record
    assert data["gait"]["period_s"] == pytest.approx(GO1_PERIOD_S, abs=1e-12)
    assert record.t_s.size == 1412 and data["fell_at_s"] is None
    assert data["cycles_measured"] == 1
    for leg, energy in data["joint_energy_per_cycle_j"].items():
        assert np.isfinite(energy["simulated"]) and energy["simulated"] > 0, leg
