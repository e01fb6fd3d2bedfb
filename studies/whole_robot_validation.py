"""The energy model against MuJoCo on all six robots: reference and default optimum.

python studies/whole_robot_validation.py [--quick] [--robots a,b] [--loads NAME] [--out DIR]

For each robot: its default optimum (`scalf-opt optimize`: joint-6, Ipopt, RF and LH; LF and
RH repeat them), then `scalf-opt simulate --from` that optimum (the reference is simulated beside
it), 10 cycles (3 with --quick), judged by the referee ensemble (`simulate`'s default: the median
over ten referees, each changing one setting of the nominal referee; --quick: the nominal referee
alone). Prints, per robot and trajectory, per leg and phase the joint energy per cycle of the
model and of the nominal referee's simulation and their difference; the trunk's height
fluctuation (absolute and over the stance height), pitch and speed; the mean stance force; what
the model does not balance and the referee had to (the PD feedback's share of the joints' gross
work, the feet pushing against each other, the work of contacts and joint stops); the joints'
closest approach to their stops; and the ensemble's verdict: per trajectory the median of the
worst leg's difference and the largest spread between the referees. Beside model and simulation,
"plan": MuJoCo's inverse dynamics of the whole robot on the plan (``simulate``'s
``plan_inverse_dynamics``), so each gap splits into the model's (model vs plan) and the referee's
(simulation vs plan). --loads: the stance load model of the optimum and of both energy models
(default whole-body; whole-body-sagittal shares the loads as the referee's planar trunk does).

Writes DIR/whole_robot_validation.json, every optimum's summary.json and every simulation.json
and simulation.png under DIR/<robot>/ (default results/whole_robot_validation).
"""

from __future__ import annotations

import argparse
import sys
import time
from pathlib import Path
from typing import Any

# isort: off
import scalf_opt as so  # first: it pins OpenBLAS's kernels before numpy loads

# isort: on
import numpy as np

from scalf_opt.energy.loads import DEFAULT_LOADS, LOAD_MODELS
from scalf_opt.files import write_atomic
from scalf_opt.io.results import to_json
from scalf_opt.sim.metrics import energy_goal
from scalf_opt.types import LEG_NAMES

ROBOTS = ("scalf", "hyq", "anymal_c", "go1", "a1", "solo12")

FORCE_GOAL = 0.03
HEIGHT_GOAL_FRACTION = 0.01
SPREAD_GOAL_POINTS = 3.0


def figures(data: dict[str, Any], stance_height_m: float) -> dict[str, Any]:
    """The row of one simulated trajectory (``simulation.json``'s figures, condensed)."""
    phases = data["joint_energy_per_phase_j"]
    plan = data["plan_inverse_dynamics"]["joint_energy_per_phase_j"]
    plan_total = sum(e["stance"] + e["swing"] for e in plan.values())
    servo = data["servo_work_per_cycle_j"]
    force_sim = np.mean(list(data["stance_force_mean_n"].values()))
    force_model = np.mean(list(data["model_stance_force_mean_n"].values()))
    clearance = data["joint_stop_clearance_rad"]
    return {
        "legs": {
            leg: {
                phase: {
                    "model_j": phases[leg][phase]["model"],
                    "simulated_j": phases[leg][phase]["simulated"],
                    "plan_inverse_dynamics_j": plan[leg][phase],
                    "difference_pct": 100 * phases[leg][phase]["relative_difference"],
                }
                for phase in ("stance", "swing")
            }
            | {
                "cycle_difference_pct": 100
                * data["joint_energy_per_cycle_j"][leg]["relative_difference"]
            }
            for leg in LEG_NAMES
        },
        "total_model_j": data["total_energy_per_cycle_j"]["model"],
        "total_simulated_j": data["total_energy_per_cycle_j"]["simulated"],
        "total_difference_pct": 100 * data["total_energy_per_cycle_j"]["relative_difference"],
        "total_plan_inverse_dynamics_j": plan_total,
        "model_vs_plan_pct": 100 * (data["total_energy_per_cycle_j"]["model"] / plan_total - 1),
        "simulated_vs_plan_pct": 100
        * (data["total_energy_per_cycle_j"]["simulated"] / plan_total - 1),
        "trunk_height_fluctuation_mm": 1e3 * data["trunk_height_fluctuation_m"],
        "trunk_height_fluctuation_over_stance_height_pct": 100
        * data["trunk_height_fluctuation_m"]
        / stance_height_m,
        "trunk_pitch_peak_mrad": 1e3 * data["trunk_pitch_peak_rad"],
        "speed_m_s": data["forward_speed_m_s"],
        "planned_speed_m_s": data["planned_speed_m_s"],
        "stance_force_mean_n": float(force_sim),
        "model_stance_force_mean_n": float(force_model),
        "stance_force_difference_pct": float(100 * (force_model / force_sim - 1)),
        "feedback_share_of_gross_work_pct": 100
        * sum(w["feedback_gross"] for w in servo.values())
        / sum(w["joints_gross"] for w in servo.values()),
        "internal_force_peak_n": max(
            f["peak"] for f in data["internal_horizontal_force_n"].values()
        ),
        "constraint_work_j": data["constraint_work_per_cycle_j"],
        "stop_clearance_planned_mrad": 1e3 * min(min(c["planned"]) for c in clearance.values()),
        "stop_clearance_simulated_mrad": 1e3 * min(min(c["simulated"]) for c in clearance.values()),
        "torque_saturation_pct": 100 * max(data["torque_saturation_fraction"].values()),
        "ensemble": _ensemble(data),
        "settings": data["settings"],
        "model_repairs": data.get("model_repairs", []),
    }


def _ensemble(data: dict[str, Any]) -> dict[str, Any] | None:
    """The ensemble's verdict of one trajectory: the worst leg's median and the largest spread."""
    energy = data["joint_energy_per_cycle_j"]
    if "relative_difference_spread" not in energy["RF"]:
        return None
    return {
        "worst_leg_median_pct": 100
        * max((e["relative_difference"] for e in energy.values()), key=abs),
        "largest_spread_points": 100
        * max(e["relative_difference_spread"] for e in energy.values()),
        "refereeable": data["goals"]["refereeable"],
        "met": data["goals"]["joint_energy_met"],
    }


def goals(name: str, row: dict[str, Any]) -> dict[str, bool]:
    """The issue's goals for one trajectory: per-leg energy, stance force, trunk height."""
    leg_goal = energy_goal(name)  # simulate's own: 5 % on SCalf, 10 % on the others
    worst = max(abs(leg["cycle_difference_pct"]) for leg in row["legs"].values())
    return {
        "leg_energy_met": worst <= 100 * leg_goal,
        "stance_force_met": abs(row["stance_force_difference_pct"]) <= 100 * FORCE_GOAL,
        "trunk_height_met": row["trunk_height_fluctuation_over_stance_height_pct"]
        <= 100 * HEIGHT_GOAL_FRACTION,
    }


def run_robot(
    name: str, out: Path, cycles: int, ensemble: bool, loads: str = DEFAULT_LOADS
) -> dict[str, Any]:
    """Optimize, simulate and condense one robot (module docstring)."""
    robot = so.load_robot(name)
    started = time.perf_counter()
    optimized = so.optimize_swing(robot, loads=loads)
    if not optimized.success:
        return {"robot": name, "failure": f"default optimization: {optimized.failure()}"}
    source = out / name / "optimum"
    optimized.write(source)
    stance_height = optimized.run.pipeline.gait.stance_height_m
    run = so.simulate(robot, swings_from=source, cycles=cycles, ensemble=ensemble)
    run.write(out / name / "simulation")
    data = run.data
    rows = {
        "reference": figures(data["reference"], stance_height),
        "optimum": figures(data, stance_height),
    }
    saving = data["saving_vs_reference"]
    return {
        "robot": name,
        "optimum_family": optimized.run.family.name,
        "saving_model_pct": saving["model_percent"],
        "saving_simulated_pct": saving["simulated_percent"],
        "saving_simulated_spread_points": saving.get("simulated_percent_spread"),
        "trajectories": rows,
        "goals": {label: goals(name, row) for label, row in rows.items()},
        "wall_time_s": time.perf_counter() - started,
    }


def print_tables(results: list[dict[str, Any]], cycles: int) -> None:
    """The Markdown tables of the module docstring."""
    ok = [r for r in results if "failure" not in r]
    for r in results:
        if "failure" in r:
            print(f"\n{r['robot']}: {r['failure']}")
    print(f"\n## Joint energy per cycle: model, plan, MuJoCo ({cycles} cycles, first excluded)\n")
    print(
        "| robot | trajectory | leg | stance model / plan / sim [J] | stance sim vs model | "
        "swing model / plan / sim [J] | swing sim vs model | cycle sim vs model |"
    )
    print("|---|---|---|---|---|---|---|---|")
    for r in ok:
        for label, row in r["trajectories"].items():
            for leg, e in row["legs"].items():
                st, sw = e["stance"], e["swing"]
                print(
                    f"| {r['robot']} | {label} | {leg} | {st['model_j']:.2f} / "
                    f"{st['plan_inverse_dynamics_j']:.2f} / {st['simulated_j']:.2f} | "
                    f"{st['difference_pct']:+.1f} % | {sw['model_j']:.2f} / "
                    f"{sw['plan_inverse_dynamics_j']:.2f} / {sw['simulated_j']:.2f} | "
                    f"{sw['difference_pct']:+.1f} % | {e['cycle_difference_pct']:+.1f} % |"
                )
    print("\n## Whole robot: the gap split, the trunk, the forces, what the referee supplied\n")
    print(
        "| robot | trajectory | total model / plan / sim [J] | sim vs model | model vs plan | "
        "sim vs plan | height p-p [mm] (of z0) | pitch [mrad] | speed sim / plan [m/s] | "
        "stance force model / sim [N] | PD share of gross work | feet push [N] | "
        "contacts+stops [J] | stop clearance plan / sim [mrad] | goals leg / force / height |"
    )
    print("|---|---|---|---|---|---|---|---|---|---|---|---|---|---|---|")
    for r in ok:
        for label, row in r["trajectories"].items():
            g = r["goals"][label]
            met = " / ".join("met" if g[k] else "NOT" for k in g)
            print(
                f"| {r['robot']} | {label} | {row['total_model_j']:.2f} / "
                f"{row['total_plan_inverse_dynamics_j']:.2f} / {row['total_simulated_j']:.2f} | "
                f"{row['total_difference_pct']:+.1f} % | {row['model_vs_plan_pct']:+.1f} % | "
                f"{row['simulated_vs_plan_pct']:+.1f} % | "
                f"{row['trunk_height_fluctuation_mm']:.2f} "
                f"({row['trunk_height_fluctuation_over_stance_height_pct']:.2f} %) | "
                f"{row['trunk_pitch_peak_mrad']:.1f} | {row['speed_m_s']:.3f} / "
                f"{row['planned_speed_m_s']:.3f} | {row['model_stance_force_mean_n']:.1f} / "
                f"{row['stance_force_mean_n']:.1f} | "
                f"{row['feedback_share_of_gross_work_pct']:.0f} % | "
                f"{row['internal_force_peak_n']:.1f} | {row['constraint_work_j']:+.2f} | "
                f"{row['stop_clearance_planned_mrad']:.0f} / "
                f"{row['stop_clearance_simulated_mrad']:.0f} | {met} |"
            )
    judged = [r for r in ok if r["trajectories"]["optimum"]["ensemble"] is not None]
    if judged:
        print("\n## The referee ensemble's verdict (median of ten referees, and their spread)\n")
        print(
            "| robot | trajectory | worst leg, median | largest spread [points] | "
            f"spread <= {SPREAD_GOAL_POINTS:g} points | refereeable | every leg within the goal |"
        )
        print("|---|---|---|---|---|---|---|")
        for r in judged:
            for label, row in r["trajectories"].items():
                e = row["ensemble"]
                print(
                    f"| {r['robot']} | {label} | {e['worst_leg_median_pct']:+.1f} % | "
                    f"{e['largest_spread_points']:.1f} | "
                    f"{'met' if e['largest_spread_points'] <= SPREAD_GOAL_POINTS else 'NOT met'} | "
                    f"{'yes' if e['refereeable'] else 'NO'} | {'met' if e['met'] else 'NOT met'} |"
                )
    print("\n## Savings of the default optimum over the reference\n")
    print("| robot | family | model | simulated | apart [points] | simulated spread [points] |")
    print("|---|---|---|---|---|---|")
    for r in ok:
        spread = r["saving_simulated_spread_points"]
        print(
            f"| {r['robot']} | {r['optimum_family']} | {r['saving_model_pct']:+.1f} % | "
            f"{r['saving_simulated_pct']:+.1f} % | "
            f"{abs(r['saving_simulated_pct'] - r['saving_model_pct']):.1f} | "
            + ("n/a" if spread is None else f"{spread:.1f}")
            + " |"
        )


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--quick", action="store_true", help="3 cycles, the nominal referee alone")
    parser.add_argument("--robots", default=",".join(ROBOTS), help="comma-separated robots")
    parser.add_argument("--loads", choices=tuple(LOAD_MODELS), default=DEFAULT_LOADS)
    parser.add_argument("--out", type=Path, default=Path("results/whole_robot_validation"))
    args = parser.parse_args(argv)
    started = time.perf_counter()
    cycles = 3 if args.quick else 10
    names = [n.strip() for n in args.robots.split(",") if n.strip()]
    results = [run_robot(name, args.out, cycles, not args.quick, args.loads) for name in names]
    print_tables(results, cycles)
    write_atomic(
        args.out / "whole_robot_validation.json",
        to_json({"cycles": cycles, "loads": args.loads, "results": results}),
    )
    print(f"\nwrote {args.out} ({time.perf_counter() - started:.0f} s)")
    return 0


if __name__ == "__main__":
    sys.exit(main())
