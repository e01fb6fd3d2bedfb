"""The paper-reproduction report: Markdown with Tables 5 and 6, its CSV and JSON, and figures."""

from __future__ import annotations

from collections.abc import Sequence
from pathlib import Path

from scalf_opt.energy.cycle import change_percent
from scalf_opt.files import write_atomic
from scalf_opt.io.results import rows_csv_text, split_timings, write_results_json
from scalf_opt.locomotion.swing.names import DEFAULT_FAMILY
from scalf_opt.model.robot import Robot
from scalf_opt.optimize.bound import bound_cycle_inputs
from scalf_opt.studies import paper_data
from scalf_opt.studies.paper import (
    AGREEMENT_PERCENT,
    PAIR,
    RUNS,
    Reproduction,
    WholeBody,
    gap_percent,
    ipopt_above_pattern_search,
    summary,
    table5_rows,
    table6_rows,
    unvalidated,
)
from scalf_opt.studies.paper_data import is_paper_setup
from scalf_opt.viz.figures import pattern_search_figure, save_atomic, swing_figure


def validation_verdict(rep: Reproduction) -> str:
    """One sentence under the validation table: do the pattern search and Ipopt agree?"""
    limit = f"{AGREEMENT_PERCENT:g} %"
    below = ipopt_above_pattern_search(rep)
    missing = unvalidated(rep)
    if missing:
        return (
            f"**Not compared** on {' and '.join(missing)}: Ipopt or the fine pattern search did "
            "not solve it (the table's status says which)."
        )
    if not below:
        return (
            f"They agree: on neither leg does the pattern search end more than {limit} (the "
            "sampling tolerance) below Ipopt's optimum."
        )
    legs = "; ".join(f"{leg} {amount:.2f} % below" for leg, amount in below.items())
    return (
        f"**They disagree**: the pattern search ends more than {limit} below Ipopt ({legs}): "
        "Ipopt stopped on a higher local optimum of the paper family, and its rows are that "
        "optimum, not the family's minimum."
    )


def _signed(x: float) -> str:
    return f"{x:+.2f} %"


def whole_body_line(whole: WholeBody) -> str:
    """The report's one line on the whole-body loads (the other commands' default)."""
    ref = whole.reference
    head = (
        f"Under whole-body loads (the stance feet carry the whole robot's inverse dynamics, "
        f"the default of the other commands; see the documentation's 'Whole-body loads'), at "
        f"{whole.run.rate_hz:g} Hz: the reference takes {ref.energy_j:.3f} J per cycle "
        f"(trunk-only {whole.trunk_reference.energy_j:.3f} J), mean stance force "
        f"{ref.mean_stance_force_n:.0f} N (trunk-only "
        f"{whole.trunk_reference.mean_stance_force_n:.0f} N), peak unbalanced moment "
        f"{ref.peak_unbalanced_moment_nm:.0f} N m; "
    )
    if not whole.run.success:
        return (
            head + f"the {whole.run.family.name} optimum did NOT converge ({whole.run.failure()})."
        )
    optimum = whole.run.cycle()
    return head + (
        f"the {whole.run.family.name} optimum, re-optimized so that a swing pays for the loads "
        f"it puts on the stance legs, takes {optimum.energy_j:.3f} J "
        f"({_signed(change_percent(optimum.energy_j, ref.energy_j))})."
    )


def paper_markdown(rep: Reproduction, robot: Robot) -> str:
    """The paper-reproduction report (Markdown): Tables 5 and 6.

    The paper's numbers stand beside ours when the robot is SCalf on the paper's gait
    (:func:`is_paper_setup`).
    """
    compare = is_paper_setup(robot, rep.gait)
    title = (
        "# SCalf paper reproduction: Tables 5 and 6"
        if compare
        else f"# The paper's comparison (Tables 5 and 6) on {robot.name}"
    )
    metered = sorted(
        {
            d.power_text
            for d in rep.pipeline.robot_physics.drives.values()
            if not d.charges_joint_power
        }
    )
    if compare:
        power = "`|tau qd| + |F_f v|`"
    elif metered:  # such drives meter their own input power: the accounting is not theirs
        power = "drawn by the drives: " + " and ".join(metered)
    else:
        power = "`|tau qd|` plus the drives' losses"
    lines = [
        *_table5(rep, robot, compare, title, power),
        *_table6(rep, compare),
        *_validation(rep),
        *_bound_section(rep),
        *_stance_section(rep),
        *_not_solved(rep),
        *_differences(rep, compare),
        "",
        "## Figures",
        "",
        "![Pattern search (the paper's Figure 8)](pattern_search.png)",
        "",
        "![RF swing foot paths and power](swing_paths.png)",
    ]
    return "\n".join(lines) + "\n"


def _table5(rep: Reproduction, robot: Robot, compare: bool, title: str, power: str) -> list[str]:
    """The report's head and Table 5 (each run's parameters, the paper's beside RF's)."""
    g = rep.gait
    lines = [
        title,
        "",
        f"Robot `{robot.urdf_path.name}` ({robot.total_mass_kg:.2f} kg); "
        f"trot T = {g.period_s:g} s, duty {g.duty_cycle:g}, S = {g.step_length_m:g} m, "
        f"H = {g.clearance_m:g} m, "
        f"z0 = {g.stance_height_m:g} m, {g.sample_rate_hz:g} Hz; power "
        f"{power}. "
        "LF and RH repeat RF and LH half a cycle later (the paper's symmetry; checked: "
        f"{rep.reference.symmetry_error:.1e}).",
        "",
        "## Table 5: trajectory parameters",
        "",
        "C1 is the hip angle's `cos(3 pi s)` amplitude, C2 the knee angle's `cos(2 pi s)` "
        "amplitude [deg] (the family: the documentation's 'Swing families and optimizers'); "
        "the paper's own basis was lost, so its values are not comparable number for number.",
        "",
        "| leg | run | C1 [deg] | C2 [deg] | iterations | evaluations | swing energy [J] "
        "| status |",
        "|---|---|---|---|---|---|---|---|",
    ]
    for leg in PAIR:
        for key in ("pattern", "pattern_fine", "ipopt"):
            o = rep.optima[key][leg]
            lines.append(
                f"| {leg} | {RUNS[key][1]} | {o.theta[0]:.3f} | {o.theta[1]:.3f} | {o.iterations} |"
                f" {o.evaluations or '-'} | {o.swing_energy_j:.3f} | {o.status} |"
            )
        if leg == "RF" and compare:
            t5 = paper_data.TABLE5_RF
            lines.append(
                f"| RF | paper, pattern search | {t5['C1']} | {t5['C2']} | {t5['iterations']} | "
                "- | - | (Table 5) |"
            )
    return lines


def _table6(rep: Reproduction, compare: bool) -> list[str]:
    """Table 6: each run's energies and changes at its rate, the paper's row, whole-body loads."""
    lines: list[str] = []
    paper6 = paper_data.TABLE6_CHANGE_PERCENT
    rows = table6_rows(rep)
    lines += [
        "",
        f"## Table 6: energy per cycle (simulation), the paper's {rep.pipeline.loads} loads",
        "",
        "Each row is sampled at the rate its optimization converged at (every optimum's swing "
        "energy agrees with its energy at ten times the rate within 0.5 %); its changes are "
        "against the reference at the same rate, whose total is in the column 'reference [J]' "
        "(the same numbers `scalf-opt optimize` prints for that family).",
        "",
        "| trajectory | rate [Hz] | RF swing [J] | RF cycle [J] | LH swing [J] | LH cycle [J] | "
        "total [J] | reference [J] | avg power [W] | RF swing | RF cycle | LH swing | LH cycle | "
        "total |",
        "|---|---|---|---|---|---|---|---|---|---|---|---|---|---|",
    ]
    for r in rows:
        lines.append(
            f"| {r['trajectory']} | {r['sample_rate_hz']:g} | {r['RF_swing_j']:.3f} | "
            f"{r['RF_cycle_j']:.3f} | "
            f"{r['LH_swing_j']:.3f} | {r['LH_cycle_j']:.3f} | {r['total_energy_j']:.3f} | "
            f"{r['reference_total_energy_j']:.3f} | {r['average_power_w']:.2f} | "
            f"{_signed(float(r['RF_swing_change_pct']))} | "
            f"{_signed(float(r['RF_cycle_change_pct']))} | "
            f"{_signed(float(r['LH_swing_change_pct']))} | "
            f"{_signed(float(r['LH_cycle_change_pct']))} | "
            f"{_signed(float(r['total_change_pct']))} |"
        )
    if compare:
        lines.append(
            f"| paper: reference -> Fourier (Table 6) | 200 | | | | | | | "
            f"{paper_data.REFERENCE_AVERAGE_POWER_W} -> {paper_data.OPTIMIZED_AVERAGE_POWER_W} | "
            f"{_signed(paper6['RF']['swing'])} | {_signed(paper6['RF']['cycle'])} | "
            f"{_signed(paper6['LH']['swing'])} | {_signed(paper6['LH']['cycle'])} | "
            f"{_signed(paper6['total']['total'])} |"
        )
    if rep.whole_body is not None:
        lines += ["", whole_body_line(rep.whole_body)]
    return lines


def _validation(rep: Reproduction) -> list[str]:
    """The pattern search against Ipopt, per leg, and the verdict."""
    lines: list[str] = []
    lines += [
        "",
        "## Validation: pattern search against the NLP optimum",
        "",
        "Both answers are evaluated with the exact, non-smooth energy.",
        "",
        "| leg | gap at precision 0.1 | gap at precision 1e-4 | Ipopt iterations | Ipopt status |",
        "|---|---|---|---|---|",
    ]
    for leg in PAIR:
        nlp = rep.optima["ipopt"][leg]
        lines.append(
            f"| {leg} | {gap_percent(rep.optima['pattern'][leg], nlp):+.4f} % | "
            f"{gap_percent(rep.optima['pattern_fine'][leg], nlp):+.5f} % | {nlp.iterations} | "
            f"{nlp.status} |"
        )
    lines += ["", validation_verdict(rep)]
    return lines


def _bound_section(rep: Reproduction) -> list[str]:
    """Beyond the paper: the free-trajectory bound and each run's gap to it."""
    lines: list[str] = []
    if rep.bounds:
        lines += [
            "",
            "## Beyond the paper: the free-trajectory bound",
            "",
            "The lowest swing energy a smooth swing reaches under the same end conditions, "
            "constraints and energy: dense cubic B-splines of the joint angles, refined until the "
            "energy still to gain is estimated below 1 % (see the documentation). Gaps compare the "
            "energies at ten times each optimization's rate.",
            "",
            "| swing | RF swing [J] | RF gap | LH swing [J] | LH gap |",
            "|---|---|---|---|---|",
        ]
        for key, run in rep.runs.items():
            cells = []
            for leg in PAIR:
                result = run.legs[leg]
                gap = result.gap_to_bound_percent
                cells += [f"{result.check_energy_j:.3f}", "-" if gap is None else f"{gap:+.2f} %"]
            lines.append(f"| {RUNS[key][1]} | " + " | ".join(cells) + " |")
        cells = []
        for leg in PAIR:
            b = rep.bounds[leg]
            state = b.status_text() if b.success else f"**NOT CONVERGED**: {b.status_text()}"
            cells += [f"{b.check_energy_j:.3f}", f"({state})"]
        lines.append("| free-trajectory bound | " + " | ".join(cells) + " |")
    return lines


def _stance_section(rep: Reproduction) -> list[str]:
    """Beyond the paper: the stance as a free variable."""
    lines: list[str] = []
    if rep.free_stance is not None and rep.free_stance.success:
        split = rep.free_stance.split_j()
        stance = rep.free_stance.best.gait
        ref_j = rep.free_stance.reference.energy_j
        lines += [
            "",
            "## Beyond the paper: the stance as a free variable",
            "",
            f"The stance height z0 and the feet's x-offsets at mid-stance (front, hind), optimized "
            f"together with the {DEFAULT_FAMILY} swings (`scalf-opt optimize --free-stance`): "
            f"z0 = {stance.stance_height_m:.3f} m, front "
            f"{1000 * stance.stance_x_offset_front_m:+.1f} mm, hind "
            f"{1000 * stance.stance_x_offset_hind_m:+.1f} mm. Against the reference "
            f"({ref_j:.3f} J per cycle) it saves {split['total']:.3f} J "
            f"({100 * split['total'] / ref_j:.1f} %): {split['stance']:.3f} J from the stance and "
            f"{split['swing']:.3f} J from the swing. The swing optimization alone saves "
            f"{split['swing_only']:.3f} J; freeing the stance adds "
            f"{split['from_freeing_the_stance']:.3f} J.",
        ]
    return lines


def _not_solved(rep: Reproduction) -> list[str]:
    """A bold line when a run did not converge."""
    lines: list[str] = []
    if not rep.all_solved:
        lines += [
            "",
            "**Not every optimizer converged: see the status columns. Rows of a run "
            "that did not converge are left out of Table 6.**",
        ]
    return lines


def _differences(rep: Reproduction, compare: bool) -> list[str]:
    """Why the numbers differ from the paper's (SCalf on the paper's gait only)."""
    lines: list[str] = []
    g = rep.gait
    ref_power = rep.reference.average_power_w
    if compare:
        lines += [
            "",
            "## Why the numbers differ from the paper",
            "",
            f"- The reference draws {ref_power:.1f} W against the paper's "
            f"{paper_data.REFERENCE_AVERAGE_POWER_W} W: the paper gives neither the stance "
            f"height z0 ({g.stance_height_m:g} m here, decision 6), nor the trunk's inertia, nor "
            "its exact stance trajectory and force treatment; the stance phase dominates the "
            "total.",
            "- The paper's Fourier basis and its Appendix A were lost. The paper family here has "
            "the same size (two coefficients per leg) but is our own design; the best of the 50 "
            "single-term pairs we scanned (`studies/paper_family_scan.py`). With two "
            "coefficients it cuts the swing energy by less than the paper's 26 %; the richer "
            "nested family shows how much a swing can save under the same constraints.",
            "- Constraints are the paper's implicit ones made explicit (joint limits, ground, "
            "cylinder stroke, at least H of clearance at mid-swing) and the actuators' limits "
            "(the URDF's joint velocity and effort limits, the cylinders' force and speed); the "
            "foot's mid-swing x is free.",
        ]
    return lines


def paper_summary(rep: Reproduction, robot: Robot, report: Path) -> str:
    """What ``scalf-opt paper`` prints: Table 6's totals, the checks, where the report is.

    The whole report (Tables 5 and 6 per leg, the validation, the bound, the stance) is
    ``report``; this is its short form, lines of at most 100 characters.
    """
    g = rep.gait
    compare = is_paper_setup(robot, g)
    head = "SCalf paper reproduction" if compare else f"The paper's comparison on {robot.name}"
    lines = [
        f"{head}: trot T = {g.period_s:g} s, duty {g.duty_cycle:g}, S = {g.step_length_m:g} m, "
        f"H = {g.clearance_m:g} m, z0 = {g.stance_height_m:g} m",
        f"Table 6, the model's energy per cycle (loads '{rep.pipeline.loads}', accounting "
        f"'{rep.reference.accounting}');",
        "each row at the rate its optimization converged at, its change against the reference "
        "there:",
        f"  {'trajectory':<48}{'rate':>7}{'total':>12}{'power':>11}{'change':>10}",
    ]
    for row in table6_rows(rep):
        label = str(row["trajectory"])
        label = label.split(" (")[0] if "free stance" in label else label
        lines.append(
            f"  {label:<48}{row['sample_rate_hz']:>4g} Hz{row['total_energy_j']:>10.3f} J"
            f"{row['average_power_w']:>9.2f} W{_signed(float(row['total_change_pct'])):>10}"
        )
    if compare:
        lines.append(
            f"  the paper (Table 6): {paper_data.REFERENCE_AVERAGE_POWER_W} W -> "
            f"{paper_data.OPTIMIZED_AVERAGE_POWER_W} W, "
            f"{_signed(paper_data.TABLE6_CHANGE_PERCENT['total']['total'])}"
        )
    if rep.whole_body is not None:
        whole = rep.whole_body
        ref = whole.reference
        answer = (
            f"{whole.run.family.name} optimum {whole.run.cycle().energy_j:.3f} J "
            f"({_signed(change_percent(whole.run.cycle().energy_j, ref.energy_j))})"
            if whole.run.success
            else f"the {whole.run.family.name} optimum did NOT converge"
        )
        lines += [
            f"under whole-body loads (the other commands' default), {whole.run.rate_hz:g} Hz:",
            f"  reference {ref.energy_j:.3f} J, {answer}",
        ]
    gaps = ", ".join(
        f"{leg} {gap_percent(rep.optima['pattern_fine'][leg], rep.optima['ipopt'][leg]):+.5f} %"
        for leg in PAIR
    )
    verdict = validation_verdict(rep).replace("**", "").split(":")[0].lower()
    lines.append(f"pattern search (precision 1e-4) against Ipopt: {gaps}; {verdict}")
    if rep.bounds:
        bound = ", ".join(f"{leg} {b.check_energy_j:.3f} J" for leg, b in rep.bounds.items())
        lines.append(f"free-trajectory bound of the swing energy: {bound}")
    if not rep.all_solved:
        lines.append("NOT every optimizer converged: the report's status columns say which")
    lines.append(f"the whole report: {report} (Tables 5 and 6 per leg, checks, figures)")
    return "\n".join(lines)


def write_paper_outputs(
    rep: Reproduction, robot: Robot, out: Path, command: Sequence[str] | None = None
) -> list[Path]:
    """Write the report, the result files and the two figures of a reproduction.

    ``report.md``, ``paper.json`` (its run times in ``timings.json``), ``table5.csv``,
    ``table6.csv``, ``pattern_search.png`` and ``swing_paths.png``.

    Returns:
        The paths written, in that order.
    """
    trajectories = [("reference (cubic spline)", rep.reference)]
    trajectories += [
        (RUNS[k][1], rep.cycles[k]) for k in ("ipopt", "ipopt_rich") if k in rep.cycles
    ]
    if rep.bounds:
        at_rate, family, thetas = bound_cycle_inputs(rep.pipeline, rep.bounds)
        trajectories.append(("free-trajectory bound", at_rate.robot_cycle(family, thetas)))
    return [
        write_atomic(out / "report.md", paper_markdown(rep, robot)),
        *write_results_json(out / "paper.json", summary(rep, robot, command)),
        write_atomic(out / "table5.csv", rows_csv_text(split_timings(table5_rows(rep))[0])),
        write_atomic(out / "table6.csv", rows_csv_text(table6_rows(rep))),
        save_atomic(pattern_search_figure(rep.optima["pattern"]), out / "pattern_search.png"),
        save_atomic(swing_figure(trajectories), out / "swing_paths.png"),
    ]
