"""The drive interface: outputs, power and bounds of one joint's actuator from ``(q, qd, tau)``.

Per sample, the energy pipeline gives a drive the joint angle ``q`` [rad], rate ``qd`` [rad/s]
and torque ``tau`` [N m] (CasADi expressions or numbers) and asks it for

* its *outputs*: named scalar channels such as a cylinder's length or force (:attr:`channels`
  declares their names and units; they become columns of ``samples.csv``);
* its *power*: the joint's signed mechanical power ``tau qd`` is charged through the chosen
  accounting when :attr:`charges_joint_power` is true, and :meth:`loss_rate` [W] is added on
  top, e.g. friction heat. A drive that meters its own input power (a valve-controlled hydraulic
  supply: pressure x flow; an electric motor: electrical power) does not charge the joint power
  and returns everything it draws from :meth:`loss_rate`;
* its *bounds*: allowed ranges of outputs over the joint's range (a cylinder's stroke).

Every method is written with CasADi operations, so one formula serves floats, numeric arrays and
the symbolic NLP. The non-smooth operations go through the ``max_fn`` argument of
:meth:`Drive.loss_rate`: the exact :func:`casadi.fmax`, or for the NLP a smooth max whose width
is 1e-4 in its argument's unit; a drive passes arguments in units where that width is negligible
(velocities in m/s or rad/s, powers scaled, see :mod:`scalf_opt.actuators.electric`).
"""

from __future__ import annotations

from collections.abc import Callable, Mapping
from dataclasses import dataclass
from typing import Any, ClassVar

import casadi as ca

from scalf_opt.tables import Table
from scalf_opt.types import Expr

MaxFn = Callable[[Expr, Expr], Expr]
"""``max_fn(x, 0)`` returns ``max(x, 0)``, exactly (:func:`casadi.fmax`) or smoothed."""


@dataclass(frozen=True)
class Channel:
    """One output of a drive.

    Attributes:
        name: Column stem, e.g. ``cyl_len``; the CSV column is ``<name>_<joint>_<unit>``.
        unit: SI unit as it appears in column names (``m``, ``m_s``, ``n``, ``w``).
        description: What it is, for the README and reports.
    """

    name: str
    unit: str
    description: str


@dataclass(frozen=True)
class Drive:
    """The actuator of one joint; the base class behaves as a lossless torque source.

    Attributes:
        joint_name: URDF name of the joint the drive moves.
        kind: Short name of the drive model (``ideal``, ``cylinder``, ...).
        channels: The outputs :meth:`outputs` returns, in order.
        charges_joint_power: The joint's mechanical power ``tau qd`` is drawn (through the
            accounting) in addition to :meth:`loss_rate`.
        power_text: What a drive that does not charge the joint power draws, in words, for
            reports (its :meth:`loss_rate` is all it draws).
        noun: What the drive is, in words (``cylinder``, ``electric drive``).
        file_table: The actuator file's table that names its joint (``cylinders``).
    """

    joint_name: str
    kind: ClassVar[str] = "drive"
    channels: ClassVar[tuple[Channel, ...]] = ()
    charges_joint_power: ClassVar[bool] = True
    power_text: ClassVar[str] = ""
    noun: ClassVar[str] = "drive"
    file_table: ClassVar[str] = ""

    def outputs(self, q: Expr, qd: Expr, tau: Expr) -> dict[str, Expr]:
        """The drive's per-sample outputs, one scalar per channel (SI units)."""
        return {}

    def loss_rate(self, q: Expr, qd: Expr, tau: Expr, max_fn: MaxFn = ca.fmax) -> Expr:
        """Power the drive draws beyond the charged joint power [W].

        Never negative, except for a drive that recovers energy (a regenerative electric
        drive). For a drive that does not charge the joint power it is all the drive draws.
        """
        return 0.0 * q

    def output_bounds(self, q_lower: float, q_upper: float) -> dict[str, tuple[float, float]]:
        """Allowed range of some outputs while the joint stays in ``[q_lower, q_upper]`` [rad]."""
        return {}

    def summary(self) -> str:
        """One line describing the drive and its parameters, for reports."""
        return f"{self.kind} drive"

    def described(self, q_lower: float, q_upper: float) -> dict[str, Any]:
        """The drive's parameters for ``scalf-opt model --json`` (SI); none by default.

        ``[q_lower, q_upper]`` [rad] is the joint's range, over which a drive may report what its
        parameters give (a cylinder: its length range).
        """
        return {}


@dataclass(frozen=True)
class IdealDrive(Drive):
    """A lossless torque source: the joint draws its mechanical power and nothing else."""

    kind: ClassVar[str] = "ideal"


DriveReader = Callable[[Table, Mapping[str, Drive]], dict[str, Drive]]
"""``read(file, drives)``: the drives one kind's table(s) of an actuator file give, keyed by
joint; ``file`` is the file's top level, ``drives`` those the kinds before it gave."""


@dataclass(frozen=True)
class DriveKind:
    """One kind of drive in the actuator-file registry (``registry.DRIVE_KINDS``).

    Attributes:
        tables: The top-level tables of the actuator file the kind reads (``cylinders``,
            ``friction``); together the registry's tables are every table a file may have.
        read: Its reader (:data:`DriveReader`), written with :class:`~scalf_opt.tables.Table` so
            that every message names the file and the key path.
        help: The kind's tables in one line, for the documentation.
        replaces: Its drives replace those the kinds before it gave the same joints (a supply
            feeding cylinders); otherwise a joint given two drives is an error.
        check: A check over the file's final drives, or ``None`` (a cylinder not fed by a supply
            needs the friction table).
    """

    tables: tuple[str, ...]
    read: DriveReader
    help: str
    replaces: bool = False
    check: Callable[[Table, Mapping[str, Drive]], None] | None = None
