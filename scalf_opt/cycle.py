"""One gait cycle of the whole robot: stance forces, every leg's phases, energies, CoT.

Each leg is computed directly with its own Pinocchio model and its own stance forces; the paper's
symmetry argument (LF repeats RF, RH repeats LH half a cycle later) is then a check, not an input.
"""

from __future__ import annotations

from dataclasses import dataclass, field
from functools import cached_property

import numpy as np

from scalf_opt.actuators import HydraulicCylinder, load_actuators_for
from scalf_opt.energy import ACCOUNTINGS, LegPhysics, PhaseResult, evaluate_phase
from scalf_opt.errors import ConfigError, GaitError, InfeasibleError
from scalf_opt.forces import GRAVITY_M_S2, min_norm_foot_forces
from scalf_opt.gait import DIAGONAL_PARTNER, SYMMETRIC_TWIN, GaitSpec
from scalf_opt.robot import LEG_NAMES, Robot
from scalf_opt.swing import AffinePath, SwingFamily, make_family

JOINT_LIMIT_TOLERANCE_RAD = 1e-9
"""Round-off allowed beyond a joint limit before a motion counts as violating it."""


@dataclass(frozen=True)
class LegCycle:
    """One leg over one cycle: stance then swing (each a :class:`PhaseResult`)."""

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


@dataclass(frozen=True)
class RobotCycle:
    """All four legs over one gait cycle, and the robot-level figures.

    Attributes:
        gait: The gait.
        accounting: Power accounting used for ``power``.
        legs: LegCycle per leg name.
        total_mass_kg: Mass of the whole robot (for the cost of transport) [kg].
    """

    gait: GaitSpec
    accounting: str
    legs: dict[str, LegCycle]
    total_mass_kg: float

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
            for a, b in (("LF", "RF"), ("RH", "LH"))
            if a in self.legs and b in self.legs
        ]
        return max(errs, default=0.0)


@dataclass
class RobotEnergyModel:
    """Evaluates cycles of one robot for one gait; caches per-leg physics and stance data.

    Attributes:
        robot: The robot.
        gait: The gait.
        accounting: Power accounting (``paper``, ``positive`` or ``regenerative``).
        actuators: Cylinders keyed by joint name; ``None`` reads the actuator file beside the
            URDF, ``{}`` gives every joint an ideal actuator (no cylinder, no friction).
    """

    robot: Robot
    gait: GaitSpec
    accounting: str = "paper"
    actuators: dict[str, HydraulicCylinder] | None = None
    _physics: dict[str, LegPhysics] = field(default_factory=dict, repr=False)

    def __post_init__(self) -> None:
        if self.accounting not in ACCOUNTINGS:
            raise ConfigError(
                f"unknown power accounting {self.accounting!r}: use {', '.join(ACCOUNTINGS)}"
            )
        if self.actuators is None:
            self.actuators = load_actuators_for(self.robot)

    def physics(self, leg: str) -> LegPhysics:
        """The leg's :class:`LegPhysics` (built once)."""
        if leg not in self._physics:
            self._physics[leg] = LegPhysics(self.robot.leg(leg, self.actuators))
        return self._physics[leg]

    def foot_in_trunk_xz(self, leg: str, p_leg: np.ndarray) -> np.ndarray:
        """Foot positions relative to the trunk COM (x, z) from leg-frame samples (2, n) [m]."""
        hip = self.physics(leg).leg.hip_origin_m - self.robot.trunk_com_m
        return np.asarray(p_leg) + np.array([[hip[0]], [hip[2]]])

    def stance_forces(self, leg: str) -> np.ndarray:
        """Ground reaction force on ``leg``'s foot over its stance samples, shape (2, n) [N]."""
        return self._stance_data[leg][1]

    @cached_property
    def _stance_data(self) -> dict[str, tuple[np.ndarray, np.ndarray]]:
        gait = self.gait
        tau = gait.phase_times_s("stance")
        p, _, _ = gait.stance_path(tau)
        accel = gait.trunk_acceleration_m_s2(tau)
        data = {}
        for leg in LEG_NAMES:
            forces = np.zeros((2, tau.size))
            for j, tau_j in enumerate(tau):
                t = gait.stance_offset_s(leg) + tau_j
                support = gait.stance_legs_at(t, leg)
                feet = []
                for other in support:
                    local = (
                        tau_j
                        if other in (leg, DIAGONAL_PARTNER[leg])
                        else (gait.local_stance_time_s(t, other))
                    )
                    p_other = gait.stance_path(np.array([local]))[0]
                    feet.append(self.foot_in_trunk_xz(other, p_other)[:, 0])
                f = min_norm_foot_forces(np.array(feet).T, self.robot.trunk_mass_kg, accel[j])
                forces[:, j] = f[:, 0]
            data[leg] = (p, forces)
        return data

    @cached_property
    def stance_motion(self) -> tuple[np.ndarray, np.ndarray]:
        """Stance samples (3, 2, n) of the foot path and the phase's time grid (n,)."""
        tau = self.gait.phase_times_s("stance")
        return np.array(self.gait.stance_path(tau)), tau

    def check_workspace(self, leg: str, space: str, samples: np.ndarray, phase: str) -> None:
        """Refuse a path that leaves the leg's reach or joint limits.

        Raises:
            GaitError: In stance (the gait itself is impossible for this leg).
            InfeasibleError: In swing.
        """
        physics = self.physics(leg)
        try:
            q = physics.kin.inverse(samples[0]) if space == "foot" else samples[0]
            lo = physics.leg.lower_limits_rad[:, None] - JOINT_LIMIT_TOLERANCE_RAD
            hi = physics.leg.upper_limits_rad[:, None] + JOINT_LIMIT_TOLERANCE_RAD
            bad = np.argwhere((q < lo) | (q > hi))
            if bad.size:
                i, j = bad[0]
                raise InfeasibleError(
                    f"leg {leg}: the {phase} path takes joint {physics.leg.joint_names[i]} to "
                    f"{q[i, j]:.4f} rad, outside its limits "
                    f"[{physics.leg.lower_limits_rad[i]:.4f}, "
                    f"{physics.leg.upper_limits_rad[i]:.4f}] rad"
                )
        except InfeasibleError as exc:
            if phase == "swing":
                raise
            g = self.gait
            raise GaitError(
                f"gait fields stance_height_m = {g.stance_height_m:g} and step_length_m = "
                f"{g.step_length_m:g} are impossible for this robot: {exc}"
            ) from exc

    def stance(self, leg: str) -> PhaseResult:
        """Evaluate ``leg``'s stance phase."""
        samples, tau = self.stance_motion
        self.check_workspace(leg, "foot", samples, "stance")
        return evaluate_phase(
            self.physics(leg),
            "foot",
            samples,
            self.stance_forces(leg),
            tau,
            self.gait.stance_offset_s(leg),
            self.gait.period_s,
            "stance",
            self.accounting,
        )

    def swing_path(self, leg: str, family: SwingFamily) -> AffinePath:
        """The family's affine swing path for ``leg``."""
        return family.path(self.gait, self.physics(leg).kin)

    def swing(self, leg: str, family: SwingFamily, theta: np.ndarray | None = None) -> PhaseResult:
        """Evaluate ``leg``'s swing for a family member (``theta`` in the family's units)."""
        path = self.swing_path(leg, family)
        samples = path.values(theta)
        self.check_workspace(leg, path.space, samples, "swing")
        return evaluate_phase(
            self.physics(leg),
            path.space,
            samples,
            np.zeros((2, path.tau_s.size)),
            path.tau_s,
            self.gait.stance_offset_s(leg) + self.gait.stance_duration_s,
            self.gait.period_s,
            "swing",
            self.accounting,
        )

    def leg_cycle(self, leg: str, family: SwingFamily, theta: np.ndarray | None = None) -> LegCycle:
        """One leg's stance and swing."""
        theta_arr = np.zeros(family.n_params) if theta is None else np.asarray(theta, float)
        return LegCycle(
            leg, self.stance(leg), self.swing(leg, family, theta_arr), family.name, theta_arr
        )

    def robot_cycle(
        self,
        family: SwingFamily,
        thetas: dict[str, np.ndarray] | None = None,
        legs: tuple[str, ...] = LEG_NAMES,
    ) -> RobotCycle:
        """Evaluate every leg in ``legs`` with the same swing family and per-leg parameters.

        The paper's symmetry: a leg without parameters of its own takes its symmetric twin's (LF
        repeats RF, RH repeats LH). When ``thetas`` names some legs, a leg with neither its own
        nor its twin's parameters keeps the reference swing; without ``thetas`` every leg uses
        the family at zero parameters.
        """
        reference = make_family("reference")
        cycles = {}
        for leg in legs:
            if thetas is None:
                cycles[leg] = self.leg_cycle(leg, family)
            elif leg in thetas or SYMMETRIC_TWIN[leg] in thetas:
                theta = thetas[leg] if leg in thetas else thetas[SYMMETRIC_TWIN[leg]]
                cycles[leg] = self.leg_cycle(leg, family, theta)
            else:
                cycles[leg] = self.leg_cycle(leg, reference)
        return RobotCycle(self.gait, self.accounting, cycles, self.robot.total_mass_kg)
