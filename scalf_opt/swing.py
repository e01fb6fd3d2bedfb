"""Swing-foot trajectory families: the cubic-spline reference and truncated Fourier series.

Every family describes the swing over normalised time ``s = tau / T_sw`` in [0, 1] and returns
its samples as an *affine* function of its free parameters ``theta``::

    y(s; theta) = y_0(s) + Y(s) theta,

for the value and the first two time derivatives of two coordinates: the foot ``(x, z)`` in the
leg frame (``space == "foot"``) or the joint angles ``(hip pitch, knee)`` (``space == "joint"``).

Boundary conditions (decisions 12-14). At lift-off (s = 0) and touch-down (s = 1) position and
velocity equal the stance path's (Table 3), so the foot neither slips nor stamps: every family
meets these by construction. The mid-swing clearance, the foot at least H above the ground at
s = 1/2 (decision 14), is a constraint of the optimization problem; the reference spline meets it
with equality (its apex knot). In joint space the end conditions are mapped through closed-form
IK and the Jacobian.

Fourier family (the analogue of the paper's lost Appendix A). Each coordinate is a half-range
Fourier series of order N, fundamental period ``2 T_sw`` (the gait period for a 50 % duty)::

    y(s) = a_0 + sum_{k=1..N} (a_k cos(k pi s) + b_k sin(k pi s)).

The four end conditions ``y(0), y(1), y'(0), y'(1)`` are linear in the coefficients. Four of them,
``a_0, a_1, b_1, b_2``, are *eliminated*: their 4 x 4 system ``B_c c_c = d - B_f c_f`` is regular::

    a_1 = (y(0) - y(1)) / 2 - (free cos terms of odd order),
    b_1 = (y'(0) - y'(1)) / (2 pi) - ...,   b_2 = (y'(0) + y'(1)) / (4 pi) - ...,
    a_0 = (y(0) + y(1)) / 2 - (free cos terms of even order),

so every choice of the free coefficients ``c_f`` (``a_2`` and all terms of orders 3..N) gives a
trajectory that meets the end conditions exactly. The free coefficients, scaled to degrees (joint
space) or centimetres (foot space), are the parameters ``theta``.

Families are nested by construction: ``joint-N`` keeps ``a_2`` and orders 3..N free in both
coordinates, so setting the new coefficients of ``joint-(N+1)`` to zero reproduces ``joint-N``
exactly. The ``paper`` family has the paper's two free coefficients per leg: C1, the
``cos(3 pi s)`` amplitude of the hip angle, and C2, the ``cos(2 pi s)`` amplitude of the knee
angle; it is the member of ``joint-3`` whose other free coefficients vanish. (Of the 50 pairs of
single terms of orders 2-4 in foot and joint space, this pair gives the lowest swing energy:
``studies/paper_family_scan.py`` reproduces the scan.)
"""

from __future__ import annotations

import math
import re
from dataclasses import dataclass

import numpy as np
from scipy.interpolate import CubicSpline

from scalf_opt.errors import ConfigError
from scalf_opt.gait import GaitSpec
from scalf_opt.kinematics import LegKinematics

DEG = math.pi / 180.0
PARAMETER_SCALE = {"joint": DEG, "foot": 0.01}
"""SI value of one unit of a free parameter: 1 degree (joint space) or 1 cm (foot space)."""

PARAMETER_UNIT = {"joint": "deg", "foot": "cm"}

ELIMINATED_TERMS: tuple[tuple[str, int], ...] = (
    ("cos", 0),
    ("cos", 1),
    ("sin", 1),
    ("sin", 2),
)
"""The four Fourier terms solved from the end conditions."""

Terms = tuple[tuple[str, int], ...]
"""Fourier terms ``(kind, order)``, kind ``cos`` or ``sin``."""


@dataclass(frozen=True)
class SwingBoundary:
    """Boundary conditions of one leg's swing in one space (position, velocity in SI units).

    Attributes:
        space: ``foot`` (metres) or ``joint`` (radians).
        start: Value at lift-off, shape (2,).
        end: Value at touch-down, shape (2,).
        start_rate: Time derivative at lift-off, shape (2,) [per s].
        end_rate: Time derivative at touch-down, shape (2,) [per s].
        duration_s: Swing duration T_sw [s].
    """

    space: str
    start: np.ndarray
    end: np.ndarray
    start_rate: np.ndarray
    end_rate: np.ndarray
    duration_s: float


def foot_boundary(gait: GaitSpec) -> SwingBoundary:
    """Swing boundary conditions in foot space (leg frame) for ``gait``."""
    p_stance, pd_stance, _ = gait.stance_path(np.array([0.0, gait.stance_duration_s]))
    return SwingBoundary(
        space="foot",
        start=p_stance[:, 1],  # lift-off = end of stance
        end=p_stance[:, 0],  # touch-down = start of stance
        start_rate=pd_stance[:, 1],
        end_rate=pd_stance[:, 0],
        duration_s=gait.swing_duration_s,
    )


def joint_boundary(gait: GaitSpec, kin: LegKinematics) -> SwingBoundary:
    """Swing boundary conditions mapped to joint space through IK and the foot Jacobian."""
    foot = foot_boundary(gait)
    points = np.column_stack([foot.start, foot.end])
    q = kin.inverse(points)
    rates = [
        np.linalg.solve(kin.jacobian(q[:, i]), v)
        for i, v in ((0, foot.start_rate), (1, foot.end_rate))
    ]
    return SwingBoundary(
        space="joint",
        start=q[:, 0],
        end=q[:, 1],
        start_rate=rates[0],
        end_rate=rates[1],
        duration_s=foot.duration_s,
    )


@dataclass(frozen=True)
class AffinePath:
    """Samples of a swing path, affine in the free parameters.

    ``values(theta)[d]`` is the d-th time derivative (d = 0, 1, 2), shape (2, n), SI units.

    Attributes:
        space: ``foot`` or ``joint``.
        tau_s: Sample times since lift-off, shape (n,) [s].
        base: Path at theta = 0, shape (3, 2, n).
        basis: Change per unit parameter, shape (3, 2, n, n_params).
    """

    space: str
    tau_s: np.ndarray
    base: np.ndarray
    basis: np.ndarray

    @property
    def n_params(self) -> int:
        """Number of free parameters."""
        return int(self.basis.shape[-1])

    def values(self, theta: np.ndarray | None = None) -> np.ndarray:
        """Position, velocity, acceleration samples, shape (3, 2, n)."""
        if theta is None or self.n_params == 0:
            return self.base.copy()
        return self.base + self.basis @ np.asarray(theta, dtype=float)


def fourier_term(kind: str, order: int, s: np.ndarray, derivative: int = 0) -> np.ndarray:
    """The ``derivative``-th derivative in ``s`` of ``cos(order pi s)`` or ``sin(order pi s)``."""
    s = np.asarray(s, dtype=float)
    if order == 0:
        return np.ones_like(s) if (kind == "cos" and derivative == 0) else np.zeros_like(s)
    w = order * math.pi
    shift = -math.pi / 2 if kind == "sin" else 0.0  # sin(x) = cos(x - pi/2)
    return w**derivative * np.cos(w * s + shift + derivative * math.pi / 2)


def _functionals(terms: Terms) -> np.ndarray:
    """Rows y(0), y(1), y'(0), y'(1) of the given terms, shape (4, len(terms))."""
    rows = []
    for s, d in ((0.0, 0), (1.0, 0), (0.0, 1), (1.0, 1)):
        rows.append([float(fourier_term(k, o, np.array(s), d)) for k, o in terms])
    return np.array(rows)


class SwingFamily:
    """Interface of a swing family: a name, a space, free parameters and an affine path.

    ``free_terms`` holds, per coordinate (hip, knee or x, z), the Fourier terms whose
    coefficients are free; parameters are ordered coordinate by coordinate.
    """

    name: str
    space: str
    free_terms: tuple[Terms, Terms] = ((), ())

    @property
    def n_params(self) -> int:
        """Number of free parameters per leg."""
        return len(self.free_terms[0]) + len(self.free_terms[1])

    @property
    def parameter_names(self) -> list[str]:
        """Names of the free parameters, e.g. ``hip_cos3`` (joint) or ``z_sin4`` (foot)."""
        coords = ("hip", "knee") if self.space == "joint" else ("x", "z")
        return [
            f"{c}_{k}{o}"
            for c, terms in zip(coords, self.free_terms, strict=True)
            for k, o in terms
        ]

    @property
    def parameter_unit(self) -> str:
        """Unit of the free parameters (``deg`` or ``cm``)."""
        return PARAMETER_UNIT.get(self.space, "")

    def boundary(self, gait: GaitSpec, kin: LegKinematics) -> SwingBoundary:
        """Boundary conditions of this family's space."""
        return joint_boundary(gait, kin) if self.space == "joint" else foot_boundary(gait)

    def path(self, gait: GaitSpec, kin: LegKinematics) -> AffinePath:
        """Swing samples on the gait's swing grid as an affine function of the parameters."""
        raise NotImplementedError

    def embed(self, theta: np.ndarray, poorer: SwingFamily) -> np.ndarray:
        """Map a poorer nested family's parameters to this family's (zeros elsewhere)."""
        nested = poorer.space == self.space and all(
            set(old) <= set(new)
            for old, new in zip(poorer.free_terms, self.free_terms, strict=True)
        )
        if not nested:
            raise ConfigError(f"family {poorer.name} is not nested in {self.name}")
        names = self.parameter_names
        out = np.zeros(self.n_params)
        for name, value in zip(poorer.parameter_names, np.asarray(theta, dtype=float), strict=True):
            out[names.index(name)] = value
        return out


class ReferenceSpline(SwingFamily):
    """The paper's reference: clamped cubic splines in x and z (decision 12), no free parameter.

    Each coordinate is a two-piece C2 cubic spline through lift-off, the mid-swing apex at
    ``T_sw / 2`` and touch-down, with end slopes equal to the stance velocity.
    """

    name = "reference"
    space = "foot"

    def path(self, gait: GaitSpec, kin: LegKinematics) -> AffinePath:  # noqa: D102
        b = foot_boundary(gait)
        apex = np.array([0.0, -gait.stance_height_m + gait.clearance_m])  # decision 12
        tau = gait.phase_times_s("swing")
        knots = np.array([0.0, 0.5 * b.duration_s, b.duration_s])
        base = np.zeros((3, 2, tau.size))
        for c in range(2):
            spline = CubicSpline(
                knots,
                [b.start[c], apex[c], b.end[c]],
                bc_type=((1, b.start_rate[c]), (1, b.end_rate[c])),
            )
            for d in range(3):
                base[d, c] = spline(tau, d)
        return AffinePath("foot", tau, base, np.zeros((3, 2, tau.size, 0)))


class FourierFamily(SwingFamily):
    """Half-range Fourier series with four coefficients eliminated by the end conditions.

    Args:
        name: Family name.
        space: ``foot`` or ``joint``.
        free_terms: Free Fourier terms of each coordinate; none may be an eliminated term.
    """

    def __init__(self, name: str, space: str, free_terms: tuple[Terms, Terms]) -> None:
        if space not in ("foot", "joint"):
            raise ConfigError(f"family space must be 'foot' or 'joint', got {space!r}")
        for terms in free_terms:
            if set(terms) & set(ELIMINATED_TERMS):
                raise ConfigError(f"family {name}: {terms} overlaps the eliminated terms")
        self.name = name
        self.space = space
        self.free_terms = free_terms

    def path(self, gait: GaitSpec, kin: LegKinematics) -> AffinePath:  # noqa: D102
        b = self.boundary(gait, kin)
        tau = gait.phase_times_s("swing")
        s = tau / b.duration_s
        inv = np.linalg.inv(_functionals(ELIMINATED_TERMS))
        scale = PARAMETER_SCALE[self.space]
        base = np.zeros((3, 2, tau.size))
        basis = np.zeros((3, 2, tau.size, self.n_params))
        column = 0
        for c, terms in enumerate(self.free_terms):
            data = np.array(
                [b.start[c], b.end[c], b.start_rate[c] * b.duration_s, b.end_rate[c] * b.duration_s]
            )
            coefficients = inv @ data
            free_map = -inv @ _functionals(terms) if terms else np.zeros((4, 0))
            for d in range(3):
                time_scale = b.duration_s**-d  # d/dtau = (1/T_sw) d/ds
                phi_c = np.column_stack([fourier_term(k, o, s, d) for k, o in ELIMINATED_TERMS])
                base[d, c] = time_scale * (phi_c @ coefficients)
                if terms:
                    phi_f = np.column_stack([fourier_term(k, o, s, d) for k, o in terms])
                    basis[d, c, :, column : column + len(terms)] = (
                        time_scale * scale * (phi_f + phi_c @ free_map)
                    )
            column += len(terms)
        return AffinePath(self.space, tau, base, basis)


PAPER_FREE_TERMS: tuple[Terms, Terms] = ((("cos", 3),), (("cos", 2),))
"""The paper family's C1 (hip) and C2 (knee) terms."""


def order_terms(order: int) -> Terms:
    """Free terms of a family of order N: ``cos(2 pi s)`` and cos and sin of orders 3..N."""
    return (("cos", 2), *((kind, k) for k in range(3, order + 1) for kind in ("cos", "sin")))


_FAMILY_PATTERN = re.compile(r"^(fourier|joint)-(\d+)$")
MAX_ORDER = 12


def make_family(name: str) -> SwingFamily:
    """Build a family from its name: ``reference``, ``paper``, ``fourier-N`` or ``joint-N``.

    Raises:
        ConfigError: Unknown name or an order outside 2..12.
    """
    if name == "reference":
        return ReferenceSpline()
    if name == "paper":
        return FourierFamily("paper", "joint", PAPER_FREE_TERMS)
    match = _FAMILY_PATTERN.match(name)
    if not match:
        raise ConfigError(
            f"unknown family {name!r}: use reference, paper, fourier-N (foot space) or "
            f"joint-N (joint space) with N in 2..{MAX_ORDER}"
        )
    order = int(match.group(2))
    if not 2 <= order <= MAX_ORDER:
        raise ConfigError(f"family {name!r}: order N must be in 2..{MAX_ORDER}, got {order}")
    space = "foot" if match.group(1) == "fourier" else "joint"
    terms = order_terms(order)
    return FourierFamily(name, space, (terms, terms))
