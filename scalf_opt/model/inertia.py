"""Physical rigid-body inertias: what a URDF's masses and inertia tensors must satisfy.

A body's inertia about its centre of mass is physical when its mass is positive and its tensor
is symmetric with principal moments that are positive and satisfy the triangle inequality
``I_a + I_b >= I_c`` (the moments of a real mass distribution; equality for a flat body). A
massless body (a foot frame) has neither mass nor inertia.
"""

from __future__ import annotations

import numpy as np
import pinocchio as pin

SYMMETRY_TOLERANCE = 1e-12
"""Largest asymmetry |I - I^T| accepted, relative to the largest moment."""

MAX_MASS_KG = 1e5
"""Heaviest body accepted [kg] (100 t: far above any legged robot's link; 1e30 kg is a typo that
would overflow the dynamics and the simulation)."""

MAX_MOMENT_KG_M2 = 1e6
"""Largest principal moment accepted [kg m^2] (a 100 t body 10 m across)."""

TRIANGLE_TOLERANCE = 1e-12
"""Slack on the triangle inequality relative to the largest moment (round-off of a flat body)."""


def inertia_problem(mass_kg: float, inertia_kg_m2: np.ndarray) -> str | None:
    """What is unphysical about a body's mass and inertia about its COM, or ``None``."""
    tensor = np.asarray(inertia_kg_m2, dtype=float)
    scale = float(np.max(np.abs(tensor))) if tensor.size else 0.0
    if mass_kg == 0.0 and scale == 0.0:
        return None
    if not mass_kg > 0.0:
        return f"mass {mass_kg} kg is not positive"
    if not mass_kg <= MAX_MASS_KG:
        return f"mass {mass_kg:.4g} kg is above the {MAX_MASS_KG:g} kg a robot's body may weigh"
    if not np.all(np.isfinite(tensor)) or scale > MAX_MOMENT_KG_M2:
        return (
            f"inertia of {scale:.4g} kg m^2 is above the {MAX_MOMENT_KG_M2:g} kg m^2 a robot's "
            "body may have"
        )
    if np.max(np.abs(tensor - tensor.T)) > SYMMETRY_TOLERANCE * scale:
        return "inertia tensor is not symmetric"
    a, b, c = np.linalg.eigvalsh(tensor)
    if a <= 0.0:
        return f"principal moment {a:.3g} kg m^2 is not positive"
    if a + b < c * (1.0 - TRIANGLE_TOLERANCE):
        return f"principal moments {a:.4g}, {b:.4g}, {c:.4g} kg m^2 break the triangle inequality"
    return None


def inertia_problems(model: pin.Model) -> list[str]:
    """Every body of a Pinocchio model with an unphysical inertia, as ``"<body>: <problem>"``.

    Pinocchio merges a link with its fixed children; body 0 is the root link (the trunk).
    """
    out = []
    for i, inertia in enumerate(model.inertias):
        problem = inertia_problem(float(inertia.mass), np.array(inertia.inertia))
        if problem is not None:
            name = model.names[i] if i else "root link"
            out.append(f"{name}: {problem}")
    return out
