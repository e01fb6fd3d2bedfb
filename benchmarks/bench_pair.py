"""Whole-body loads: a diagonal pair's two swings as one NLP, against the legs in turn.

For each robot's default trot, the default family and the default whole-body loads,
``scalf-opt optimize``'s optimization of the pair (RF, LH), twice in the same run: Ipopt on the
pair as one problem (the default, :class:`~scalf_opt.optimize.problem.PairProblem`), and the
legs optimized in turn until a round changes the pair's energy by less than 1e-5 (block
coordinate descent: what the pattern search does, and what Ipopt did before). Each line gives
both times, the pair's cycle energy of both answers (half the robot's, the exact evaluation every
report prints), and the ratio of the times; the machine's load moves the times, not their ratio
much.

    python benchmarks/bench_pair.py [ROBOT ...]
"""

from __future__ import annotations

import sys
import time
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parent.parent))

# isort: off
import scalf_opt  # noqa: F401 (first: it pins OpenBLAS's kernels before numpy loads)

# isort: on
from scalf_opt.energy.pipeline import EnergyPipeline
from scalf_opt.locomotion.scaling import default_gait_for
from scalf_opt.locomotion.swing.names import DEFAULT_FAMILY
from scalf_opt.locomotion.swing.registry import make_family
from scalf_opt.optimize.driver import Settings, SwingOptimization, optimize_swings
from scalf_opt.robots.loading import load_robot
from scalf_opt.types import FIRST_PAIR

ROBOTS = ("scalf", "anymal_c", "hyq", "go1", "solo12", "a1")


def pair_energy_j(run: SwingOptimization) -> float:
    """Half the robot's energy over a cycle, as the reports evaluate it [J]: what the pair's
    optimization minimizes (the pair's energy on a robot symmetric about its midplane)."""
    return run.cycle().energy_j / 2.0


def timed(pipeline: EnergyPipeline, settings: Settings) -> tuple[SwingOptimization, float]:
    start = time.perf_counter()
    run = optimize_swings(pipeline, FIRST_PAIR, make_family(DEFAULT_FAMILY), settings)
    return run, time.perf_counter() - start


def main() -> None:
    robots = sys.argv[1:] or list(ROBOTS)
    print(
        f"{'robot':9s} {'in turn':>22s} {'together':>22s} {'time ratio':>10s} "
        f"{'energy change':>13s}"
    )
    for name in robots:
        robot = load_robot(name)
        pipeline = EnergyPipeline(robot, default_gait_for(robot))
        together, t_together = timed(pipeline, Settings())
        in_turn, t_in_turn = timed(pipeline, Settings(pair_together=False))
        assert together.solved_together and not in_turn.solved_together
        e_together, e_in_turn = pair_energy_j(together), pair_energy_j(in_turn)
        status = "" if together.success and in_turn.success else "  (NOT CONVERGED)"
        print(
            f"{name:9s} {in_turn.rounds:2d} rounds {t_in_turn:5.1f} s {e_in_turn:8.3f} J "
            f"{'1 solve':>8s} {t_together:4.1f} s {e_together:8.3f} J "
            f"{t_in_turn / t_together:9.1f}x "
            f"{100 * (e_together / e_in_turn - 1):+12.3f} %{status}"
        )


if __name__ == "__main__":
    main()
