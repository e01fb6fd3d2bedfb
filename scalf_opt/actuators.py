"""Hydraulic cylinders: mounting geometry (Table 2, decision 7) and Stribeck friction (decision 8).

Geometry. A cylinder spans the triangle formed by its two mounting arms ``a`` and ``b``, which
meet at the joint axis with angle ``phi``; by the law of cosines (Eq. 52)::

    l(theta)      = sqrt(a^2 + b^2 - 2 a b cos(phi)),     phi = phi_offset + sign * theta
    dl/dtheta     = sign * a b sin(phi) / l                  [m/rad]
    v             = (dl/dtheta) theta_dot                     cylinder velocity [m/s]
    F_cylinder    = tau / (dl/dtheta)                         virtual work [N]

For the RF leg, hip ``phi = (90 deg - e1 - e2) - theta`` and knee ``phi = theta - (e3 - e4)``;
hind legs use the negated angle (the ``sign`` flips).

Friction (Eq. 50-51). With the parameter row chosen by the sign of ``v`` (extension ``v > 0``,
retraction ``v < 0``)::

    F_f(v) = sign(v) (F_c + (F_s - F_c) exp(-|v| / v_s)) + B v

and the heat rate is ``|F_f(v) v| = h_ext(max(v, 0)) + h_ret(max(-v, 0))`` with
``h(u) = u (F_c + (F_s - F_c) exp(-u / v_s)) + B u^2`` (exact, because ``h(0) = 0`` and
``F_f(v) v >= 0``). Replacing ``max`` by a smooth max gives the NLP's differentiable heat.

Every formula is written once with CasADi operations: it accepts floats, numpy scalars, DM, SX
and MX alike.
"""

from __future__ import annotations

import math
from collections.abc import Callable
from dataclasses import dataclass
from pathlib import Path
from typing import TYPE_CHECKING, Any

import casadi as ca

from scalf_opt.errors import ConfigError
from scalf_opt.tomlfile import read_toml

if TYPE_CHECKING:
    from scalf_opt.robot import Robot


@dataclass(frozen=True)
class StribeckBranch:
    """Stribeck parameters for one direction of motion (SI units)."""

    viscous_n_s_per_m: float
    static_n: float
    coulomb_n: float
    stribeck_velocity_m_s: float


@dataclass(frozen=True)
class StribeckFriction:
    """Asymmetric cylinder friction: one branch per direction (decision 8)."""

    extend: StribeckBranch
    retract: StribeckBranch


@dataclass(frozen=True)
class HydraulicCylinder:
    """A joint's hydraulic cylinder.

    Attributes:
        joint_name: URDF joint it drives.
        a_m: Mounting arm a [m].
        b_m: Mounting arm b [m].
        phi_offset_rad: Arm angle at theta = 0 [rad].
        angle_sign: +1 or -1: ``phi = phi_offset + angle_sign * theta``.
        stroke_m: Piston stroke [m].
        friction: Friction law of the cylinder.
    """

    joint_name: str
    a_m: float
    b_m: float
    phi_offset_rad: float
    angle_sign: int
    stroke_m: float
    friction: StribeckFriction


def cylinder_angle(cyl: HydraulicCylinder, theta: Any) -> Any:
    """Angle phi between the mounting arms [rad] at joint angle ``theta`` [rad]."""
    return cyl.phi_offset_rad + cyl.angle_sign * theta


def cylinder_length(cyl: HydraulicCylinder, theta: Any) -> Any:
    """Cylinder length [m] at joint angle ``theta`` [rad] (law of cosines)."""
    phi = cylinder_angle(cyl, theta)
    return ca.sqrt(cyl.a_m**2 + cyl.b_m**2 - 2 * cyl.a_m * cyl.b_m * ca.cos(phi))


def cylinder_length_rate(cyl: HydraulicCylinder, theta: Any) -> Any:
    """dl/dtheta [m/rad]: the cylinder's moment arm, signed."""
    phi = cylinder_angle(cyl, theta)
    return cyl.angle_sign * cyl.a_m * cyl.b_m * ca.sin(phi) / cylinder_length(cyl, theta)


def friction_force(friction: StribeckFriction, v: Any) -> Any:
    """Stribeck friction force [N] at cylinder velocity ``v`` [m/s] (0 at v = 0)."""

    def branch(p: StribeckBranch, sign: float) -> Any:
        decay = ca.exp(-ca.fabs(v) / p.stribeck_velocity_m_s)
        return sign * (p.coulomb_n + (p.static_n - p.coulomb_n) * decay) + p.viscous_n_s_per_m * v

    return ca.if_else(
        v > 0, branch(friction.extend, 1.0), ca.if_else(v < 0, branch(friction.retract, -1.0), 0.0)
    )


def _heat(p: StribeckBranch, u: Any) -> Any:
    """h(u) = u (F_c + (F_s - F_c) exp(-u / v_s)) + B u^2 for a speed u >= 0 [W]."""
    decay = ca.exp(-u / p.stribeck_velocity_m_s)
    return u * (p.coulomb_n + (p.static_n - p.coulomb_n) * decay) + p.viscous_n_s_per_m * u**2


def friction_heat_rate(
    friction: StribeckFriction, v: Any, max_fn: Callable[[Any, Any], Any] = ca.fmax
) -> Any:
    """Heat rate ``|F_f(v) v|`` [W] at cylinder velocity ``v`` [m/s].

    Args:
        friction: The friction law.
        v: Cylinder velocity [m/s].
        max_fn: ``max(x, 0)``; :func:`ca.fmax` for the exact heat, or a smooth max.
    """
    return _heat(friction.extend, max_fn(v, 0)) + _heat(friction.retract, max_fn(-v, 0))


def smooth_max(x: Any, eps: float) -> Any:
    """Smooth ``max(x, 0)`` = ``(x + sqrt(x^2 + eps^2)) / 2``; overestimates by at most eps/2."""
    return 0.5 * (x + ca.sqrt(x**2 + eps**2))


def stroke_limits_m(
    cyl: HydraulicCylinder, theta_lower: float, theta_upper: float
) -> tuple[float, float]:
    """Cylinder length range allowed by the stroke [m]: the shorter end-of-range length + stroke.

    ``l`` is monotonic over each joint's range (phi stays inside (0, pi)), so the shortest length
    is at one of the joint limits.
    """
    lengths = [float(cylinder_length(cyl, t)) for t in (theta_lower, theta_upper)]
    phis = [float(cylinder_angle(cyl, t)) for t in (theta_lower, theta_upper)]
    if not all(0.0 < p < math.pi for p in phis):
        raise ConfigError(
            f"cylinder {cyl.joint_name}: mounting angle leaves (0, pi) over the joint range"
        )
    shortest = min(lengths)
    return shortest, shortest + cyl.stroke_m


# --- the actuator file ------------------------------------------------------------------------
_BRANCH_KEYS = ("viscous_n_s_per_m", "static_n", "coulomb_n", "stribeck_velocity_m_s")
_CYLINDER_KEYS = ("a_mm", "b_mm", "phi_offset_deg", "angle_sign", "stroke_mm")


def _number(path: Path, key: str, value: Any, positive: bool = True) -> float:
    ok = isinstance(value, int | float) and not isinstance(value, bool) and math.isfinite(value)
    if not ok or (positive and value <= 0):
        need = "a positive number" if positive else "a number"
        raise ConfigError(f"{path}: {key} must be {need}, got {value!r}")
    return float(value)


def _table(path: Path, data: dict[str, Any], key: str) -> dict[str, Any]:
    value = data.get(key)
    if not isinstance(value, dict):
        raise ConfigError(f"{path}: missing table [{key}]")
    return value


def _branch(path: Path, data: dict[str, Any], key: str) -> StribeckBranch:
    table = _table(path, data, key)
    for extra in set(table) - set(_BRANCH_KEYS):
        raise ConfigError(f"{path}: unknown key {key}.{extra}")
    values = []
    for name in _BRANCH_KEYS:
        if name not in table:
            raise ConfigError(f"{path}: missing key {key}.{name}")
        values.append(_number(path, f"{key}.{name}", table[name]))
    return StribeckBranch(*values)


def load_actuators(path: str | Path) -> dict[str, HydraulicCylinder]:
    """Read an actuator file (TOML) into cylinders keyed by joint name.

    Raises:
        ConfigError: Unreadable file, TOML syntax error, missing, unknown or invalid key (the
            message names the file and the key).
    """
    path = Path(path)
    data = read_toml(path, "actuator")
    friction_table = _table(path, data, "friction")
    friction = StribeckFriction(
        extend=_branch(path, {"friction.extend": friction_table.get("extend")}, "friction.extend"),
        retract=_branch(
            path, {"friction.retract": friction_table.get("retract")}, "friction.retract"
        ),
    )
    cylinders = _table(path, data, "cylinders")
    out: dict[str, HydraulicCylinder] = {}
    for joint, table in cylinders.items():
        prefix = f"cylinders.{joint}"
        if not isinstance(table, dict):
            raise ConfigError(f"{path}: [{prefix}] must be a table")
        for extra in set(table) - set(_CYLINDER_KEYS):
            raise ConfigError(f"{path}: unknown key {prefix}.{extra}")
        for name in _CYLINDER_KEYS:
            if name not in table:
                raise ConfigError(f"{path}: missing key {prefix}.{name}")
        sign = table["angle_sign"]
        if sign not in (1, -1) or isinstance(sign, bool):
            raise ConfigError(f"{path}: {prefix}.angle_sign must be +1 or -1, got {sign!r}")
        out[joint] = HydraulicCylinder(
            joint_name=joint,
            a_m=_number(path, f"{prefix}.a_mm", table["a_mm"]) * 1e-3,
            b_m=_number(path, f"{prefix}.b_mm", table["b_mm"]) * 1e-3,
            phi_offset_rad=math.radians(
                _number(path, f"{prefix}.phi_offset_deg", table["phi_offset_deg"], positive=False)
            ),
            angle_sign=int(sign),
            stroke_m=_number(path, f"{prefix}.stroke_mm", table["stroke_mm"]) * 1e-3,
            friction=friction,
        )
    if not out:
        raise ConfigError(f"{path}: [cylinders] is empty")
    return out


def actuator_path_for(urdf_path: str | Path) -> Path:
    """The actuator file that belongs to a URDF: ``<name>_actuators.toml`` beside it."""
    urdf_path = Path(urdf_path)
    return urdf_path.with_name(f"{urdf_path.stem}_actuators.toml")


def load_actuators_for(robot: Robot) -> dict[str, HydraulicCylinder]:
    """The robot's cylinders from the actuator file beside its URDF.

    Without such a file the result is ``{}``: every joint has an ideal actuator (no cylinder, no
    friction).
    """
    path = actuator_path_for(robot.urdf_path)
    if not path.is_file():
        return {}
    cylinders = load_actuators(path)
    for joint in cylinders:
        if not robot.model.existJointName(joint):
            raise ConfigError(f"{path}: cylinders.{joint} names no joint of {robot.urdf_path}")
    return cylinders
