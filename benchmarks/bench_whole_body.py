"""Speed of the 3-D cycle NLP: its assembled derivatives against CasADi's own.

On one robot's default trot (default Go1) on a coarse grid (``--rate``, default 25 Hz), from the
kinematic start, the same NLP is solved twice:

* as ``optimize --model 3d`` solves it: the constraint Jacobian and the Lagrangian's Hessian
  assembled from the read point's compiled kernel (:mod:`scalf_opt.optimize.whole_body_kernel`);
* with CasADi's own derivatives of the whole NLP, expanded to one graph and run in CasADi's
  virtual machine (the kernel left uncompiled), as the first versions did.

Each line gives the build (graph and ``nlpsol``) and the solve's time, Ipopt's iterations and
the objective; the ratio is the baseline's total time over the assembled one's, measured in the
same run (wall-clock times vary with the machine's load; ratios are what to compare). The
compiled kernel comes from the disk cache after the first run (its compilation is printed on its
own). The last line is ``3-D cycle: assembled T s, CasADi's T s, ratio Rx``.

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

from scalf_opt.energy.whole_body import WholeBodyPhysics
from scalf_opt.locomotion.contact_schedule import trot_schedule
from scalf_opt.locomotion.scaling import default_gait_for
from scalf_opt.optimize import whole_body_kernel
from scalf_opt.optimize.whole_body_nlp import (
    IPOPT_DEFAULTS,
    NO_PARAMETERS,
    CycleNlp,
    CycleProblem,
    build_cycle_nlp,
    kinematic_start,
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


def solve(nlp: CycleNlp, options: dict) -> tuple[float, float, int, float, str]:
    """``(build s, solve s, iterations, objective, status)`` of Ipopt on ``nlp``."""
    began = time.perf_counter()
    solver = ca.nlpsol(
        "bench",
        "ipopt",
        {"x": nlp.variables, "p": NO_PARAMETERS, "f": nlp.objective, "g": nlp.constraints},
        {"ipopt": IPOPT_DEFAULTS, "print_time": False, **options},
    )
    built = time.perf_counter() - began
    began = time.perf_counter()
    result = solver(x0=nlp.w0, lbx=nlp.lbw, ubx=nlp.ubw, lbg=nlp.lbg, ubg=nlp.ubg)
    stats = solver.stats()
    return (
        built,
        time.perf_counter() - began,
        int(stats["iter_count"]),
        float(result["f"]),
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
    nlp = build_cycle_nlp(problem, kinematic_start(problem))
    graph = time.perf_counter() - began
    built, solved, iterations, objective, status = solve(nlp, nlp.derivatives)
    assembled = graph + built + solved
    print(
        f"assembled: graph {graph:.1f} s, nlpsol {built:.1f} s, solve {solved:.1f} s, "
        f"{iterations} iterations, objective {objective:.6f} ({status})"
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
    built, solved, iterations, objective, status = solve(plain, {"expand": True})
    casadi = graph + built + solved
    print(
        f"CasADi's:  graph {graph:.1f} s, nlpsol {built:.1f} s, solve {solved:.1f} s, "
        f"{iterations} iterations, objective {objective:.6f} ({status})"
    )
    print(
        f"3-D cycle: assembled {assembled:.1f} s, CasADi's {casadi:.1f} s, "
        f"ratio {casadi / assembled:.1f}x"
    )


if __name__ == "__main__":
    main()
