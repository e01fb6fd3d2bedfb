"""The stance as a free variable: feasible, lower, and the saving split into stance and swing."""

from dataclasses import replace

import numpy as np
import pytest

from scalf_opt.energy.peaks import cycle_violations
from scalf_opt.energy.pipeline import EnergyPipeline
from scalf_opt.errors import GaitError
from scalf_opt.locomotion.forces import balance_matrix
from scalf_opt.locomotion.gait import Gait
from scalf_opt.locomotion.swing.registry import make_family
from scalf_opt.optimize.free_stance import optimize_stance, stance_gait, stance_vector_cm


@pytest.fixture(scope="module")
def result(scalf):
    return optimize_stance(EnergyPipeline(scalf, Gait(), loads="trunk"), make_family("paper"))


def test_the_free_stance_saves_energy_within_every_limit(result, scalf):
    assert result.success
    cycle = result.cycle()
    assert cycle.energy_j < result.nominal_cycle().energy_j < result.reference.energy_j
    best = result.best.run
    physics = {leg: best.pipeline.physics(leg) for leg in cycle.legs}
    assert cycle_violations(cycle, physics) == []
    # the stance search moved something, and the search's total is the cycle's (RF + LH; LF, RH
    # repeat them)
    assert not np.allclose(stance_vector_cm(result.best.gait), stance_vector_cm(Gait()))
    pair = sum(cycle.legs[leg].energy_j for leg in ("RF", "LH"))
    assert result.best.total_j == pytest.approx(pair, rel=1e-9)
    assert cycle.symmetry_error < 1e-12


def test_the_saving_splits_into_stance_and_swing(result):
    split = result.split_j()
    assert split["stance"] + split["swing"] == pytest.approx(split["total"], rel=1e-12)
    assert split["swing_only"] + split["from_freeing_the_stance"] == pytest.approx(
        split["total"], rel=1e-12
    )
    assert split["from_freeing_the_stance"] > 0


def test_stance_variables_round_trip():
    gait = stance_gait(Gait(), np.array([78.0, 3.5, -2.0]))
    assert gait.stance_height_m == pytest.approx(0.78)
    assert gait.stance_x_offset_front_m == pytest.approx(0.035)
    assert gait.stance_x_offset_hind_m == pytest.approx(-0.02)
    np.testing.assert_allclose(stance_vector_cm(gait), [78.0, 3.5, -2.0])


def test_offset_stance_forces_still_balance_the_trunk(scalf):
    gait = replace(Gait(), stance_x_offset_front_m=0.08, stance_x_offset_hind_m=-0.06)
    pipeline = EnergyPipeline(scalf, gait, loads="trunk")
    com = scalf.trunk_com_m
    feet = {}
    for leg in ("RF", "LH"):
        hip = scalf.leg(leg).hip_origin_m - com
        feet[leg] = pipeline.stance_paths[leg][0] + np.array([[hip[0]], [hip[2]]])
    weight = scalf.trunk_mass_kg * 9.81
    forces = pipeline.trunk_stance_forces
    for j in range(forces["RF"].shape[1]):
        a = balance_matrix(np.column_stack([feet["RF"][:, j], feet["LH"][:, j]]))
        f = np.concatenate([forces["RF"][:, j], forces["LH"][:, j]])
        np.testing.assert_allclose(a @ f, [0.0, weight, 0.0], atol=1e-9)
    # the front foot stands 8 cm ahead of its hip at mid-stance
    mid = pipeline.stance_paths["RF"].shape[-1] // 2
    assert pipeline.stance_paths["RF"][0][0, mid] == pytest.approx(0.08)


def test_an_impossible_stance_names_the_offset_fields(scalf):
    pipeline = EnergyPipeline(scalf, replace(Gait(), stance_x_offset_front_m=0.5), loads="trunk")
    with pytest.raises(GaitError, match=r"stance_x_offset_front_m = 0\.5"):
        pipeline.stance("RF")


def test_a_search_s_trial_is_solved_warm_once_and_a_cold_start_with_every_strategy(
    scalf, monkeypatch
):
    # Ipopt held to 3 iterations (a user option every strategy keeps): every solve fails, so
    # the calls show the policy. The first gait has no neighbour: cold, the three strategies in
    # turn. The next starts at a neighbour's optimum: the warm strategy alone, no retry (near a
    # limit the cold strategies took minutes per gait on a search that fails there anyway).
    from scalf_opt.optimize import solve as solve_module
    from scalf_opt.optimize.driver import Settings
    from scalf_opt.optimize.free_stance import GaitTrials
    from scalf_opt.optimize.solvers import IPOPT_ATTEMPTS, IPOPT_WARM_ATTEMPT

    calls = []
    real = solve_module.run_ipopt

    def spy(problem, theta0=None, ipopt_options=None, screen=False):
        calls.append((problem.leg, dict(ipopt_options)))
        return real(problem, theta0, ipopt_options, screen)

    monkeypatch.setattr(solve_module, "run_ipopt", spy)
    pipeline = EnergyPipeline(scalf, Gait(), loads="trunk")
    family = make_family("paper")
    trials = GaitTrials(pipeline, family, Settings(ipopt={"max_iter": 3}))
    cold = trials.evaluate(Gait())
    assert cold.run is not None and not cold.run.success
    assert "swing not solved" in cold.reason
    strategies = [{**a, "max_iter": 3} for a in IPOPT_ATTEMPTS]
    assert [options for leg, options in calls if leg == "RF"] == strategies
    assert [options for leg, options in calls if leg == "LH"] == strategies

    calls.clear()
    trials.warm = {"RF": np.array([5.0, -5.0]), "LH": np.array([-5.0, 5.0])}
    warm = trials.evaluate(replace(Gait(), stance_height_m=0.74))
    assert warm.run is not None and not warm.run.success
    assert sorted(leg for leg, _ in calls) == ["LH", "RF"]
    assert all(options == {**IPOPT_WARM_ATTEMPT, "max_iter": 3} for _, options in calls)


def _spy_on_solves(monkeypatch):
    """The legs of every one-leg and pair solve of the driver, in order."""
    from scalf_opt.optimize import solve as solve_module

    calls = []
    one, pair = solve_module.run_ipopt, solve_module.run_ipopt_pair

    def spy_one(problem, theta0=None, ipopt_options=None, screen=False):
        calls.append(problem.leg)
        return one(problem, theta0, ipopt_options, screen)

    def spy_pair(problem, thetas0, ipopt_options=None):
        calls.append("+".join(problem.legs))
        return pair(problem, thetas0, ipopt_options)

    monkeypatch.setattr(solve_module, "run_ipopt", spy_one)
    monkeypatch.setattr(solve_module, "run_ipopt_pair", spy_pair)
    return calls


def test_an_uncoupled_leg_keeps_its_optimum_when_only_the_other_pair_moves(scalf, monkeypatch):
    # under trunk loads RF's swing problem does not depend on the hind feet's offset: a trial
    # that moves only them solves LH alone and keeps RF's optimum of the gait it was found at
    from scalf_opt.optimize.driver import Settings, optimize_swings
    from scalf_opt.optimize.free_stance import GaitTrials

    pipeline = EnergyPipeline(scalf, Gait(), loads="trunk")
    family = make_family("paper")
    trials = GaitTrials(pipeline, family, Settings(), keep_uncoupled=True)
    first = trials.evaluate(Gait())
    calls = _spy_on_solves(monkeypatch)
    hind = trials.evaluate(replace(Gait(), stance_x_offset_hind_m=-0.01))
    assert calls == ["LH"]
    assert hind.run.legs["RF"] is first.run.legs["RF"]
    assert hind.run.pipeline.gait.stance_x_offset_hind_m == -0.01
    # the pair's total is that of its own gait with both optima: the same as evaluating them
    # there from scratch (the energy does not depend on where the optimum was found)
    cycle = hind.run.pipeline.robot_cycle(family, hind.run.thetas, ("RF", "LH"))
    assert hind.total_j == pytest.approx(cycle.energy_j, rel=1e-12)
    # a gait whose two leg problems were both posed before solves nothing: RF from the first
    # gait, LH from the second (z0 and the front offset the first gait's)
    calls.clear()
    front = trials.evaluate(replace(Gait(), stance_x_offset_front_m=0.01))
    assert calls == ["RF"]
    calls.clear()
    both = trials.evaluate(
        replace(Gait(), stance_x_offset_front_m=0.01, stance_x_offset_hind_m=-0.01)
    )
    assert calls == []
    assert both.run.legs["RF"] is front.run.legs["RF"]
    assert both.run.legs["LH"] is hind.run.legs["LH"]
    assert both.run.success and both.run.wall_time_s == 0.0
    # and it is the same pair a fresh optimization finds at that gait
    fresh = optimize_swings(pipeline.with_gait(both.gait), ("RF", "LH"), family, Settings())
    for leg in ("RF", "LH"):
        assert both.run.legs[leg].best.swing_energy_j == pytest.approx(
            fresh.legs[leg].best.swing_energy_j, rel=1e-6
        )


def test_a_kept_optimum_at_another_rate_is_solved_again(scalf, monkeypatch):
    # the pair reports one rate: when the new leg's optimization converges at another rate
    # than the kept leg's, both are solved at the new gait
    from scalf_opt.optimize.driver import Settings
    from scalf_opt.optimize.free_stance import GaitTrials

    pipeline = EnergyPipeline(scalf, Gait(), loads="trunk")
    trials = GaitTrials(pipeline, make_family("paper"), Settings(), keep_uncoupled=True)
    first = trials.evaluate(Gait())
    key = GaitTrials.leg_key(Gait(), "RF")
    kept = trials.leg_runs[key]
    trials.leg_runs[key] = replace(kept, rates_hz=[kept.rate_hz / 2, *kept.rates_hz])
    calls = _spy_on_solves(monkeypatch)
    moved = trials.evaluate(replace(Gait(), stance_x_offset_hind_m=-0.01))
    assert calls == ["LH", "RF", "LH"]
    assert moved.run.legs["RF"] is not first.run.legs["RF"]
    assert moved.run.rates_hz == first.run.rates_hz


def test_coupled_legs_are_solved_together_at_every_trial(scalf, monkeypatch):
    # under whole-body loads the front leg's objective holds the pair's stance, which the hind
    # swing loads: nothing is kept
    from scalf_opt.optimize.driver import Settings
    from scalf_opt.optimize.free_stance import GaitTrials

    trials = GaitTrials(
        EnergyPipeline(scalf, Gait()), make_family("paper"), Settings(), keep_uncoupled=True
    )
    trials.evaluate(Gait())
    calls = _spy_on_solves(monkeypatch)
    trials.evaluate(replace(Gait(), stance_x_offset_hind_m=-0.01))
    assert calls == ["RF+LH"]
    assert trials.leg_runs == {}


def test_the_gait_search_solves_both_legs_at_every_trial(scalf, monkeypatch):
    # its trials keep nothing (a kept optimum would change the local search's path): the same
    # move under trunk loads solves both legs again
    from scalf_opt.optimize.driver import Settings
    from scalf_opt.optimize.free_stance import GaitTrials

    pipeline = EnergyPipeline(scalf, Gait(), loads="trunk")
    trials = GaitTrials(pipeline, make_family("paper"), Settings(), stance_at_swing_rate=True)
    trials.evaluate(Gait())
    calls = _spy_on_solves(monkeypatch)
    trials.evaluate(replace(Gait(), stance_x_offset_hind_m=-0.01))
    assert sorted(calls) == ["LH", "RF"]
    assert trials.leg_runs == {}


def test_a_trial_runs_no_extra_start_and_the_answer_every_start(scalf, monkeypatch):
    # --starts N: a search's trial is one warm solve per leg; the gait the search settles on is
    # optimized again from every start, its trial's optimum the first
    from scalf_opt.optimize.driver import Settings
    from scalf_opt.optimize.free_stance import GaitTrials, pair_energy_j

    pipeline = EnergyPipeline(scalf, Gait(), loads="trunk")
    family = make_family("joint-2")
    trials = GaitTrials(pipeline, family, Settings(starts=3))
    trials.evaluate(Gait())  # cold: no neighbour yet, every start
    calls = _spy_on_solves(monkeypatch)
    trial = trials.evaluate(replace(Gait(), stance_height_m=0.76))
    assert sorted(calls) == ["LH", "RF"]
    assert all(len(r.starts) == 1 for r in trial.run.legs.values())
    calls.clear()
    answer = trials.from_every_start(trial)
    assert sorted(calls) == ["LH", "LH", "LH", "RF", "RF", "RF"]
    for leg, result in answer.run.legs.items():
        assert result.starts[0].label == "given" and len(result.starts) == 3
        assert result.best.objective_j <= trial.run.legs[leg].best.objective_j + 1e-9
    total, why = pair_energy_j(
        answer.run.pipeline.with_gait(answer.gait), family, answer.run, ("RF", "LH")
    )
    assert why is None and answer.total_j == pytest.approx(total, rel=1e-12)
    # one start asked for: the trial's answer stands
    single = GaitTrials(pipeline, family, Settings())
    assert single.from_every_start(trial) is trial


def test_the_free_stance_reports_every_start_of_its_answer(scalf):
    from scalf_opt.optimize.driver import Settings

    pipeline = EnergyPipeline(scalf, Gait(), loads="trunk")
    found = optimize_stance(pipeline, make_family("paper"), Settings(starts=2))
    assert found.success
    for result in found.best.run.legs.values():
        assert result.starts[0].label == "given" and len(result.starts) == 2
