"""Time of ``scalf-opt gait``: six speeds on SCalf and six on an electric robot, two workers.

Goal: each robot's six speeds in under 10 minutes on 2 workers. The cases are the command's
(:func:`~scalf_opt.studies.study_file.speed_study`, default family and solver) and run without
cache on the local process pool (fresh worker interpreters: their imports are in the time). The
baseline, measured in the same run and process: one plain swing optimization of the robot's
default trot (``scalf-opt optimize``'s), so a speed's cost reads as that many optimizations. The
machine's load average is printed before and after: on a shared machine other jobs take cores,
so the workers' CPU time is printed too (divided by the workers: the time on idle cores).

    python benchmarks/bench_gait.py [--keep DIR] [--workers N]
    python benchmarks/bench_gait.py --loads-ratio

``--keep DIR`` keeps each robot's cache in ``DIR/<robot>``: ``scalf-opt gait`` with the same
speeds and ``--out DIR/<robot>`` then takes every speed from it.

``--loads-ratio`` times instead one speed of SCalf and one of Solo12 (:data:`ONE_SPEED`) on one
worker under the trunk-only loads and under the default whole-body loads, in turn, and prints
the ratio: what the page's run times, all under trunk loads, become under the default model.
"""

from __future__ import annotations

import argparse
import os
import resource
import sys
import tempfile
import time
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parent.parent))

from scalf_opt.cli.commands.gait import parse_speeds
from scalf_opt.energy.pipeline import EnergyPipeline
from scalf_opt.locomotion.scaling import default_gait_for
from scalf_opt.locomotion.swing.names import DEFAULT_FAMILY
from scalf_opt.locomotion.swing.registry import make_family
from scalf_opt.optimize.driver import optimize_swings
from scalf_opt.robots.loading import load_robot
from scalf_opt.studies.progress import Progress
from scalf_opt.studies.runner import _pool, run_cases
from scalf_opt.studies.study_file import speed_study
from scalf_opt.types import FIRST_PAIR

ROBOTS = (("scalf", "0.25:1.5:0.25"), ("go1", "0.2:0.7:0.1"))
"""Each robot and its six speeds [m/s] (Go1's default trot walks 0.71 m/s)."""

ONE_SPEED = (("scalf", 1.0), ("solo12", 0.4))
"""The ``--loads-ratio`` cases: a robot and one speed [m/s]."""

GOAL_S = 600.0
"""Six speeds of one robot on two workers in under 10 minutes."""


def baseline_s(robot_name: str, loads: str) -> float:
    """One plain optimization of the robot's default trot (the diagonal pair) [s]."""
    robot = load_robot(robot_name)
    pipeline = EnergyPipeline(robot, default_gait_for(robot), loads=loads)
    start = time.perf_counter()
    run = optimize_swings(pipeline, FIRST_PAIR, make_family(DEFAULT_FAMILY))
    assert run.success, run.failure()
    return time.perf_counter() - start


def workers_cpu_s() -> float:
    """CPU time of this process's finished children (the pool's workers) [s]: what the speeds
    cost whatever else the machine runs."""
    usage = resource.getrusage(resource.RUSAGE_CHILDREN)
    return usage.ru_utime + usage.ru_stime


def run_speeds(
    robot: str, speeds: list[float], loads: str, workers: int, out: Path
) -> tuple[dict[int, dict], float, float]:
    """``scalf-opt gait``'s cases for ``speeds``, cached in ``out`` (which must hold none yet).

    Returns each case's row, the wall time [s] and the workers' CPU time [s].
    """
    study = speed_study(speeds, robot=robot, loads=loads)
    start, cpu_start = time.perf_counter(), workers_cpu_s()
    rows, cached = run_cases(study, out, _pool(workers), Progress(len(study.cases), enabled=False))
    elapsed, cpu = time.perf_counter() - start, workers_cpu_s() - cpu_start
    assert cached == 0, f"{out}: {cached} speeds came from an old cache; give a new --keep"
    return rows, elapsed, cpu


def search_s(robot: str, speeds: list[float], loads: str) -> tuple[float, int]:
    """One worker's time for ``speeds`` with no cache [s], and how many it solved."""
    with tempfile.TemporaryDirectory() as scratch:
        rows, elapsed, _ = run_speeds(robot, speeds, loads, 1, Path(scratch))
    return elapsed, sum(r["status"] == "ok" for r in rows.values())


def loads_ratio() -> None:
    """One speed per robot on one worker, trunk-only and whole-body loads in turn."""
    print(f"load average before: {os.getloadavg()[0]:.2f} (2 cores, shared)")
    for robot, speed in ONE_SPEED:
        trunk, trunk_ok = search_s(robot, [speed], "trunk")
        whole, whole_ok = search_s(robot, [speed], "whole-body")
        status = "ok" if trunk_ok and whole_ok else "NOT solved"
        print(
            f"{robot:6s} {speed:4.2f} m/s  trunk {trunk:6.1f} s  whole-body {whole:6.1f} s  "
            f"ratio {whole / trunk:4.1f}x  {status}",
            flush=True,
        )
    print(f"load average after: {os.getloadavg()[0]:.2f}")
    print(f"1 worker, family {DEFAULT_FAMILY}, Ipopt, no cache; the ratio: whole-body over trunk")


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--keep", type=Path, help="keep each robot's cache in DIR/<robot>")
    parser.add_argument("--workers", type=int, default=2)
    # trunk-only by default: the loads of the tables and run times on docs/gaits.md
    parser.add_argument("--loads", default="trunk", help="stance load model (default trunk)")
    parser.add_argument(
        "--loads-ratio",
        action="store_true",
        help="one speed of SCalf and of Solo12 on one worker under both load models",
    )
    args = parser.parse_args()
    if args.loads_ratio:
        loads_ratio()
        return
    print(f"load average before: {os.getloadavg()[0]:.2f} (2 cores, shared)")
    lines = []
    for robot, speeds in ROBOTS:
        base = baseline_s(robot, args.loads)
        with tempfile.TemporaryDirectory() as scratch:
            out = args.keep / robot if args.keep else Path(scratch)
            rows, elapsed, cpu = run_speeds(
                robot, parse_speeds(speeds), args.loads, args.workers, out
            )
        ok = sum(r["status"] == "ok" for r in rows.values())
        evaluations = sum(r.get("evaluations") or 0 for r in rows.values())
        lines.append(
            f"{robot:6s} {speeds:>14s} {ok}/{len(rows)} ok {elapsed:8.1f} s "
            f"({'met' if elapsed < GOAL_S else 'NOT met'}: < {GOAL_S:.0f} s)  "
            f"baseline {base:5.2f} s  ratio {elapsed / base:6.0f}x  "
            f"{evaluations} gaits searched; the workers' CPU time {cpu:.0f} s "
            f"(on {args.workers} idle cores: {cpu / args.workers:.0f} s)"
        )
        print(lines[-1], flush=True)
    print(f"load average after: {os.getloadavg()[0]:.2f}")
    print(
        f"{args.workers} workers, family {DEFAULT_FAMILY}, Ipopt, loads {args.loads}; the ratio: "
        "the six speeds'"
    )
    print("time over one plain optimization of the default trot, measured in this run")


if __name__ == "__main__":
    main()
