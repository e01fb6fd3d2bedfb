"""Time of ``scalf-opt gait --model 3d``: six speeds of Go1 and of SCalf on two workers.

Goal: each robot's six speeds (0.4 to 1.4 m/s) in under 3 minutes on 2 workers. The cases are
the command's (:func:`~scalf_opt.cli.commands.gait_3d.cases`: one start, duty 0.5 and the
robot's default period, the period free, 25 Hz; chains of three speeds) run on fresh worker
interpreters (their imports
and kernel loading are in the time; the compiled kernels come from the disk cache, so run the
command once first on a new machine). The baseline, measured in the same run and process: one
solve of the robot's default trot on its first grid with the period fixed, so a sweep reads as
that many solves. The load average is printed before and after (the machine is shared).

    python benchmarks/bench_gait_3d.py [--robots go1,scalf] [--workers N]
"""

from __future__ import annotations

import argparse
import os
import sys
import time
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parent.parent))

from scalf_opt.api.gait_3d import (
    DEFAULT_GAIT_RATE_HZ,
    PERIOD_RANGE_SHARES,
    SpeedCase,
    StartAnswer,
    default_starts,
    solve_cases,
    speed_row,
)
from scalf_opt.cli.commands.gait import parse_speeds
from scalf_opt.energy.whole_body import WholeBodyPhysics
from scalf_opt.locomotion.contact_schedule import trot_schedule
from scalf_opt.locomotion.scaling import default_gait_for
from scalf_opt.optimize.whole_body_nlp import CycleProblem, solve_cycle
from scalf_opt.robots.loading import load_robot

SPEEDS = "0.4:1.4:0.2"
"""The six speeds [m/s]."""

GOAL_S = 180.0
"""Six speeds of one robot on two workers in under 3 minutes."""


def baseline_s(robot_name: str) -> float:
    """One solve of the robot's default trot on the first grid, the period fixed [s]."""
    robot = load_robot(robot_name)
    gait = default_gait_for(robot)
    problem = CycleProblem(
        WholeBodyPhysics.of(robot),
        trot_schedule(gait.period_s, 0.5, DEFAULT_GAIT_RATE_HZ),
        gait.step_length_m / (0.5 * gait.period_s),
        gait.stance_height_m,
        gait.clearance_m,
    )
    start = time.perf_counter()
    solution = solve_cycle(problem)
    assert solution.success, solution.status
    return time.perf_counter() - start


def sweep_s(robot_name: str, workers: int) -> tuple[float, list[dict], list[list[StartAnswer]]]:
    """The six speeds' wall time [s], their rows and every start's answer."""
    gait = default_gait_for(load_robot(robot_name))
    low, high = PERIOD_RANGE_SHARES
    cases = [
        SpeedCase(
            robot_name,
            None,
            speed,
            default_starts(gait.period_s, None, None),
            (low * gait.period_s, high * gait.period_s),
            DEFAULT_GAIT_RATE_HZ,
        )
        for speed in parse_speeds(SPEEDS)
    ]
    start = time.perf_counter()
    answers = solve_cases(cases, workers)
    elapsed = time.perf_counter() - start
    rows = [speed_row(robot_name, c.speed_m_s, a) for c, a in zip(cases, answers, strict=True)]
    return elapsed, rows, answers


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--robots", default="go1,scalf")
    parser.add_argument("--workers", type=int, default=2)
    args = parser.parse_args()
    print(f"load average before: {os.getloadavg()[0]:.2f} ({os.cpu_count()} cores, shared)")
    for robot in args.robots.split(","):
        base = baseline_s(robot)
        elapsed, rows, answers = sweep_s(robot, args.workers)
        solved = sum(r["status"] == "ok" for r in rows)
        verdict = "met" if elapsed < GOAL_S and solved == len(rows) else "NOT met"
        print(
            f"{robot:6s} {SPEEDS} {solved}/{len(rows)} converged {elapsed:7.1f} s ({verdict}: "
            f"< {GOAL_S:g} s, every speed)  baseline {base:5.1f} s  ratio {elapsed / base:5.1f}x",
            flush=True,
        )
        for row, speed_answers in zip(rows, answers, strict=True):
            if row["status"] != "ok":
                print(f"    {row['speed_m_s']:g} m/s: {row['error']}")
                continue
            solves = [s for a in speed_answers if a.summary for s in a.summary["solves"]]
            grids = "/".join(
                f"{s['nodes']}" + ("d" if s.get("reads_per_interval", 4) > 4 else "")
                for s in solves
            )
            print(
                f"    {row['speed_m_s']:g} m/s: CoT {row['cost_of_transport']:.4f}, "
                f"T {row['period_s']:.3f} s, grids {grids} nodes, "
                f"{row['solve_s']:.0f} s in Ipopt"
            )
    print(f"load average after: {os.getloadavg()[0]:.2f}")
    print(
        f"{args.workers} workers, one start per speed (duty 0.5, the default period, the period "
        f"free), {DEFAULT_GAIT_RATE_HZ:g} Hz; grids: each solve's nodes (d: read at eight points "
        "per interval); the ratio: the six speeds' time over one solve of the default trot's "
        "first grid, measured in this run"
    )


if __name__ == "__main__":
    main()
