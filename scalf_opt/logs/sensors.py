"""What SCalf's cylinder sensors would log of a joint motion: sample rate, accuracy, noise.

SCalf's controller (a cRIO-9039) logs at 80 Hz; each cylinder has a position sensor of 0.1 mm
accuracy and a force sensor of 0 to 14,000 N at 0.5 % of full scale, 70 N (Section 2 and 6.2).
The log of a joint motion ``q(t)``, ``tau(t)`` (a simulation's record, or the model's samples)
samples it at the logging rate (linear interpolation between the given samples) and converts it
with the cylinder's own mapping, ``l = l(q)`` and ``F = tau / (dl/dq)``; each reading then gets
an independent Gaussian error whose standard deviation is the sensor's accuracy (a conservative
reading of "accuracy"), from a seeded generator, so that the same seed gives the same log.
"""

from __future__ import annotations

from collections.abc import Mapping
from dataclasses import dataclass

import numpy as np

from scalf_opt.actuators.cylinder import HydraulicCylinder
from scalf_opt.logs.log_file import CylinderLog, LegLog

FORCE_SENSOR_RANGE_N = 14000.0
"""Full scale of SCalf's cylinder force sensors [N]."""


@dataclass(frozen=True)
class SensorModel:
    """Logging rate and accuracy of the cylinder sensors (defaults: SCalf's).

    Attributes:
        rate_hz: Logging rate [Hz].
        position_accuracy_m: Standard deviation of a length reading [m].
        force_accuracy_n: Standard deviation of a force reading [N].
    """

    rate_hz: float = 80.0
    position_accuracy_m: float = 1e-4
    force_accuracy_n: float = 0.005 * FORCE_SENSOR_RANGE_N

    @classmethod
    def exact(cls, rate_hz: float) -> SensorModel:
        """Noiseless sensors at ``rate_hz`` (for cross-checks)."""
        return cls(rate_hz, 0.0, 0.0)


@dataclass(frozen=True)
class JointMotion:
    """One leg's joint motion over time, as recorded.

    Attributes:
        t_s: Times, shape (n,) [s].
        q_rad: (hip pitch, knee) angles, shape (2, n) [rad].
        tau_nm: Joint torques, shape (2, n) [N m].
        contact: Foot on the ground, shape (n,), or ``None``.
    """

    t_s: np.ndarray
    q_rad: np.ndarray
    tau_nm: np.ndarray
    contact: np.ndarray | None = None


def sensor_log(
    motions: Mapping[str, JointMotion],
    cylinders: Mapping[str, tuple[HydraulicCylinder, HydraulicCylinder]],
    sensors: SensorModel,
    seed: int,
    source: str = "simulated log",
) -> CylinderLog:
    """The log the sensors would record of each leg's motion (module docstring).

    Args:
        motions: Per leg, its joint motion.
        cylinders: Per leg, its (hip pitch, knee) cylinders.
        sensors: Rate and accuracy.
        seed: Seed of the noise.
        source: Name of the log for messages.
    """
    rng = np.random.default_rng(seed)
    legs = {}
    for leg, motion in motions.items():
        t_first, t_last = float(motion.t_s[0]), float(motion.t_s[-1])
        count = int(np.floor((t_last - t_first) * sensors.rate_hz + 1e-9)) + 1
        t = t_first + np.arange(count) / sensors.rate_hz
        lengths, forces = np.zeros((2, count)), np.zeros((2, count))
        for j, cylinder in enumerate(cylinders[leg]):
            q = np.interp(t, motion.t_s, motion.q_rad[j])
            tau = np.interp(t, motion.t_s, motion.tau_nm[j])
            lengths[j] = np.array(cylinder.length_m(q)).ravel()
            forces[j] = tau / np.array(cylinder.moment_arm_m(q)).ravel()
        lengths += rng.normal(0.0, 1.0, lengths.shape) * sensors.position_accuracy_m
        forces += rng.normal(0.0, 1.0, forces.shape) * sensors.force_accuracy_n
        contact = None
        if motion.contact is not None:
            nearest = np.clip(np.searchsorted(motion.t_s, t), 0, motion.t_s.size - 1)
            contact = np.asarray(motion.contact, dtype=bool)[nearest]
        legs[leg] = LegLog(t, lengths, forces, contact, np.arange(count))
    return CylinderLog(source, legs)
