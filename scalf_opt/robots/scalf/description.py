"""The SCalf robot description: the paper's numbers and the URDF generated from them.

``urdf/scalf.urdf`` is this module's output (``python -m scalf_opt.robots.scalf.description
urdf/scalf.urdf`` rewrites it; a test checks that the committed file equals it). Paper values are
given in the paper's units in comments and converted to SI once, here. The hydraulic cylinders
are not part of the URDF; they live in ``urdf/scalf_actuators.toml`` (see
:mod:`scalf_opt.actuators.sidecar`), from which only the chosen effort limits are derived.

Frames: trunk frame at the trunk COM (precondition c), x forward, y left, z up; fixed base, root
link ``trunk``. Each leg: hip roll about +x at (+-0.68, +-0.20, -0.15) m; hip pitch about +y,
45 mm below and 57 mm outboard of the roll axis (decision 4); knee about +y at l1 below the hip;
foot at l2 below the knee. At zero angles the leg hangs straight down (decision 5). Hind legs
mirror the front legs across the trunk's y-z plane: x offsets, COM angles and pitch/knee limits
negated.
"""

from __future__ import annotations

import math
import sys
from collections.abc import Sequence
from dataclasses import dataclass
from pathlib import Path

from scalf_opt.actuators.cylinder import HydraulicCylinder
from scalf_opt.actuators.sidecar import load_sidecar
from scalf_opt.errors import ModelError
from scalf_opt.files import number_text, write_atomic
from scalf_opt.robots.files import shipped_file

# --- Table 1 (sagittal links) --------------------------------------------------------------------
THIGH_MASS_KG = 4.10  # m1 = 4.10 kg
SHANK_MASS_KG = 2.24  # m2 = 2.24 kg
THIGH_LENGTH_M = 0.45099  # l1 = 450.99 mm
SHANK_LENGTH_M = 0.40487  # l2 = 404.87 mm
THIGH_COM_DISTANCE_M = 0.21043  # l_m1 = 210.43 mm
SHANK_COM_DISTANCE_M = 0.22720  # l_m2 = 227.20 mm
THIGH_COM_ANGLE_RAD = 0.037  # eps1 = 0.037 rad (decision 3)
SHANK_COM_ANGLE_RAD = -0.083  # eps2 = -0.083 rad
THIGH_INERTIA_KG_M2 = 0.178  # I1 = 0.178 kg m^2, about the COM (decision 2)
SHANK_INERTIA_KG_M2 = 0.057  # I2 = 0.057 kg m^2, about the COM
# chosen (decision 2): the paper gives only the pitch-axis moment; Ixx = Iyy and a small axial
# moment Izz make a slender rod, and Izz < Ixx + Iyy keeps the triangle inequality
THIGH_AXIAL_INERTIA_KG_M2 = 0.010
SHANK_AXIAL_INERTIA_KG_M2 = 0.004
THIGH_RADIUS_M = 0.03  # chosen: visual/collision cylinder
SHANK_RADIUS_M = 0.025  # chosen
FOOT_RADIUS_M = 0.03  # chosen: visual/collision sphere at the shank tip

# --- hip (Section 2.2, decision 4) and trunk (Section 6.1, decision 1) --------------------------
HIP_DROP_M = 0.045  # 45 mm: pitch axis below the roll axis
HIP_OUTBOARD_M = 0.057  # 57 mm: leg plane outboard of the roll axis
HIP_X_M = 0.68  # 0.68 m: trunk COM to rolling hip, x
HIP_Z_M = -0.15  # 0.15 m: trunk COM to rolling hip, z (hips below the COM)
HIP_Y_M = 0.20  # chosen: lateral position of the rolling hips (not given)
TRUNK_MASS_KG = 200.0  # decision 1: 980 N per stance foot is half the trunk weight
TRUNK_SIZE_M = (1.50, 0.45, 0.30)  # chosen: a uniform cuboid; hips (z = -0.15) on its bottom face
HIP_MASS_KG = 2.0  # chosen: hip housing between roll and pitch axes (not given)
HIP_BOX_M = (0.10, 0.08, 0.08)  # chosen: its inertia is that of this uniform box

# --- Table 4 (front legs; hind legs negated, decision 5) and chosen limits ------------------------
HIP_PITCH_LIMITS_RAD = (-2.032, 0.047)  # RF/LF pitching hip: -2.032 to 0.047 rad
KNEE_LIMITS_RAD = (0.491, 2.570)  # RF/LF pitching knee: 0.491 to 2.570 rad
ROLL_LIMITS_RAD = (-0.35, 0.35)  # chosen: +-20 deg, not given
VELOCITY_LIMIT_RAD_S = 10.0  # chosen: not given
FORCE_SENSOR_RANGE_N = 14000.0  # Section 2: force sensor range 0 to 14,000 N
EFFORT_ROUNDING_NM = 10.0  # effort limits are rounded up to a multiple of this


@dataclass(frozen=True)
class LegSide:
    """Signs of one leg: ``sx`` +1 front / -1 hind, ``sy`` +1 left / -1 right."""

    sx: int
    sy: int


SIDES = {"RF": LegSide(1, -1), "LF": LegSide(1, 1), "RH": LegSide(-1, -1), "LH": LegSide(-1, 1)}
LEGS = tuple(SIDES)
"""The legs in the URDF's order."""


def _f(x: float) -> str:
    """Shortest text that reads back as ``x`` to 15 significant digits (no ``-0``).

    Paper numbers appear as written (``0.45099``); derived ones keep 15 digits without the
    float noise of the last bit (``4.875``, not ``4.875000000000001``).
    """
    return "0" if float(x) == 0 else number_text(x)


def _vec(*xs: float) -> str:
    return " ".join(_f(x) for x in xs)


def joint_limits_rad(joint: str, sx: int) -> tuple[float, float]:
    """Position limits of a pitch or knee joint [rad] (Table 4; hind legs negated, decision 5).

    Args:
        joint: ``"hip_pitch"`` or ``"knee"``.
        sx: +1 for a front leg, -1 for a hind leg.
    """
    lo, hi = HIP_PITCH_LIMITS_RAD if joint == "hip_pitch" else KNEE_LIMITS_RAD
    return (lo, hi) if sx > 0 else (-hi, -lo)


def link_com_m(distance_m: float, angle_rad: float, sx: int) -> tuple[float, float, float]:
    """COM of a leg link in its frame [m].

    Decision 3: ``R_y(eps) (0, 0, -l_m) = (-l_m sin eps, 0, -l_m cos eps)``, with ``eps``
    negated for hind legs (decision 5).

    Args:
        distance_m: COM distance from the joint, l_m [m].
        angle_rad: COM angle from the link axis, eps [rad], as for the front legs.
        sx: +1 for a front leg, -1 for a hind leg.
    """
    eps = sx * angle_rad
    return (-distance_m * math.sin(eps), 0.0, -distance_m * math.cos(eps))


def max_moment_arm_m(cyl: HydraulicCylinder, lower_rad: float, upper_rad: float) -> float:
    """Largest ``|dl/dtheta|`` [m/rad] of a cylinder over a joint range, exactly.

    ``(dl/dtheta)^2 = a^2 b^2 sin^2(phi) / (a^2 + b^2 - 2 a b cos(phi))`` is stationary where
    ``cos(phi) = min(a, b) / max(a, b)`` (there it equals ``min(a, b)^2``), so the maximum is at
    that angle if the range contains it, else at a joint limit.

    Args:
        cyl: The cylinder.
        lower_rad: Lower joint limit [rad].
        upper_rad: Upper joint limit [rad].
    """
    candidates = [lower_rad, upper_rad]
    phi_star = math.acos(min(cyl.a_m, cyl.b_m) / max(cyl.a_m, cyl.b_m))
    phi_lo, phi_hi = sorted(float(cyl.angle_rad(t)) for t in (lower_rad, upper_rad))
    first, last = (
        math.floor((phi_lo - math.pi) / math.tau),
        math.ceil((phi_hi + math.pi) / math.tau),
    )
    for turn in range(first, last + 1):
        for phi in (phi_star + turn * math.tau, -phi_star + turn * math.tau):
            if phi_lo <= phi <= phi_hi:
                candidates.append((phi - cyl.phi_offset_rad) / cyl.angle_sign)
    return max(abs(float(cyl.moment_arm_m(t))) for t in candidates)


def effort_limits_nm(actuator_file: str | Path | None = None) -> dict[str, float]:
    """Chosen effort limits [N m] of the hip pitch and knee joints, keyed by URDF joint name.

    Not in the paper. Each is the force sensor's full range (14,000 N, Section 2) times the
    largest moment arm ``|dl/dtheta|`` of the joint's cylinder over its Table 4 range, rounded up
    to the next 10 N m. For SCalf the arm peaks at ``b`` (56.87 / 56.89 mm), so every one is
    800 N m. The roll joints take the hip pitch value.

    Args:
        actuator_file: The actuator sidecar; ``None`` for SCalf's (``scalf_actuators.toml``).
    """
    drives = load_sidecar(actuator_file or shipped_file("scalf_actuators.toml"))
    out: dict[str, float] = {}
    for leg in LEGS:
        for joint in ("hip_pitch", "knee"):
            name = f"{leg}_{joint}"
            cylinder = drives[name]
            if not isinstance(cylinder, HydraulicCylinder):
                raise ModelError(f"{actuator_file}: {name} is not driven by a cylinder")
            arm = max_moment_arm_m(cylinder, *joint_limits_rad(joint, SIDES[leg].sx))
            steps = math.ceil(FORCE_SENSOR_RANGE_N * arm / EFFORT_ROUNDING_NM)
            out[name] = EFFORT_ROUNDING_NM * steps
    return out


def _box_inertia(mass: float, size: tuple[float, float, float]) -> tuple[float, float, float]:
    """Principal moments [kg m^2] of a uniform solid box of ``size`` (x, y, z) [m]."""
    x, y, z = size
    return (mass * (y * y + z * z) / 12, mass * (x * x + z * z) / 12, mass * (x * x + y * y) / 12)


def _inertial(
    mass: float, com: tuple[float, float, float], moments: tuple[float, float, float]
) -> str:
    ixx, iyy, izz = moments
    return (
        f'    <inertial>\n      <origin xyz="{_vec(*com)}" rpy="0 0 0"/>\n'
        f'      <mass value="{_f(mass)}"/>\n'
        f'      <inertia ixx="{_f(ixx)}" ixy="0" ixz="0" iyy="{_f(iyy)}" iyz="0" '
        f'izz="{_f(izz)}"/>\n'
        "    </inertial>\n"
    )


def _geometry(kind: str, shape: str, origin: tuple[float, float, float], material: str) -> str:
    mat = f'      <material name="{material}"/>\n' if kind == "visual" else ""
    return (
        f'    <{kind}>\n      <origin xyz="{_vec(*origin)}" rpy="0 0 0"/>\n'
        f"      <geometry>{shape}</geometry>\n{mat}    </{kind}>\n"
    )


def _link(name: str, body: str = "") -> str:
    return f'  <link name="{name}">\n{body}  </link>\n'


def _joint(
    name: str,
    kind: str,
    parent: str,
    child: str,
    xyz: tuple[float, float, float],
    axis: str = "",
    limits: tuple[float, float, float, float] | None = None,
) -> str:
    text = (
        f'  <joint name="{name}" type="{kind}">\n    <parent link="{parent}"/>\n'
        f'    <child link="{child}"/>\n    <origin xyz="{_vec(*xyz)}" rpy="0 0 0"/>\n'
    )
    if axis:
        text += f'    <axis xyz="{axis}"/>\n'
    if limits:
        lo, hi, effort, velocity = limits
        text += (
            f'    <limit lower="{_f(lo)}" upper="{_f(hi)}" effort="{_f(effort)}" '
            f'velocity="{_f(velocity)}"/>\n'
        )
    return text + "  </joint>\n"


def _leg_links(leg: str, effort: dict[str, float]) -> list[str]:
    """URDF text of one leg: roll joint, hip, pitch joint, thigh, knee, shank, foot."""
    sx, sy = SIDES[leg].sx, SIDES[leg].sy
    hip_com = (0.0, sy * HIP_OUTBOARD_M / 2, -HIP_DROP_M / 2)
    hip_box = f'<box size="{_vec(*HIP_BOX_M)}"/>'
    parts = [
        _joint(
            f"{leg}_hip_roll",
            "revolute",
            "trunk",
            f"{leg}_hip",
            (sx * HIP_X_M, sy * HIP_Y_M, HIP_Z_M),
            "1 0 0",
            (*ROLL_LIMITS_RAD, effort[f"{leg}_hip_pitch"], VELOCITY_LIMIT_RAD_S),
        ),
        _link(
            f"{leg}_hip",
            _inertial(HIP_MASS_KG, hip_com, _box_inertia(HIP_MASS_KG, HIP_BOX_M))
            + _geometry("visual", hip_box, hip_com, "hip_dark"),
        ),
        _joint(
            f"{leg}_hip_pitch",
            "revolute",
            f"{leg}_hip",
            f"{leg}_thigh",
            (0.0, sy * HIP_OUTBOARD_M, -HIP_DROP_M),
            "0 1 0",
            (
                *joint_limits_rad("hip_pitch", sx),
                effort[f"{leg}_hip_pitch"],
                VELOCITY_LIMIT_RAD_S,
            ),
        ),
    ]
    links = (
        (
            "thigh",
            THIGH_MASS_KG,
            THIGH_LENGTH_M,
            THIGH_COM_DISTANCE_M,
            THIGH_COM_ANGLE_RAD,
            THIGH_INERTIA_KG_M2,
            THIGH_AXIAL_INERTIA_KG_M2,
            THIGH_RADIUS_M,
        ),
        (
            "shank",
            SHANK_MASS_KG,
            SHANK_LENGTH_M,
            SHANK_COM_DISTANCE_M,
            SHANK_COM_ANGLE_RAD,
            SHANK_INERTIA_KG_M2,
            SHANK_AXIAL_INERTIA_KG_M2,
            SHANK_RADIUS_M,
        ),
    )
    for link, mass, length, dist, angle, iyy, izz, radius in links:
        cyl = f'<cylinder radius="{_f(radius)}" length="{_f(length)}"/>'
        middle = (0.0, 0.0, -length / 2)
        parts.append(
            _link(
                f"{leg}_{link}",
                _inertial(mass, link_com_m(dist, angle, sx), (iyy, iyy, izz))
                + _geometry("visual", cyl, middle, "leg_blue")
                + _geometry("collision", cyl, middle, ""),
            )
        )
        if link == "thigh":
            parts.append(
                _joint(
                    f"{leg}_knee",
                    "revolute",
                    f"{leg}_thigh",
                    f"{leg}_shank",
                    (0.0, 0.0, -length),
                    "0 1 0",
                    (*joint_limits_rad("knee", sx), effort[f"{leg}_knee"], VELOCITY_LIMIT_RAD_S),
                )
            )
        else:
            parts.append(
                _joint(
                    f"{leg}_foot_fixed", "fixed", f"{leg}_shank", f"{leg}_foot", (0.0, 0.0, -length)
                )
            )
    sphere = f'<sphere radius="{_f(FOOT_RADIUS_M)}"/>'
    parts.append(
        _link(
            f"{leg}_foot",
            _geometry("visual", sphere, (0, 0, 0), "foot_black")
            + _geometry("collision", sphere, (0, 0, 0), ""),
        )
    )
    return parts


def scalf_urdf_xml(actuator_file: str | Path | None = None) -> str:
    """The SCalf URDF as text (deterministic: the same input gives the same bytes).

    Args:
        actuator_file: Actuator file the effort limits are derived from; ``None`` for SCalf's
            (``scalf_actuators.toml``).

    Raises:
        ModelError: ``actuator_file`` is ``None`` and SCalf's actuator file is not found.
        ConfigError: The actuator file is invalid.
    """
    effort = effort_limits_nm(actuator_file)
    box = f'<box size="{_vec(*TRUNK_SIZE_M)}"/>'
    parts = [
        '<?xml version="1.0"?>\n',
        "<!-- SCalf hydraulic quadruped, generated by scalf_opt/robots/scalf/description.py from\n"
        "     the paper's Tables 1, 2 and 4 and reconstruction decisions 1-5 and 7 (README).\n"
        "     Do not edit by hand. -->\n",
        '<robot name="scalf">\n',
        '  <material name="trunk_grey"><color rgba="0.55 0.57 0.6 1"/></material>\n',
        '  <material name="hip_dark"><color rgba="0.3 0.3 0.33 1"/></material>\n',
        '  <material name="leg_blue"><color rgba="0.2 0.45 0.8 1"/></material>\n',
        '  <material name="foot_black"><color rgba="0.05 0.05 0.05 1"/></material>\n',
        _link(
            "trunk",
            _inertial(TRUNK_MASS_KG, (0, 0, 0), _box_inertia(TRUNK_MASS_KG, TRUNK_SIZE_M))
            + _geometry("visual", box, (0, 0, 0), "trunk_grey")
            + _geometry("collision", box, (0, 0, 0), ""),
        ),
    ]
    for leg in LEGS:
        parts.extend(_leg_links(leg, effort))
    parts.append("</robot>\n")
    return "".join(parts)


def write_scalf_urdf(path: str | Path) -> Path:
    """Write :func:`scalf_urdf_xml` to ``path`` atomically (temp file beside it, then rename).

    Args:
        path: Target file, e.g. ``urdf/scalf.urdf``.

    Returns:
        The path written.
    """
    return write_atomic(path, scalf_urdf_xml())


def main(argv: Sequence[str] | None = None) -> int:
    """Command line: ``python -m scalf_opt.robots.scalf.description [PATH]``.

    The default PATH is ``urdf/scalf.urdf``.

    Args:
        argv: Arguments after the program name; ``None`` reads ``sys.argv``.

    Returns:
        The exit status (0).
    """
    args = list(sys.argv[1:] if argv is None else argv)
    print(write_scalf_urdf(args[0] if args else "urdf/scalf.urdf"))
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
