"""The planned trot the simulated legs track: joint angles, rates and feed-forward torques.

Everything comes from the energy pipeline (:class:`~scalf_opt.energy.pipeline.EnergyPipeline`),
evaluated on a grid as fine as the simulation's time step: per leg and phase the joint motion
``q, qd`` (closed-form IK of the planned foot path, or the joint-space swing) and the torque
``tau = M qdd + C qd + G - J^T F`` with the minimum-norm stance forces. Between grid samples the
plan is interpolated linearly, inside one phase at a time: at touch-down and lift-off the planned
torque jumps (the stance force appears and vanishes at once), and the plan keeps that jump.
"""

from __future__ import annotations

from collections.abc import Mapping
from dataclasses import dataclass, replace

import numpy as np

from scalf_opt.energy.cycle import RobotCycle
from scalf_opt.energy.pipeline import EnergyPipeline
from scalf_opt.energy.swings import REFERENCE_SWINGS, SwingChoice, planned_cycle
from scalf_opt.locomotion.trot import stance_start_s

__all__ = ["PHASE_EDGE_S", "REFERENCE_SWINGS", "SwingChoice", "TrotPlan", "planned_cycle"]

PHASE_EDGE_S = 1e-9
"""A time within this of lift-off counts as swing (the stance ends there)."""


@dataclass(frozen=True)
class TrotPlan:
    """The planned joint motion and torque of every leg, periodic in the gait cycle.

    Attributes:
        cycle: The planned cycle on a fine grid (every leg's stance and swing samples).
    """

    cycle: RobotCycle

    @classmethod
    def build(
        cls, pipeline: EnergyPipeline, swings: Mapping[str, SwingChoice], rate_hz: float
    ) -> TrotPlan:
        """Sample the plan at (at least) ``rate_hz`` [Hz] through the pipeline."""
        dense = pipeline.with_gait(replace(pipeline.gait, sample_rate_hz=rate_hz))
        return cls(planned_cycle(dense, swings))

    def since_touchdown_s(self, leg: str, t_s: np.ndarray) -> np.ndarray:
        """Time since ``leg``'s last planned touch-down at times ``t_s``, in [0, T) [s]."""
        gait = self.cycle.gait
        return np.mod(np.asarray(t_s, dtype=float) - stance_start_s(gait, leg), gait.period_s)

    def in_stance(self, leg: str, t_s: np.ndarray) -> np.ndarray:
        """Whether ``leg`` is planned on the ground at times ``t_s`` [s] (boolean, shape (n,))."""
        return self.since_touchdown_s(leg, t_s) < self.cycle.gait.stance_duration_s - PHASE_EDGE_S

    def scheduled_stance(self, leg: str, t_s: np.ndarray, touchdown_shift_s: float) -> np.ndarray:
        """Whether the controller calls ``leg`` in stance at times ``t_s`` (boolean, (n,)).

        Its touch-down runs ``touchdown_shift_s`` [s] late against the plan (negative: early);
        its lift-off is the plan's.
        """
        planned = self.in_stance(leg, t_s)
        if touchdown_shift_s == 0.0:
            return planned
        since = self.since_touchdown_s(leg, t_s)
        if touchdown_shift_s > 0:
            return planned & (since >= touchdown_shift_s)
        return planned | (since >= self.cycle.gait.period_s + touchdown_shift_s)

    def sample(
        self, leg: str, t_s: np.ndarray, names: tuple[str, ...] = ("q", "qd", "tau")
    ) -> dict[str, np.ndarray]:
        """Planned ``q`` [rad], ``qd`` [rad/s] and ``tau`` [N m] of ``leg`` at times ``t_s``.

        Args:
            leg: The leg.
            t_s: Times [s].
            names: The per-sample quantities to give (two-row ones: ``qdd`` too).

        Returns:
            Arrays of shape (2, n), rows (hip pitch, knee), keyed by ``names``.
        """
        gait = self.cycle.gait
        t = np.asarray(t_s, dtype=float)
        local = np.mod(t - stance_start_s(gait, leg), gait.period_s)
        stance = self.in_stance(leg, t)
        out = {name: np.zeros((2, t.size)) for name in names}
        leg_cycle = self.cycle.legs[leg]
        for phase, mask, offset in (
            (leg_cycle.stance, stance, 0.0),
            (leg_cycle.swing, ~stance, gait.stance_duration_s),
        ):
            for name, values in out.items():
                for row in range(2):
                    values[row, mask] = np.interp(
                        local[mask] - offset, phase.t_phase_s, phase.values[name][row]
                    )
        return out
