"""Truncated Fourier series with the end conditions built in: the energy-efficient families.

Fourier family (the analogue of the paper's lost Appendix A). Each coordinate is a half-range
Fourier series of order N, fundamental period ``2 T_sw`` (the gait period for a 50 % duty)::

    y(s) = a_0 + sum_{k=1..N} (a_k cos(k pi s) + b_k sin(k pi s)).

The four end conditions ``y(0), y(1), y'(0), y'(1)`` are linear in the coefficients. Four of them,
``a_0, a_1, b_1, b_2``, are *eliminated*: their 4 x 4 system ``B_c c_c = d - B_f c_f`` is regular::

    a_1 = (y(0) - y(1)) / 2 - (free cos terms of odd order),
    b_1 = (y'(0) - y'(1)) / (2 pi) - ...,   b_2 = (y'(0) + y'(1)) / (4 pi) - ...,
    a_0 = (y(0) + y(1)) / 2 - (free cos terms of even order),

so every choice of the free coefficients ``c_f`` (``a_2`` and all terms of orders 3..N) gives a
trajectory that meets the end conditions exactly.

The parameters ``theta`` of ``joint-N`` and ``fourier-N`` are not those coefficients but the
amplitudes of the family's **modes**: per coordinate, the free terms' functions (each with its
eliminated part, so that it vanishes with its rate at both ends) orthonormalised over the swing in
term order (Gram-Schmidt, computed as a QR factorisation on Gauss-Legendre nodes). Mode ``k`` has
a root mean square of one unit (1 degree or 1 cm) over the swing and is orthogonal to the others,
so a parameter is its mode's rms contribution to the swing's departure from the family's base
path (all parameters zero), and the parameters' root sum of squares is that departure's rms: no
parameter exceeds the motion's own size. The coefficients of cosines and sines of one half-range
series grow nearly dependent with the order (the joint angles' condition number of ``joint-12``
is 3e9, whose optimum needed coefficients of 10^6 degrees that cancel); the modes span the same
trajectories and have a condition number of 1. The transform is triangular, so ``joint-N``'s
modes are the first modes of ``joint-(N+1)`` and the families stay nested.
:meth:`FourierFamily.fourier_coefficients` gives a member's Fourier coefficients back.

Families are nested by construction: ``joint-N`` keeps ``a_2`` and orders 3..N free in both
coordinates, so setting the new coefficients of ``joint-(N+1)`` to zero reproduces ``joint-N``
exactly. The ``paper`` family has the paper's two free coefficients per leg: C1, the
``cos(3 pi s)`` amplitude of the hip angle, and C2, the ``cos(2 pi s)`` amplitude of the knee
angle; it is the member of ``joint-3`` whose other free coefficients vanish. (Of the 50 pairs of
single terms of orders 2-4 in foot and joint space, this pair gives the lowest swing energy:
``studies/paper_family_scan.py`` reproduces the scan.)
"""

from __future__ import annotations

import functools
import math

import numpy as np

from scalf_opt.errors import ConfigError
from scalf_opt.locomotion.gait import Gait
from scalf_opt.locomotion.swing.family import PARAMETER_SCALE, AffinePath, SwingFamily, Terms
from scalf_opt.locomotion.swing.names import MAX_ORDER
from scalf_opt.model.kinematics import LegKinematics
from scalf_opt.types import Space, check_choice

ELIMINATED_TERMS: Terms = (
    ("cos", 0),
    ("cos", 1),
    ("sin", 1),
    ("sin", 2),
)
"""The four Fourier terms solved from the end conditions."""


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


QUADRATURE_NODES = 128
"""Gauss-Legendre nodes of the modes' inner product over the swing: exact to the round-off for
the products of terms up to order 2 x 12 (a polynomial of degree 255 is integrated exactly)."""


def term_columns(terms: Terms, s: np.ndarray, derivative: int = 0) -> np.ndarray:
    """The ``derivative``-th derivatives of ``terms`` at ``s``, shape (len(s), len(terms))."""
    return np.column_stack([fourier_term(k, o, s, derivative) for k, o in terms])


@functools.cache
def _eliminated_share(terms: Terms) -> np.ndarray:
    """How the eliminated terms' coefficients follow the free ones', shape (4, len(terms))."""
    share = -(np.linalg.inv(_functionals(ELIMINATED_TERMS)) @ _functionals(terms))
    share.setflags(write=False)
    return share


def free_functions(
    terms: Terms, s: np.ndarray, derivative: int = 0, eliminated: np.ndarray | None = None
) -> np.ndarray:
    """The free terms' functions of ``s`` with their eliminated parts, shape (len(s), len(terms)).

    Every column and its first derivative vanish at ``s = 0`` and ``s = 1``. ``eliminated``: the
    eliminated terms' columns at ``s`` (:func:`term_columns`), when the caller has them already.
    """
    if eliminated is None:
        eliminated = term_columns(ELIMINATED_TERMS, s, derivative)
    return np.asarray(term_columns(terms, s, derivative) + eliminated @ _eliminated_share(terms))


@functools.cache
def mode_transform(terms: Terms) -> tuple[np.ndarray, np.ndarray]:
    """``(R, R^-1)``: a mode's amplitudes are ``R c`` of the free terms' coefficients ``c``.

    ``R`` is upper triangular with a positive diagonal: the QR factor of the free functions
    sampled at the Gauss-Legendre nodes of [0, 1] and weighted by the roots of the weights, so
    that the columns of ``free_functions(terms, s) @ R^-1`` are orthonormal in ``L2(0, 1)``.
    Terms that begin the order-12 list (every ``joint-N`` and ``fourier-N``) take the leading
    block of that list's factor: the families' shared modes are the same numbers.
    """
    longest = order_terms(MAX_ORDER)
    if len(terms) < len(longest) and terms == longest[: len(terms)]:
        r, r_inv = mode_transform(longest)
        k = len(terms)
        return r[:k, :k], r_inv[:k, :k]
    nodes, weights = np.polynomial.legendre.leggauss(QUADRATURE_NODES)
    s, w = (nodes + 1.0) / 2.0, weights / 2.0
    r = np.linalg.qr(np.sqrt(w)[:, None] * free_functions(terms, s)).R
    r = r * np.sign(np.diag(r))[:, None]  # a positive diagonal: mode k leans on term k
    r_inv = np.linalg.solve(r, np.eye(len(terms)))
    r.setflags(write=False)
    r_inv.setflags(write=False)
    return r, r_inv


class FourierFamily(SwingFamily):
    """Half-range Fourier series with four coefficients eliminated by the end conditions.

    Args:
        name: Family name.
        space: ``foot`` or ``joint``.
        free_terms: Free Fourier terms of each coordinate; none may be an eliminated term.
        modes: The parameters are the amplitudes of the orthonormal modes (module docstring)
            instead of the free terms' coefficients (the paper family's C1 and C2).
    """

    def __init__(
        self, name: str, space: Space, free_terms: tuple[Terms, Terms], modes: bool = False
    ) -> None:
        check_choice(space, Space, "family space")
        for terms in free_terms:
            if set(terms) & set(ELIMINATED_TERMS):
                raise ConfigError(f"family {name}: {terms} overlaps the eliminated terms")
        self.name = name
        self.space = space
        self.free_terms = free_terms
        self.modes = modes

    @property
    def parameter_names(self) -> list[str]:
        """``hip_mode1``... (``x_mode1``... in foot space) for modes, else the terms' names."""
        if not self.modes:
            return self.coefficient_names
        coords = ("hip", "knee") if self.space == "joint" else ("x", "z")
        return [
            f"{c}_mode{k + 1}"
            for c, terms in zip(coords, self.free_terms, strict=True)
            for k in range(len(terms))
        ]

    def _per_coordinate(self, values: np.ndarray, which: int) -> np.ndarray:
        """``values`` with each coordinate's block multiplied by its ``R`` (0) or ``R^-1`` (1)."""
        values = np.asarray(values, dtype=float)
        if not self.modes:
            return values.copy()
        out, start = np.empty_like(values), 0
        for terms in self.free_terms:
            stop = start + len(terms)
            if terms:
                out[start:stop] = mode_transform(terms)[which] @ values[start:stop]
            start = stop
        return out

    def fourier_coefficients(self, theta: np.ndarray) -> np.ndarray:  # noqa: D102
        return self._per_coordinate(theta, 1)

    def from_fourier_coefficients(self, coefficients: np.ndarray) -> np.ndarray:  # noqa: D102
        return self._per_coordinate(coefficients, 0)

    @property
    def order(self) -> int:
        """Highest Fourier order of a member (the eliminated terms reach order 2)."""
        orders = [o for terms in (*self.free_terms, ELIMINATED_TERMS) for _, o in terms]
        return max(orders)

    def shortest_period_s(self, swing_duration_s: float) -> float:
        """Period of the highest harmonic, ``cos(N pi s)``: ``2 T_sw / N`` [s]."""
        return 2.0 * swing_duration_s / self.order

    def path(  # noqa: D102
        self, gait: Gait, kin: LegKinematics, t_s: np.ndarray | None = None
    ) -> AffinePath:
        b = self.boundary(gait, kin)
        t = gait.phase_times_s("swing") if t_s is None else np.asarray(t_s, dtype=float)
        s = t / b.duration_s
        inv = np.linalg.inv(_functionals(ELIMINATED_TERMS))
        scale = PARAMETER_SCALE[self.space]
        base = np.zeros((3, 2, t.size))
        basis = np.zeros((3, 2, t.size, self.n_params))
        phi_c = [term_columns(ELIMINATED_TERMS, s, d) for d in range(3)]  # both coordinates'
        column = 0
        for c, terms in enumerate(self.free_terms):
            data = np.array(
                [b.start[c], b.end[c], b.start_rate[c] * b.duration_s, b.end_rate[c] * b.duration_s]
            )
            coefficients = inv @ data
            to_terms = mode_transform(terms)[1] if (terms and self.modes) else None
            for d in range(3):
                time_scale = b.duration_s**-d  # d/dt = (1/T_sw) d/ds
                base[d, c] = time_scale * (phi_c[d] @ coefficients)
                if terms:
                    functions = free_functions(terms, s, d, phi_c[d])
                    if to_terms is not None:
                        functions = functions @ to_terms
                    basis[d, c, :, column : column + len(terms)] = time_scale * scale * functions
            column += len(terms)
        return AffinePath(self.space, t, base, basis)


PAPER_FREE_TERMS: tuple[Terms, Terms] = ((("cos", 3),), (("cos", 2),))
"""The paper family's C1 (hip) and C2 (knee) terms."""


def order_terms(order: int) -> Terms:
    """Free terms of a family of order N: ``cos(2 pi s)`` and cos and sin of orders 3..N."""
    return (("cos", 2), *((kind, k) for k in range(3, order + 1) for kind in ("cos", "sin")))
