"""Settings of the trot simulation: time step, joint servo, ground contact.

The paper does not give its simulator's settings (Webots) nor the robot's servo gains; these are
chosen, derived from the robot and stated in ``simulation.json`` (``settings`` and
``settings_derivation``):

* **time step** 0.5 ms (semi-implicit Euler): every time constant below is at least 2 steps.
* **joint servo**: a PD loop per joint whose gains give a closed-loop natural frequency ``f`` and
  damping ratio ``zeta`` on the joint's own inertia ``I`` (the diagonal of the leg's mass matrix
  at touch-down, so the robot's masses set the gains): ``K_p = I (2 pi f)^2``,
  ``K_d = 2 zeta I (2 pi f)``. ``f`` scales with the robot's leg length ``L`` the way every time
  of dynamically similar robots does, ``f = N_servo sqrt(g / L) / (2 pi)``, with
  :data:`SERVO_FREQUENCY_OVER_PENDULUM` chosen so that SCalf (L = 0.856 m) gets 30 Hz; Go1
  (0.426 m) gets 42.5 Hz, Solo12 (0.32 m) 49 Hz. The URDF's effort limit clips the torque (the
  fraction of clipped steps is in the result).
* **contact**: MuJoCo's soft contact with damping ratio 1 and time constant
  ``t_c = N_contact sqrt(L / g)`` (2 ms on SCalf): the static sink of a soft contact grows with
  ``g t_c^2``, so every robot sinks the same fraction of its leg length. Coulomb friction 1.0.
* **feet**: spheres of radius :data:`DEFAULT_FOOT_RADIUS_FRACTION` of the leg length (4.3 mm on
  SCalf): nearly the point feet the energy model assumes. A large round foot rolls during the
  stance, which carries the trunk ``r dphi`` further than planned (SCalf's 30 mm collision sphere:
  the trunk walked 3.5 % fast); ``foot_radius_m`` sets another radius.

A derived frequency above the step's stability limit (:data:`MAX_SERVO_STEP_PHASE`) or a time
constant below two steps is raised or lowered to the limit, and the derivation says so.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, fields, replace

from scalf_opt.errors import ConfigError
from scalf_opt.locomotion.forces import GRAVITY_M_S2

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
    servo_bandwidth_hz: float | None = None
    servo_damping_ratio: float = 1.0
    foot_friction: float = 1.0
    contact_time_constant_s: float | None = None
    contact_damping_ratio: float = 1.0
    foot_radius_m: float | None = None

    def __post_init__(self) -> None:
        for field in fields(self):
            value = getattr(self, field.name)
            if value is None and field.name in DERIVED_FIELDS:
                continue
            ok = isinstance(value, int | float) and not isinstance(value, bool)
            if not (ok and math.isfinite(value) and value > 0):
                raise ConfigError(f"simulation setting {field.name} = {value!r} must be > 0")
        if self.servo_bandwidth_hz is None:
            pass
        elif (
            phase := 2 * math.pi * self.servo_bandwidth_hz * self.timestep_s
        ) > MAX_SERVO_STEP_PHASE:
            raise ConfigError(
                f"simulation setting servo_bandwidth_hz = {self.servo_bandwidth_hz!r} is too high "
                f"for the time step {self.timestep_s} s (2 pi f dt = {phase:.3f} > "
                f"{MAX_SERVO_STEP_PHASE})"
            )
        tc = self.contact_time_constant_s
        if tc is not None and tc < 2 * self.timestep_s:
            raise ConfigError(
                f"simulation setting contact_time_constant_s = {self.contact_time_constant_s!r} "
                f"must be at least two time steps ({2 * self.timestep_s} s)"
            )

    def to_dict(self) -> dict[str, float | None]:
        """The settings as plain data."""
        return {f.name: getattr(self, f.name) for f in fields(self)}

    def for_leg_length(self, leg_length_m: float) -> tuple[SimSettings, dict[str, str]]:
        """These settings with every derived field (``None``) set for a robot of leg length ``L``.

        Args:
            leg_length_m: The robot's leg length, thigh + shank [m].

        Returns:
            The complete settings, and per field set here how its value was found (a sentence
            for ``simulation.json``); fields given explicitly are not in it.
        """
        length = float(leg_length_m)
        root_g_over_l = math.sqrt(GRAVITY_M_S2 / length)
        values: dict[str, float] = {}
        how: dict[str, str] = {}
        if self.servo_bandwidth_hz is None:
            f = SERVO_FREQUENCY_OVER_PENDULUM * root_g_over_l / (2 * math.pi)
            how["servo_bandwidth_hz"] = (
                f"{SERVO_FREQUENCY_OVER_PENDULUM:g} sqrt(g / L) / (2 pi), L = {length:.4g} m"
            )
            f_max = MAX_SERVO_STEP_PHASE / (2 * math.pi * self.timestep_s)
            if f > f_max:
                how["servo_bandwidth_hz"] += f" ({f:.4g} Hz), lowered to the step's limit"
                f = f_max
            values["servo_bandwidth_hz"] = f
        if self.contact_time_constant_s is None:
            tc = CONTACT_TIME_CONSTANT_OVER_FALL * length / math.sqrt(GRAVITY_M_S2 * length)
            how["contact_time_constant_s"] = (
                f"{CONTACT_TIME_CONSTANT_OVER_FALL:g} sqrt(L / g), L = {length:.4g} m"
            )
            if tc < 2 * self.timestep_s:
                how["contact_time_constant_s"] += f" ({tc:.3g} s), raised to two time steps"
                tc = 2 * self.timestep_s
            values["contact_time_constant_s"] = tc
        if self.foot_radius_m is None:
            values["foot_radius_m"] = DEFAULT_FOOT_RADIUS_FRACTION * length
            how["foot_radius_m"] = (
                f"{DEFAULT_FOOT_RADIUS_FRACTION:g} L, L = {length:.4g} m (nearly point feet)"
            )
        return replace(self, **values), how


DERIVED_FIELDS = ("servo_bandwidth_hz", "contact_time_constant_s", "foot_radius_m")
"""Settings that, left ``None``, are derived from the robot (:meth:`SimSettings.for_leg_length`)."""

SERVO_FREQUENCY_OVER_PENDULUM = 55.7
"""The servo's natural frequency over the leg's pendulum frequency ``sqrt(g / L) / (2 pi)``:
30.0 Hz on SCalf (L = 0.8559 m), the frequency this servo was first tuned at."""

CONTACT_TIME_CONSTANT_OVER_FALL = 0.00677
"""The contact's time constant over ``sqrt(L / g)``: 2 ms on SCalf."""

DEFAULT_FOOT_RADIUS_FRACTION = 0.005
"""Foot radius as a fraction of the leg's length (thigh + shank): 4.3 mm on SCalf, 1.6 mm on
Solo12; small enough that the foot's rolling moves the trunk by under 0.3 % of the step."""
