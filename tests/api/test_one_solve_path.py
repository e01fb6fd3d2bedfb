"""One solve path: every consumer of an optimum prints the same optimized and reference energies.

``optimize``, a one-case study, ``view``'s legend, ``figures``, the API and ``paper`` all get
their optimum from the one driver, so for the same gait and family they print the same numbers
to the last digit they print (3 decimals of a joule), the reference at the optimum's rate.

joint-6 runs under the default whole-body loads; joint-12 (the family that refines its rate)
under the trunk-only loads, which solve the legs apart: one path is one path whatever the loads,
and whole-body joint-12 alternates its coupled legs for minutes per route.

Each ``optimize`` run is made once (the module's ``optimized`` fixture) and read by every test
that compares with it; the module runs on one worker (its xdist group) so that it is made once.
"""

import contextlib
import csv
import io
import json
import re

import pytest

import scalf_opt as so
from scalf_opt.cli import main

pytestmark = [pytest.mark.slow, pytest.mark.xdist_group("one_solve_path")]

ENERGY_LINE = re.compile(r"^  (?P<label>.+): (?P<energy>\d+\.\d{3}) J, ", re.MULTILINE)


def printed(value: float) -> str:
    return f"{value:.3f}"


def legend(text: str) -> dict[str, str]:
    """``label -> energy`` from the lines ``view`` and ``figures`` print."""
    return {m["label"]: m["energy"] for m in ENERGY_LINE.finditer(text)}


def numbers(summary):
    """The optimized and reference energies ``optimize --json`` printed, as printed."""
    return (
        printed(summary["total_energy_per_cycle_j"]),
        printed(summary["reference_total_energy_per_cycle_j"]),
    )


@pytest.fixture(scope="module")
def optimized(tmp_path_factory):
    """``optimize --family F --json --out DIR OPTIONS``, run once per family and options:
    ``optimized(F, *OPTIONS)`` is what it printed (parsed) and DIR."""
    runs = {}

    def run(family, *options):
        if (family, *options) not in runs:
            out = tmp_path_factory.mktemp(f"optimum-{family}")
            argv = ["optimize", "--family", family, "--json", *options, "--out", str(out)]
            text = io.StringIO()
            with contextlib.redirect_stdout(text):
                assert main(argv) == 0
            runs[family, *options] = json.loads(text.getvalue()), out
        return runs[family, *options]

    return run


LOADS = {"joint-6": "whole-body", "joint-12": "trunk"}
"""The loads each family's checks run under."""

OPTIONS = {"joint-6": (), "joint-12": ("--loads", "trunk")}
"""``optimize``'s options for them: joint-6 under the default loads, which are whole-body (the
tests check the loads its summary names), and which ``view`` and ``figures`` use too."""


def study_numbers(family, tmp_path, capsys):
    study = tmp_path / f"{family}.toml"
    study.write_text(f'[study]\nrobot = "scalf"\nfamily = "{family}"\nloads = "{LOADS[family]}"\n')
    out = tmp_path / f"study-{family}"
    assert main(["study", str(study), "--workers", "1", "--out", str(out)]) == 0
    capsys.readouterr()
    with (out / "results.csv").open() as f:
        (row,) = list(csv.DictReader(f))
    return printed(float(row["optimized_energy_j"])), printed(float(row["reference_energy_j"]))


def api_numbers(family):
    result = so.optimize_swing(so.load_robot("scalf"), family=family, loads=LOADS[family])
    assert result.cycle is not None
    return printed(result.cycle.energy_j), printed(result.reference.energy_j)


@pytest.mark.parametrize("family", ["joint-6", "joint-12"])
def test_optimize_study_and_api_agree(family, optimized, tmp_path, capsys):
    summary, _ = optimized(family, *OPTIONS[family])
    assert summary["optimization_run"]["loads"] == LOADS[family]
    assert study_numbers(family, tmp_path, capsys) == numbers(summary)
    assert api_numbers(family) == numbers(summary)


def test_view_figures_and_paper_print_the_optimize_numbers(optimized, tmp_path, capsys):
    default, _ = optimized("joint-6")  # optimize's default loads, as view's and figures'
    assert default["optimization_run"]["loads"] == "whole-body"
    optimum, reference = numbers(default)
    assert main(["view", "--out", str(tmp_path / "scene.html")]) == 0
    shown = legend(capsys.readouterr().out)
    assert shown == {"reference (cubic spline)": reference, "optimum (joint-6, ipopt)": optimum}
    figures = tmp_path / "figures"
    assert main(["figures", "--format", "png", "--grid", "3", "--out", str(figures)]) == 0
    assert legend(capsys.readouterr().out) == shown
    # paper's tables use the trunk-only loads: optimize's numbers under them; its one line
    # under whole-body loads: optimize's default numbers
    trunk_optimized, trunk_reference = numbers(optimized("joint-6", "--loads", "trunk")[0])
    assert main(["paper", "--quick", "--out", str(tmp_path / "paper")]) == 0
    summary = capsys.readouterr().out  # the short form; the whole report is report.md
    lines = summary.replace(str(tmp_path), "DIR").splitlines()[:-1]  # the "wrote" line
    assert max(map(len, lines)) <= 100 and len(lines) <= 20
    assert f"{trunk_optimized} J" in summary and f"reference {reference} J" in summary
    table6 = json.loads((tmp_path / "paper" / "paper.json").read_text())["table6"]
    (row,) = [r for r in table6 if r["trajectory"] == "Ipopt, joint-6 family"]
    assert (printed(row["total_energy_j"]), printed(row["reference_total_energy_j"])) == (
        trunk_optimized,
        trunk_reference,
    )
    report = (tmp_path / "paper" / "report.md").read_text()
    assert f"| {trunk_optimized} | {trunk_reference} |" in report
    assert f"the reference takes {reference} J per cycle" in report
    assert f"takes {optimum} J" in report


def test_view_of_a_saved_joint_12_optimum_prints_its_numbers(optimized, tmp_path, capsys):
    summary, saved = optimized("joint-12", *OPTIONS["joint-12"])
    # its parameters are its modes' rms amplitudes: none beyond ten times the largest joint
    # range in degrees (its coefficients reached a million degrees)
    leg = so.load_robot("scalf").leg("RF")
    largest_range_deg = max(leg.upper_limits_rad - leg.lower_limits_rad) * 180 / 3.141592653589793
    for record in summary["optimization"].values():
        assert max(map(abs, record["parameters"].values())) < 10 * largest_range_deg
        assert max(map(abs, record["parameters"].values())) < 30.0  # measured 16 degrees
    assert main(["view", "--from", str(saved), "--out", str(tmp_path / "j12.html")]) == 0
    shown = legend(capsys.readouterr().out)
    assert shown["reference (cubic spline)"] == printed(
        summary["reference_total_energy_per_cycle_j"]
    )
    assert list(shown.values())[1] == printed(summary["total_energy_per_cycle_j"])
