"""The columns of a study's ``results.csv`` that every case fills, whatever the study sweeps.

The study file's reader checks its plot's x against them, the runner writes them, the study
figure tells them from the swept columns.
"""

from __future__ import annotations

from scalf_opt.types import LEG_NAMES

RESULT_COLUMNS = (
    "status",
    "robot",
    "speed_m_s",
    "total_mass_kg",
    "thigh_length_m",
    "shank_length_m",
    "thigh_to_shank",
    "reference_energy_j",
    "optimized_energy_j",
    "saving_pct",
    "reference_power_w",
    "optimized_power_w",
    "cost_of_transport_reference",
    "cost_of_transport_optimized",
    *(f"{leg}_{kind}_j" for leg in LEG_NAMES for kind in ("reference", "optimized")),
    "error",
)
"""The columns of a case's row after its swept values (energies per gait cycle; geometry of the
RF leg)."""
