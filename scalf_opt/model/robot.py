"""A URDF loaded into Pinocchio once: the whole robot, fixed at its trunk, with named legs.

Frames (the trunk frame, which is Pinocchio's world for the fixed-base model): x forward, y left,
z up, origin at the URDF root link.
"""

from __future__ import annotations

from collections.abc import Iterable
from dataclasses import dataclass
from functools import cached_property
from pathlib import Path

import numpy as np
import pinocchio as pin

from scalf_opt.errors import ModelError
from scalf_opt.model.leg import Leg
from scalf_opt.model.naming import LegNaming, detect_naming
from scalf_opt.model.urdf_file import read_urdf_text

INERTIA_TOLERANCE = 1e-9
"""Relative round-off allowed in the eigenvalue and triangle checks of a body's inertia."""


def check_bodies(model: pin.Model, path: Path) -> None:
    """Every body Pinocchio built (fixed-joint children merged in) has a physical inertia.

    Its rotational inertia about the COM is symmetric positive semi-definite and its principal
    moments satisfy the triangle inequality ``I_a + I_b >= I_c``. The check is on Pinocchio's
    bodies, not on the URDF's links: many published URDFs carry massless marker links with
    degenerate inertias (HyQ's feet, ANYmal's camera frames) that vanish in the merged body.

    Raises:
        ModelError: A body's inertia is not physical; the message names the body's joint.
    """
    for i in range(model.njoints):
        inertia = model.inertias[i]
        if inertia.mass <= 0:
            continue
        moments = np.linalg.eigvalsh(0.5 * (inertia.inertia + inertia.inertia.T))
        scale = max(float(np.abs(moments).max()), 1e-12)
        body = model.names[i] if i else "the root link"
        if moments[0] < -INERTIA_TOLERANCE * scale:
            raise ModelError(
                f"{path}: the body of {body} has a rotational inertia that is not positive "
                f"semi-definite (principal moments {moments} kg m^2)"
            )
        if moments[0] + moments[1] < moments[2] - INERTIA_TOLERANCE * scale:
            raise ModelError(
                f"{path}: the body of {body} breaks the triangle inequality of inertia "
                f"(principal moments {moments} kg m^2)"
            )


def parse_urdf(path: Path) -> pin.Model:
    """Pinocchio's fixed-base model of a URDF file, read as untrusted input.

    Raises:
        ModelError: The file is missing, unsafe or unphysical (:func:`read_urdf_text`,
            :func:`check_bodies`), or is not a URDF Pinocchio reads.
    """
    text = read_urdf_text(path)
    try:
        model = pin.buildModelFromXML(text)
    except (RuntimeError, ValueError) as exc:
        first = str(exc).strip().splitlines()[0] if str(exc).strip() else type(exc).__name__
        raise ModelError(f"{path}: not a valid URDF ({first})") from exc
    check_bodies(model, path)
    return model


@dataclass(frozen=True)
class Robot:
    """A whole robot as Pinocchio sees it (fixed base at the trunk), with named legs.

    Attributes:
        model: Pinocchio model of the whole robot, root = trunk, gravity (0, 0, -9.81) m/s^2.
        urdf_path: The URDF it was built from.
        naming: How its legs' joints and feet are named.
        name: Robot name for reports (the catalog's name, or the URDF file's stem).
        nominal_stance_height_m: Pitching hip above the ground in the robot's nominal standing
            posture [m], when known (the catalog's value); the default gait uses it.
        reference_q: The robot's standing configuration (nq), when known (an SRDF's
            ``standing`` state); it fixes each leg's IK branch.
    """

    model: pin.Model
    urdf_path: Path
    naming: LegNaming
    name: str
    nominal_stance_height_m: float | None = None
    reference_q: np.ndarray | None = None

    @classmethod
    def from_urdf(
        cls,
        urdf_path: str | Path,
        namings: Iterable[LegNaming],
        name: str | None = None,
        nominal_stance_height_m: float | None = None,
        srdf: tuple[Path, str] | None = None,
    ) -> Robot:
        """Parse a URDF with Pinocchio (once) and recognise its leg naming among ``namings``.

        Args:
            urdf_path: The URDF.
            namings: Naming conventions to try.
            name: Robot name (default: the file's stem).
            nominal_stance_height_m: See the attribute.
            srdf: ``(SRDF path, state name)`` of the standing configuration, if any.

        Raises:
            ModelError: The file is missing, is not a URDF Pinocchio reads, or has no known legs.
        """
        path = Path(urdf_path)
        model = parse_urdf(path)
        naming = detect_naming(model, namings, str(path))
        reference = None
        if srdf is not None:
            srdf_path, state = srdf
            pin.loadReferenceConfigurations(model, str(srdf_path), False)
            if state not in model.referenceConfigurations:
                raise ModelError(f"{srdf_path}: no group state {state!r}")
            reference = np.array(model.referenceConfigurations[state], dtype=float)
        return cls(model, path, naming, name or path.stem, nominal_stance_height_m, reference)

    @property
    def total_mass_kg(self) -> float:
        """Mass of the whole robot [kg]."""
        return float(sum(inertia.mass for inertia in self.model.inertias))

    @property
    def trunk_com_m(self) -> np.ndarray:
        """Centre of mass of the root link (the trunk) in the trunk frame, shape (3,) [m]."""
        # Pinocchio attaches the root link's inertia of a fixed-base model to the universe joint.
        return np.array(self.model.inertias[0].lever, dtype=float)

    @property
    def trunk_mass_kg(self) -> float:
        """Mass of the root link (the trunk) [kg]: what the stance legs carry (decision 11)."""
        return float(self.model.inertias[0].mass)

    def leg(self, name: str) -> Leg:
        """The sagittal two-joint view of leg ``name`` (RF, LH, LF or RH), built once."""
        if name not in self._legs:
            self._legs[name] = Leg.from_robot_model(
                self.model, name, self.naming.names(name), self.urdf_path, self.reference_q
            )
        return self._legs[name]

    @cached_property
    def _legs(self) -> dict[str, Leg]:
        return {}
