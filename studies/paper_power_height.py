"""Which stance height z0 gives the paper's reference power, 671.52 W (Table 6)?

The paper does not give z0; we take 0.75 m (decision 6), where our reference trajectory draws
564.52 W, 15.9 % below the paper's 671.52 W. This study scans the reference power of SCalf's
cubic-spline trot over z0 (the paper's gait otherwise), finds by Brent's method the z0 inside the
feasible range at which it equals 671.52 W, and there optimizes the paper family and the richest
default family (Ipopt) to compare the saving with Table 6 (-8.02 % of the total energy).

    python studies/paper_power_height.py [--quick] [--out DIR]

Writes ``scan.csv`` (z0, average power, feasible), ``result.csv`` (the z0 found and the
optimizations there) and ``power_vs_height.png`` in DIR (default results/paper_power_height).
--quick: a coarse scan and the paper family only (the tests run it).
"""

from __future__ import annotations

import argparse
import sys
from pathlib import Path

# isort: off
import scalf_opt  # noqa: F401 (first: it pins OpenBLAS's kernels before numpy loads)

# isort: on
import numpy as np
from scipy.optimize import brentq

from scalf_opt.energy.cycle import change_percent
from scalf_opt.energy.pipeline import EnergyPipeline
from scalf_opt.errors import GaitError
from scalf_opt.files import write_atomic
from scalf_opt.io.results import rows_csv_text
from scalf_opt.locomotion.gait import Gait
from scalf_opt.locomotion.swing.registry import make_family
from scalf_opt.optimize.driver import optimize_swings
from scalf_opt.robots.loading import load_robot
from scalf_opt.studies.paper_data import (
    OPTIMIZED_AVERAGE_POWER_W,
    REFERENCE_AVERAGE_POWER_W,
    TABLE6_CHANGE_PERCENT,
)
from scalf_opt.viz.figures import save_atomic
from scalf_opt.viz.study_figures import scan_figure

ROBOT = load_robot("scalf")


def reference_power_w(height_m: float) -> float:
    """Average total power of the reference trot at stance height ``height_m`` [W]."""
    pipeline = EnergyPipeline(ROBOT, Gait(stance_height_m=height_m), loads="trunk")
    return pipeline.robot_cycle(make_family("reference")).average_power_w


def scan(heights: np.ndarray) -> list[dict[str, object]]:
    rows: list[dict[str, object]] = []
    for z0 in heights:
        try:
            rows.append(
                {"stance_height_m": float(z0), "power_w": reference_power_w(z0), "feasible": True}
            )
        except GaitError:
            rows.append({"stance_height_m": float(z0), "power_w": None, "feasible": False})
    return rows


def optimized(height_m: float, family: str) -> dict[str, object]:
    pipeline = EnergyPipeline(ROBOT, Gait(stance_height_m=height_m), loads="trunk")
    run = optimize_swings(pipeline, ("RF", "LH"), make_family(family))
    solved = run.success
    reference = run.reference_cycle()  # at the optimum's converged rate, like with like
    cycle = run.cycle()
    return {
        "stance_height_m": height_m,
        "family": family,
        "solved": solved,
        "reference_power_w": reference.average_power_w,
        "optimized_power_w": cycle.average_power_w if solved else None,
        "total_change_pct": change_percent(cycle.energy_j, reference.energy_j) if solved else None,
        "RF_swing_change_pct": change_percent(
            cycle.legs["RF"].swing_energy_j, reference.legs["RF"].swing_energy_j
        )
        if solved
        else None,
        "LH_swing_change_pct": change_percent(
            cycle.legs["LH"].swing_energy_j, reference.legs["LH"].swing_energy_j
        )
        if solved
        else None,
    }


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--quick", action="store_true", help="coarse scan, paper family only")
    parser.add_argument("--out", type=Path, default=Path("results/paper_power_height"))
    args = parser.parse_args(argv)
    step = 0.02 if args.quick else 0.005
    rows = scan(np.round(np.arange(0.45, 0.86 + 1e-9, step), 4))
    feasible = [r for r in rows if r["feasible"]]
    # the power falls from the crouch to a minimum near 0.73 m and rises again until the knee
    # reaches its limit; the paper's power is met on the falling branch
    lowest = min(feasible, key=lambda r: r["power_w"])  # type: ignore[arg-type,return-value]
    below = [r for r in feasible if r["stance_height_m"] < lowest["stance_height_m"]]
    bracket = (below[0]["stance_height_m"], lowest["stance_height_m"])
    target = REFERENCE_AVERAGE_POWER_W
    root = brentq(lambda z: reference_power_w(z) - target, *bracket, xtol=1e-6)
    highest = max(
        r["power_w"] for r in feasible if r["stance_height_m"] > lowest["stance_height_m"]
    )  # type: ignore[type-var]
    families = ("paper",) if args.quick else ("paper", "joint-6")
    results = [optimized(root, f) for f in families] + [optimized(0.75, f) for f in families]
    write_atomic(args.out / "scan.csv", rows_csv_text(rows))
    write_atomic(args.out / "result.csv", rows_csv_text(results))
    fig = scan_figure(
        [r["stance_height_m"] for r in feasible],  # type: ignore[misc]
        [r["power_w"] for r in feasible],  # type: ignore[misc]
        (
            "stance height z0 [m]",
            "reference average power [W]",
            "SCalf, paper's trot: power against z0",
        ),
        target=(target, f"the paper, Table 6: {target} W"),
        marks=[
            (root, target, f"z0 = {root:.4f} m"),
            (0.75, reference_power_w(0.75), "decision 6: z0 = 0.75 m"),
        ],
    )
    save_atomic(fig, args.out / "power_vs_height.png")
    print(
        f"reference power {target} W (the paper, Table 6) at z0 = {root:.4f} m "
        f"(feasible z0: {feasible[0]['stance_height_m']}..{feasible[-1]['stance_height_m']} m; "
        f"above the power's minimum it reaches only {highest:.1f} W before the knee limit)"
    )
    print(f"{'z0 [m]':>8s} {'family':8s} {'reference W':>12s} {'optimized W':>12s} ", end="")
    print(f"{'total':>9s} {'RF swing':>9s} {'LH swing':>9s}")
    for r in results:
        changes = [r[k] for k in ("total_change_pct", "RF_swing_change_pct", "LH_swing_change_pct")]
        cells = [f"{v:+8.2f}%" if isinstance(v, float) else "     n/a " for v in changes]
        power = r["optimized_power_w"]
        opt = f"{power:12.2f}" if isinstance(power, float) else f"{'not solved':>12s}"
        print(
            f"{r['stance_height_m']:8.4f} {r['family']:8s} {r['reference_power_w']:12.2f} {opt} ",
            end="",
        )
        print(" ".join(cells))
    table6 = TABLE6_CHANGE_PERCENT
    print(
        f"the paper (Table 6): {target} -> {OPTIMIZED_AVERAGE_POWER_W} W, total "
        f"{table6['total']['total']:+.2f} %, RF swing {table6['RF']['swing']:+.2f} %, "
        f"LH swing {table6['LH']['swing']:+.2f} %"
    )
    print(f"wrote scan.csv, result.csv and power_vs_height.png in {args.out}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
