"""The MuJoCo model of a robot's sagittal trot, built from its URDF.

MuJoCo reads the URDF itself (masses, inertias, joint placements, axes, limits and effort
limits), after four edits made here so that it simulates what the energy model describes:

* every joint except the legs' hip pitch and knee becomes ``fixed`` (the hip roll joints of the
  sagittal model are locked at zero; MuJoCo then merges those links into their parent, which
  changes nothing physical);
* the URDF's visual and collision geometry is dropped (the dynamics need none of it, and meshes
  need not be found); the only contact geometry is a sphere at each foot frame and the ground;
  an inertia tensor that is not positive definite (HyQ's 1e-6 kg placeholder links carry
  ``ixx = ixy = ... = 1e-6``), which MuJoCo refuses, keeps only its diagonal; a tensor whose
  principal moments break the triangle inequality ``A + B >= C`` (ANYmal C's depth cameras:
  8.7e-6, 6.7e-4 and 1.4e-3 kg m^2, which no real body has), which MuJoCo also refuses, is
  repaired as MuJoCo documents: the compiler flag ``balanceinertia`` sets its three principal
  moments to their mean. Every repair is listed in :attr:`SimModel.repairs` (and so in
  ``simulation.json`` and the command's report);
* the trunk (the URDF's root link) gets three joints: slide along x, slide along z and a hinge
  about y, in that order (the paper's assumption (a): the trunk moves in the sagittal plane);
* the joints' ``<dynamics damping friction>`` are left out. In the energy model a joint's
  friction belongs to its drive (the actuator file's Coulomb and viscous friction, charged as
  heat on top of ``|tau qd|`` by the power formula); MuJoCo would apply the URDF's as forces, so
  the simulated torques would carry that friction and the power formula would charge friction a
  second time. Go1's URDF (0.2 N m friction, 0.01 N m s/rad damping on every joint) made its
  swing cost MuJoCo's inverse dynamics 30 % more than the model, HyQ's (0.1 N m s/rad) a
  little. What is left out is listed in :attr:`SimModel.repairs`.

Each leg joint gets a torque motor (gear 1). Ground: the plane ``z = 0``; feet collide only
with it. Generalised coordinates: ``(x, z, pitch)`` of the trunk, then the leg joints in the
URDF's order (:class:`SimModel` keeps the addresses by leg).
"""

from __future__ import annotations

import xml.etree.ElementTree as ET
from dataclasses import dataclass
from pathlib import Path
from typing import Any

import mujoco
import numpy as np
from defusedxml.ElementTree import fromstring

from scalf_opt.errors import ModelError
from scalf_opt.model.leg import Leg
from scalf_opt.model.robot import Robot
from scalf_opt.model.urdf_file import read_urdf_text
from scalf_opt.sim.settings import SimSettings
from scalf_opt.types import LEG_NAMES

TRUNK_JOINTS: tuple[str, str, str] = ("trunk_x", "trunk_z", "trunk_pitch")
"""Names of the trunk's sagittal joints in the MuJoCo model, in qpos order."""

_TORSIONAL_FRICTION = 0.005
_ROLLING_FRICTION = 0.0001
"""MuJoCo's default second and third friction coefficients (unused with ``condim`` 3)."""


@dataclass(frozen=True)
class SimModel:
    """A compiled MuJoCo model and where each leg's quantities live in it.

    Attributes:
        model: The compiled model (z up, gravity -9.81 m/s^2, ground plane at z = 0).
        trunk_qpos: qpos addresses of the trunk's x, z and pitch [m, m, rad].
        trunk_dof: qvel addresses of the same.
        leg_qpos: Per leg, qpos addresses of (hip pitch, knee).
        leg_dof: Per leg, qvel addresses of (hip pitch, knee).
        leg_actuators: Per leg, actuator ids of (hip pitch, knee).
        foot_geom: Per leg, the foot sphere's geom id.
        foot_body: Per leg, the body the foot sphere belongs to.
        foot_radius_m: Radius of the foot spheres [m].
        effort_limit_nm: Per leg, the (hip pitch, knee) effort limits of the URDF [N m].
        repairs: One sentence per URDF inertia changed so that MuJoCo accepts it, and one for
            the leg joints' URDF friction and damping left out (empty when MuJoCo takes the URDF
            as it is).
    """

    model: mujoco.MjModel
    trunk_qpos: np.ndarray
    trunk_dof: np.ndarray
    leg_qpos: dict[str, np.ndarray]
    leg_dof: dict[str, np.ndarray]
    leg_actuators: dict[str, np.ndarray]
    foot_geom: dict[str, int]
    foot_body: dict[str, int]
    foot_radius_m: float
    effort_limit_nm: dict[str, np.ndarray]
    repairs: tuple[str, ...] = ()

    @property
    def total_mass_kg(self) -> float:
        """Mass of the whole simulated robot [kg]."""
        return float(self.model.body_subtreemass[0])


def _root_link(root: ET.Element, path: Path) -> str:
    children = {
        child.get("link")
        for joint in root.iter("joint")
        if (child := joint.find("child")) is not None
    }
    roots = [link.get("name") for link in root.iter("link") if link.get("name") not in children]
    if len(roots) != 1:
        raise ModelError(f"{path}: the URDF has {len(roots)} root links, expected one")
    return str(roots[0])


_INERTIA_KEYS = ("ixx", "ixy", "ixz", "iyy", "iyz", "izz")


def _link_inertias(root: ET.Element) -> list[tuple[str, float, ET.Element]]:
    """Every link's name, mass [kg] and ``inertia`` element (links with an inertial block)."""
    out = []
    for link in root.iter("link"):
        inertial = link.find("inertial")
        if inertial is None or (inertia := inertial.find("inertia")) is None:
            continue
        mass = inertial.find("mass")
        out.append(
            (
                str(link.get("name")),
                float(mass.get("value", "0")) if mass is not None else 0.0,
                inertia,
            )
        )
    return out


def _tensor(inertia: ET.Element) -> np.ndarray:
    xx, xy, xz, yy, yz, zz = (float(inertia.get(k, "0")) for k in _INERTIA_KEYS)
    return np.array([[xx, xy, xz], [xy, yy, yz], [xz, yz, zz]])


def _repair_singular_inertias(root: ET.Element) -> list[str]:
    """Drop the products of inertia of a tensor that is not positive definite (see module).

    Returns:
        One sentence per link repaired.
    """
    repairs = []
    for name, mass, inertia in _link_inertias(root):
        tensor = _tensor(inertia)
        if np.linalg.eigvalsh(tensor).min() <= 0.0 and np.any(tensor != np.diag(np.diag(tensor))):
            for key in ("ixy", "ixz", "iyz"):
                inertia.set(key, "0")
            repairs.append(
                f"link {name} ({mass:g} kg): inertia not positive definite, products of inertia "
                "set to zero"
            )
    return repairs


def _unbalanced_inertias(root: ET.Element) -> list[str]:
    """Links with mass whose principal moments break ``A + B >= C`` (see module), as sentences."""
    repairs = []
    for name, mass, inertia in _link_inertias(root):
        if mass <= 0.0:
            continue
        moments = np.sort(np.linalg.eigvalsh(_tensor(inertia)))
        if moments[0] + moments[1] < moments[2]:
            repairs.append(
                f"link {name} ({mass:g} kg): principal moments "
                + ", ".join(f"{m:.3g}" for m in moments)
                + " kg m^2 break A + B >= C; MuJoCo's balanceinertia set them to their mean "
                f"{moments.mean():.3g} kg m^2"
            )
    return repairs


def _drop_joint_dynamics(root: ET.Element, legs: set[str]) -> list[str]:
    """Remove every joint's ``<dynamics>``; one sentence on what the leg joints had.

    (The module docstring says why: joint friction is the drives', charged by the power formula.)
    """
    found: dict[tuple[float, float], list[str]] = {}
    for joint in root.iter("joint"):
        for dynamics in joint.findall("dynamics"):
            joint.remove(dynamics)
            values = (float(dynamics.get("friction", 0.0)), float(dynamics.get("damping", 0.0)))
            if joint.get("name") in legs and values != (0.0, 0.0):
                found.setdefault(values, []).append(str(joint.get("name")))
    return [
        f"joints {', '.join(sorted(names))}: the URDF's friction {friction:g} N m and damping "
        f"{damping:g} N m s/rad left out (joint friction is the drives', which the power formula "
        "charges)"
        for (friction, damping), names in sorted(found.items())
    ]


def _child_link(root: ET.Element, joint: str) -> str:
    for element in root.iter("joint"):
        if element.get("name") == joint:
            return str(element.find("child").get("link"))  # type: ignore[union-attr]
    raise ModelError(f"URDF has no joint {joint!r}")


def _strip_bodies(root: Any, kept: set[str]) -> None:
    """Strip the URDF tree to its bodies and the ``kept`` joints.

    No visual or collision geometry (the feet are added), every other joint fixed.
    """
    for link in root.iter("link"):
        for tag in ("visual", "collision"):
            for element in link.findall(tag):
                link.remove(element)
    for joint in root.iter("joint"):
        if joint.get("name") not in kept:
            joint.set("type", "fixed")


def _add_foot_and_motors(
    spec: Any,
    name: str,
    leg: Leg,
    shank_link: str,
    radius: float,
    friction: list[float],
    solref: list[float],
) -> None:
    """A leg's point foot (a sphere of ``radius`` at its foot frame) and its joints' motors."""
    placement = leg.model.frames[leg.foot_frame_id].placement
    spec.body(shank_link).add_geom(
        name=f"{name}_foot_contact",
        type=mujoco.mjtGeom.mjGEOM_SPHERE,
        size=[radius, 0, 0],
        pos=np.array(placement.translation),
        contype=1,
        conaffinity=0,
        condim=3,
        friction=friction,
        solref=solref,
        mass=0.0,
    )
    for joint_name in leg.joint_names:
        spec.add_actuator(
            name=joint_name,
            target=joint_name,
            trntype=mujoco.mjtTrn.mjTRN_JOINT,
            gear=[1, 0, 0, 0, 0, 0],
        )


@dataclass(frozen=True)
class UrdfSpec:
    """A robot's URDF as a MuJoCo spec, stripped to its bodies and kept joints, on the ground.

    Attributes:
        spec: The editable MuJoCo spec (ground plane, time step and energy flag set).
        trunk_link: The URDF's root link (a body of ``spec``).
        child_links: Each kept joint's child link.
        friction: The feet's friction triple (sliding, torsional, rolling).
        solref: The contact's ``solref`` (time constant [s], damping ratio).
        repairs: What was changed so that MuJoCo takes the URDF (:attr:`SimModel.repairs`).
    """

    spec: Any
    trunk_link: str
    child_links: dict[str, str]
    friction: list[float]
    solref: list[float]
    repairs: list[str]


def urdf_spec(robot: Robot, kept: set[str], settings: SimSettings) -> UrdfSpec:
    """``robot``'s URDF read by MuJoCo, every joint not in ``kept`` fixed (module docstring).

    ``settings`` must be complete (:meth:`SimSettings.for_leg_length`).

    Raises:
        ModelError: The URDF cannot be read, or MuJoCo refuses it (the message names the file).
    """
    path = Path(robot.urdf_path)
    # the checked text (size, UTF-8, no DTD, finite numbers), parsed without entities
    root = fromstring(read_urdf_text(path).encode("utf-8"), forbid_dtd=True)
    trunk_link = _root_link(root, path)
    child_links = {name: _child_link(root, name) for name in kept}
    _strip_bodies(root, kept)
    repairs = _repair_singular_inertias(root)
    repairs += _unbalanced_inertias(root)
    repairs += _drop_joint_dynamics(root, kept)
    try:
        spec = mujoco.MjSpec.from_string(ET.tostring(root, encoding="unicode"))
    except ValueError as exc:
        raise ModelError(f"{path}: MuJoCo cannot read the URDF ({exc})") from exc
    spec.compiler.balanceinertia = True  # acts only on the tensors _unbalanced_inertias lists
    friction = [settings.foot_friction, _TORSIONAL_FRICTION, _ROLLING_FRICTION]
    solref = [settings.value("contact_time_constant_s"), settings.contact_damping_ratio]
    spec.worldbody.add_geom(
        name="ground",
        type=mujoco.mjtGeom.mjGEOM_PLANE,
        size=[0, 0, 1],
        contype=0,
        conaffinity=1,
        friction=friction,
        solref=solref,
    )
    spec.option.timestep = settings.value("timestep_s")
    spec.option.enableflags |= mujoco.mjtEnableBit.mjENBL_ENERGY
    return UrdfSpec(spec, trunk_link, child_links, friction, solref, repairs)


def compile_spec(spec: Any, robot: Robot) -> mujoco.MjModel:
    """Compile ``spec``.

    Raises:
        ModelError: MuJoCo refuses the model (the message names the URDF and gives the reason).
    """
    try:
        return spec.compile()
    except ValueError as exc:
        raise ModelError(f"{robot.urdf_path}: MuJoCo cannot compile the model ({exc})") from exc


def build_sim_model(robot: Robot, settings: SimSettings) -> SimModel:
    """Build the sagittal MuJoCo model of ``robot`` from its URDF.

    Raises:
        ModelError: The URDF cannot be read, or MuJoCo refuses the model (the message names
            the file and gives MuJoCo's reason).
    """
    legs = {leg: robot.leg(leg) for leg in LEG_NAMES}
    sagittal = {name for leg in legs.values() for name in leg.joint_names}
    settings, _ = settings.for_leg_length(robot.leg_length_m)
    radius = settings.value("foot_radius_m")
    built = urdf_spec(robot, sagittal, settings)
    spec, friction, solref, repairs = built.spec, built.friction, built.solref, built.repairs
    shank_links = {name: built.child_links[leg.joint_names[1]] for name, leg in legs.items()}
    trunk = spec.body(built.trunk_link)
    trunk.add_joint(name=TRUNK_JOINTS[0], type=mujoco.mjtJoint.mjJNT_SLIDE, axis=[1, 0, 0])
    trunk.add_joint(name=TRUNK_JOINTS[1], type=mujoco.mjtJoint.mjJNT_SLIDE, axis=[0, 0, 1])
    trunk.add_joint(name=TRUNK_JOINTS[2], type=mujoco.mjtJoint.mjJNT_HINGE, axis=[0, 1, 0])
    for name, leg in legs.items():
        _add_foot_and_motors(spec, name, leg, shank_links[name], radius, friction, solref)
    model = compile_spec(spec, robot)

    def addresses(joints: tuple[str, ...], kind: str) -> np.ndarray:
        field = "jnt_qposadr" if kind == "qpos" else "jnt_dofadr"
        return np.array([getattr(model, field)[model.joint(j).id] for j in joints], dtype=int)

    return SimModel(
        model=model,
        trunk_qpos=addresses(TRUNK_JOINTS, "qpos"),
        trunk_dof=addresses(TRUNK_JOINTS, "dof"),
        leg_qpos={n: addresses(leg.joint_names, "qpos") for n, leg in legs.items()},
        leg_dof={n: addresses(leg.joint_names, "dof") for n, leg in legs.items()},
        leg_actuators={
            n: np.array([model.actuator(j).id for j in leg.joint_names]) for n, leg in legs.items()
        },
        foot_geom={n: model.geom(f"{n}_foot_contact").id for n in legs},
        foot_body={n: int(model.geom_bodyid[model.geom(f"{n}_foot_contact").id]) for n in legs},
        foot_radius_m=radius,
        effort_limit_nm={n: leg.effort_limits_nm for n, leg in legs.items()},
        repairs=tuple(repairs),
    )
