"""Solves on worker threads and processes: the same answers as one after the other, and stopped
on request."""

import threading

import numpy as np
import pytest

from scalf_opt.energy.pipeline import EnergyPipeline
from scalf_opt.interrupts import map_in_threads, stop_requested
from scalf_opt.locomotion.gait import Gait
from scalf_opt.locomotion.swing.registry import make_family
from scalf_opt.optimize.bound import bounds_for
from scalf_opt.optimize.nlp import build_nlp, solve_nlp
from scalf_opt.optimize.problem import SwingProblem


@pytest.fixture(scope="module")
def model(scalf):
    return EnergyPipeline(scalf, Gait())


def test_map_in_threads_keeps_the_order_and_raises_the_first_error():
    assert map_in_threads(lambda x: x * x, [1, 2, 3, 4], 2) == [1, 4, 9, 16]
    assert map_in_threads(lambda x: x + 1, [1], 2) == [2]

    def fail(x):
        if x == 2:
            raise ValueError("two")
        return x

    with pytest.raises(ValueError, match="two"):
        map_in_threads(fail, [1, 2, 3], 2)
    assert not stop_requested()  # the cancellation ends with the call


def test_two_legs_bounds_in_processes_are_bitwise_those_one_after_the_other(model):
    labels: list[str] = []
    parallel = bounds_for(model, ("RF", "LH"), processes=2, spans=(16, 32), progress=labels.append)
    serial = bounds_for(model, ("RF", "LH"), processes=1, spans=(16, 32))
    for leg in ("RF", "LH"):
        np.testing.assert_array_equal(
            parallel[leg].result.best.theta, serial[leg].result.best.theta
        )
        assert parallel[leg].check_energy_j == serial[leg].check_energy_j
        assert parallel[leg].levels[-1].swing_energy_j == serial[leg].levels[-1].swing_energy_j
    # every level's label reached this process
    assert sorted(labels) == sorted(
        f"{leg}: free-trajectory bound, {n} spans" for leg in ("RF", "LH") for n in (16, 32)
    )


def test_a_solve_on_a_worker_thread_stops_when_the_main_thread_unwinds(model):
    """A worker's Ipopt ends at its next iteration once another worker failed (or a signal)."""
    problem = SwingProblem(model, "RF", make_family("bspline-32"))
    theta0 = np.zeros(problem.n_params)
    problem.evaluate(theta0)
    seen: dict[str, object] = {}
    started = threading.Event()

    def work(item: str) -> None:
        if item == "fail":
            started.wait()
            raise RuntimeError("the other worker failed")
        built = build_nlp(problem)  # built on this worker thread: with the stop callback
        started.set()
        try:
            solve_nlp(built, problem, theta0)
        except KeyboardInterrupt:  # what a cancelled worker raises (discarded by the pool)
            seen["stopped"] = True
        seen["status"] = built.solver.stats()["return_status"]
        seen["iterations"] = built.solver.stats()["iter_count"]

    full = solve_nlp(build_nlp(problem), problem, theta0)  # the same solve, uninterrupted
    with pytest.raises(RuntimeError, match="the other worker failed"):
        map_in_threads(work, ["solve", "fail"], 2)
    assert seen["stopped"] is True
    assert seen["status"] == "User_Requested_Stop"
    assert seen["iterations"] < full.iterations


def test_paper_s_independent_solves_in_processes_are_bitwise_those_in_this_one(scalf):
    """``paper`` runs its whole-body line and its free stance beside the bounds in worker
    processes: the same answers, to the bit, as in this process (the paper family: quick)."""
    from scalf_opt.optimize.driver import Settings
    from scalf_opt.studies.paper import FREE_STANCE_JOB, WHOLE_BODY_JOB, independent_solve
    from scalf_opt.workers import map_in_processes

    trunk = EnergyPipeline(scalf, Gait(), loads="trunk")
    jobs = [
        (WHOLE_BODY_JOB, (trunk.with_loads("whole-body"), "paper", Settings())),
        (FREE_STANCE_JOB, (trunk, "paper", Settings())),
    ]
    labels: list[str] = []
    whole, stance = map_in_processes(independent_solve, jobs, 2, labels.append)
    whole_here, stance_here = (independent_solve(job) for job in jobs)
    assert whole.pipeline.load_model.couples_legs and whole.success
    for leg in ("RF", "LH"):
        np.testing.assert_array_equal(whole.legs[leg].best.theta, whole_here.legs[leg].best.theta)
    assert stance.best.gait == stance_here.best.gait and stance.success
    assert stance.cycle().energy_j == stance_here.cycle().energy_j
    assert {"paper under whole-body loads", "the free stance"} <= set(labels)
