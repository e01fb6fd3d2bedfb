"""The loop closed in simulation: export the optimum as a bag, run it in MuJoCo, log the run as a
ROS 2 bag, analyze the bag against the plan, and get what the CSV path gets."""

import re
from pathlib import Path

import pytest

from scalf_opt.api import analyze_log, export_plan, simulate
from scalf_opt.cli import main
from scalf_opt.energy.pipeline import EnergyPipeline
from scalf_opt.io.ros_bag import read_joint_states
from scalf_opt.sim.metrics import windowed_mechanical_energy_j
from scalf_opt.types import LEG_NAMES

TRAPEZOID_RTOL = 0.01
"""The 1 kHz trapezoid of the 2 kHz steps' power: measured 0.03 to 0.2 % per leg with a joint
servo in stance, up to 0.57 % with the stance loop on the trunk (its torques carry more above
500 Hz: 0.1 to 0.2 % of their power, against 0.02 to 0.13 %)."""

pytestmark = pytest.mark.slow  # an optimization and two 3-cycle simulations: about 10 s


def test_export_simulate_and_analyze_the_bag(optimum, scalf, tmp_path):
    plan = export_plan(optimum, scalf, rate_hz=1000, cycles=3)
    planned = read_joint_states(plan.write(tmp_path / "plan.mcap"), "/plan/joint_states")
    assert planned.names == tuple(n for leg in LEG_NAMES for n in scalf.leg(leg).joint_names)

    run = simulate(scalf, swings_from=optimum, cycles=3)
    csv, bag = run.write_log(tmp_path / "run.csv"), run.write_log(tmp_path / "run.mcap")
    by_csv = analyze_log(csv, scalf, plan=optimum).to_dict()
    joints = analyze_log(bag, scalf, topic="/joint_states", plan=optimum).to_dict()
    sensors = analyze_log(bag, scalf, topic="/cylinder_states", plan=optimum).to_dict()
    assert joints["velocity_source"] == "measured" and sensors["velocity_source"] == "filter"
    assert joints["period_source"] == sensors["period_source"] == "motion"
    assert joints["period_s"] == pytest.approx(0.5, rel=2e-3)

    # the CSV path: SCalf's 80 Hz sensors with their noise, cycles from the contacts
    reference = by_csv["plan_comparison"]
    # the same cylinder readings over other windows (the motion's period, not the contacts):
    # the same energy within 2 % (measured 1.1 % on the whole-body optimum, 0.6 % on the
    # trunk-only one, whose swing is gentler); the joints they come from, at 1 kHz with their
    # measured rates, more (measured +0.7 % to +4.2 %): the 80 Hz lengths differentiated by the
    # 75 ms cubic smooth the stance's fast power changes (the feedback, the touch-down jumps)
    for result, rtol in ((sensors, 0.02), (joints, 0.06)):
        comparison = result["plan_comparison"]
        assert comparison["measured_average_power_w"] == pytest.approx(
            reference["measured_average_power_w"], rel=rtol
        )
    assert (
        joints["plan_comparison"]["measured_average_power_w"]
        > (reference["measured_average_power_w"])
    )
    # the simulation's own mechanical joint energy over the bag's windows: the joint states
    # hold the step's own torque and rate, so only the 1 kHz trapezoid differs
    pipeline = EnergyPipeline(scalf, plan.export.saved.gait)
    windows = analyze_log(bag, scalf, topic="/joint_states", plan=optimum).analysis.legs
    for leg in LEG_NAMES:
        simulated = windowed_mechanical_energy_j(pipeline, run.record, leg, windows[leg].windows_s)
        measured = joints["mechanical_energy_per_cycle_j"][leg]
        assert measured == pytest.approx(simulated, rel=TRAPEZOID_RTOL)


def test_the_pages_numbers_are_these_commands(optimum, tmp_path, capsys):
    """docs/plan-to-robot.md quotes these commands' output (the same 3-cycle run)."""
    page = (Path(__file__).parents[2] / "docs" / "plan-to-robot.md").read_text()
    bag, csv = tmp_path / "run.mcap", tmp_path / "run.csv"
    sim = ["simulate", "--from", str(optimum), "--cycles", "3", "--out", str(tmp_path), "-q"]
    assert main([*sim, "--log", str(bag)]) == 0 and main([*sim, "--log", str(csv)]) == 0
    for log, topic in ((bag, "/joint_states"), (bag, "/cylinder_states"), (csv, None)):
        argv = ["analyze-log", str(log), "--plan", str(optimum)]
        assert main(argv + (["--topic", topic] if topic else [])) == 0
        out = capsys.readouterr().out
        line = next(x for x in out.splitlines() if x.startswith("average power:"))
        measured, _, change = re.findall(r"[-+]?[\d.]+ (?:W|%)", line)
        assert f"| {measured} | {change} |" in page, line
        if topic == "/joint_states":
            assert line in page
            for row in out.splitlines()[1:11]:  # all but the first, which names the file
                assert row in page
