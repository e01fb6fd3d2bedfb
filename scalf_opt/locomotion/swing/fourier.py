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

import numpy as np

from scalf_opt.errors import ConfigError
from scalf_opt.locomotion.gait import Gait
from scalf_opt.locomotion.swing.family import PARAMETER_SCALE, AffinePath, SwingFamily, Terms
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


class FourierFamily(SwingFamily):
    """Half-range Fourier series with four coefficients eliminated by the end conditions.

    Args:
        name: Family name.
        space: ``foot`` or ``joint``.
        free_terms: Free Fourier terms of each coordinate; none may be an eliminated term.
    """

    def __init__(self, name: str, space: Space, free_terms: tuple[Terms, Terms]) -> None:
        check_choice(space, Space, "family space")
        for terms in free_terms:
            if set(terms) & set(ELIMINATED_TERMS):
                raise ConfigError(f"family {name}: {terms} overlaps the eliminated terms")
        self.name = name
        self.space = space
        self.free_terms = free_terms

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
        column = 0
        for c, terms in enumerate(self.free_terms):
            data = np.array(
                [b.start[c], b.end[c], b.start_rate[c] * b.duration_s, b.end_rate[c] * b.duration_s]
            )
            coefficients = inv @ data
            free_map = -inv @ _functionals(terms) if terms else np.zeros((4, 0))
            for d in range(3):
                time_scale = b.duration_s**-d  # d/dt = (1/T_sw) d/ds
                phi_c = np.column_stack([fourier_term(k, o, s, d) for k, o in ELIMINATED_TERMS])
                base[d, c] = time_scale * (phi_c @ coefficients)
                if terms:
                    phi_f = np.column_stack([fourier_term(k, o, s, d) for k, o in terms])
                    basis[d, c, :, column : column + len(terms)] = (
                        time_scale * scale * (phi_f + phi_c @ free_map)
                    )
            column += len(terms)
        return AffinePath(self.space, t, base, basis)


PAPER_FREE_TERMS: tuple[Terms, Terms] = ((("cos", 3),), (("cos", 2),))
"""The paper family's C1 (hip) and C2 (knee) terms."""


def order_terms(order: int) -> Terms:
    """Free terms of a family of order N: ``cos(2 pi s)`` and cos and sin of orders 3..N."""
    return (("cos", 2), *((kind, k) for k in range(3, order + 1) for kind in ("cos", "sin")))
