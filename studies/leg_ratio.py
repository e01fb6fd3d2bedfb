"""Thigh-to-shank length ratio on SCalf variants of the same total leg length, at the paper's trot.

Each variant keeps SCalf's leg length ``L = l1 + l2 = 0.85586 m`` and gives it the ratio
``r = l1 / l2``: ``l1 = L r / (1 + r)``, ``l2 = L / (1 + r)``. A link's mass scales with its
length (the same tube, longer or shorter); the cylinders and their mounts stay (see
``scalf-opt variant``). Every variant walks the paper's trot at z0 = 0.75 m (T = 0.5 s,
S = 0.25 m, H = 0.08 m), so only the leg changes; a ratio whose stance leaves the joint limits is
recorded as failed. SCalf's own ratio is 450.99 / 404.87 = 1.114.

    python studies/leg_ratio.py [--quick] [--out DIR] [--workers N]

Writes ``leg_ratio.toml``, ``results.csv`` and ``study.png`` in DIR (default results/leg_ratio).
--quick: three ratios (SCalf's among them), family joint-3 (the tests run it).
"""

from __future__ import annotations

import sys

from scalf_opt.studies.script import run_study_script
from scalf_opt.studies.table import results_table

THIGH_M, SHANK_M = 0.45099, 0.40487  # SCalf, Table 1
SCALF_RATIO = THIGH_M / SHANK_M
FULL = (0.8, 0.9, 1.0, SCALF_RATIO, 1.2, 1.3, 1.4)
QUICK = (1.0, SCALF_RATIO, 1.2)


def scales(ratio: float) -> tuple[float, float]:
    """(thigh, shank) length scales that give ``ratio`` at SCalf's total leg length."""
    total = THIGH_M + SHANK_M
    return total * ratio / (1.0 + ratio) / THIGH_M, total / (1.0 + ratio) / SHANK_M


def study_text(quick: bool) -> str:
    points = []
    for ratio in QUICK if quick else FULL:
        thigh, shank = scales(ratio)
        points.append(f"[{thigh!r}, {shank!r}, {thigh!r}, {shank!r}]")
    body = ",\n    ".join(points)
    axis = " + ".join(
        f"variant.{link}_{kind}_scale" for kind in ("length", "mass") for link in ("thigh", "shank")
    )
    return f"""# Written by studies/leg_ratio.py
# l1 = L r / (1 + r), l2 = L / (1 + r); a link's mass scales with its length
[study]
name = "thigh-to-shank ratio (SCalf variants, L = 0.85586 m)"
robot = "scalf"
family = "{"joint-3" if quick else "joint-6"}"
[gait]
period_s = 0.5
step_length_m = 0.25
clearance_m = 0.08
stance_height_m = 0.75
[sweep]
"{axis}" = [
    {body},
]
[plot]
x = "thigh_to_shank"
"""


def main(argv: list[str] | None = None) -> int:
    study, result, _ = run_study_script(
        argv,
        __doc__,
        study_text,
        file_name="leg_ratio.toml",
        default_out="results/leg_ratio",
        quick_help="three ratios, family joint-3",
    )
    print(results_table(study.name, result))
    return 0 if not result.failed else 3


if __name__ == "__main__":
    sys.exit(main())
