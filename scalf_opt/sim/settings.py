"""Settings of the trot simulation: time step, joint servo, ground contact.

The paper does not give its simulator's settings (Webots) nor the robot's servo gains; these are
chosen and documented (README, "Validation against physics and logs"):

* **time step** 0.5 ms (semi-implicit Euler): every time constant below is at least 4 steps.
* **joint servo**: a PD loop per joint whose gains give a chosen closed-loop natural frequency
  ``f`` and damping ratio ``zeta`` on the joint's own inertia ``I`` (the diagonal of the leg's
  mass matrix at touch-down): ``K_p = I (2 pi f)^2``, ``K_d = 2 zeta I (2 pi f)``. Scaling by the
  inertia makes the same ``f`` mean the same stiffness on any robot (SCalf or Solo12).
* **contact**: MuJoCo's soft contact with time constant 2 ms and damping ratio 1 (a stiff
  ground: the trunk sinks about 0.5 mm under the robot's weight), Coulomb friction 1.0.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, fields

from scalf_opt.errors import ConfigError

MAX_SERVO_STEP_PHASE = 0.2
"""Largest ``2 pi f dt`` allowed: the explicit PD loop stays well inside its stability limit."""


@dataclass(frozen=True)
class SimSettings:
    """How the trot is simulated.

    Attributes:
        timestep_s: Integration step [s].
        servo_bandwidth_hz: Closed-loop natural frequency ``f`` of each joint's PD loop [Hz].
        servo_damping_ratio: Damping ratio ``zeta`` of the PD loop.
        foot_friction: Coulomb friction coefficient between feet and ground.
        contact_time_constant_s: MuJoCo ``solref`` time constant of the foot contact [s].
        contact_damping_ratio: MuJoCo ``solref`` damping ratio of the foot contact.
        foot_radius_m: Radius of the spherical feet [m]; ``None`` takes the URDF's foot collision
            sphere (SCalf: 30 mm, HyQ: 21.75 mm), else :data:`DEFAULT_FOOT_RADIUS_FRACTION` of
            the leg's length.
    """

    timestep_s: float = 0.0005
    servo_bandwidth_hz: float = 30.0
    servo_damping_ratio: float = 1.0
    foot_friction: float = 1.0
    contact_time_constant_s: float = 0.002
    contact_damping_ratio: float = 1.0
    foot_radius_m: float | None = None

    def __post_init__(self) -> None:
        for field in fields(self):
            value = getattr(self, field.name)
            if value is None and field.name == "foot_radius_m":
                continue
            ok = isinstance(value, int | float) and not isinstance(value, bool)
            if not (ok and math.isfinite(value) and value > 0):
                raise ConfigError(f"simulation setting {field.name} = {value!r} must be > 0")
        phase = 2 * math.pi * self.servo_bandwidth_hz * self.timestep_s
        if phase > MAX_SERVO_STEP_PHASE:
            raise ConfigError(
                f"simulation setting servo_bandwidth_hz = {self.servo_bandwidth_hz!r} is too high "
                f"for the time step {self.timestep_s} s (2 pi f dt = {phase:.3f} > "
                f"{MAX_SERVO_STEP_PHASE})"
            )
        if self.contact_time_constant_s < 2 * self.timestep_s:
            raise ConfigError(
                f"simulation setting contact_time_constant_s = {self.contact_time_constant_s!r} "
                f"must be at least two time steps ({2 * self.timestep_s} s)"
            )

    def to_dict(self) -> dict[str, float | None]:
        """The settings as plain data."""
        return {f.name: getattr(self, f.name) for f in fields(self)}


DEFAULT_FOOT_RADIUS_FRACTION = 0.03
"""Foot radius, as a fraction of the leg's length (thigh + shank), of a URDF without a collision
sphere at the foot (Solo12, whose foot is a mesh: 9.6 mm)."""
