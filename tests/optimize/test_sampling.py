"""Every reported optimum is a converged energy: the optimization never exploits the sampling.

The check of the issue: the optimum's swing energy at the optimization's rate and at ten times
that rate agree within 0.5 %. The energy at ten times the rate is computed here independently
of the optimizer: a fresh pipeline at that rate evaluates the swing through the reports' own
per-phase evaluation (not the optimizer's compiled kernel), and the constraints are checked on
those fine samples too.

The fast suite checks a representative subset on both robots (joint and foot space, the paper
family, the default family, a family that needs a finer rate than its first); the test marked
``slow`` checks every family the command line offers, on SCalf and HyQ, RF and LH.
"""

import math

import numpy as np
import pytest

from scalf_opt.energy.limits import violations
from scalf_opt.energy.margins import NO_MARGINS
from scalf_opt.energy.pipeline import EnergyPipeline
from scalf_opt.locomotion.gait import Gait
from scalf_opt.locomotion.swing.names import MAX_ORDER, MIN_ORDER
from scalf_opt.locomotion.swing.registry import make_family
from scalf_opt.optimize.driver import FAILED_CHECK, Check, optimize_swings
from scalf_opt.optimize.problem import SwingProblem
from scalf_opt.optimize.sampling import (
    BETWEEN_SAMPLES_RTOL,
    CHECK_FACTOR,
    SAMPLING_TOLERANCE,
    initial_rate_hz,
    with_rate,
)
from scalf_opt.optimize.solve import IpoptDetails, SwingOptimum

OFFERED = [
    "paper",
    *(f"joint-{n}" for n in range(MIN_ORDER, MAX_ORDER + 1)),
    *(f"fourier-{n}" for n in range(MIN_ORDER, MAX_ORDER + 1)),
]
"""Every family ``scalf-opt optimize --family`` accepts."""

# Between samples the foot may dip below the ground by the curvature of the path over one
# interval: on SCalf a few micrometres, on HyQ at its standing height (0.509 m) up to 53 um just
# after lift-off; the fine check allows 0.1 mm, the position sensor's accuracy [m].
FINE_GROUND_TOLERANCE_M = 1e-4


def check_converged(robot, family_name, legs=("RF", "LH"), loads="trunk"):
    gait = Gait(stance_height_m=robot.nominal_stance_height_m)
    pipeline = EnergyPipeline(robot, gait, loads=loads)
    family = make_family(family_name)
    run = optimize_swings(pipeline, legs, family)
    assert run.success, {leg: r.best.status for leg, r in run.legs.items()}
    assert run.rate_hz >= initial_rate_hz(pipeline.gait, family)
    fine = pipeline.with_gait(with_rate(pipeline.gait, CHECK_FACTOR * run.rate_hz))
    for leg, result in run.legs.items():
        swing = fine.swing(leg, family, result.best.theta)
        others = None
        if pipeline.load_model.couples_legs:  # the objective adds the pair's stance
            others = {o: run.thetas[o] for o in legs if o != leg}
        energy = SwingProblem(fine, leg, family, others).energy_j(result.best.theta)
        assert abs(result.best.objective_j - energy) <= SAMPLING_TOLERANCE * energy
        assert energy == pytest.approx(result.check_energy_j, rel=1e-9)
        # what is printed of it converged too: its swing energy alone, and the stance part
        swing_j = float(swing.energy_j.sum())
        assert abs(result.best.swing_energy_j - swing_j) <= SAMPLING_TOLERANCE * swing_j
        assert result.check_swing_energy_j == pytest.approx(swing_j, rel=1e-9)
        stance, fine_stance = result.best.objective_j - result.best.swing_energy_j, energy - swing_j
        assert abs(stance - fine_stance) <= SAMPLING_TOLERANCE * max(abs(fine_stance), 1e-12)
        # the optimum is feasible on the fine samples too: every limit, the ground, clearance
        problem = SwingProblem(fine, leg, family)
        for v in violations(swing.values, problem.bounds):
            scale = max(abs(v.bound.lower), abs(v.bound.upper))
            assert v.excess <= BETWEEN_SAMPLES_RTOL * scale, v
        at_rate = run.pipeline.swing(leg, family, result.best.theta)
        assert violations(at_rate.values, SwingProblem(run.pipeline, leg, family).bounds) == []
        foot_z = swing.values["foot"][1]
        assert foot_z.min() >= problem.ground_z_m - FINE_GROUND_TOLERANCE_M
        assert foot_z[problem.mid_index] >= problem.clearance_z_m - 1e-9
    return run


@pytest.mark.parametrize("name", ["paper", "joint-6", "joint-8", "fourier-4"])
def test_optima_are_converged_energies_on_scalf(scalf, name):
    run = check_converged(scalf, name)
    if name == "joint-8":  # 25 samples per period (400 Hz) is not enough for it: refined
        # (to 800 Hz before the lift profile; its sharper lift-off needs 1600 Hz)
        assert run.rates_hz == [400.0, 800.0, 1600.0]


def test_whole_body_optima_are_converged_energies_on_scalf(scalf):
    check_converged(scalf, "joint-6", loads="whole-body")


@pytest.mark.parametrize("name", ["joint-6", "fourier-6"])
def test_optima_are_converged_energies_on_hyq(hyq, name):
    check_converged(hyq, name)


def test_the_first_rate_resolves_the_highest_harmonic():
    gait = Gait()
    assert initial_rate_hz(gait, make_family("paper")) == 200.0  # the gait's rate is finer
    # joint-12: cos(12 pi s) over a 0.25 s swing is 24 Hz; 25 samples per period: 600 Hz
    assert initial_rate_hz(gait, make_family("joint-12")) == pytest.approx(600.0)
    assert initial_rate_hz(Gait(sample_rate_hz=1000), make_family("joint-12")) == 1000.0


@pytest.mark.parametrize(("name", "sign"), [("joint-6", 1), ("joint-9", -1)])
def test_a_coarse_grid_would_be_exploited(scalf, name, sign):
    # why the refinement exists: an optimum at the gait's 200 Hz is not its energy (measured:
    # joint-6 1.7 % above its energy at 2000 Hz, joint-9 6.1 % below; joint-8's lands 0.3 %
    # above or 2.1 % below depending on the BLAS kernels, so it is not the example)
    from scalf_opt.optimize.solve import run_ipopt

    pipeline = EnergyPipeline(scalf, Gait(), loads="trunk")
    family = make_family(name)
    # at the limits themselves (no margins), where it was measured
    optimum = run_ipopt(SwingProblem(pipeline, "RF", family, margins=NO_MARGINS))
    fine = pipeline.with_gait(with_rate(pipeline.gait, 2000.0))
    true_energy = SwingProblem(fine, "RF", family, margins=NO_MARGINS).energy_j(optimum.theta)
    assert sign * (optimum.swing_energy_j / true_energy - 1) > 0.01


ON_HYQ = [
    "paper",
    *(f"joint-{n}" for n in range(MIN_ORDER, 11)),
    f"fourier-{MIN_ORDER}",
    "fourier-10",
]
"""The families also checked on HyQ: SCalf checks every offered family; on HyQ the other orders
(joint-11 and -12, the Fourier ones between) took five of the suite's fourteen minutes
(measured on two cores) and run the same code on the same robot."""


@pytest.mark.slow
@pytest.mark.parametrize(
    ("robot_name", "name"), [("scalf", n) for n in OFFERED] + [("hyq", n) for n in ON_HYQ]
)
def test_every_offered_family_solves_with_converged_energies(request, robot_name, name):
    check_converged(request.getfixturevalue(robot_name), name)


def test_offered_families_are_what_the_command_line_accepts():
    from scalf_opt.errors import ConfigError

    for name in OFFERED:
        assert make_family(name).n_params > 0
    for bad in (f"joint-{MIN_ORDER - 1}", f"fourier-{MAX_ORDER + 1}", "joint-x"):
        with pytest.raises(ConfigError):
            make_family(bad)


def test_an_optimum_crossing_a_limit_between_samples_is_refined(hyq):
    """HyQ's joint-7 optimum at 350 Hz rides its hip cylinder's pull limit and crosses it between
    samples by more than 1 %: the rate is doubled although the energy had converged."""
    from scalf_opt.optimize.solve import run_ipopt

    run = check_converged(hyq, "joint-7", legs=("LH",))  # <= 1 % on the fine samples
    assert run.rates_hz == [350.0, 700.0]
    gait = Gait(stance_height_m=hyq.nominal_stance_height_m, sample_rate_hz=350.0)
    family = make_family("joint-7")
    coarse = run_ipopt(SwingProblem(EnergyPipeline(hyq, gait, loads="trunk"), "LH", family))
    fine = EnergyPipeline(hyq, with_rate(gait, 3500.0), loads="trunk")
    energy, share = SwingProblem(fine, "LH", family).energy_and_bound_excess(coarse.theta)
    assert share > BETWEEN_SAMPLES_RTOL
    # the same share from the reports' own evaluation of those samples
    swing = fine.swing("LH", family, coarse.theta)
    worst = max(
        v.excess / max(abs(x) for x in (v.bound.lower, v.bound.upper) if abs(x) < float("inf"))
        for v in violations(swing.values, SwingProblem(fine, "LH", family).bounds)
    )
    assert share == pytest.approx(worst, rel=1e-9)
    assert energy == pytest.approx(float(swing.energy_j.sum()), rel=1e-9)


def _optimum(swing_j: float, objective_j: float) -> SwingOptimum:
    return SwingOptimum(
        "RF", "joint-6", "ipopt", np.zeros(1), ["a"], "deg", swing_j, True, "", 1, 0.0,
        IpoptDetails({}), objective_j,
    )  # fmt: skip


def test_the_check_asks_every_printed_energy_to_agree():
    # a whole-body objective 0.2 % off whose swing is 1.1 % off (the joint-12 case of the issue)
    optimum = _optimum(14.205, 139.086)
    check = Check(139.322, 14.364)
    assert abs(optimum.objective_j / check.objective_j - 1) < SAMPLING_TOLERANCE
    assert check.error(optimum) == pytest.approx(abs(14.205 / 14.364 - 1), rel=1e-12)
    # the stance part alone off: the swing and the objective within, the stance not
    stance_off = Check(100.0 + 10.0 * (1 + 2 * SAMPLING_TOLERANCE), 100.0)
    assert abs(110.0 / stance_off.objective_j - 1) < SAMPLING_TOLERANCE
    assert stance_off.error(_optimum(100.0, 110.0)) == pytest.approx(
        1 - 1 / (1 + 2 * SAMPLING_TOLERANCE), rel=1e-9
    )
    # under trunk loads the objective is the swing energy: one number, no stance part
    assert Check(10.01, 10.01).error(_optimum(10.0, 10.0)) == pytest.approx(0.01 / 10.01, rel=1e-9)
    assert math.isinf(FAILED_CHECK.error(_optimum(10.0, 10.0)))
    assert math.isinf(Check(10.0, 10.0).error(_optimum(math.inf, math.inf)))
