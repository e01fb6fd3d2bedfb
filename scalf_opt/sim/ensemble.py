"""The referee ensemble: one verdict over a stated set of perturbed referees.

A referee's settings are chosen, not measured (:mod:`scalf_opt.sim.settings`): a servo bandwidth
scaled from one robot, a contact time constant, a foot radius, a friction coefficient, a contact
schedule that switches exactly on time. A plan that only agrees with the model at one such
point has not been refereed: SCalf's first default optimum moved 10.6 points between half and
one and a half times the servo bandwidth. So every verdict is the median over
:data:`ENSEMBLE`, the nominal referee and one member per perturbation, each simulating the plan
and the reference swing alike, and the verdict states its spread (largest minus smallest member)
beside it. A plan whose spread exceeds the agreement goal is *not refereeable*: its verdict
depends on the referee's settings, and it is never reported as agreeing.

The perturbations (each one alone, the others nominal):

* servo gains x0.5 and x2: the servo's natural frequency x1/sqrt(2) and x sqrt(2) (its
  stiffness scales with the square), the time step re-derived;
* the contact's time constant x0.5 and x2;
* the feet's radius x0.5 and x3;
* friction 0.6 (the nominal is 1.0);
* a touch-down detected 5 ms early and 5 ms late: the controller switches a leg from its swing
  loop to the stance loop that much off the planned touch-down (early: with the foot still in
  the air; late: the landed foot still on its swing loop).

The members are independent: they run side by side, one process per core (:func:`run_members`),
with the numbers of one process.
"""

from __future__ import annotations

import math
import statistics
from collections.abc import Callable, Iterable, Sequence
from dataclasses import dataclass, replace
from typing import Any

from scalf_opt.interrupts import results_in_order
from scalf_opt.sim.metrics import saving_met
from scalf_opt.sim.settings import SimSettings
from scalf_opt.types import LEG_NAMES
from scalf_opt.workers import WorkerProcesses, in_worker_process, thread_budget


@dataclass(frozen=True)
class Perturbation:
    """One member of the ensemble: one setting of the nominal referee changed.

    Attributes:
        name: What is changed, for reports (``servo gains x0.5``).
        field: The :class:`~scalf_opt.sim.settings.SimSettings` field it changes (``None``: the
            nominal referee).
        factor: The nominal (derived) value times this, when not ``None``.
        value: Else the field's new value.
    """

    name: str
    field: str | None = None
    factor: float | None = None
    value: float | None = None

    def applied(self, nominal: SimSettings, derived: SimSettings) -> SimSettings:
        """The member's settings: ``nominal`` (as given) with this field changed.

        ``derived`` is ``nominal`` with its derived fields set for the robot
        (:meth:`~scalf_opt.sim.settings.SimSettings.for_leg_length`): a factor scales the
        derived value. The time step stays the nominal's own (given or derived anew), so a
        faster servo or a stiffer contact gets the finer step it needs.
        """
        if self.field is None:
            return nominal
        value = self.value if self.factor is None else self.factor * derived.value(self.field)
        changes: dict[str, Any] = {self.field: value}
        return replace(nominal, **changes)


NOMINAL = Perturbation("nominal")
"""The referee at its own settings."""

ENSEMBLE: tuple[Perturbation, ...] = (
    NOMINAL,
    Perturbation("servo gains x0.5", "servo_bandwidth_hz", factor=math.sqrt(0.5)),
    Perturbation("servo gains x2", "servo_bandwidth_hz", factor=math.sqrt(2.0)),
    Perturbation("contact time constant x0.5", "contact_time_constant_s", factor=0.5),
    Perturbation("contact time constant x2", "contact_time_constant_s", factor=2.0),
    Perturbation("foot radius x0.5", "foot_radius_m", factor=0.5),
    Perturbation("foot radius x3", "foot_radius_m", factor=3.0),
    Perturbation("friction 0.6", "foot_friction", value=0.6),
    Perturbation("touch-down 5 ms early", "schedule_shift_s", value=-0.005),
    Perturbation("touch-down 5 ms late", "schedule_shift_s", value=0.005),
)
"""The members, the nominal referee first (module docstring)."""


@dataclass(frozen=True)
class MemberResult:
    """What one member measured: per leg and in total the joint energy, and the saving.

    Attributes:
        perturbation: The member.
        relative_difference: Per leg, simulated over model joint energy per cycle, minus 1.
        simulated_j: Per leg, the simulated joint energy per cycle [J].
        total_relative_difference: The same of the whole robot's.
        saving_percent: The plan's simulated change against the reference [%], when the
            reference was simulated.
        torque_saturation: The largest share of steps any joint asked beyond its effort limit.
        fell_at_s: When the robot fell in this member's run [s], ``None`` when it did not.
        diverged_at_s: When MuJoCo's integration diverged in this member's run [s]
            (:mod:`~scalf_opt.sim.divergence`), ``None`` when it did not.
        divergence: Which of MuJoCo's checks failed then, in words.
    """

    perturbation: Perturbation
    relative_difference: dict[str, float]
    simulated_j: dict[str, float]
    total_relative_difference: float
    saving_percent: float | None
    torque_saturation: float
    fell_at_s: float | None = None
    diverged_at_s: float | None = None
    divergence: str | None = None

    @classmethod
    def of(cls, perturbation: Perturbation, data: dict[str, Any]) -> MemberResult:
        """The member's figures from its run's data (plan, and ``saving_vs_reference``)."""
        energy = data["joint_energy_per_cycle_j"]
        saving = data.get("saving_vs_reference")
        return cls(
            perturbation,
            {leg: float(energy[leg]["relative_difference"]) for leg in LEG_NAMES},
            {leg: float(energy[leg]["simulated"]) for leg in LEG_NAMES},
            float(data["total_energy_per_cycle_j"]["relative_difference"]),
            None if saving is None else float(saving["simulated_percent"]),
            float(max(data["torque_saturation_fraction"].values())),
            data.get("fell_at_s"),
            data.get("diverged_at_s"),
            data.get("divergence"),
        )

    def to_dict(self) -> dict[str, Any]:
        """Plain data for ``simulation.json``'s ``ensemble.members``."""
        p = self.perturbation
        return {
            "name": p.name,
            "setting": p.field,
            "factor": p.factor,
            "value": p.value,
            "relative_difference": self.relative_difference,
            "total_relative_difference": self.total_relative_difference,
            "saving_simulated_percent": self.saving_percent,
            "torque_saturation_fraction": self.torque_saturation,
            "fell_at_s": self.fell_at_s,
            "diverged_at_s": self.diverged_at_s,
            "divergence": self.divergence,
        }


def _measured(values: Iterable[float]) -> list[float]:
    """The finite ``values``: a member whose run measured nothing (NaN) has no say."""
    return [v for v in values if math.isfinite(v)]


def _median(values: Iterable[float]) -> float:
    """The median of the finite ``values``, NaN when none is."""
    finite = _measured(values)
    return statistics.median(finite) if finite else math.nan


def _spread(values: Iterable[float]) -> float:
    """The largest minus the smallest of the finite ``values``, NaN when none is."""
    finite = _measured(values)
    return max(finite) - min(finite) if finite else math.nan


def ensemble_verdict(
    nominal: dict[str, Any], members: Sequence[MemberResult], goal: float
) -> dict[str, Any]:
    """``nominal``'s data with the ensemble's verdict in place of the nominal referee's.

    Per leg under ``joint_energy_per_cycle_j``: ``relative_difference`` and ``simulated`` become
    the members' medians, ``relative_difference_spread`` their largest minus smallest;
    ``total_energy_per_cycle_j`` likewise; ``saving_vs_reference.simulated_percent`` the median
    saving with its spread in points. ``goals``: ``refereeable`` (every spread within ``goal``)
    and ``joint_energy_met`` (refereeable, and every median within ``goal``); a member whose
    robot fell, or whose run MuJoCo's integration diverged in, makes the plan not refereeable
    whatever the spread (``ensemble.fell`` and ``ensemble.diverged`` name them). A member that
    measured no number (NaN: a run that diverged or fell before a whole cycle was measured) is
    left out of that number's median and spread. ``ensemble`` lists the members. The rest
    (trunk, forces, the phase split, the servo's work) stays the nominal referee's.
    """
    data = dict(nominal)
    energy = {}
    for leg in LEG_NAMES:
        diffs = [m.relative_difference[leg] for m in members]
        energy[leg] = {
            **nominal["joint_energy_per_cycle_j"][leg],
            "simulated": _median(m.simulated_j[leg] for m in members),
            "relative_difference": _median(diffs),
            "relative_difference_spread": _spread(diffs),
        }
    totals = [m.total_relative_difference for m in members]
    total = dict(nominal["total_energy_per_cycle_j"])
    total["relative_difference"] = _median(totals)
    total["relative_difference_spread"] = _spread(totals)
    total["simulated"] = total["model"] * (1.0 + total["relative_difference"])
    data["joint_energy_per_cycle_j"] = energy
    data["total_energy_per_cycle_j"] = total
    spread = max(e["relative_difference_spread"] for e in energy.values())
    largest = max(abs(e["relative_difference"]) for e in energy.values())
    fell = [m.perturbation.name for m in members if m.fell_at_s is not None]
    diverged = [m.perturbation.name for m in members if m.diverged_at_s is not None]
    refereeable = spread <= goal and not fell and not diverged
    data["goals"] = {
        **nominal["goals"],
        "ensemble_spread_at_most": goal,
        "refereeable": refereeable,
        "joint_energy_met": refereeable and largest <= goal,
    }
    if "saving_vs_reference" in nominal and all(m.saving_percent is not None for m in members):
        savings = [float(m.saving_percent) for m in members]  # type: ignore[arg-type]
        data["saving_vs_reference"] = _saving(nominal["saving_vs_reference"], savings)
    data["ensemble"] = {
        "members": [m.to_dict() for m in members],
        "largest_spread": spread,
        "fell": fell,
        "diverged": diverged,
    }
    return data


def _saving(nominal: dict[str, Any], savings: list[float]) -> dict[str, Any]:
    """The saving's verdict on the members' median (the nominal's goal: same sign, a third)."""
    model, simulated = float(nominal["model_percent"]), _median(savings)
    return {
        **nominal,
        "simulated_percent": simulated,
        "simulated_percent_spread": _spread(savings),
        "same_sign_within_a_third_met": saving_met(model, simulated),
    }


def member_processes(workers: int | None = None) -> int:
    """The processes the members share: ``workers``, by default as many as this process's cores.

    The default is :func:`~scalf_opt.workers.thread_budget` (``SCALF_OPT_THREADS``, else the
    cores). In a worker process of :mod:`scalf_opt.workers`: one, this process (its work starts
    no workers of its own).
    """
    if in_worker_process():
        return 1
    return thread_budget() if workers is None else max(1, workers)


def run_members(
    run: Callable[[SimSettings], dict[str, Any]],
    nominal: Callable[[], dict[str, Any]],
    settings: SimSettings,
    derived: SimSettings,
    members: Sequence[Perturbation] = ENSEMBLE,
    workers: int | None = None,
) -> list[tuple[Perturbation, dict[str, Any]]]:
    """Every member's run data: the nominal referee's ``nominal()``, each other's ``run(at)``.

    ``run(at)`` simulates plan and reference at a member's settings ``at``; ``nominal()`` those
    of the nominal referee, called once, in this process. The members are independent: they
    share :func:`member_processes` processes (``workers``), this one and worker processes of
    :class:`~scalf_opt.workers.WorkerProcesses` (``run`` then pickles: a module-level function,
    or an instance of a module-level class, whose data the worker builds its models from). This
    process runs the nominal referee and every ``count``-th member after it, each worker its own
    members one after another, all at once; each member's data is bitwise what one process
    would compute. One process: the members one after another, here. Ctrl-C, SIGTERM or an error
    (this process's first, else the first worker's in order) kills the workers.
    """
    others = [p.applied(settings, derived) for p in members if p.field is not None]
    count = min(member_processes(workers), len(others) + 1)
    if count == 1:
        return _in_order(members, nominal(), run_each((run, others)))
    # the members dealt out in turn, the nominal referee first: process i runs the i-th, the
    # (i + count)-th... (the nominal referee, the 0-th, in this process: its run stays here)
    shares = [others[i - 1 :: count] if i else others[count - 1 :: count] for i in range(count)]
    with WorkerProcesses(count) as processes:
        away = [processes.submit(run_each, (run, share)) for share in shares[1:]]
        data = nominal()
        done = [[data, *run_each((run, shares[0]))], *results_in_order(away)]
    return _in_order(
        members, data, [done[i % count][i // count] for i in range(1, len(others) + 1)]
    )


MemberJob = tuple[Callable[[SimSettings], dict[str, Any]], Sequence[SimSettings]]
"""Members' runs as work for :func:`run_each`: the run, and each member's settings."""


def run_each(job: MemberJob) -> list[dict[str, Any]]:
    """``run(at)`` for each member's settings ``at`` in turn (in this process or a worker)."""
    run, members = job
    return [run(at) for at in members]


def _in_order(
    members: Sequence[Perturbation], nominal: dict[str, Any], others: Sequence[dict[str, Any]]
) -> list[tuple[Perturbation, dict[str, Any]]]:
    """Each member beside its data: the nominal referee's ``nominal``, the others' in turn."""
    found = iter(others)
    return [(p, nominal if p.field is None else next(found)) for p in members]


def with_ensemble_verdicts(
    nominal: dict[str, Any], runs: Sequence[tuple[Perturbation, dict[str, Any]]], goal: float
) -> dict[str, Any]:
    """The plan's verdict (:func:`ensemble_verdict`) and, when simulated, the reference's."""
    data = ensemble_verdict(nominal, [MemberResult.of(p, d) for p, d in runs], goal)
    if "reference" in nominal and all("reference" in d for _, d in runs):
        references = [MemberResult.of(p, d["reference"]) for p, d in runs]
        data["reference"] = ensemble_verdict(nominal["reference"], references, goal)
    return data
