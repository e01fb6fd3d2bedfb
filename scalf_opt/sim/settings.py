"""Settings of the trot simulation: time step, joint servo, ground contact.

The paper does not give its simulator's settings (Webots) nor the robot's servo gains; these are
chosen, derived from the robot and stated in ``simulation.json`` (``settings`` and
``settings_derivation``):

* **time step** 0.5 ms (semi-implicit Euler), or less when the servo's frequency asks for it
  (``2 pi f dt`` at most :data:`MAX_SERVO_STEP_PHASE`) or the contact's time constant (at least
  two steps).
* **servo** (:mod:`scalf_opt.sim.control`): feed-forward plus feedback loops (each swing joint's,
  and in stance the trunk's) of closed-loop natural frequency ``f`` and damping ratio ``zeta``
  on their own inertia (a joint's, the trunk's with the feet on the ground: the robot's masses
  set the gains). ``f`` scales with the robot's leg length ``L`` the way every time
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

Every derived value and how it was found is in ``simulation.json`` (``settings_derivation``).
"""

from __future__ import annotations

import math
from dataclasses import dataclass, fields, replace
from typing import Any

from scalf_opt.errors import ConfigError
from scalf_opt.locomotion.forces import GRAVITY_M_S2

MAX_SERVO_STEP_PHASE = 0.2
"""Largest ``2 pi f dt`` allowed: the explicit PD loop stays well inside its stability limit."""

MAX_SCHEDULE_SHIFT_S = 0.05
"""Largest shift of the controller's contact schedule against the plan [s]."""


def _number(value: object) -> bool:
    return isinstance(value, int | float) and not isinstance(value, bool)


@dataclass(frozen=True)
class SimSettings:
    """How the trot is simulated.

    Attributes:
        timestep_s: Integration step [s]; ``None``: 0.5 ms or finer (module docstring).
        servo_bandwidth_hz: Closed-loop natural frequency ``f`` of each joint's PD loop [Hz].
        servo_damping_ratio: Damping ratio ``zeta`` of the PD loop.
        foot_friction: Coulomb friction coefficient between feet and ground.
        contact_time_constant_s: MuJoCo ``solref`` time constant of the foot contact [s].
        contact_damping_ratio: MuJoCo ``solref`` damping ratio of the foot contact.
        foot_radius_m: Radius of the spherical feet [m]; ``None``:
            :data:`DEFAULT_FOOT_RADIUS_FRACTION` of the leg's length.
        stance_control: ``trunk``: the stance legs' feedback is a loop on the trunk's plan;
            ``joint``: every joint's own loop, in stance too (:mod:`scalf_opt.sim.control`).
        schedule_shift_s: How late the controller detects a touch-down against the plan [s]
            (negative: early): it switches a leg from its swing loop to the stance loop this
            much after the planned touch-down (early: this much before it, the foot still in
            the air); lift-off, the feed-forward and the measurements keep the plan's times.
    """

    timestep_s: float | None = None
    servo_bandwidth_hz: float | None = None
    servo_damping_ratio: float = 1.0
    foot_friction: float = 1.0
    contact_time_constant_s: float | None = None
    contact_damping_ratio: float = 1.0
    foot_radius_m: float | None = None
    stance_control: str = "trunk"
    schedule_shift_s: float = 0.0

    def __post_init__(self) -> None:
        if self.stance_control not in STANCE_CONTROLS:
            raise ConfigError(
                f"simulation setting stance_control = {self.stance_control!r} must be one of "
                + ", ".join(STANCE_CONTROLS)
            )
        for field in fields(self):
            value = getattr(self, field.name)
            if field.name == "stance_control" or (value is None and field.name in DERIVED_FIELDS):
                continue
            if field.name == "schedule_shift_s":
                if not (_number(value) and abs(value) <= MAX_SCHEDULE_SHIFT_S):
                    raise ConfigError(
                        f"simulation setting schedule_shift_s = {value!r} must be within "
                        f"+-{MAX_SCHEDULE_SHIFT_S} s"
                    )
                continue
            if not (_number(value) and math.isfinite(value) and value > 0):
                raise ConfigError(f"simulation setting {field.name} = {value!r} must be > 0")
        dt, f, tc = self.timestep_s, self.servo_bandwidth_hz, self.contact_time_constant_s
        if dt is not None and f is not None and 2 * math.pi * f * dt > MAX_SERVO_STEP_PHASE:
            raise ConfigError(
                f"simulation setting servo_bandwidth_hz = {f!r} is too high for the time step "
                f"{dt} s (2 pi f dt = {2 * math.pi * f * dt:.3f} > {MAX_SERVO_STEP_PHASE})"
            )
        if dt is not None and tc is not None and tc < 2 * dt:
            raise ConfigError(
                f"simulation setting contact_time_constant_s = {tc!r} must be at least two time "
                f"steps ({2 * dt} s)"
            )

    def value(self, name: str) -> float:
        """A numeric setting, which must be set (:meth:`for_leg_length` sets the derived ones).

        Raises:
            ValueError: The setting is still ``None`` (a programming error).
        """
        value = getattr(self, name)
        if value is None:
            raise ValueError(f"simulation setting {name} is derived: call for_leg_length first")
        return float(value)

    def to_dict(self) -> dict[str, float | str | None]:
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
        values: dict[str, Any] = {}
        how: dict[str, str] = {}
        f = self.servo_bandwidth_hz
        if f is None:
            f = SERVO_FREQUENCY_OVER_PENDULUM * root_g_over_l / (2 * math.pi)
            how["servo_bandwidth_hz"] = (
                f"{SERVO_FREQUENCY_OVER_PENDULUM:g} sqrt(g / L) / (2 pi), L = {length:.4g} m"
            )
            if self.timestep_s is not None:
                f_max = MAX_SERVO_STEP_PHASE / (2 * math.pi * self.timestep_s)
                if f > f_max:
                    how["servo_bandwidth_hz"] += f" ({f:.4g} Hz), lowered to the step's limit"
                    f = f_max
            values["servo_bandwidth_hz"] = f
        tc = self.contact_time_constant_s
        if tc is None:
            tc = CONTACT_TIME_CONSTANT_OVER_FALL / root_g_over_l
            how["contact_time_constant_s"] = (
                f"{CONTACT_TIME_CONSTANT_OVER_FALL:g} sqrt(L / g), L = {length:.4g} m"
            )
            if self.timestep_s is not None and tc < 2 * self.timestep_s:
                how["contact_time_constant_s"] += f" ({tc:.3g} s), raised to two time steps"
                tc = 2 * self.timestep_s
            values["contact_time_constant_s"] = tc
        if self.timestep_s is None:
            dt = min(DEFAULT_TIMESTEP_S, MAX_SERVO_STEP_PHASE / (2 * math.pi * f), tc / 2)
            values["timestep_s"] = dt
            how["timestep_s"] = (
                f"min({1e3 * DEFAULT_TIMESTEP_S:g} ms, {MAX_SERVO_STEP_PHASE:g} / (2 pi f), "
                "t_c / 2)"
            )
        if self.foot_radius_m is None:
            values["foot_radius_m"] = DEFAULT_FOOT_RADIUS_FRACTION * length
            how["foot_radius_m"] = (
                f"{DEFAULT_FOOT_RADIUS_FRACTION:g} L, L = {length:.4g} m (nearly point feet)"
            )
        return replace(self, **values), how


STANCE_CONTROLS = ("trunk", "joint")
"""The stance legs' feedback: on the trunk's plan, or each joint's own."""

DERIVED_FIELDS = ("timestep_s", "servo_bandwidth_hz", "contact_time_constant_s", "foot_radius_m")
"""Settings that, left ``None``, are derived from the robot (:meth:`SimSettings.for_leg_length`)."""

DEFAULT_TIMESTEP_S = 0.0005
"""The time step when nothing asks for a finer one [s]."""

SERVO_FREQUENCY_OVER_PENDULUM = 55.7
"""The servo's natural frequency over the leg's pendulum frequency ``sqrt(g / L) / (2 pi)``:
30.0 Hz on SCalf (L = 0.8559 m), the frequency this servo was first tuned at."""

CONTACT_TIME_CONSTANT_OVER_FALL = 0.00677
"""The contact's time constant over ``sqrt(L / g)``: 2 ms on SCalf."""

DEFAULT_FOOT_RADIUS_FRACTION = 0.005
"""Foot radius as a fraction of the leg's length (thigh + shank): 4.3 mm on SCalf, 1.6 mm on
Solo12; small enough that the foot's rolling moves the trunk by under 0.3 % of the step."""
