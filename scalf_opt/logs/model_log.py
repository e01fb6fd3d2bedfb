"""The cylinder log a perfect robot would record of the model's own motion (for cross-checks).

The pipeline's planned cycle, sampled on the gait's grid at the log's rate, repeated over several
periods, converted by the cylinders' mapping without noise. Each phase's last sample is dropped
(it is the next phase's first): a log holds one value per instant, so at lift-off it has the
swing's (no foot force), at touch-down the stance's. Fed to the log analysis
(:mod:`scalf_opt.logs.analysis`), it must give back the model's mechanical energy, up to what
sampling at that rate loses.
"""

from __future__ import annotations

from collections.abc import Mapping
from dataclasses import replace

import numpy as np

from scalf_opt.energy.cycle import RobotCycle
from scalf_opt.energy.pipeline import EnergyPipeline
from scalf_opt.energy.swings import SwingChoice, planned_cycle
from scalf_opt.locomotion.trot import stance_start_s
from scalf_opt.logs.analysis import leg_cylinders
from scalf_opt.logs.log_file import CylinderLog
from scalf_opt.logs.sensors import JointMotion, SensorModel, sensor_log


def model_log(
    pipeline: EnergyPipeline, swings: Mapping[str, SwingChoice], rate_hz: float, cycles: int
) -> tuple[CylinderLog, RobotCycle]:
    """The noiseless log of ``cycles`` periods of the planned motion at ``rate_hz`` [Hz].

    Returns the log (t = 0: RF and LH touch down) and the planned cycle on that grid.

    Raises:
        LogError: A leg has no hydraulic cylinders.
    """
    gait = replace(pipeline.gait, sample_rate_hz=rate_hz)
    cycle: RobotCycle = planned_cycle(pipeline.with_gait(gait), swings)
    motions = {}
    for leg, leg_cycle in cycle.legs.items():
        stance, swing = leg_cycle.stance, leg_cycle.swing
        t_one = np.concatenate(
            [stance.t_phase_s[:-1], gait.stance_duration_s + swing.t_phase_s[:-1]]
        )
        q_one = np.hstack([stance.values["q"][:, :-1], swing.values["q"][:, :-1]])
        tau_one = np.hstack([stance.values["tau"][:, :-1], swing.values["tau"][:, :-1]])
        contact_one = np.arange(t_one.size) < stance.t_phase_s.size - 1
        offset = stance_start_s(gait, leg)
        t = np.concatenate([t_one + offset + k * gait.period_s for k in range(-1, cycles + 1)])
        keep = (t >= -1e-12) & (t <= cycles * gait.period_s + 1e-12)
        reps = cycles + 2
        motions[leg] = JointMotion(
            t[keep],
            np.tile(q_one, reps)[:, keep],
            np.tile(tau_one, reps)[:, keep],
            np.tile(contact_one, reps)[keep],
        )
    cylinders = {leg: leg_cylinders(pipeline, leg) for leg in motions}
    return sensor_log(
        motions, cylinders, SensorModel.exact(rate_hz), seed=0, source="model log"
    ), cycle
