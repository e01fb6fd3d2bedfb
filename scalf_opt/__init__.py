"""scalf-opt: energy-efficient swing-foot trajectories for legged robots.

The package implements, and extends, the energy model and swing-trajectory optimization of the
hydraulic quadruped SCalf (Energies 2019, 12(13), 2514): Pinocchio for rigid-body kinematics and
dynamics, a CasADi twin of the leg for symbolic derivatives, drive models (SCalf's hydraulic
cylinder with Stribeck friction), and two optimizers (the paper's pattern search and an Ipopt NLP).

The public API (:mod:`scalf_opt.api`) is importable from here; it is loaded on first use, so that
``import scalf_opt`` stays cheap::

    import scalf_opt as so

    robot = so.load_robot("scalf")
    reference = so.evaluate(robot)
    optimum = so.optimize_swing(robot, family="joint-6")
"""

import sys
from typing import TYPE_CHECKING, Any

from scalf_opt.blas_kernels import pin_blas_kernels, single_blas_thread, warn_if_kernels_differ
from scalf_opt.version import __version__

_pinned = pin_blas_kernels()  # before numpy loads: the same numbers on every x86-64 machine
single_blas_thread()  # MUMPS's BLAS: no spinning threads taking the other solve's core
if "numpy" in sys.modules or "scipy" in sys.modules:  # too late for the pin to reach them
    warn_if_kernels_differ(_pinned)


__all__ = [  # noqa: RUF022 (the version first, then the API of scalf_opt.api)
    "__version__",
    "CycleSimulationResult",
    "EvaluationResult",
    "ExportResult",
    "Gait",
    "Gait3dSweep",
    "GaitResult",
    "GaitSweep",
    "LogResult",
    "NotSolvedError",
    "OptimizationResult",
    "PaperResult",
    "RobotLogResult",
    "SimulationResult",
    "SpeedCase",
    "analyze_log",
    "analyze_robot_log",
    "evaluate",
    "export_plan",
    "figures",
    "load_robot",
    "optimize_gait",
    "optimize_swing",
    "paper",
    "read_gait",
    "simulate",
    "simulate_3d",
    "simulate_cycle",
    "sweep_gaits",
    "sweep_gaits_3d",
    "view",
    "view_cycles",
]

if TYPE_CHECKING:
    from scalf_opt.api import (
        CycleSimulationResult,
        EvaluationResult,
        ExportResult,
        Gait,
        Gait3dSweep,
        GaitResult,
        GaitSweep,
        LogResult,
        NotSolvedError,
        OptimizationResult,
        PaperResult,
        RobotLogResult,
        SimulationResult,
        SpeedCase,
        analyze_log,
        analyze_robot_log,
        evaluate,
        export_plan,
        figures,
        load_robot,
        optimize_gait,
        optimize_swing,
        paper,
        read_gait,
        simulate,
        simulate_3d,
        simulate_cycle,
        sweep_gaits,
        sweep_gaits_3d,
        view,
        view_cycles,
    )


def __getattr__(name: str) -> Any:
    if name in __all__:
        from scalf_opt import api

        return getattr(api, name)
    raise AttributeError(f"module 'scalf_opt' has no attribute {name!r}")
