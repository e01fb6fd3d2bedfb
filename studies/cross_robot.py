"""Six robots, one question: how much energy does an optimized swing save on each?

SCalf, HyQ, Solo12, ANYmal C, Unitree Go1 and A1, each on its own default trot (the paper's trot
scaled to the robot's leg length, at the same Froude number, and its own stance height) with its
own drives (SCalf: the paper's cylinders with Stribeck friction; HyQ: valve-controlled cylinders,
pressure x flow; the others: electric drives with copper loss). The reference swing (cubic
spline) against the Ipopt optimum of the diagonal pair (LF, RH by symmetry): energy per gait
cycle, percent saved, cost of transport.

    python studies/cross_robot.py [--quick] [--out DIR] [--workers N]

Writes ``cross_robot.toml`` (the study file), ``results.csv``, ``study.png`` and ``table.md`` (the
README's table) in DIR (default results/cross_robot). --quick: family joint-3 (the tests run it);
the full run uses the default family, joint-6.
"""

from __future__ import annotations

import sys

from scalf_opt.actuators.sidecar import drives_for
from scalf_opt.files import write_atomic
from scalf_opt.robots.catalog import robot_names
from scalf_opt.robots.loading import load_robot
from scalf_opt.studies.runner import StudyRun
from scalf_opt.studies.script import run_study_script

DRIVE_NAMES = {
    "cylinder": "hydraulic cylinders, Stribeck friction (paper)",
    "valve_cylinder": "valve-controlled cylinders, pressure x flow",
    "electric": "electric, copper loss + joint friction",
    "ideal": "ideal",
}


def study_text(quick: bool) -> str:
    robots = ", ".join(f'"{name}"' for name in robot_names())
    return f"""# Written by studies/cross_robot.py
[study]
name = "six robots, each on its own Froude-similar trot"
family = "{"joint-3" if quick else "joint-6"}"
[sweep]
robot = [{robots}]
"""


def table(result: StudyRun) -> str:
    lines = [
        "| robot | drives | mass [kg] | speed [m/s] | reference [J/cycle] | optimized [J/cycle] "
        "| saved | CoT reference | CoT optimized |",
        "|---|---|---|---|---|---|---|---|---|",
    ]
    for row in result.rows:
        robot = load_robot(row["robot"])
        leg = robot.leg("RF")
        kind = {drives_for(robot).get(j).kind for j in leg.joint_names}  # type: ignore[union-attr]
        drives = ", ".join(DRIVE_NAMES.get(k, k) for k in sorted(kind))
        if row["status"] != "ok":
            lines.append(
                f"| {row['robot']} | {drives} | | | | | {row['status']}: {row['error']} | | |"
            )
            continue
        lines.append(
            f"| {row['robot']} | {drives} | {row['total_mass_kg']:.2f} | {row['speed_m_s']:.3f} "
            f"| {row['reference_energy_j']:.3f} | {row['optimized_energy_j']:.3f} "
            f"| {row['saving_pct']:.1f} % | {row['cost_of_transport_reference']:.3f} "
            f"| {row['cost_of_transport_optimized']:.3f} |"
        )
    return "\n".join(lines) + "\n"


def main(argv: list[str] | None = None) -> int:
    _, result, out = run_study_script(
        argv,
        __doc__,
        study_text,
        file_name="cross_robot.toml",
        default_out="results/cross_robot",
        quick_help="family joint-3",
    )
    text = table(result)
    write_atomic(out / "table.md", text)
    print(text, end="")
    print(f"wrote {result.results_path}, {result.figure_path} and {out / 'table.md'}")
    return 0 if not result.failed else 3


if __name__ == "__main__":
    sys.exit(main())
