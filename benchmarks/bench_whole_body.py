"""Speed of the 3-D cycle NLP: as ``optimize --model 3d`` solves it, against its first versions.

On one robot's default trot (default Go1) on a coarse grid (``--rate``, default 25 Hz), from the
kinematic start, the same NLP is solved twice:

* as ``optimize --model 3d`` solves it (``solve_cycle``): the constraint Jacobian and the
  Lagrangian's Hessian assembled from the read point's compiled kernel
  (:mod:`scalf_opt.optimize.whole_body_kernel`), the losses' smoothing width narrowed over three
  solves (``SMOOTHING_STEPS``);
* as the first versions did: CasADi's own derivatives of the whole NLP, expanded to one graph
  and run in CasADi's virtual machine (the kernel left uncompiled), one solve at the last width.

Each line gives the build (graph and ``nlpsol``) and the solves' time, Ipopt's iterations and
the energy per cycle of the answer (exact, at the nodes); the ratio is the first versions' total
time over the current one's, measured in the same run (wall-clock times vary with the machine's
load; ratios are what to compare). The compiled kernel comes from the disk cache after the first
run (its compilation is printed on its own). The last line is
``3-D cycle: now T s, first versions T s, ratio Rx``.

    python benchmarks/bench_whole_body.py [--robot NAME] [--rate HZ]
"""

from __future__ import annotations

import argparse
import sys
import time
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parent.parent))

# isort: off
import scalf_opt  # noqa: F401 (first: it pins OpenBLAS's kernels before numpy loads)

# isort: on
import casadi as ca
import numpy as np

from scalf_opt.energy.whole_body import WholeBodyPhysics
from scalf_opt.locomotion.contact_schedule import trot_schedule
from scalf_opt.locomotion.scaling import default_gait_for
from scalf_opt.optimize import whole_body_kernel
from scalf_opt.optimize.whole_body_nlp import (
    IPOPT_DEFAULTS,
    SMOOTHING,
    SMOOTHING_STEPS,
    CycleNlp,
    CycleProblem,
    build_cycle_nlp,
    kinematic_start,
    solve_cycle,
)
from scalf_opt.robots.loading import load_robot


def problem_for(robot_name: str, rate_hz: float) -> CycleProblem:
    """The robot's default trot on a grid at ``rate_hz`` (a fresh model: nothing built yet)."""
    robot = load_robot(robot_name)
    gait = default_gait_for(robot)
    return CycleProblem(
        WholeBodyPhysics.of(robot),
        trot_schedule(gait.period_s, 0.5, rate_hz),
        gait.speed_m_s,
        gait.stance_height_m,
        gait.clearance_m,
    )


def first_version_solve(nlp: CycleNlp) -> tuple[float, float, int, float, str]:
    """``(build s, solve s, iterations, energy J, status)``: CasADi's derivatives, one width."""
    began = time.perf_counter()
    solver = ca.nlpsol(
        "bench",
        "ipopt",
        {"x": nlp.variables, "p": SMOOTHING, "f": nlp.objective, "g": nlp.constraints},
        {"ipopt": IPOPT_DEFAULTS, "print_time": False, "expand": True},
    )
    built = time.perf_counter() - began
    began = time.perf_counter()
    result = solver(
        x0=nlp.w0, p=SMOOTHING_STEPS[-1], lbx=nlp.lbw, ubx=nlp.ubw, lbg=nlp.lbg, ubg=nlp.ubg
    )
    stats = solver.stats()
    energy = nlp.plan_of(np.array(result["x"])).evaluate(nlp.problem.accounting).total_j
    return (
        built,
        time.perf_counter() - began,
        int(stats["iter_count"]),
        energy,
        str(stats["return_status"]),
    )


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--robot", default="go1")
    parser.add_argument("--rate", type=float, default=25.0)
    args = parser.parse_args()

    problem = problem_for(args.robot, args.rate)
    began = time.perf_counter()
    whole_body_kernel.point_kernel(problem.physics, problem.accounting)
    print(
        f"{args.robot}, {problem.schedule.intervals} nodes: kernel compiled or loaded in "
        f"{time.perf_counter() - began:.1f} s"
    )
    began = time.perf_counter()
    solution = solve_cycle(problem)
    now = time.perf_counter() - began
    energy = solution.plan.evaluate(problem.accounting).total_j
    print(
        f"now:            {now:.1f} s in all, solves {solution.solve_s:.1f} s, "
        f"{solution.iterations} iterations, {energy:.4f} J ({solution.status})"
    )

    baseline_problem = problem_for(args.robot, args.rate)
    original = whole_body_kernel.compile_library
    whole_body_kernel.compile_library = lambda *_: None  # the kernel in the virtual machine
    try:
        began = time.perf_counter()
        plain = build_cycle_nlp(baseline_problem, kinematic_start(baseline_problem))
        graph = time.perf_counter() - began
    finally:
        whole_body_kernel.compile_library = original
    built, solved, iterations, energy, status = first_version_solve(plain)
    first = graph + built + solved
    print(
        f"first versions: {first:.1f} s in all (graph {graph:.1f} s, nlpsol {built:.1f} s), "
        f"solve {solved:.1f} s, {iterations} iterations, {energy:.4f} J ({status})"
    )
    print(f"3-D cycle: now {now:.1f} s, first versions {first:.1f} s, ratio {first / now:.1f}x")


if __name__ == "__main__":
    main()
