"""How much do the whole-body stance loads change each robot's energy, and its optimum?

For every catalog robot on its default trot: the reference swing's energy per cycle and the
mean stance foot force under the paper's trunk-only loads and under the whole-body loads, and
the largest moment two diagonal point feet cannot supply. Without ``--quick`` also the default
family's optimum (Ipopt) under each load model, both evaluated under whole-body loads: what a
swing that pays for the loads it causes saves over one that does not, and what that costs in
optimization time.

    python studies/whole_body_loads.py [--quick] [--robot NAME ...] [--out FILE]

Prints a Markdown table and writes it as CSV to FILE (default results/whole_body_loads.csv), with
the optimizations' wall times (which the table leaves out: they change from run to run).
"""

from __future__ import annotations

import argparse
import sys
import time
from pathlib import Path

from scalf_opt.energy.cycle import change_percent
from scalf_opt.energy.loads import DEFAULT_LOADS, PAPER_LOADS
from scalf_opt.energy.pipeline import EnergyPipeline
from scalf_opt.files import write_atomic
from scalf_opt.io.results import rows_csv_text
from scalf_opt.locomotion.scaling import default_gait_for
from scalf_opt.locomotion.swing.names import DEFAULT_FAMILY
from scalf_opt.locomotion.swing.registry import make_family
from scalf_opt.optimize.driver import optimize_swings
from scalf_opt.robots.catalog import robot_names
from scalf_opt.robots.loading import load_robot
from scalf_opt.types import FIRST_PAIR


def robot_row(name: str, optimize: bool) -> dict[str, float | str]:
    """One robot's comparison of the two load models."""
    robot = load_robot(name)
    gait = default_gait_for(robot)
    reference = make_family("reference")
    trunk = EnergyPipeline(robot, gait, loads=PAPER_LOADS)
    whole = trunk.with_loads(DEFAULT_LOADS)
    ref_trunk, ref_whole = trunk.robot_cycle(reference), whole.robot_cycle(reference)
    row: dict[str, float | str] = {
        "robot": name,
        "mass_kg": robot.total_mass_kg,
        "trunk_share_pct": 100.0 * robot.trunk_mass_kg / robot.total_mass_kg,
        "reference_trunk_j": ref_trunk.energy_j,
        "reference_whole_body_j": ref_whole.energy_j,
        "reference_change_pct": change_percent(ref_whole.energy_j, ref_trunk.energy_j),
        "stance_force_trunk_n": ref_trunk.mean_stance_force_n,
        "stance_force_whole_body_n": ref_whole.mean_stance_force_n,
        "peak_unbalanced_moment_nm": ref_whole.peak_unbalanced_moment_nm,
    }
    if optimize:
        family = make_family(DEFAULT_FAMILY)
        start = time.perf_counter()
        run_trunk = optimize_swings(trunk, FIRST_PAIR, family)
        trunk_s = time.perf_counter() - start
        start = time.perf_counter()
        run_whole = optimize_swings(whole, FIRST_PAIR, family)
        whole_s = time.perf_counter() - start
        # both optima at the whole-body run's rate, under whole-body loads
        at_rate = whole.with_gait(run_whole.pipeline.gait)
        ref = at_rate.robot_cycle(reference).energy_j
        e_trunk = at_rate.robot_cycle(family, run_trunk.thetas).energy_j
        e_whole = at_rate.robot_cycle(family, run_whole.thetas).energy_j
        row.update(
            {
                "solved": str(run_trunk.success and run_whole.success),
                "alternation_rounds": run_whole.rounds,
                "legs_solved_together": run_whole.solved_together,
                "trunk_optimum_under_whole_body_pct": change_percent(e_trunk, ref),
                "whole_body_optimum_pct": change_percent(e_whole, ref),
                "optimization_trunk_s": trunk_s,
                "optimization_whole_body_s": whole_s,
            }
        )
    return row


def markdown(rows: list[dict[str, float | str]]) -> str:
    """The rows as a Markdown table (energies per cycle, forces as means over the stance)."""
    optimized = "whole_body_optimum_pct" in rows[0]
    head = (
        "| robot | mass [kg] | trunk share | reference, trunk [J] | reference, whole-body [J] "
        "| change | stance force, trunk [N] | stance force, whole-body [N] "
        "| peak unbalanced moment [N m] |"
    )
    rule = "|---|---|---|---|---|---|---|---|---|"
    if optimized:
        head += " trunk optimum | whole-body optimum |"
        rule += "---|---|"
    lines = [head, rule]
    for r in rows:
        line = (
            f"| {r['robot']} | {r['mass_kg']:.1f} | {r['trunk_share_pct']:.0f} % | "
            f"{r['reference_trunk_j']:.2f} | {r['reference_whole_body_j']:.2f} | "
            f"{r['reference_change_pct']:+.1f} % | {r['stance_force_trunk_n']:.1f} | "
            f"{r['stance_force_whole_body_n']:.1f} | {r['peak_unbalanced_moment_nm']:.1f} |"
        )
        if optimized:
            line += (
                f" {r['trunk_optimum_under_whole_body_pct']:+.2f} % | "
                f"{r['whole_body_optimum_pct']:+.2f} % |"
            )
        lines.append(line)
    return "\n".join(lines)


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--quick", action="store_true", help="the reference swings only")
    parser.add_argument("--robot", nargs="+", default=list(robot_names()), metavar="NAME")
    parser.add_argument("--out", type=Path, default=Path("results/whole_body_loads.csv"))
    args = parser.parse_args(argv)
    rows = [robot_row(name, not args.quick) for name in args.robot]
    print(markdown(rows))
    for r in rows if not args.quick else []:
        print(
            f"\n{r['robot']}: the trunk-only optimization took {r['optimization_trunk_s']:.1f} s, "
            f"the whole-body one took {r['optimization_whole_body_s']:.1f} s "
            + (
                "(both legs as one problem)"
                if r["legs_solved_together"]
                else f"({r['alternation_rounds']} rounds of the alternation)"
            )
        )
    args.out.parent.mkdir(parents=True, exist_ok=True)
    write_atomic(args.out, rows_csv_text(rows))
    return 0


if __name__ == "__main__":
    sys.exit(main())
