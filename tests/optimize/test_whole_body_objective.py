"""Under whole-body loads every optimizer minimizes what the evaluator reports.

A leg's objective is its swing energy plus its diagonal pair's stance energy, which its twin's
swing loads. Here it is compared with the pipeline's own cycle (the numbers every report
prints), Ipopt's answer with the pattern search's, and the free stance's total with the cycle.
"""

import numpy as np
import pytest

from scalf_opt.api.gaits import read_gait
from scalf_opt.energy.margins import NO_LIFT_PROFILE, LimitMargins
from scalf_opt.energy.pipeline import EnergyPipeline
from scalf_opt.locomotion.gait import Gait
from scalf_opt.locomotion.swing.registry import make_family
from scalf_opt.optimize import driver, sampling
from scalf_opt.optimize.driver import Settings, optimize_swings
from scalf_opt.optimize.free_stance import pair_energy_j
from scalf_opt.optimize.problem import PairProblem, SwingProblem
from scalf_opt.optimize.solvers import SolverOptions, solver
from scalf_opt.viz.optimization_report import optimization_report

RTOL = 1e-10  # the same formulas through two code paths: round-off only


@pytest.mark.parametrize("duty", [0.5, 0.6])  # 0.6: grids that do not line up, four feet
@pytest.mark.parametrize("family", ["paper", "joint-4", "fourier-3"])
def test_the_objective_is_the_pairs_cycle_energy_up_to_the_partners_swing(scalf, family, duty):
    swing_family = make_family(family)
    pipeline = EnergyPipeline(scalf, Gait(duty_cycle=duty), loads="whole-body")
    rng = np.random.default_rng(4)
    theta, partner = (rng.normal(0.0, 1.0, swing_family.n_params) for _ in range(2))
    problem = SwingProblem(pipeline, "RF", swing_family, {"LH": partner})
    cycle = pipeline.robot_cycle(swing_family, {"RF": theta, "LH": partner}, ("RF", "LH"))
    expected = cycle.legs["RF"].swing_energy_j + sum(
        cycle.legs[leg].stance_energy_j for leg in ("RF", "LH")
    )
    assert problem.energy_j(theta) == pytest.approx(expected, rel=RTOL)
    assert problem.swing_energy_j(theta) == pytest.approx(cycle.legs["RF"].swing_energy_j, rel=RTOL)


def test_under_trunk_loads_the_objective_is_the_swing_alone(scalf):
    family = make_family("paper")
    problem = SwingProblem(
        EnergyPipeline(scalf, Gait(), loads="trunk"), "RF", family, {"LH": np.ones(2)}
    )
    theta = np.array([1.0, -5.0])
    assert problem.couplings == ()
    assert problem.energy_j(theta) == problem.swing_energy_j(theta)


def test_ipopt_and_the_pattern_search_agree_on_the_coupled_objective(scalf):
    family = make_family("paper")
    pipeline = EnergyPipeline(scalf, Gait(), loads="whole-body")
    problem = SwingProblem(pipeline, "RF", family, {"LH": np.array([2.0, 11.0])})
    options = SolverOptions(Settings().pattern, None)
    nlp = solver("ipopt").solve(problem, np.zeros(2), options)
    search = solver("pattern").solve(problem, np.zeros(2), options)
    assert nlp.success and search.success
    assert nlp.objective_j == pytest.approx(problem.energy_j(nlp.theta), rel=RTOL)
    # the pattern search stops at precision 0.1 deg: within 0.1 % above Ipopt's optimum
    assert nlp.objective_j <= search.objective_j * (1 + 1e-9)
    assert search.objective_j <= nlp.objective_j * 1.001
    # the whole-body optimum differs from the trunk-only one: the swing pays for its loads
    trunk = SwingProblem(pipeline.with_loads("trunk"), "RF", family)
    trunk_nlp = solver("ipopt").solve(trunk, np.zeros(2), options)
    assert np.abs(trunk_nlp.theta - nlp.theta).max() > 0.1
    assert problem.energy_j(trunk_nlp.theta) > nlp.objective_j


def test_the_driver_reports_cycles_the_evaluator_reproduces(scalf):
    family = make_family("paper")
    pipeline = EnergyPipeline(scalf, Gait(), loads="whole-body")
    run = optimize_swings(pipeline, ("RF", "LH"), family)
    assert run.success
    cycle = run.cycle()
    thetas = run.thetas
    rf = SwingProblem(run.pipeline, "RF", family, {"LH": thetas["LH"]})
    assert rf.energy_j(thetas["RF"]) == pytest.approx(
        cycle.legs["RF"].swing_energy_j
        + cycle.legs["RF"].stance_energy_j
        + cycle.legs["LH"].stance_energy_j,
        rel=RTOL,
    )
    total, reason = pair_energy_j(run.pipeline, family, run, ("RF", "LH"))
    assert reason is None
    assert total == pytest.approx(cycle.legs["RF"].energy_j + cycle.legs["LH"].energy_j, rel=RTOL)
    # Ipopt solved the pair as one problem; neither leg gains by moving alone at its answer
    assert run.solved_together and run.rounds == 1
    for leg, other in (("RF", "LH"), ("LH", "RF")):
        problem = SwingProblem(run.pipeline, leg, family, {other: thetas[other]})
        again = solver("ipopt").solve(problem, thetas[leg], SolverOptions(Settings().pattern, None))
        assert again.objective_j >= problem.energy_j(thetas[leg]) * (1 - 1e-5)
    assert "both solved as one problem" in optimization_report(run)


@pytest.mark.parametrize("family", ["paper", "joint-4"])
def test_the_pairs_stance_term_is_the_evaluators_stance_of_both_swings(scalf, family):
    # one coupling over both legs (both twins' wrenches added) against the pipeline's own cycle
    # (the whole robot's wrench distributed over the stance feet) and against the one-leg
    # coupling with the other leg fixed
    swing_family = make_family(family)
    pipeline = EnergyPipeline(scalf, Gait(duty_cycle=0.6), loads="whole-body")
    rng = np.random.default_rng(7)
    thetas = {leg: rng.normal(0.0, 1.0, swing_family.n_params) for leg in ("RF", "LH")}
    pair = PairProblem(pipeline, ("RF", "LH"), swing_family)
    stance = pair.stance_energy_j((thetas["RF"], thetas["LH"]))
    cycle = pipeline.robot_cycle(swing_family, thetas, ("RF", "LH"))
    assert stance == pytest.approx(
        cycle.legs["RF"].stance_energy_j + cycle.legs["LH"].stance_energy_j, rel=RTOL
    )
    alone = SwingProblem(pipeline, "LH", swing_family, {"RF": thetas["RF"]})
    assert alone.stance_energy_j(thetas["LH"]) == pytest.approx(stance, rel=RTOL)
    assert all(p.couplings == () for p in pair.problems)  # the pair owns the stance term


def test_the_pair_solved_as_one_problem_is_no_worse_than_the_legs_in_turn(scalf):
    family = make_family("joint-4")
    pipeline = EnergyPipeline(scalf, Gait(), loads="whole-body")
    together = optimize_swings(pipeline, ("RF", "LH"), family)
    in_turn = optimize_swings(pipeline, ("RF", "LH"), family, Settings(pair_together=False))
    assert together.success and in_turn.success
    assert together.solved_together and not in_turn.solved_together and in_turn.rounds > 1
    # local optima of one objective: the pair's energy, the same to 1e-5 or lower
    assert together.cycle().energy_j <= in_turn.cycle().energy_j * (1 + 1e-5)
    # the NLP's smooth objective is the exact pair energy, swings and stance, plus what the
    # drives' smooth max adds: (v + sqrt(v^2 + eps^2)) / 2 >= max(v, 0), by at most
    # F_s eps / 2 = 2.5 mW per cylinder, over 2 joint-seconds here (two swing and two stance
    # joints for 0.25 s each, both legs): at most 5 mJ, never below the exact energy
    stats = together.legs["RF"].best.details.stats
    exact = sum(r.best.swing_energy_j for r in together.legs.values()) + PairProblem(
        together.pipeline, ("RF", "LH"), family
    ).stance_energy_j(tuple(together.thetas.values()))
    assert -1e-9 <= stats["smooth_objective_j"] - exact <= 5e-3


def test_an_alternation_cut_short_is_not_converged(scalf, monkeypatch):
    # one round cannot tell that the legs have settled: the run says so, it is not a success
    # (the pattern search cannot take the pair as one problem: it alternates)
    monkeypatch.setattr(driver, "MAX_ALTERNATIONS", 1)
    pipeline = EnergyPipeline(scalf, Gait(), loads="whole-body")
    run = optimize_swings(pipeline, ("RF", "LH"), make_family("paper"), Settings(method="pattern"))
    assert all(r.success for r in run.legs.values()) and run.converged_sampling
    assert not run.alternation_settled and not run.success
    assert run.failure() == "the legs' alternation (stopped after 1 round)"
    assert "solved in turn, 1 round and stopped there" in optimization_report(run)
    assert "NOT CONVERGED" in optimization_report(run)


def test_an_alternation_stopped_by_a_leg_it_could_not_solve_says_so(hyq, monkeypatch):
    # LH's feasibility phase made hopeless: HyQ's start is infeasible under whole-body loads
    # (below), and a violation that never falls leaves LH without a feasible point; the
    # alternation stops at that leg, and the report said it had settled ("1 rounds until a
    # round changed the pair's energy ...")
    real = SwingProblem.violation

    def violation(self, theta):
        return 1.0 if self.leg == "LH" else real(self, theta)

    monkeypatch.setattr(SwingProblem, "violation", violation)
    pipeline = EnergyPipeline(hyq, read_gait(robot=hyq), loads="whole-body")
    run = optimize_swings(pipeline, ("RF", "LH"), make_family("paper"), Settings(method="pattern"))
    assert run.legs["RF"].success and not run.legs["LH"].success and not run.success
    assert run.legs["LH"].best.status == "no feasible point found"
    text = optimization_report(run)
    assert "solved in turn, stopped in round 1, where LH was not solved;" in text
    assert "until a round changed" not in text


def test_the_feasibility_phase_counts_every_crossed_limit(hyq):
    """HyQ's default trot under whole-body loads: the start (the member closest to the
    reference swing) misses the mid-swing clearance by a fraction of a millimetre and loads a
    stance hip's cylinder a fifth beyond its pull. The feasibility phase judged a point by its
    first crossing alone, so a step that met the clearance, leaving the stance limit crossed
    (a share of 0.2), looked worse than the start (1e-4) and the search found no feasible
    point on either leg; every crossing counted, it reaches one and the energy search runs."""
    from scalf_opt.optimize.solve import run_pattern_search
    from scalf_opt.optimize.starts import closest_member, reference_path

    pipeline = EnergyPipeline(hyq, read_gait(robot=hyq), loads="whole-body")
    family = make_family("joint-6")
    # the ground and effort rows as they were: the case needs the clearance crossed first
    margins = LimitMargins(effort_share=0.0, lift=NO_LIFT_PROFILE)
    problem = SwingProblem(pipeline, "RF", family, margins=margins)
    start = closest_member(problem, reference_path(problem))
    found = problem.evaluate(start)
    assert found.reason == "mid-swing clearance" and 0.0 < found.violation < 1e-3
    share, why = problem.stance_excess(start)
    assert share > 0.2 and why.startswith("stance of ") and "cyl_force_hip" in why
    # the total counts both: the rows' (as evaluate weighs them) and the stance samples'
    assert problem.violation(start) > found.violation + share
    result = run_pattern_search(problem, start)
    assert result.success and result.pattern_details.feasibility_phase_iterations > 0
    assert problem.violation(result.theta) == 0.0 and problem.evaluate(result.theta).reason is None
    assert result.objective_j == pytest.approx(problem.energy_j(result.theta), rel=1e-12)


@pytest.mark.slow
def test_the_bound_is_on_the_swing_energy_under_any_loads(scalf):
    # no foot force in swing: the swing energy, and its bound, do not depend on the loads
    from scalf_opt.api import optimize_swing

    result = optimize_swing(scalf, Gait(), family="paper", bound=True, legs=("RF",))
    (leg,) = result.run.legs.values()
    assert result.pipeline.loads == "whole-body" and leg.check_swing_energy_j is not None
    assert leg.check_swing_energy_j < leg.check_energy_j  # the objective adds the stance
    gap = 100.0 * (leg.check_swing_energy_j / leg.bound_check_energy_j - 1.0)
    assert leg.gap_to_bound_percent == pytest.approx(gap, rel=1e-12)
    assert gap > 0.0  # the paper family's two parameters stay well above the bound


def test_the_loaded_stance_limits_are_the_torque_and_force_ones(scalf):
    from scalf_opt.optimize.kernels import stance_limited_bounds

    names = [b.name for b in stance_limited_bounds(EnergyPipeline(scalf, Gait()).physics("RF"))]
    assert names == ["tau_hip", "tau_knee", "cyl_force_hip", "cyl_force_knee"]


def test_an_optimum_keeps_the_stance_legs_it_loads_inside_their_force_limits(hyq):
    """HyQ's default trot under whole-body loads: the reference swings load the stance hips'
    cylinders beyond their 1.96 kN pull; the optimized swings must not, and the pipeline's own
    cycle (the 3-D distribution of the whole robot's wrench, not the NLP's affine coupling)
    confirms it on every stance leg: HyQ's trunk is 21.5 mm left of its midplane, so LF's
    stance, loaded by RF's and LH's own swings, is not RF's mirror image (when only the pair's
    stance was in the problem, LF's hip cylinder ended 1.5 % beyond its pull)."""
    from scalf_opt.energy.limits import leg_bounds, violations
    from scalf_opt.locomotion.scaling import default_gait_for

    pipeline = EnergyPipeline(hyq, default_gait_for(hyq), loads="whole-body")
    family = make_family("joint-6")
    reference = SwingProblem(pipeline, "RF", family, {"LH": np.zeros(family.n_params)})
    share, reason = reference.stance_excess(np.zeros(family.n_params))
    assert share > 0.01 and "cyl_force_hip" in reason  # the reference swings: beyond
    run = optimize_swings(pipeline, ("RF", "LH"), family)
    assert run.success
    cycle = run.pipeline.robot_cycle(family, run.thetas)
    for leg in ("RF", "LH", "LF", "RH"):
        beyond = violations(cycle.legs[leg].stance.values, leg_bounds(run.pipeline.physics(leg)))
        assert [v for v in beyond if v.excess > 1e-6 * abs(v.bound.lower)] == []


def test_the_lifted_and_the_condensed_stance_term_reach_the_same_optimum(scalf, monkeypatch):
    # two transcriptions of one problem: the twins' stance samples eliminated (condensed) or
    # variables with their linear equalities (lifted, with the lifted swing)
    from scalf_opt.optimize import nlp
    from scalf_opt.optimize.solve import run_ipopt_pair

    family = make_family("paper")
    pipeline = EnergyPipeline(scalf, Gait(), loads="whole-body")
    pair = PairProblem(pipeline, ("RF", "LH"), family)
    start = {leg: np.zeros(2) for leg in ("RF", "LH")}
    condensed = run_ipopt_pair(pair, start)
    assert not nlp.build_nlp(pair).coupled[0].lifted
    monkeypatch.setattr(sampling, "CONDENSED_MAX_PARAMS", 1)
    lifted_nlp = nlp.build_nlp(pair)
    assert lifted_nlp.coupled[0].lifted and lifted_nlp.lifted
    lifted = run_ipopt_pair(pair, start)
    for leg in ("RF", "LH"):
        assert condensed[leg].success and lifted[leg].success
        assert lifted[leg].objective_j == pytest.approx(condensed[leg].objective_j, rel=1e-7)
        assert np.abs(lifted[leg].theta - condensed[leg].theta).max() < 1e-3  # deg


def test_ipopts_first_strategy_gives_way_sooner_where_asked():
    # every strategy fails: the order and the iteration limits they were run with
    from scalf_opt.optimize.solvers import IPOPT_ATTEMPTS, _with_retries

    def attempts(options):
        seen = []
        _with_retries(
            lambda attempt: seen.append(attempt) or attempt, lambda _: False, options, False
        )
        return seen

    assert attempts(SolverOptions()) == list(IPOPT_ATTEMPTS)
    capped = attempts(SolverOptions(first_strategy_iterations=7))
    assert capped == [{**IPOPT_ATTEMPTS[0], "max_iter": 7}, *IPOPT_ATTEMPTS[1:]]
    user = {"max_iter": 5}  # the user's limit wins over the cap, as over every strategy's
    assert attempts(SolverOptions(ipopt=user, first_strategy_iterations=7)) == [
        {**a, **user} for a in IPOPT_ATTEMPTS
    ]


def test_only_the_first_round_that_starts_a_pair_caps_the_first_strategy(scalf, monkeypatch):
    # the first round's solves only start the pair's problem; the pair's own solve (its answer)
    # gets every strategy's full iterations
    from scalf_opt.optimize import solve as solve_module
    from scalf_opt.optimize.solvers import FIRST_ROUND_ITERATIONS, IPOPT_ATTEMPTS

    calls = []
    for name in ("run_ipopt", "run_ipopt_pair"):
        real = getattr(solve_module, name)

        def spy(problem, start, options=None, *rest, _real=real, _name=name):
            calls.append((_name, dict(options)))
            return _real(problem, start, options, *rest)

        monkeypatch.setattr(solve_module, name, spy)
    pipeline = EnergyPipeline(scalf, Gait(), loads="whole-body")
    run = optimize_swings(pipeline, ("RF", "LH"), make_family("paper"), Settings())
    assert run.success and run.solved_together
    first = {**IPOPT_ATTEMPTS[0], "max_iter": FIRST_ROUND_ITERATIONS}
    assert calls == [
        ("run_ipopt", first),
        ("run_ipopt", first),
        ("run_ipopt_pair", dict(IPOPT_ATTEMPTS[0])),
    ]


@pytest.mark.parametrize("legs", [("RF",), ("LH",), ("RF", "LH")])
def test_on_an_asymmetric_robot_the_objective_is_half_the_robots_cycle(hyq, scalf, legs):
    """Both pairs' stances count where they are not mirror images, each at half weight.

    HyQ's trunk is off its midplane: the stance of LF and RH, which RF's and LH's own swings
    load, differs from RF's and LH's, which the twins' swings load. The objective's stance part
    is then half the stance energy of all four legs, and with the legs' swings (a twin repeats
    its leg's swing energy) the objective of the pair is half the robot's cycle, the evaluator's
    number. On SCalf, symmetric, one window stands for both and the objective is the pair's.
    """
    from scalf_opt.locomotion.scaling import default_gait_for

    family = make_family("joint-4")
    rng = np.random.default_rng(11)
    thetas = {leg: rng.normal(0.0, 2.0, family.n_params) for leg in ("RF", "LH")}
    for robot, windows in ((hyq, 2), (scalf, 1)):
        pipeline = EnergyPipeline(robot, default_gait_for(robot), loads="whole-body")
        cycle = pipeline.robot_cycle(family, thetas)
        half_stance = sum(leg.stance_energy_j for leg in cycle.legs.values()) / 2
        if len(legs) == 2:
            problem = PairProblem(pipeline, legs, family)
            stance = problem.stance_energy_j(tuple(thetas[leg] for leg in legs))
        else:
            (leg,) = legs
            other = "LH" if leg == "RF" else "RF"
            problem = SwingProblem(pipeline, leg, family, {other: thetas[other]})
            stance = problem.stance_energy_j(thetas[leg])
            swing = cycle.legs[leg].swing_energy_j
            assert problem.energy_j(thetas[leg]) == pytest.approx(swing + half_stance, rel=RTOL)
        assert len(problem.couplings) == windows
        assert all(c.legs == legs for c in problem.couplings)
        if windows == 2:  # the pair's stance (twins swinging), then the other pair's (legs)
            twins = tuple({"RF": "LF", "LH": "RH"}[leg] for leg in legs)
            assert [c.varying for c in problem.couplings] == [twins, legs]
        assert stance == pytest.approx(half_stance, rel=RTOL)
        if windows == 1:  # the symmetric robot: the pair's stance is half the four legs'
            pair_stance = cycle.legs["RF"].stance_energy_j + cycle.legs["LH"].stance_energy_j
            assert stance == pytest.approx(pair_stance, rel=RTOL)
    # HyQ's stances differ: the pair's alone is not half the robot's (its legs' limits differ
    # too: LF's hip cylinder is loaded more than RF's)
    hyq_cycle = EnergyPipeline(hyq, default_gait_for(hyq), loads="whole-body").robot_cycle(
        family, thetas
    )
    rf_peak = np.abs(hyq_cycle.legs["RF"].stance.values["cyl_force_hip"]).max()
    lf_peak = np.abs(hyq_cycle.legs["LF"].stance.values["cyl_force_hip"]).max()
    assert abs(lf_peak - rf_peak) > 1e-3 * rf_peak


@pytest.mark.parametrize("duty", [0.5, 0.6])
def test_a_leg_optimized_on_its_own_pays_for_the_stance_its_own_swing_loads(scalf, duty):
    """Every leg optimized on its own (a study's ``optimize = "all"``): a twin keeps its own
    swing, so only the other pair's stance, during the leg's own swing, depends on the leg's
    parameters; the objective is the leg's swing plus that stance, as the evaluator reports it
    with all four legs' own swings."""
    family = make_family("joint-4")
    pipeline = EnergyPipeline(scalf, Gait(duty_cycle=duty), loads="whole-body")
    rng = np.random.default_rng(5)
    thetas = {leg: rng.normal(0.0, 2.0, family.n_params) for leg in ("RF", "LH", "LF", "RH")}
    cycle = pipeline.robot_cycle(family, thetas)
    for leg, loaded in (("RF", ("LF", "RH")), ("LF", ("RF", "LH"))):
        others = {o: t for o, t in thetas.items() if o != leg}
        problem = SwingProblem(pipeline, leg, family, others)
        assert len(problem.couplings) == 1 and problem.couplings[0].varying == (leg,)
        expected = cycle.legs[leg].swing_energy_j + sum(
            cycle.legs[s].stance_energy_j for s in loaded
        )
        assert problem.energy_j(thetas[leg]) == pytest.approx(expected, rel=RTOL)
