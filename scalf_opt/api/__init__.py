"""The Python API: load a robot, choose a gait, evaluate, optimize, simulate, in a few lines.

>>> import scalf_opt as so
>>> robot = so.load_robot("scalf")
>>> result = so.evaluate(robot)            # the cubic-spline reference on the paper's trot
>>> round(result.average_power_w, 2)
564.52

Every result has ``to_dict()``, the same plain data the command line writes to its JSON file,
and the numbers are the command line's: the ``scalf-opt`` commands call these functions.
(``optimize_swing`` is not called ``optimize``: that name is the package's optimizer floor,
:mod:`scalf_opt.optimize`.)
"""

from scalf_opt.api.evaluation import EvaluationResult, evaluate
from scalf_opt.api.export import ExportResult, export_plan
from scalf_opt.api.gait_3d import Gait3dSweep, SpeedCase, sweep_gaits_3d
from scalf_opt.api.gait_optimization import GaitResult, GaitSweep, optimize_gait, sweep_gaits
from scalf_opt.api.gaits import read_gait
from scalf_opt.api.logs import LogResult, analyze_log
from scalf_opt.api.optimization import OptimizationResult, optimize_swing
from scalf_opt.api.presentation import NotSolvedError, figures, view, view_cycles
from scalf_opt.api.reproduction import PaperResult, paper
from scalf_opt.api.robot_logs import RobotLogResult, analyze_robot_log
from scalf_opt.api.simulation import (
    CycleSimulationResult,
    SimulationResult,
    simulate,
    simulate_3d,
    simulate_cycle,
)
from scalf_opt.locomotion.gait import Gait
from scalf_opt.robots.loading import load_robot

__all__ = [
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
