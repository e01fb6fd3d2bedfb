"""The SCalf robot description: the paper's numbers and the URDF generated from them.

``urdf/scalf.urdf`` is this module's output (``python -m scalf_opt.scalf_description
urdf/scalf.urdf`` rewrites it; a test checks that the committed file equals it). Paper values are
given in the paper's units in comments and converted to SI once, here.

Frames: trunk frame at the trunk COM (precondition c), x forward, y left, z up. Each leg: hip roll
about +x at (+-0.68, +-0.20, -0.15) m; hip pitch about +y, 45 mm below and 57 mm outboard of the
roll axis (decision 4); knee about +y at l1 below the hip; foot at l2 below the knee. At zero
angles the leg hangs straight down (decision 5). Hind legs mirror the front legs across the
trunk's y-z plane: COM angles and pitch/knee limits negated.
"""

from __future__ import annotations

import math
import sys
from dataclasses import dataclass
from pathlib import Path

import numpy as np

from scalf_opt.actuators import load_actuators

# --- Table 1 (sagittal links) --------------------------------------------------------------------
THIGH_MASS_KG = 4.10
SHANK_MASS_KG = 2.24
THIGH_LENGTH_M = 0.45099  # 450.99 mm
SHANK_LENGTH_M = 0.40487  # 404.87 mm
THIGH_COM_DISTANCE_M = 0.21043  # 210.43 mm
SHANK_COM_DISTANCE_M = 0.22720  # 227.20 mm
THIGH_COM_ANGLE_RAD = 0.037
SHANK_COM_ANGLE_RAD = -0.083
THIGH_INERTIA_KG_M2 = 0.178  # about the COM, decision 2
SHANK_INERTIA_KG_M2 = 0.057
# chosen: the axial moment of a slender rod (the paper gives only the pitch-axis moment)
THIGH_AXIAL_INERTIA_KG_M2 = 0.010
SHANK_AXIAL_INERTIA_KG_M2 = 0.004

# --- hip (Section 2.2, decision 4) and trunk (Section 6.1, decision 1) --------------------------
HIP_DROP_M = 0.045  # 45 mm: pitch axis below the roll axis
HIP_OUTBOARD_M = 0.057  # 57 mm: leg plane outboard of the roll axis
HIP_X_M = 0.68  # trunk COM to rolling hip, x
HIP_Z_M = -0.15  # trunk COM to rolling hip, z (hips below the COM)
HIP_Y_M = 0.20  # chosen: lateral position of the rolling hips
TRUNK_MASS_KG = 200.0
TRUNK_SIZE_M = (1.50, 0.45, 0.30)  # chosen: a cuboid (Section 6.1) spanning the hips
HIP_MASS_KG = 2.0  # chosen: hip housing between roll and pitch axes
HIP_BOX_M = (0.10, 0.08, 0.08)

# --- Table 4 (front legs; hind legs negated) and chosen limits ----------------------------------
HIP_PITCH_LIMITS_RAD = (-2.032, 0.047)
KNEE_LIMITS_RAD = (0.491, 2.570)
ROLL_LIMITS_RAD = (-0.35, 0.35)  # chosen: +-20 deg, not given
VELOCITY_LIMIT_RAD_S = 10.0  # chosen
FORCE_SENSOR_RANGE_N = 14000.0  # Section 2: force sensor range 0 to 14,000 N

LEGS = ("RF", "LF", "RH", "LH")


@dataclass(frozen=True)
class LegSide:
    """Signs of one leg: ``sx`` +1 front / -1 hind, ``sy`` +1 left / -1 right."""

    sx: int
    sy: int


SIDES = {"RF": LegSide(1, -1), "LF": LegSide(1, 1), "RH": LegSide(-1, -1), "LH": LegSide(-1, 1)}


def _f(x: float) -> str:
    """Shortest float text that reads back exactly (no -0)."""
    x = float(x)
    return "0" if x == 0 else repr(round(x, 12))


def _vec(*xs: float) -> str:
    return " ".join(_f(x) for x in xs)


def link_com_m(distance_m: float, angle_rad: float, sx: int) -> tuple[float, float, float]:
    """COM in the link frame (decision 3): R_y(eps) (0, 0, -l_m), eps negated for hind legs."""
    eps = sx * angle_rad
    return (-distance_m * math.sin(eps), 0.0, -distance_m * math.cos(eps))


def effort_limits_nm(actuator_file: Path) -> dict[str, float]:
    """Chosen effort limits [N m] of the hip pitch and knee joints.

    Force-sensor range times the largest moment arm |dl/dtheta| over the joint range, rounded up
    to 10 N m; the roll joint gets the hip value.
    """
    from scalf_opt.actuators import cylinder_length_rate

    cylinders = load_actuators(actuator_file)
    out = {}
    for joint, (lo, hi) in (("RF_hip_pitch", HIP_PITCH_LIMITS_RAD), ("RF_knee", KNEE_LIMITS_RAD)):
        grid = np.linspace(lo, hi, 20001)
        arm = max(abs(float(cylinder_length_rate(cylinders[joint], t))) for t in grid)
        out[joint.split("_", 1)[1]] = 10.0 * math.ceil(FORCE_SENSOR_RANGE_N * arm / 10.0)
    return out


def _box_inertia(mass: float, size: tuple[float, float, float]) -> tuple[float, float, float]:
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


def scalf_urdf_xml(actuator_file: Path | None = None) -> str:
    """The SCalf URDF as text (deterministic)."""
    actuator_file = actuator_file or Path(__file__).resolve().parent.parent / "urdf" / (
        "scalf_actuators.toml"
    )
    effort = effort_limits_nm(actuator_file)
    parts = [
        '<?xml version="1.0"?>\n',
        "<!-- SCalf hydraulic quadruped, generated by scalf_opt/scalf_description.py from the\n"
        "     paper's Tables 1 and 4 and reconstruction decisions 1-5 (README).\n"
        "     Do not edit by hand. -->\n",
        '<robot name="scalf">\n',
        '  <material name="trunk_grey"><color rgba="0.55 0.57 0.6 1"/></material>\n',
        '  <material name="hip_dark"><color rgba="0.3 0.3 0.33 1"/></material>\n',
        '  <material name="leg_blue"><color rgba="0.2 0.45 0.8 1"/></material>\n',
        '  <material name="foot_black"><color rgba="0.05 0.05 0.05 1"/></material>\n',
    ]
    box = f'<box size="{_vec(*TRUNK_SIZE_M)}"/>'
    parts.append(
        _link(
            "trunk",
            _inertial(TRUNK_MASS_KG, (0, 0, 0), _box_inertia(TRUNK_MASS_KG, TRUNK_SIZE_M))
            + _geometry("visual", box, (0, 0, 0), "trunk_grey")
            + _geometry("collision", box, (0, 0, 0), ""),
        )
    )
    for leg in LEGS:
        side = SIDES[leg]
        sx, sy = side.sx, side.sy
        hip_lim = (
            HIP_PITCH_LIMITS_RAD if sx > 0 else (-HIP_PITCH_LIMITS_RAD[1], -HIP_PITCH_LIMITS_RAD[0])
        )
        knee_lim = KNEE_LIMITS_RAD if sx > 0 else (-KNEE_LIMITS_RAD[1], -KNEE_LIMITS_RAD[0])
        parts.append(
            _joint(
                f"{leg}_hip_roll",
                "revolute",
                "trunk",
                f"{leg}_hip",
                (sx * HIP_X_M, sy * HIP_Y_M, HIP_Z_M),
                "1 0 0",
                (*ROLL_LIMITS_RAD, effort["hip_pitch"], VELOCITY_LIMIT_RAD_S),
            )
        )
        hip_com = (0.0, sy * HIP_OUTBOARD_M / 2, -HIP_DROP_M / 2)
        hip_box = f'<box size="{_vec(*HIP_BOX_M)}"/>'
        parts.append(
            _link(
                f"{leg}_hip",
                _inertial(HIP_MASS_KG, hip_com, _box_inertia(HIP_MASS_KG, HIP_BOX_M))
                + _geometry("visual", hip_box, hip_com, "hip_dark"),
            )
        )
        parts.append(
            _joint(
                f"{leg}_hip_pitch",
                "revolute",
                f"{leg}_hip",
                f"{leg}_thigh",
                (0.0, sy * HIP_OUTBOARD_M, -HIP_DROP_M),
                "0 1 0",
                (*hip_lim, effort["hip_pitch"], VELOCITY_LIMIT_RAD_S),
            )
        )
        for link, mass, length, dist, angle, iyy, izz, radius, child_joint in (
            (
                "thigh",
                THIGH_MASS_KG,
                THIGH_LENGTH_M,
                THIGH_COM_DISTANCE_M,
                THIGH_COM_ANGLE_RAD,
                THIGH_INERTIA_KG_M2,
                THIGH_AXIAL_INERTIA_KG_M2,
                0.03,
                "knee",
            ),
            (
                "shank",
                SHANK_MASS_KG,
                SHANK_LENGTH_M,
                SHANK_COM_DISTANCE_M,
                SHANK_COM_ANGLE_RAD,
                SHANK_INERTIA_KG_M2,
                SHANK_AXIAL_INERTIA_KG_M2,
                0.025,
                "foot_fixed",
            ),
        ):
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
            if child_joint == "knee":
                parts.append(
                    _joint(
                        f"{leg}_knee",
                        "revolute",
                        f"{leg}_thigh",
                        f"{leg}_shank",
                        (0.0, 0.0, -length),
                        "0 1 0",
                        (*knee_lim, effort["knee"], VELOCITY_LIMIT_RAD_S),
                    )
                )
            else:
                parts.append(
                    _joint(
                        f"{leg}_foot_fixed",
                        "fixed",
                        f"{leg}_shank",
                        f"{leg}_foot",
                        (0.0, 0.0, -length),
                    )
                )
        sphere = '<sphere radius="0.03"/>'
        parts.append(
            _link(
                f"{leg}_foot",
                _geometry("visual", sphere, (0, 0, 0), "foot_black")
                + _geometry("collision", sphere, (0, 0, 0), ""),
            )
        )
    parts.append("</robot>\n")
    return "".join(parts)


def write_scalf_urdf(path: str | Path) -> Path:
    """Write the URDF to ``path`` atomically."""
    from scalf_opt.results import write_atomic

    return write_atomic(path, scalf_urdf_xml())


if __name__ == "__main__":
    target = sys.argv[1] if len(sys.argv) > 1 else "urdf/scalf.urdf"
    print(write_scalf_urdf(target))
