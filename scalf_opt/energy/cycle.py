"""Results of one gait cycle: per leg (stance and swing) and for the whole robot."""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from scalf_opt.energy.phase import PhaseResult
from scalf_opt.locomotion.forces import GRAVITY_M_S2
from scalf_opt.locomotion.gait import Gait
from scalf_opt.locomotion.trot import SYMMETRIC_TWIN
from scalf_opt.types import FIRST_PAIR, Accounting


def energy_basis(loads: str, accounting: str, sample_rate_hz: float) -> str:
    """What a printed energy of the model is: its stance loads, accounting and sample rate.

    The same motion's energy differs with each (SCalf's reference: 382.299 J whole-body at
    200 Hz, 381.999 J at 300 Hz, 282.259 J under the trunk-only loads), so every command that
    prints one says which.
    """
    return f"loads '{loads}', accounting '{accounting}', {sample_rate_hz:.4g} Hz"


def change_percent(new: float, reference: float) -> float:
    """Signed change of ``new`` against ``reference`` [%]."""
    return 100.0 * (new - reference) / reference


@dataclass(frozen=True)
class LegCycle:
    """One leg over one cycle: stance then swing, and the swing that was evaluated.

    Attributes:
        leg: Leg name.
        stance: The stance phase.
        swing: The swing phase.
        swing_family: Name of the swing family.
        swing_theta: The family's parameters (family units; empty for the reference).
    """

    leg: str
    stance: PhaseResult
    swing: PhaseResult
    swing_family: str
    swing_theta: np.ndarray

    @property
    def energy_j(self) -> float:
        """Energy of the leg over one cycle [J]."""
        return float(self.stance.energy_j.sum() + self.swing.energy_j.sum())

    @property
    def stance_energy_j(self) -> float:
        """Energy of both joints during stance [J]."""
        return float(self.stance.energy_j.sum())

    @property
    def swing_energy_j(self) -> float:
        """Energy of both joints during swing [J]."""
        return float(self.swing.energy_j.sum())

    @property
    def loss_j(self) -> float:
        """The drives' losses over the cycle (SCalf: friction heat) [J]."""
        return float(self.stance.loss_j.sum() + self.swing.loss_j.sum())


@dataclass(frozen=True)
class RobotCycle:
    """All legs over one gait cycle, and the robot-level figures.

    Attributes:
        gait: The gait.
        accounting: Power accounting used for ``power``.
        legs: LegCycle per leg name, in :data:`~scalf_opt.types.LEG_NAMES` order.
        total_mass_kg: Mass of the whole robot (for the cost of transport) [kg].
        loads: The stance load model (:mod:`scalf_opt.energy.loads`).
    """

    gait: Gait
    accounting: Accounting
    legs: dict[str, LegCycle]
    total_mass_kg: float
    loads: str = "whole-body"

    @property
    def peak_unbalanced_moment_nm(self) -> float:
        """Largest moment the stance feet could not supply, over every stance sample [N m]."""
        peaks = [np.linalg.norm(c.stance.unbalanced_nm, axis=0).max() for c in self.legs.values()]
        return float(max(peaks, default=0.0))

    @property
    def mean_stance_force_n(self) -> float:
        """Mean magnitude of the stance foot force over every stance sample and leg [N]."""
        norms = [
            np.hypot(
                np.hypot(c.stance.values["grf"][0], c.stance.values["grf"][1]),
                c.stance.grf_lateral_n,
            ).mean()
            for c in self.legs.values()
        ]
        return float(np.mean(norms))

    @property
    def basis(self) -> str:
        """What this cycle's energies are (:func:`energy_basis`)."""
        return energy_basis(self.loads, self.accounting, self.gait.sample_rate_hz)

    @property
    def energy_j(self) -> float:
        """Energy of all legs over one cycle [J] (mean of ``gait.cycles`` identical cycles)."""
        return float(sum(leg.energy_j for leg in self.legs.values()))

    @property
    def average_power_w(self) -> float:
        """Average total leg power [W]: energy per cycle / period."""
        return self.energy_j / self.gait.period_s

    @property
    def cost_of_transport(self) -> float:
        """Dimensionless cost of transport: E / (m g d) over one cycle."""
        return self.energy_j / (self.total_mass_kg * GRAVITY_M_S2 * self.gait.distance_per_cycle_m)

    @property
    def symmetry_error(self) -> float:
        """Largest relative difference of LF vs RF and RH vs LH cycle energy (paper: 0)."""
        errs = [
            abs(self.legs[a].energy_j - self.legs[b].energy_j) / abs(self.legs[b].energy_j)
            for b in FIRST_PAIR
            if (a := SYMMETRIC_TWIN[b]) in self.legs and b in self.legs
        ]
        return max(errs, default=0.0)
