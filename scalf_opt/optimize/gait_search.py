r"""Beyond the paper: the cheapest trot at a given speed, its timing and posture with the swing.

At a target speed ``v`` the trot has five free numbers: the period ``T``, the duty cycle ``d``,
the stance height ``z0`` and the two stance x-offsets (front, hind); the step length follows
from the speed, ``S = v d T`` (:attr:`~scalf_opt.locomotion.gait.Gait.speed_m_s`), and the
clearance ``H`` stays the robot's. The search minimizes the cost of transport

.. math::

    \mathrm{CoT} = \frac{E_\mathrm{cycle}}{m g v T}, \qquad
    E_\mathrm{cycle} = 2 \sum_{RF, LH} \left(E_\mathrm{stance} + \min_\theta E_\mathrm{swing}\right)

(LF and RH repeat RF and LH half a cycle later), which at a fixed speed is the energy per metre.
A gait the reference swing cannot walk (it leaves the joint range) is refused: every command
compares an optimum with the reference on its gait (``view --from``, ``simulate --from``).
Every other gait is evaluated as :mod:`~scalf_opt.optimize.free_stance` evaluates a stance
(:class:`~scalf_opt.optimize.free_stance.GaitTrials`): its stance is checked against the reach,
the joint range and every limit of every stance sample, and its swings are optimized by the one
solve path (:func:`~scalf_opt.optimize.driver.optimize_swings`: converged in the sampling,
checked at ten times its rate, every limit a constraint), warm-started from the last optimum.

The search is nested, not one NLP: the swing problem's time grid, its sampling refinement and its
limit checks all depend on ``T`` and ``d``; nested, the inner solve is the one every command
uses, warm-started from the last gait's optimum (a cold one takes 0.8 s on SCalf and 1.3 s on
Go1: ``benchmarks/bench_gait.py``'s baseline), and every gait compared is a converged,
limit-checked optimum. A speed's search tries 130 to 150 gaits.

It is honest about its answer:

1. a coarse grid over ``(T, d)`` at the robot's own stance (:data:`GRID_PERIOD_FACTORS` times
   the default period, :data:`GRID_DUTIES`), with the default trot retimed to the speed beside
   it, chooses the start: the search does not depend on one start's basin;
2. the paper's pattern search over the five numbers (:data:`INITIAL_STEP`, :data:`PRECISION`,
   in search units of 10 ms, 0.01, 1 cm) refines the best of them; it accepts only strict
   improvements, so the answer is never worse than the default trot with optimized swings
   (when the reference swing can walk it);
3. every neighbour of the answer one last step away is looked at: one that leaves the search box
   (:class:`GaitBox`: the duty floor 0.5 that keeps a trot a trot without a flight phase) or
   breaks a limit is reported with the limit's name (:attr:`GaitSearch.pinned`).
"""

from __future__ import annotations

import math
import re
import time
from collections.abc import Callable
from dataclasses import dataclass, field, replace

import numpy as np

from scalf_opt.energy.cycle import RobotCycle
from scalf_opt.energy.pipeline import EnergyPipeline
from scalf_opt.errors import ConfigError, ScalfError
from scalf_opt.locomotion.forces import GRAVITY_M_S2
from scalf_opt.locomotion.gait import Gait
from scalf_opt.locomotion.swing.family import SwingFamily
from scalf_opt.locomotion.swing.registry import make_family
from scalf_opt.optimize.driver import Settings
from scalf_opt.optimize.free_stance import GaitTrials, StanceEvaluation
from scalf_opt.optimize.pattern_search import PatternSearchOptions, pattern_search
from scalf_opt.optimize.sampling import on_check_grid
from scalf_opt.tables import is_number
from scalf_opt.types import FIRST_PAIR

SEARCH_VARIABLES = (
    "period_s",
    "duty_cycle",
    "stance_height_m",
    "stance_x_offset_front_m",
    "stance_x_offset_hind_m",
)
"""The gait fields the search changes, in the order of its variables (the step length follows)."""

SEARCH_UNIT = 0.01
"""One search unit of every variable: 10 ms, a duty of 0.01, 1 cm."""


def from_search_units(units: float) -> float:
    """A searched field's value [s, 1 or m] from search units.

    Divided by the units per value (100, exact) rather than multiplied by ``SEARCH_UNIT``
    (0.01, not a binary fraction): 57.5 units is the duty 0.575, not 0.5750000000000001.
    """
    return float(units) / (1.0 / SEARCH_UNIT)


INITIAL_STEP = (5.0, 5.0, 2.0, 2.0, 2.0)
"""First step per variable [search units]: 50 ms, 0.05, 2 cm, 2 cm, 2 cm."""

PRECISION = 1.0
"""The search stops when every step is below this [search units]: its last exploration around
the answer, with steps of 12.5 ms, 0.0125 and 5 mm, found nothing cheaper."""

DUTY_FLOOR = 0.5
"""The least duty cycle: below it a trot has a flight phase (the constant-height trunk model
carries none; :class:`~scalf_opt.locomotion.gait.Gait` refuses it too)."""

DUTY_CEILING = 0.75
"""The greatest duty cycle searched: above it the swing is shorter than a third of the stance."""

PERIOD_RANGE = (0.4, 2.5)
"""The periods searched, as multiples of the robot's default period."""

GRID_PERIOD_FACTORS = (0.5, 0.7, 1.0, 1.4, 2.0)
"""The coarse grid's periods, as multiples of the robot's default period."""

GRID_DUTIES = (0.5, 0.6, 0.7)
"""The coarse grid's duty cycles."""

USUAL_GAITS_PER_SPEED = 145
"""About how many gaits one speed's search tries (SCalf's and Go1's six speeds in
``benchmarks/bench_gait.py``: 146 and 140 a speed); the progress line's "of about"."""

MAX_SPEED_M_S = 10.0
"""The fastest target speed accepted [m/s] (no trotting robot's; the reach refuses far less)."""


@dataclass(frozen=True)
class GaitBox:
    """The search box of the period and the duty cycle (the stance is bounded by the limits).

    Attributes:
        period_min_s: Shortest period [s].
        period_max_s: Longest period [s].
        duty_min: Least duty cycle (at least :data:`DUTY_FLOOR`).
        duty_max: Greatest duty cycle.
    """

    period_min_s: float
    period_max_s: float
    duty_min: float = DUTY_FLOOR
    duty_max: float = DUTY_CEILING

    def __post_init__(self) -> None:
        if not 0 < self.period_min_s < self.period_max_s:
            raise ConfigError(
                f"the period box [{self.period_min_s:g}, {self.period_max_s:g}] s is empty"
            )
        if not DUTY_FLOOR <= self.duty_min < self.duty_max < 1.0:
            raise ConfigError(
                f"the duty box [{self.duty_min:g}, {self.duty_max:g}] must lie in "
                f"[{DUTY_FLOOR:g}, 1): below {DUTY_FLOOR:g} a trot has a flight phase"
            )

    @classmethod
    def around(cls, gait: Gait) -> GaitBox:
        """The default box: :data:`PERIOD_RANGE` times ``gait``'s period, duty 0.5 to 0.75."""
        low, high = PERIOD_RANGE
        return cls(low * gait.period_s, high * gait.period_s)

    def outside(self, gait: Gait, duty: float | None = None) -> str | None:
        """Which edge of the box ``gait`` (or its period with ``duty``) lies beyond, or ``None``."""
        tol = 1e-12
        duty = gait.duty_cycle if duty is None else duty
        if gait.period_s < self.period_min_s - tol:
            return f"period_s below the search box's {self.period_min_s:.4g} s"
        if gait.period_s > self.period_max_s + tol:
            return f"period_s above the search box's {self.period_max_s:.4g} s"
        if duty < self.duty_min - tol:
            floor = ", a trot's floor" if self.duty_min == DUTY_FLOOR else ""
            return f"duty_cycle below the search box's {self.duty_min:g}{floor}"
        if duty > self.duty_max + tol:
            return f"duty_cycle above the search box's {self.duty_max:g}"
        return None


def check_speed(speed_m_s: float) -> float:
    """``speed_m_s`` as a float, or a one-line error naming the speed.

    Raises:
        ConfigError: Not a finite number in (0, :data:`MAX_SPEED_M_S`].
    """
    if not (is_number(speed_m_s) and 0 < speed_m_s <= MAX_SPEED_M_S):
        raise ConfigError(
            f"the speed must be a number in (0, {MAX_SPEED_M_S:g}] m/s, got {speed_m_s!r}",
            field="speed",
        )
    return float(speed_m_s)


def at_speed(gait: Gait, speed_m_s: float) -> Gait:
    """``gait`` with the step length that makes it walk at ``speed_m_s``: ``S = v d T``."""
    return gait.with_speed(speed_m_s)


def search_vector(gait: Gait) -> np.ndarray:
    """The searched fields of ``gait`` in search units."""
    return np.array([getattr(gait, name) / SEARCH_UNIT for name in SEARCH_VARIABLES])


def gait_at(base: Gait, speed_m_s: float, x: np.ndarray) -> Gait:
    """``base`` with the searched fields ``x`` (search units), at ``speed_m_s``.

    Raises:
        GaitError: A field out of its range (the duty below 0.5, say).
    """
    values = {name: from_search_units(v) for name, v in zip(SEARCH_VARIABLES, x, strict=True)}
    return at_speed(replace(base, **values), speed_m_s)  # type: ignore[arg-type]


_LIMIT_PATTERNS: tuple[tuple[re.Pattern[str], str], ...] = (
    (
        re.compile(r"^the reference swing of \w+ .* leg (\w+): .* takes joint \S+ \((q_\w+)\) to"),
        r"\1 \2: joint range under the reference swing",
    ),
    (
        re.compile(r"^the reference swing of (\w+) .* outside the reach"),
        r"\1 reach, reference swing",
    ),
    (re.compile(r"leg (\w+): .* takes joint \S+ \((q_\w+)\) to"), r"\1 \2: joint range (URDF)"),
    (re.compile(r"leg (\w+): foot target .* outside the reach"), r"\1 reach"),
    (re.compile(r"stance of (\w+): (\S+) beyond its (.*)$"), r"\1 \2: \3"),
    (re.compile(r"^(\w+) (below|above) the search box's (.*)$"), r"\1 \2 the search box's \3"),
    (re.compile(r"^swing not solved: (.*)$"), r"swing not solved: \1"),
)
"""How a reason for an infeasible gait reads as the name of the limit it meets."""


def limit_name(reason: str) -> str:
    """The short name of the limit an infeasible gait's ``reason`` speaks of.

    ``"leg RF: the stance path takes joint RF_knee (q_knee) to 0.4886 rad, outside ..."`` is
    ``"RF q_knee: joint range (URDF)"``, the name the stance's own bounds have (a leg's role and
    the joint's, whatever the URDF calls the joint); a reason of no known kind is its first 80
    characters.
    """
    for pattern, name in _LIMIT_PATTERNS:
        match = pattern.search(reason)
        if match:
            return match.expand(name)
    return reason if len(reason) <= 80 else reason[:77] + "..."


def reference_unwalkable(pipeline: EnergyPipeline) -> str | None:
    """Why the reference swing cannot walk the pipeline's gait, or ``None`` when it can.

    Every command compares an optimum with the reference swing on its gait (``view --from``,
    ``simulate --from``), so a gait it cannot walk is no answer. Checked at ten times the
    gait's rate, finer than any rate an optimum converges at.
    """
    fine = on_check_grid(pipeline)
    for leg in FIRST_PAIR:
        try:
            fine.swing(leg, make_family("reference"))
        except ScalfError as exc:
            return f"the reference swing of {leg} cannot walk it: {exc}"
    return None


def cost_of_transport(evaluation: StanceEvaluation, mass_kg: float, speed_m_s: float) -> float:
    """The robot's cost of transport of a pair's evaluation (inf when infeasible).

    ``2 total / (m g v T)``: LF and RH repeat RF and LH.
    """
    if not math.isfinite(evaluation.total_j):
        return math.inf
    distance_m = speed_m_s * evaluation.gait.period_s
    return 2.0 * evaluation.total_j / (mass_kg * GRAVITY_M_S2 * distance_m)


@dataclass(frozen=True)
class GaitSearch:
    """The cheapest trot found at one speed, and what it is compared with.

    Attributes:
        speed_m_s: The target speed [m/s].
        family: The swing family.
        settings: How the swings were optimized.
        box: The search box.
        default: The robot's default trot retimed to the speed (step length ``v d T``), with
            optimized swings (``total_j`` inf and ``reason`` set when it cannot walk it).
        reference: The default trot at the speed with the reference swing, at the rate its
            optimized swings converged at (``None`` when it cannot walk it).
        best: The cheapest gait, with its optimized swings.
        grid: The coarse grid's gaits (its start candidates), in grid order.
        pinned: The answer's neighbours one last step away that leave the box or break a
            limit: ``{"<field> up|down": reason}``.
        iterations: Pattern-search iterations.
        evaluations: Gaits evaluated by the pattern search (the grid's not counted).
        converged: The search's steps fell below the precision.
        mass_kg: The robot's total mass [kg].
        wall_time_s: Time spent [s].
    """

    speed_m_s: float
    family: SwingFamily
    settings: Settings
    box: GaitBox
    default: StanceEvaluation
    reference: RobotCycle | None
    best: StanceEvaluation
    grid: list[StanceEvaluation]
    pinned: dict[str, str]
    iterations: int
    evaluations: int
    converged: bool
    mass_kg: float
    wall_time_s: float = 0.0
    history: list[tuple[float, ...]] = field(default_factory=list)

    @property
    def success(self) -> bool:
        """The search converged to a feasible gait whose swings are solved."""
        return self.converged and self.best.run is not None and self.best.run.success

    def cost_of_transport(self, evaluation: StanceEvaluation) -> float:
        """The robot's cost of transport of one of the search's evaluations (inf: infeasible)."""
        return cost_of_transport(evaluation, self.mass_kg, self.speed_m_s)

    def cycle(self) -> RobotCycle:
        """The robot's cycle with the cheapest gait and its optimized swings."""
        if self.best.run is None:
            raise ConfigError(f"no feasible gait at {self.speed_m_s:g} m/s: {self.best.reason}")
        return self.best.run.cycle()

    def default_cycle(self) -> RobotCycle | None:
        """The default trot at the speed with optimized swings (``None``: it cannot walk it)."""
        if self.default.run is None or not self.default.run.success:
            return None
        return self.default.run.cycle()


def _last_steps() -> np.ndarray:
    """The step of the search's last exploration around its answer [search units]."""
    step = np.asarray(INITIAL_STEP, dtype=float)
    shrink = PatternSearchOptions().shrinkage
    while np.any(step * shrink >= PRECISION):
        step *= shrink
    return step


def _default_evaluation(
    trials: GaitTrials, default: Gait
) -> tuple[StanceEvaluation, RobotCycle | None]:
    """The default trot at the speed with optimized swings, and with the reference swing."""
    evaluation = trials.evaluate(default)
    if evaluation.run is None or not evaluation.run.success:
        return evaluation, None
    try:
        reference = evaluation.run.reference_cycle()
    except ScalfError:  # the reference swing leaves the reach at this gait
        reference = None
    return evaluation, reference


def search_progress(
    gait: int, start: float, now: float | None = None, usual: int = USUAL_GAITS_PER_SPEED
) -> str:
    """How far a speed's search is: ``gait 40 of about 145, about 2 min left``.

    ``gait``: the count of gaits tried, this one included; ``start``: when the search began
    (:func:`time.perf_counter`); the time left is estimated from the pace so far.
    """
    now = time.perf_counter() if now is None else now
    if gait > usual:
        return f"gait {gait} (more than the usual {usual})"
    text = f"gait {gait} of about {usual}"
    if gait < 5:  # too few to tell a pace
        return text
    left_s = (now - start) / (gait - 1) * (usual - gait + 1)
    left = f"{left_s:.0f} s" if left_s < 90 else f"{left_s / 60:.0f} min"
    return f"{text}, about {left} left"


@dataclass(frozen=True)
class GaitGoal:
    """What a gait search asks for: the cheapest trot at one speed.

    Attributes:
        speed_m_s: Target speed [m/s], in (0, 10].
        family: The swing family every gait's swings are optimized in.
        settings: How the swings are optimized (default: ``scalf-opt optimize``'s).
        box: The search box (``None``: :meth:`GaitBox.around` the base gait).
    """

    speed_m_s: float
    family: SwingFamily
    settings: Settings = field(default_factory=Settings)
    box: GaitBox | None = None

    def __post_init__(self) -> None:
        check_speed(self.speed_m_s)


def optimize_gait(
    pipeline: EnergyPipeline,
    goal: GaitGoal,
    progress: Callable[[str], None] | None = None,
) -> GaitSearch:
    """The cheapest trot at ``goal``'s speed (see the module docstring).

    Args:
        pipeline: Robot, accounting and the base gait: the robot's default trot (its period,
            duty, stance, clearance and rate are the grid's centre and the start).
        goal: The speed, the swing family, the swings' settings and the search box.
        progress: Called with a label as each new gait's swings start being optimized
            (``0.5 m/s: gait 7 of about 145, about 4 min left, T = 0.550 s, duty 0.600``).
    """
    speed_m_s, family, settings = float(goal.speed_m_s), goal.family, goal.settings
    start = time.perf_counter()
    base = pipeline.gait
    box = goal.box or GaitBox.around(base)
    trials = GaitTrials(pipeline, family, settings, FIRST_PAIR, stance_at_swing_rate=True)
    mass = pipeline.robot.total_mass_kg

    def evaluate(x: np.ndarray) -> StanceEvaluation:
        period_s, duty = (from_search_units(v) for v in x[:2])
        outside = box.outside(replace(base, period_s=period_s), duty)
        if outside is not None:  # before the gait: a duty below 0.5 is no Gait at all
            return StanceEvaluation(base, math.inf, outside)
        try:
            gait = gait_at(base, speed_m_s, x)
        except ScalfError as exc:
            return StanceEvaluation(base, math.inf, str(exc))
        why = reference_unwalkable(pipeline.with_gait(gait))
        if why is not None:
            return StanceEvaluation(gait, math.inf, why)
        if progress is not None and GaitTrials.key(gait) not in trials.seen:
            progress(
                f"{speed_m_s:g} m/s: {search_progress(len(trials.seen) + 1, start)}, "
                f"T = {gait.period_s:.3f} s, duty {gait.duty_cycle:.3f}"
            )
        return trials.evaluate(gait)

    def objective(x: np.ndarray) -> tuple[float, str | None]:
        e = evaluate(x)
        return cost_of_transport(e, mass, speed_m_s), e.reason

    if progress is not None:
        progress(f"{speed_m_s:g} m/s: the default trot")
    default, reference = _default_evaluation(trials, at_speed(base, speed_m_s))
    grid = []
    for factor in GRID_PERIOD_FACTORS:
        for duty in GRID_DUTIES:
            x = search_vector(replace(base, period_s=factor * base.period_s, duty_cycle=duty))
            grid.append((x, evaluate(x)))
    candidates = list(grid)
    if reference_unwalkable(pipeline.with_gait(default.gait)) is None:  # else no answer either
        candidates.insert(0, (search_vector(default.gait), default))
    x0, first = min(candidates, key=lambda c: cost_of_transport(c[1], mass, speed_m_s))
    result = pattern_search(
        objective, x0, PatternSearchOptions(initial_step=INITIAL_STEP, precision=PRECISION)
    )
    best = trials.from_every_start(evaluate(result.x) if math.isfinite(result.value) else first)
    pinned: dict[str, str] = {}
    if best.run is not None:
        for i, (name, step) in enumerate(zip(SEARCH_VARIABLES, _last_steps(), strict=True)):
            for sign, word in ((1.0, "up"), (-1.0, "down")):
                x = result.x.copy()
                x[i] += sign * step
                neighbour = evaluate(x)
                if neighbour.reason is not None:
                    pinned[f"{name} {word}"] = neighbour.reason
    return GaitSearch(
        speed_m_s=speed_m_s,
        family=family,
        settings=settings,
        box=box,
        default=default,
        reference=reference,
        best=best,
        grid=[e for _, e in grid],
        pinned=pinned,
        iterations=result.iterations,
        evaluations=result.evaluations,
        converged=result.converged and best.run is not None,
        mass_kg=mass,
        wall_time_s=time.perf_counter() - start,
        history=list(result.history),
    )
