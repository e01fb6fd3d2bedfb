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
and MX alike (a float argument gives a DM; ``float(...)`` turns it back into a number).

The data live in an actuator file (TOML, ``urdf/scalf_actuators.toml`` for SCalf) keyed by the
URDF joint a cylinder drives; :func:`load_actuators` reads and validates it.
"""

from __future__ import annotations

import math
from collections.abc import Callable
from dataclasses import dataclass
from pathlib import Path
from typing import TYPE_CHECKING, Any

import casadi as ca

from scalf_opt.errors import ConfigError, ModelError
from scalf_opt.tomlfile import read_toml

if TYPE_CHECKING:
    from scalf_opt.robot import Robot


@dataclass(frozen=True)
class StribeckBranch:
    """Stribeck parameters for one direction of motion (one row of the paper's friction table).

    Attributes:
        viscous_n_s_per_m: Viscous coefficient B [N s/m].
        static_n: Static (break-away) friction F_s [N].
        coulomb_n: Coulomb friction F_c [N].
        stribeck_velocity_m_s: Stribeck velocity v_s [m/s].
    """

    viscous_n_s_per_m: float
    static_n: float
    coulomb_n: float
    stribeck_velocity_m_s: float


@dataclass(frozen=True)
class StribeckFriction:
    """Asymmetric cylinder friction: one branch per direction (decision 8).

    Attributes:
        extend: Parameters for a cylinder velocity v > 0.
        retract: Parameters for a cylinder velocity v < 0.
    """

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
    """Angle between the mounting arms, ``phi = phi_offset + angle_sign * theta`` [rad].

    Args:
        cyl: The cylinder.
        theta: Joint angle [rad] (float, DM, SX or MX).
    """
    return cyl.phi_offset_rad + cyl.angle_sign * theta


def cylinder_length(cyl: HydraulicCylinder, theta: Any) -> Any:
    """Cylinder length ``l = sqrt(a^2 + b^2 - 2 a b cos(phi))`` [m] (Eq. 52, decision 7).

    Args:
        cyl: The cylinder.
        theta: Joint angle [rad] (float, DM, SX or MX).
    """
    phi = cylinder_angle(cyl, theta)
    return ca.sqrt(cyl.a_m**2 + cyl.b_m**2 - 2 * cyl.a_m * cyl.b_m * ca.cos(phi))


def cylinder_length_rate(cyl: HydraulicCylinder, theta: Any) -> Any:
    """Moment arm ``dl/dtheta = angle_sign * a b sin(phi) / l`` [m/rad], signed (decision 7).

    The cylinder velocity is ``(dl/dtheta) theta_dot`` [m/s] and its force ``tau / (dl/dtheta)``
    [N] (virtual work).

    Args:
        cyl: The cylinder.
        theta: Joint angle [rad] (float, DM, SX or MX).
    """
    phi = cylinder_angle(cyl, theta)
    return cyl.angle_sign * cyl.a_m * cyl.b_m * ca.sin(phi) / cylinder_length(cyl, theta)


def friction_force(friction: StribeckFriction, v: Any) -> Any:
    """Stribeck friction force [N] at cylinder velocity ``v`` [m/s] (decision 8, Eq. 50-51).

    ``F_f(v) = sign(v) (F_c + (F_s - F_c) exp(-|v| / v_s)) + B v`` with the ``extend`` row for
    ``v > 0``, the ``retract`` row for ``v < 0`` and ``F_f(0) = 0``. It jumps from ``-F_s`` to
    ``+F_s`` across ``v = 0`` (both rows have F_s = 50 N for SCalf).

    Args:
        friction: The friction law.
        v: Cylinder velocity [m/s] (float, DM, SX or MX).
    """

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
    """Friction heat rate ``|F_f(v) v|`` [W] at cylinder velocity ``v`` [m/s] (decisions 8, 9).

    Written as ``h_extend(max(v, 0)) + h_retract(max(-v, 0))`` with
    ``h(u) = u (F_c + (F_s - F_c) exp(-u / v_s)) + B u^2``. This equals ``|F_f(v) v|`` exactly:
    only one of the two speeds is non-zero, ``h(0) = 0`` and ``F_f(v) v >= 0``. With ``max_fn =
    ca.fmax`` it is exact (kinked at ``v = 0``); with a smooth max (see :func:`smooth_max`) it is
    differentiable everywhere, as the NLP needs.

    Args:
        friction: The friction law.
        v: Cylinder velocity [m/s] (float, DM, SX or MX).
        max_fn: ``max_fn(x, 0)`` must return ``max(x, 0)``: :func:`casadi.fmax` (default) for the
            exact heat, or e.g. ``lambda x, _: smooth_max(x, eps)``.
    """
    return _heat(friction.extend, max_fn(v, 0)) + _heat(friction.retract, max_fn(-v, 0))


def smooth_max(x: Any, eps: float) -> Any:
    """Smooth ``max(x, 0) = (x + sqrt(x^2 + eps^2)) / 2``.

    It is infinitely differentiable, always above ``max(x, 0)`` and at most ``eps / 2`` above it
    (the gap is largest at ``x = 0`` and falls like ``eps^2 / (4 |x|)``); it tends to ``max(x, 0)``
    as ``eps -> 0``.

    Args:
        x: Argument (float, DM, SX or MX), e.g. a cylinder velocity [m/s].
        eps: Smoothing width in the unit of ``x`` (> 0). For cylinder velocities choose it well
            below the Stribeck velocities (7 and 15 mm/s), e.g. 1e-4 m/s, so the smoothed heat
            differs from the exact one only near ``v = 0``, where both are tiny.
    """
    return 0.5 * (x + ca.sqrt(x**2 + eps**2))


def stroke_limits_m(
    cyl: HydraulicCylinder, theta_lower: float, theta_upper: float
) -> tuple[float, float]:
    """Cylinder length range allowed by the stroke [m] (decision 14).

    ``l_min`` is the shorter of the lengths at the two joint limits and ``l_max = l_min + stroke``.
    ``l`` is monotonic in ``theta`` over the range because ``dl/dphi = a b sin(phi) / l`` keeps its
    sign while ``phi`` stays inside ``(0, pi)``; this is verified.

    Args:
        cyl: The cylinder.
        theta_lower: Lower joint limit [rad].
        theta_upper: Upper joint limit [rad].

    Raises:
        ModelError: The mounting angle leaves ``(0, pi)`` over the range (``l`` not monotonic).
    """
    phis = [float(cylinder_angle(cyl, t)) for t in (theta_lower, theta_upper)]
    if not all(0.0 < p < math.pi for p in phis):
        raise ModelError(
            f"cylinder {cyl.joint_name}: mounting angle phi goes from {phis[0]:.4f} to "
            f"{phis[1]:.4f} rad over the joint range [{theta_lower}, {theta_upper}] rad, "
            "outside (0, pi): the cylinder length is not monotonic"
        )
    shortest = min(float(cylinder_length(cyl, t)) for t in (theta_lower, theta_upper))
    return shortest, shortest + cyl.stroke_m


# --- the actuator file ------------------------------------------------------------------------
_BRANCH_KEYS = ("viscous_n_s_per_m", "static_n", "coulomb_n", "stribeck_velocity_m_s")
_CYLINDER_KEYS = ("a_mm", "b_mm", "phi_offset_deg", "angle_sign", "stroke_mm")
_TOP_KEYS = ("friction", "cylinders")
_FRICTION_KEYS = ("extend", "retract")


def default_actuator_path() -> Path:
    """SCalf's actuator file, ``urdf/scalf_actuators.toml`` beside the package directory.

    Raises:
        ModelError: The file is not there (e.g. a non-editable install, which does not ship
            ``urdf/``); the message says where it looked.
    """
    path = Path(__file__).resolve().parent.parent / "urdf" / "scalf_actuators.toml"
    if not path.is_file():
        raise ModelError(
            f"SCalf actuator file not found: looked for {path} (install the repository editable, "
            "pip install -e ., or pass the file's path)"
        )
    return path


def _number(path: Path, key: str, value: Any, positive: bool = True) -> float:
    ok = isinstance(value, int | float) and not isinstance(value, bool) and math.isfinite(value)
    if not ok or (positive and value <= 0):
        need = "a positive number" if positive else "a number"
        raise ConfigError(f"{path}: {key} must be {need}, got {value!r}")
    return float(value)


def _table(path: Path, parent: dict[str, Any], key: str, name: str) -> dict[str, Any]:
    """``parent[key]`` as a table; ``name`` is its full key path for messages."""
    if key not in parent:
        raise ConfigError(f"{path}: missing table [{name}]")
    value = parent[key]
    if not isinstance(value, dict):
        raise ConfigError(f"{path}: {name} must be a table, got {value!r}")
    return value


def _no_extra(path: Path, table: dict[str, Any], allowed: tuple[str, ...], prefix: str) -> None:
    extra = sorted(set(table) - set(allowed))
    if extra:
        key = f"{prefix}.{extra[0]}" if prefix else extra[0]
        raise ConfigError(f"{path}: unknown key {key} (allowed: {', '.join(allowed)})")


def _branch(path: Path, friction: dict[str, Any], key: str) -> StribeckBranch:
    name = f"friction.{key}"
    table = _table(path, friction, key, name)
    _no_extra(path, table, _BRANCH_KEYS, name)
    values = []
    for field in _BRANCH_KEYS:
        if field not in table:
            raise ConfigError(f"{path}: missing key {name}.{field}")
        values.append(_number(path, f"{name}.{field}", table[field]))
    return StribeckBranch(*values)


def _cylinder(path: Path, joint: str, table: Any, friction: StribeckFriction) -> HydraulicCylinder:
    prefix = f"cylinders.{joint}"
    if not isinstance(table, dict):
        raise ConfigError(f"{path}: {prefix} must be a table, got {table!r}")
    _no_extra(path, table, _CYLINDER_KEYS, prefix)
    for field in _CYLINDER_KEYS:
        if field not in table:
            raise ConfigError(f"{path}: missing key {prefix}.{field}")
    sign = table["angle_sign"]
    if isinstance(sign, bool) or not isinstance(sign, int) or sign not in (1, -1):
        raise ConfigError(f"{path}: {prefix}.angle_sign must be +1 or -1, got {sign!r}")
    offset_deg = _number(path, f"{prefix}.phi_offset_deg", table["phi_offset_deg"], positive=False)
    return HydraulicCylinder(
        joint_name=joint,
        a_m=_number(path, f"{prefix}.a_mm", table["a_mm"]) * 1e-3,
        b_m=_number(path, f"{prefix}.b_mm", table["b_mm"]) * 1e-3,
        phi_offset_rad=math.radians(offset_deg),
        angle_sign=sign,
        stroke_m=_number(path, f"{prefix}.stroke_mm", table["stroke_mm"]) * 1e-3,
        friction=friction,
    )


def load_actuators(path: str | Path) -> dict[str, HydraulicCylinder]:
    """Read an actuator file (TOML) into cylinders keyed by joint name.

    The file has a ``[friction.extend]`` and a ``[friction.retract]`` table (keys
    ``viscous_n_s_per_m``, ``static_n``, ``coulomb_n``, ``stribeck_velocity_m_s``, all > 0)
    shared by every cylinder, and one ``[cylinders.<joint>]`` table per driven joint
    (``a_mm``, ``b_mm``, ``stroke_mm`` > 0; ``phi_offset_deg`` any number; ``angle_sign`` +1 or
    -1). Millimetres and degrees are converted to SI here. Which joints exist is checked against
    a robot by :func:`load_actuators_for`, not here.

    Args:
        path: The actuator file.

    Returns:
        The cylinders keyed by URDF joint name, in file order.

    Raises:
        ConfigError: Unreadable file, TOML syntax error, missing, unknown or invalid key; the
            one-line message names the file and the key path (``cylinders.RF_knee.a_mm``).
    """
    path = Path(path)
    data = read_toml(path, "actuator")
    _no_extra(path, data, _TOP_KEYS, "")
    friction_table = _table(path, data, "friction", "friction")
    _no_extra(path, friction_table, _FRICTION_KEYS, "friction")
    friction = StribeckFriction(
        extend=_branch(path, friction_table, "extend"),
        retract=_branch(path, friction_table, "retract"),
    )
    cylinders = _table(path, data, "cylinders", "cylinders")
    out = {joint: _cylinder(path, joint, table, friction) for joint, table in cylinders.items()}
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

    Raises:
        ConfigError: The file is invalid or names a joint the robot does not have.
    """
    path = actuator_path_for(robot.urdf_path)
    if not path.is_file():
        return {}
    cylinders = load_actuators(path)
    for joint in cylinders:
        if not robot.model.existJointName(joint):
            raise ConfigError(f"{path}: cylinders.{joint} names no joint of {robot.urdf_path}")
    return cylinders
