"""Check the energy model against physics (MuJoCo) and the log pipeline against known energies.

python studies/simulation_validation.py [--quick] [--from DIR] [--out DIR]

1. The reference and the default optimum (`scalf-opt optimize`: joint-6, Ipopt, RF and LH,
   LF and RH by symmetry; or the swings of DIR/summary.json), simulated for 10 cycles (2 with
   --quick): trunk height and pitch, foot forces, joint energy against the model, the saving.
2. How much those numbers depend on the simulation's chosen settings: the servo's bandwidth,
   the contact's stiffness and the time step.
3. The cylinder-log pipeline on an 80 Hz log of each simulated run (3 cycles): noiseless, and
   with the sensors' noise over 20 seeds (5 with --quick), against the run's own energy over the
   same cycles; and on 80 Hz logs of the model's own samples, per phase.

Writes DIR/validation.json, the optimum's summary.json (DIR/optimum-swings) and the two runs'
simulation.json and simulation.png under DIR
(default results/simulation_validation).
"""

from __future__ import annotations

import argparse
import sys
import time
from dataclasses import replace
from pathlib import Path
from typing import Any

# isort: off
import scalf_opt as so  # first: it pins OpenBLAS's kernels before numpy loads

# isort: on
import numpy as np

from scalf_opt.energy.pipeline import EnergyPipeline
from scalf_opt.files import write_atomic
from scalf_opt.io.results import to_json
from scalf_opt.io.saved import read_saved_swings
from scalf_opt.logs.analysis import analyze_log, leg_cylinders
from scalf_opt.logs.model_log import model_log
from scalf_opt.logs.sensors import JointMotion, SensorModel, sensor_log
from scalf_opt.sim.experiment import run_trot
from scalf_opt.sim.metrics import windowed_mechanical_energy_j
from scalf_opt.sim.plan import REFERENCE_SWINGS, planned_cycle
from scalf_opt.sim.settings import SimSettings
from scalf_opt.types import FIRST_PAIR, LEG_NAMES


def results_row(label: str, data: dict[str, Any]) -> dict[str, Any]:
    energy = data["joint_energy_per_cycle_j"]
    worst = max(LEG_NAMES, key=lambda leg: abs(energy[leg]["relative_difference"]))
    row = {
        "trajectory": label,
        "height_fluctuation_mm": 1e3 * data["trunk_height_fluctuation_m"],
        "pitch_peak_mrad": 1e3 * data["trunk_pitch_peak_rad"],
        "speed_m_s": data["forward_speed_m_s"],
        "stance_force_mean_n": float(np.mean(list(data["stance_force_mean_n"].values()))),
        "stance_force_peak_n": max(data["stance_force_peak_n"].values()),
        "slip_mm": 1e3 * max(data["foot_slip_m"].values()),
        "energy_sim_j": data["total_energy_per_cycle_j"]["simulated"],
        "energy_model_j": data["total_energy_per_cycle_j"]["model"],
        "energy_difference_pct": 100 * data["total_energy_per_cycle_j"]["relative_difference"],
        "largest_leg_difference_pct": 100 * energy[worst]["relative_difference"],
        "largest_leg": worst,
        "sim_vs_plan_pct": 100
        * (
            data["total_energy_per_cycle_j"]["simulated"]
            / sum(
                e["stance"] + e["swing"]
                for e in data["plan_inverse_dynamics"]["joint_energy_per_phase_j"].values()
            )
            - 1
        ),
    }
    if "saving_vs_reference" in data:
        row["saving_model_pct"] = data["saving_vs_reference"]["model_percent"]
        row["saving_sim_pct"] = data["saving_vs_reference"]["simulated_percent"]
    return row


def print_results(rows: list[dict[str, Any]], cycles: int) -> None:
    print(f"\n## Simulated trot ({cycles} cycles, the first excluded), servo 30 Hz\n")
    print(
        "| trajectory | trunk height p-p [mm] | pitch peak [mrad] | speed [m/s] | stance force "
        "mean / peak [N] | slip [mm] | joint energy sim / model [J/cycle] | difference "
        "(largest leg) | saving model / sim |"
    )
    print("|---|---|---|---|---|---|---|---|---|")
    for r in rows:
        saving = (
            f"{r['saving_model_pct']:+.2f} % / {r['saving_sim_pct']:+.2f} %"
            if "saving_model_pct" in r
            else ""
        )
        print(
            f"| {r['trajectory']} | {r['height_fluctuation_mm']:.2f} | {r['pitch_peak_mrad']:.2f} "
            f"| {r['speed_m_s']:.3f} | {r['stance_force_mean_n']:.0f} / "
            f"{r['stance_force_peak_n']:.0f} | {r['slip_mm']:.2f} | {r['energy_sim_j']:.2f} / "
            f"{r['energy_model_j']:.2f} | {r['energy_difference_pct']:+.2f} % "
            f"({r['largest_leg']} {r['largest_leg_difference_pct']:+.2f} %) | {saving} |"
        )


def sensitivity(
    robot, pipeline, optimum, cycles: int, quick: bool, default: tuple[dict, dict]
) -> list[dict[str, Any]]:
    """Each setting's reference and optimum runs; ``default``: the two runs at the defaults."""
    cases = [("servo 30 Hz (default)", SimSettings())]
    if not quick:
        cases += [
            ("servo 20 Hz", SimSettings(servo_bandwidth_hz=20.0)),
            ("servo 40 Hz", SimSettings(servo_bandwidth_hz=40.0)),
            ("servo 50 Hz", SimSettings(servo_bandwidth_hz=50.0)),
            ("contact 4 ms", SimSettings(contact_time_constant_s=0.004)),
            ("time step 0.25 ms", SimSettings(timestep_s=0.00025)),
        ]
    rows = []
    for label, settings in cases:
        if settings == SimSettings():  # simulated already (deterministic: the same numbers)
            ref, opt = default
        else:
            ref = run_trot(robot, pipeline, REFERENCE_SWINGS, settings, cycles).result
            opt = run_trot(robot, pipeline, optimum, settings, cycles).result
        r, o = ref["total_energy_per_cycle_j"], opt["total_energy_per_cycle_j"]
        rows.append(
            {
                "settings": label,
                "height_ref_mm": 1e3 * ref["trunk_height_fluctuation_m"],
                "height_opt_mm": 1e3 * opt["trunk_height_fluctuation_m"],
                "energy_ref_pct": 100 * r["relative_difference"],
                "energy_opt_pct": 100 * o["relative_difference"],
                "largest_leg_opt_pct": 100
                * max(
                    (e["relative_difference"] for e in opt["joint_energy_per_cycle_j"].values()),
                    key=abs,
                ),
                "saving_sim_pct": 100 * (o["simulated"] / r["simulated"] - 1),
                "saving_model_pct": 100 * (o["model"] / r["model"] - 1),
            }
        )
    print(f"\n## Sensitivity to the simulation's settings ({cycles} cycles)\n")
    print(
        "| settings | height p-p ref / opt [mm] | energy vs model ref / opt (largest leg) | "
        "saving sim (model) |"
    )
    print("|---|---|---|---|")
    for r in rows:
        print(
            f"| {r['settings']} | {r['height_ref_mm']:.2f} / {r['height_opt_mm']:.2f} | "
            f"{r['energy_ref_pct']:+.2f} % / {r['energy_opt_pct']:+.2f} % "
            f"({r['largest_leg_opt_pct']:+.2f} %) | {r['saving_sim_pct']:+.2f} % "
            f"({r['saving_model_pct']:+.2f} %) |"
        )
    return rows


def log_recovery(robot, pipeline, swings, label: str, seeds: int) -> dict[str, Any]:
    """An 80 Hz log of a 3-cycle run against the run's own mechanical energy, same cycles."""
    record = run_trot(robot, pipeline, swings, SimSettings(), 3).record
    motions = {
        leg: JointMotion(record.t_s, record.q_rad[leg], record.tau_nm[leg], record.in_contact(leg))
        for leg in LEG_NAMES
    }
    cylinders = {leg: leg_cylinders(pipeline, leg) for leg in LEG_NAMES}

    def errors(sensors: SensorModel, seed: int) -> list[float]:
        analysis = analyze_log(sensor_log(motions, cylinders, sensors, seed), pipeline)
        out, got_total, sim_total = [], 0.0, 0.0
        for leg in LEG_NAMES:
            windows = analysis.legs[leg].windows_s
            sim = windowed_mechanical_energy_j(pipeline, record, leg, windows)
            got = analysis.legs[leg].mechanical_j["cycle"]
            out.append(100 * (got / sim - 1))
            got_total += got
            sim_total += sim
        return [*out, 100 * (got_total / sim_total - 1)]

    exact = errors(SensorModel.exact(80.0), 0)
    noisy = np.array([errors(SensorModel(), seed) for seed in range(seeds)])
    return {
        "trajectory": label,
        "noiseless_pct": exact,
        "noisy_mean_pct": noisy.mean(axis=0).tolist(),
        "noisy_std_pct": noisy.std(axis=0).tolist(),
        "noisy_min_pct": noisy.min(axis=0).tolist(),
        "noisy_max_pct": noisy.max(axis=0).tolist(),
    }


def model_log_errors(pipeline, swings, label: str) -> dict[str, Any]:
    """An 80 Hz noiseless log of the model's own samples against the model, per phase [%].

    The model's energy is taken at 2 kHz (converged in the sample rate): at 80 Hz its own
    trapezoidal sum is off too (the optimum's RF swing: 14.3 J at 80 Hz, 9.6 J at 2 kHz).
    """
    log, cycle = model_log(pipeline, swings, 80.0, cycles=6)
    analysis = analyze_log(log, pipeline)
    fine = replace(pipeline, gait=replace(pipeline.gait, sample_rate_hz=2000.0))
    exact = planned_cycle(fine, swings)
    out: dict[str, Any] = {"trajectory": label}
    for leg in FIRST_PAIR:
        leg_cycle = exact.legs[leg]
        model = {
            "stance": leg_cycle.stance_energy_j - float(leg_cycle.stance.loss_j.sum()),
            "swing": leg_cycle.swing_energy_j - float(leg_cycle.swing.loss_j.sum()),
        }
        model["cycle"] = model["stance"] + model["swing"]
        got = analysis.legs[leg].mechanical_j
        out[leg] = {phase: 100 * (got[phase] / model[phase] - 1) for phase in model}
    del cycle
    return out


def print_log_tables(recovery: list[dict[str, Any]], model_logs: list[dict[str, Any]], seeds: int):
    print(f"\n## Log pipeline on the simulated runs' 80 Hz logs (3 cycles; noise: {seeds} seeds)\n")
    print("| trajectory | log | " + " | ".join(LEG_NAMES) + " | robot |")
    print("|---|---|" + "---|" * (len(LEG_NAMES) + 1))
    for r in recovery:
        cells = [f"{v:+.2f} %" for v in r["noiseless_pct"]]
        print(f"| {r['trajectory']} | noiseless | " + " | ".join(cells) + " |")
        cells = [
            f"{lo:+.1f} to {hi:+.1f} % (sd {sd:.1f})"
            for lo, hi, sd in zip(
                r["noisy_min_pct"], r["noisy_max_pct"], r["noisy_std_pct"], strict=True
            )
        ]
        print(f"| {r['trajectory']} | with noise | " + " | ".join(cells) + " |")
    print("\n## Log pipeline on 80 Hz noiseless logs of the model's own samples (per phase)\n")
    print("| trajectory | RF stance | RF swing | RF cycle | LH stance | LH swing | LH cycle |")
    print("|---|---|---|---|---|---|---|")
    for r in model_logs:
        cells = [f"{r[leg][p]:+.2f} %" for leg in FIRST_PAIR for p in ("stance", "swing", "cycle")]
        print(f"| {r['trajectory']} | " + " | ".join(cells) + " |")


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--quick", action="store_true", help="2 cycles, 5 seeds, no sensitivity")
    parser.add_argument("--from", dest="source", type=Path, help="the optimum's summary.json DIR")
    parser.add_argument("--out", type=Path, default=Path("results/simulation_validation"))
    args = parser.parse_args(argv)
    started = time.perf_counter()
    cycles, seeds = (2, 5) if args.quick else (10, 20)
    robot = so.load_robot("scalf")
    source = args.source
    if source is None:  # `scalf-opt optimize --out DIR`: joint-6, Ipopt, RF and LH
        optimized = so.optimize_swing(robot)
        if not optimized.success:
            raise RuntimeError("the default optimization did not converge")
        source = args.out / "optimum-swings"
        optimized.write(source)
    planned = read_saved_swings(source)
    planned.check_robot(robot)
    pipeline, optimum = EnergyPipeline(robot, planned.gait), planned.require_all_legs()
    label = f"optimum ({optimum['RF'][0]})"
    rows, runs = [], []
    for name, run in (
        ("reference", so.simulate(robot, planned.gait, cycles=cycles)),
        ("optimum", so.simulate(robot, swings_from=source, cycles=cycles)),
    ):
        run.write(args.out / name)
        rows.append(results_row("reference" if name == "reference" else label, run.data))
        runs.append(run.data)
    print_results(rows, cycles)
    sensitivity_rows = sensitivity(robot, pipeline, optimum, cycles, args.quick, tuple(runs))
    recovery = [
        log_recovery(robot, pipeline, REFERENCE_SWINGS, "reference", seeds),
        log_recovery(robot, pipeline, optimum, label, seeds),
    ]
    model_logs = [
        model_log_errors(pipeline, REFERENCE_SWINGS, "reference"),
        model_log_errors(pipeline, optimum, label),
    ]
    print_log_tables(recovery, model_logs, seeds)
    write_atomic(
        args.out / "validation.json",
        to_json(
            {
                "cycles": cycles,
                "results": rows,
                "sensitivity": sensitivity_rows,
                "log_recovery": recovery,
                "model_logs": model_logs,
            }
        ),
    )
    print(f"\nwrote {args.out} ({time.perf_counter() - started:.1f} s)")
    return 0


if __name__ == "__main__":
    sys.exit(main())
