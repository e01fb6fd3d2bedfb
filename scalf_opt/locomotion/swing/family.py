"""The interface of swing families and the affine path every family returns.

Every family describes the swing over normalised time ``s = t / T_sw`` in [0, 1] and returns its
samples as an *affine* function of its free parameters ``theta``::

    y(s; theta) = y_0(s) + Y(s) theta,

for the value and the first two time derivatives of two coordinates: the foot ``(x, z)`` in the
leg frame (``space == "foot"``) or the joint angles ``(hip pitch, knee)`` (``space == "joint"``).
"""

from __future__ import annotations

import math
from abc import ABC, abstractmethod
from collections.abc import Sequence
from dataclasses import dataclass
from typing import TYPE_CHECKING

import numpy as np

from scalf_opt.errors import ConfigError
from scalf_opt.locomotion.gait import Gait
from scalf_opt.locomotion.swing.boundary import SwingBoundary, foot_boundary, joint_boundary
from scalf_opt.model.kinematics import LegKinematics
from scalf_opt.types import Space

if TYPE_CHECKING:  # SciPy's sparse matrices load only with the families that use them
    from scipy.sparse import csr_array

DEG = math.pi / 180.0
PARAMETER_SCALE = {"joint": DEG, "foot": 0.01}
"""SI value of one unit of a free parameter: 1 degree (joint space) or 1 cm (foot space)."""

PARAMETER_UNIT = {"joint": "deg", "foot": "cm"}

Terms = tuple[tuple[str, int], ...]
"""Fourier terms ``(kind, order)``, kind ``cos`` or ``sin``."""


@dataclass(frozen=True)
class AffinePath:
    """Samples of a swing path, affine in the free parameters.

    ``values(theta)[d]`` is the d-th time derivative (d = 0, 1, 2), shape (2, n), SI units.

    Attributes:
        space: ``foot`` or ``joint``.
        t_s: Sample times since lift-off, shape (n,) [s].
        base: Path at theta = 0, shape (3, 2, n).
        basis: Change per unit parameter: dense, shape (3, 2, n, n_params); or, for a family
            whose every sample depends on a few parameters (the B-splines), a SciPy sparse
            matrix of shape (6 n, n_params) whose rows are ``base``'s entries in C order.
    """

    space: Space
    t_s: np.ndarray
    base: np.ndarray
    basis: np.ndarray | csr_array

    @property
    def n_params(self) -> int:
        """Number of free parameters."""
        return int(self.basis.shape[-1])

    @property
    def sparse(self) -> bool:
        """The basis is a sparse matrix."""
        return not isinstance(self.basis, np.ndarray)

    def basis_rows(self) -> np.ndarray | csr_array:
        """The basis as a matrix of shape (6 n, n_params), rows in ``base``'s C order."""
        if isinstance(self.basis, np.ndarray):
            return self.basis.reshape(-1, self.n_params)
        return self.basis

    def dense_basis(self) -> np.ndarray:
        """The basis as a dense array of shape (3, 2, n, n_params)."""
        if isinstance(self.basis, np.ndarray):
            return self.basis
        return np.asarray(self.basis.toarray()).reshape(*self.base.shape, self.n_params)

    def values(self, theta: np.ndarray | None = None) -> np.ndarray:
        """Position, velocity, acceleration samples, shape (3, 2, n)."""
        if theta is None or self.n_params == 0:
            return self.base.copy()
        theta = np.asarray(theta, dtype=float)
        if isinstance(self.basis, np.ndarray):
            return self.base + self.basis @ theta
        return self.base + np.asarray(self.basis @ theta).reshape(self.base.shape)


class SwingFamily(ABC):
    """Interface of a swing family: a name, a space, free parameters and an affine path.

    ``free_terms`` holds, per coordinate (hip, knee or x, z), the Fourier terms whose
    coefficients are free; parameters are ordered coordinate by coordinate.
    """

    name: str
    space: Space
    free_terms: tuple[Terms, Terms] = ((), ())

    @property
    def n_params(self) -> int:
        """Number of free parameters per leg."""
        return len(self.free_terms[0]) + len(self.free_terms[1])

    @property
    def coefficient_names(self) -> list[str]:
        """Names of the free terms' coefficients, e.g. ``hip_cos3`` (joint) or ``z_sin4`` (foot)."""
        coords = ("hip", "knee") if self.space == "joint" else ("x", "z")
        return [
            f"{c}_{k}{o}"
            for c, terms in zip(coords, self.free_terms, strict=True)
            for k, o in terms
        ]

    @property
    def parameter_names(self) -> list[str]:
        """Names of the free parameters: the coefficients' unless a family says otherwise."""
        return self.coefficient_names

    def fourier_coefficients(self, theta: np.ndarray) -> np.ndarray:
        """The free terms' coefficients (family units) of the member with parameters ``theta``."""
        return np.asarray(theta, dtype=float).copy()

    def from_fourier_coefficients(self, coefficients: np.ndarray) -> np.ndarray:
        """The parameters of the member whose free terms' coefficients are ``coefficients``."""
        return np.asarray(coefficients, dtype=float).copy()

    def theta_from_record(self, values: Sequence[float], names: Sequence[str] | None) -> np.ndarray:
        """Parameters saved with their names (or without: a file from before the names).

        A record names either this family's parameters or its terms' coefficients (files
        written before the modal parameters of ``joint-N`` and ``fourier-N``); values saved
        without names are coefficients, as every file without them was written.

        Raises:
            ConfigError: The names are neither, or their count is not the values'.
        """
        theta = np.asarray(values, dtype=float)
        if names is not None and list(names) == self.parameter_names:
            return theta
        if names is None or list(names) == self.coefficient_names:
            if theta.size != self.n_params:
                raise ConfigError(
                    f"family {self.name}: {self.n_params} parameters expected, got {theta.size}"
                )
            return self.from_fourier_coefficients(theta)
        raise ConfigError(
            f"family {self.name}: parameters named {list(names)} are neither "
            f"{self.parameter_names} nor {self.coefficient_names}"
        )

    @property
    def parameter_unit(self) -> str:
        """Unit of the free parameters (``deg`` or ``cm``)."""
        return PARAMETER_UNIT.get(self.space, "")

    def shortest_period_s(self, swing_duration_s: float) -> float:
        """Period of the fastest variation a member can have [s]; the sampling must resolve it.

        The default, for families without free parameters, is the swing itself.
        """
        return swing_duration_s

    def boundary(self, gait: Gait, kin: LegKinematics) -> SwingBoundary:
        """Boundary conditions of this family's space."""
        if self.space == "joint":
            return joint_boundary(gait, kin)
        return foot_boundary(gait, kin.leg.name)

    @abstractmethod
    def path(self, gait: Gait, kin: LegKinematics, t_s: np.ndarray | None = None) -> AffinePath:
        """Swing samples as an affine function of the parameters.

        Args:
            gait: The gait (its swing duration and boundary conditions).
            kin: The leg's kinematics.
            t_s: Times since lift-off, in [0, T_sw] [s]; ``None``: the gait's swing grid. (The
                whole-body loads need the swinging legs at the stance legs' sample times.)
        """

    def embed(self, theta: np.ndarray, poorer: SwingFamily) -> np.ndarray:
        """Map a poorer nested family's parameters to this family's (zeros elsewhere)."""
        nested = poorer.space == self.space and all(
            set(old) <= set(new)
            for old, new in zip(poorer.free_terms, self.free_terms, strict=True)
        )
        if not nested:
            raise ConfigError(f"family {poorer.name} is not nested in {self.name}")
        theta = np.asarray(theta, dtype=float)
        shared = set(poorer.parameter_names) <= set(self.parameter_names)
        if shared and all(
            new[: len(old)] == old
            for old, new in zip(poorer.free_terms, self.free_terms, strict=True)
        ):  # the same parameters (terms or modes) of leading terms: mapped by name, exactly
            return self._by_name(theta, poorer.parameter_names, self.parameter_names)
        coefficients = self._by_name(
            poorer.fourier_coefficients(theta), poorer.coefficient_names, self.coefficient_names
        )
        return self.from_fourier_coefficients(coefficients)

    @staticmethod
    def _by_name(values: np.ndarray, names: list[str], into: list[str]) -> np.ndarray:
        """``values`` named ``names`` placed at their names in a zero vector named ``into``."""
        out = np.zeros(len(into))
        for name, value in zip(names, values, strict=True):
            out[into.index(name)] = value
        return out
